"""The remaining commands of the core: ramp selection, GN, limit settings, probes."""

import math

import pytest

from maxk import MAXk
from maxk.commands.max.table import COMMANDS
from maxk.firmware_model.profiles import RampShape


@pytest.mark.parametrize("cmd,shape", [("PN", RampShape.PARABOLIC), ("PN2", RampShape.PARABOLIC),
                                       ("SC", RampShape.SCURVE), ("CN", RampShape.COSINE),
                                       ("LA", RampShape.LINEAR)])
def test_ramp_selection(cmd, shape):
    b = MAXk()
    b.send(f"AX; {cmd};")
    assert b.board.axes[0].config.ramp is shape
    b.send("PF")
    assert b.board.axes[0].config.ramp is RampShape.LINEAR


def test_ramp_parameters_are_stored():
    b = MAXk()
    b.send("AX; SC; SS30; PR40; PN7;")
    c = b.board.axes[0].config
    assert (c.scurve_factor, c.ramp_parameter, c.ramp_factor) == (30, 40, 7)
    assert not b.command_error


@pytest.mark.parametrize("cmd,ramp_s,ramp_fraction", [
    ("LA", 0.1, 1 / 2), ("PN", 0.2, 2 / 3), ("SC", 0.2, 1 / 2), ("CN", math.pi / 20, 1 / 2)])
def test_ramp_shape_changes_the_move_time(cmd, ramp_s, ramp_fraction):
    b = MAXk()
    b.send(f"AX; {cmd}; VL10000; AC100000; MR100000; GO; ID;")
    b.run_until_done("X", timeout=60)
    assert b.position("X") == 100000
    # each ramp lasts k*VL/AC and covers ramp_fraction * VL * its time
    ramp_steps = ramp_fraction * 10000 * ramp_s
    analytic = 2 * ramp_s + (100000 - 2 * ramp_steps) / 10000
    assert analytic * 8192 <= b.tick < analytic * 8192 + 1


def test_gn_is_go():
    b = MAXk()
    b.send("AX; MA500; GN; ID;")
    assert b.run_until_done("X")
    assert b.position("X") == 500


def test_limit_settings_round_trip():
    b = MAXk()
    b.send("AX LF")
    assert b.query("LM?") == "=f"
    b.send("LN")
    assert b.query("LM?") == "=h"
    b.send("LMS")
    assert b.query("LM?") == "=s"
    b.send("LH")
    assert b.query("LT?") == "=h"
    b.send("LL")
    assert b.query("LT?") == "=l"


def test_settings_are_queued_behind_a_move():
    b = MAXk()
    b.send("AX; VL1000; MR1000; GO; LTH;")
    assert b.query("LT?") == "=l"  # LTH waits in the queue behind the move
    b.run_until_idle()
    assert b.query("LT?") == "=h"


def test_manual_tuning_check_on_an_open_loop_stepper():
    b = MAXk()
    b.send("AC100000;VL5000;MR64000;GO;")
    b.run_until_idle(timeout=30)
    assert b.query("RE") == b.query("RP") == "64000"


def test_every_table_entry_has_a_behaviour_and_every_behaviour_an_entry():
    """A command's behaviour is bound once: by its table entry's timing (and properties
    such as `start`) to exactly one handler; no handler exists without an entry."""
    from maxk.commands.max.immediate import IMMEDIATE
    from maxk.commands.max.queued import NOT_MODELLED_YET, QUEUED, SETTING_QUERIES
    from maxk.commands.max.table import Start, Timing
    from maxk.commands.max.vector import _HANDLERS

    for m, spec in COMMANDS.items():
        linear = spec.start in (Start.LINEAR_ABSOLUTE, Start.LINEAR_RELATIVE)
        bound = [m in IMMEDIATE, m in QUEUED, m in NOT_MODELLED_YET, linear, m in _HANDLERS]
        if spec.timing is Timing.MODE:
            assert not any(bound), m
        else:
            assert sum(bound) == 1, (m, bound)
            assert spec.timing is {0: Timing.IMMEDIATE, 1: Timing.QUEUED, 2: Timing.QUEUED,
                                   3: Timing.QUEUED, 4: Timing.VECTOR}[bound.index(True)], m
        if spec.timing is Timing.QUEUED and spec.query:
            assert m in SETTING_QUERIES, m
        assert spec.confidence in "CID", m
        assert spec.source, m
    for handlers in (IMMEDIATE, QUEUED, NOT_MODELLED_YET, SETTING_QUERIES, _HANDLERS):
        assert set(handlers) <= set(COMMANDS), set(handlers) - set(COMMANDS)


def test_every_mnemonic_is_accepted_by_the_lexer_in_both_cases():
    from maxk.commands.max.lexer import Lexer, ParsedCommand

    for m, spec in COMMANDS.items():
        operand = {"none": "", "#": "1", "letter": spec.letters[:1],
                   "pattern": spec.letters[:1] * 4, "hex": "0",
                   "vector": "1" if spec.arity else ""}[spec.operand.value]
        for text in (m + operand, (m + operand).lower()):
            out = Lexer().feed(text + ";")
            assert len(out) == 1 and isinstance(out[0], ParsedCommand), (text, out)
            assert out[0].mnemonic == m

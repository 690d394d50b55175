"""The "must" sentences of the host reference files that no other test pinned down.

Each test names the sentence it holds the emulator to (maxk-host-interface.md,
max-command-evidence.md, max-command-reference-facts.md); the others are covered where
their behaviour lives (see the docstrings of the tests named in docs/commands.md).
"""

import pytest

from maxk import MAXk
from maxk.commands.max.lexer import Lexer, ParsedCommand

SERVO_TUNED = "KP100; KD400; KI40; KU400; KV680;"  # docs/servo.md: the default motor, tuned


def test_manual_tuning_check_runs_as_written_without_an_axis_prefix() -> None:
    """Host interface: "Examples from the manual that must run as written":
    `AC100000;VL5000;MR64000;GO;` then RE and RP to compare. As written it has no axis
    command and no blanks, so it runs on the axis addressed after power-up (X)."""
    board = MAXk()
    board.send(f"AX PSM; LP0; {SERVO_TUNED} CL1;")
    board.send("AC100000;VL5000;MR64000;GO;")
    assert not board.command_error, board.last_error
    assert board.run_until_idle(timeout=20)
    assert board.query("RP") == "64000"
    assert board.query("RE") == "64000"
    assert board.query("AY RP") == "0"  # the example moved X only


def test_vl_and_ac_sent_before_er_stay_in_motor_steps() -> None:
    """Facts Table 2, ER + MA: NMSU sends `ax vl#; ac#; er e,m; ... ma<enc>; gd; ip;`, so
    "the table's conversion must happen when an entry executes, not later to stored
    values": ER4000,1000 must not turn the VL1000/AC100000 given before it into counts."""
    board = MAXk()
    board.send("AX PSE; VL1000; AC100000; ER4000,1000; MA8000; GD; ID;")
    assert not board.command_error, board.last_error
    config = board.board.axis("X").config
    assert config.velocity == 1000  # steps/s, as sent (250 if ER rescaled it)
    assert config.acceleration == 100000
    assert board.run_until_done("X", timeout=10)
    assert board.query("AX RE") == "8000"  # the target is in encoder counts
    assert board.query("AX RP") == "2000"  # 4 counts per motor step


def test_a_queued_vl_after_a_queued_er_is_converted_when_it_runs() -> None:
    """Same sentence, queued: while a move runs, `ER4000,1000; VL8000;` waits in the queue.
    The VL is converted when it executes (after the ER ran), so it is 8000 counts/s =
    2000 steps/s; converting when the text arrived (ratio still 1:1) would give 8000."""
    board = MAXk()
    board.send("AX PSE; VL20000; AC200000; MR20000; GO;")
    board.advance(0.2)
    board.send("AX ER4000,1000; VL8000;")
    config = board.board.axis("X").config
    assert config.velocity == 20000  # still queued behind the running move
    assert board.run_until_idle(timeout=10)
    assert not board.command_error, board.last_error
    assert config.velocity == 2000


def test_after_a_soft_limit_stop_the_rest_of_the_queue_still_runs() -> None:
    """Facts Table 2, limit trip: TALON queues `ln sl mr<-2 rev> go ... ma0 goid` in one
    string; "the rest (home, back off, home slowly, go to 0, ID) must still run after that
    move stops on the limit" when soft limits (SL) are on."""
    board = MAXk("MAXk-4000")
    board.set_limits("X", plus=5000, minus=-5000)
    board.send("AX LN SL AC100000 VL10000 MR-20000 GO VL5000 MA0 GOID")
    assert board.run_until_idle(timeout=10)
    assert not board.command_error, board.last_error
    assert board.position("X") == 0  # the MA0 after the limit stop ran
    assert board.done("X")


def test_jf_takes_six_decimals_and_leading_zeros_after_the_sign() -> None:
    """Facts J3: "The lexer must accept leading zeros after the sign, and up to 6
    decimals" (`JF500.600000`, `JF-00012.3456`, `JF000003.5000`)."""
    board = MAXk()
    board.send("AX AC8000000; JF500.600000;")
    board.advance(1.0)
    assert board.velocity("X") == pytest.approx(500.6, abs=1e-9)
    board.send("AX ST; JF-000012.345678;")
    board.advance(5.0)
    assert board.velocity("X") == pytest.approx(-12.345678, abs=1e-9)
    assert not board.command_error, board.last_error


def test_the_dll_home_template_is_split_by_mnemonic() -> None:
    """Evidence 2.2: the DLL sends `AXHEHM0;ID`; "an emulator must therefore tokenize
    greedily by known mnemonic, not by separators"."""
    commands = [c for c in Lexer().feed("AXHEHM0;ID\r") if isinstance(c, ParsedCommand)]
    assert [(c.mnemonic, c.slots) for c in commands] == [
        ("AX", ()), ("HE", ()), ("HM", ("0",)), ("ID", ())]

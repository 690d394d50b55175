"""SCOPE_DELAY and SCOPE_TRIGGER_POS: SCOPE's delayed start and pre-trigger capture (their
TrioBASIC help pages). The scope samples TICKS, which in the scope's own context (as in a
process that never set it) reads minus the servo tick, so each stored value names the
tick it was taken on."""

from __future__ import annotations

from maxk.controllers.trio import MC405


def _run(program: str, ticks: int = 2000) -> MC405:
    trio = MC405()
    trio.load("P", program)
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=ticks)
    return trio


def _table(trio: MC405, index: int) -> float:
    return float(trio.query(f"?TABLE({index})"))


def test_the_pages_pre_trigger_keeps_what_was_taken_when_it_is_too_short() -> None:
    """The pages' example: 500 ms asked for, TRIGGER 320 ms after SCOPE: the 320 samples
    of the cycles since SCOPE are stored, then the trigger's own (place 321)."""
    trio = _run("SCOPE_DELAY = -500\nSCOPE(ON, 1, 1000, 3000, TICKS)\nWA(320)\n"
                "VR(1) = TICKS\nTRIGGER")
    trigger = trio.machine.vr_read(1)  # minus the trigger's tick
    assert trio.query("?SCOPE_TRIGGER_POS") == "321"
    assert _table(trio, 1000 + 320) == trigger  # TABLE(start - 1 + SCOPE_TRIGGER_POS)
    assert _table(trio, 1000 + 319) == trigger + 1  # the cycle before
    assert _table(trio, 1000) == trigger + 320  # SCOPE's own cycle, 320 before
    assert _table(trio, 1000 + 321) == trigger - 1  # and on after it, one a cycle


def test_a_long_enough_wait_keeps_exactly_the_delay() -> None:
    trio = _run("SCOPE_DELAY = -500\nSCOPE(ON, 1, 1000, 3000, TICKS)\nWA(800)\n"
                "VR(1) = TICKS\nTRIGGER")
    trigger = trio.machine.vr_read(1)
    assert trio.query("?SCOPE_TRIGGER_POS") == "501"
    assert [_table(trio, 1000 + k) for k in (0, 499, 500, 501)] == \
        [trigger + 500, trigger + 1, trigger, trigger - 1]


def test_the_pre_trigger_counts_samples_at_the_scopes_period() -> None:
    """20 ms before, a sample every 5 cycles: 4 samples from before, 5 cycles apart."""
    trio = _run("SCOPE_DELAY = -20\nSCOPE(ON, 5, 0, 100, TICKS)\nWA(100)\n"
                "VR(1) = TICKS\nTRIGGER")
    trigger = trio.machine.vr_read(1)
    assert trio.query("?SCOPE_TRIGGER_POS") == "5"
    steps = [_table(trio, k) - trigger for k in range(6)]
    assert steps[4] == 0 and steps[5] == -5  # the trigger's sample, then every 5 cycles
    assert [steps[k] - steps[k + 1] for k in range(4)] == [5, 5, 5, 5]


def test_scope_delay_set_after_scope_still_captures_before_trigger() -> None:
    """SCOPE's example 5: the delay set after SCOPE and before the TRIGGER."""
    trio = _run("SCOPE(ON, 1, 0, 1000, TICKS)\nSCOPE_DELAY = -20\nWA(100)\n"
                "VR(1) = TICKS\nTRIGGER")
    trigger = trio.machine.vr_read(1)
    assert trio.query("?SCOPE_TRIGGER_POS") == "21"
    assert _table(trio, 0) == trigger + 20
    assert _table(trio, 20) == trigger


def test_a_positive_delay_starts_the_capture_later() -> None:
    """SCOPE_DELAY's example 1 with our numbers: 20 ms after the TRIGGER."""
    trio = _run("SCOPE_DELAY = 20\nSCOPE(ON, 1, 0, 800, TICKS)\nWA(50)\nVR(1) = TICKS\n"
                "TRIGGER\nWA(10)\nVR(2) = SCOPE_POS")
    trigger = trio.machine.vr_read(1)
    assert trio.machine.vr_read(2) == 0  # 10 ms after: nothing stored yet
    assert _table(trio, 0) == trigger - 20
    assert _table(trio, 1) == trigger - 21
    assert trio.query("?SCOPE_TRIGGER_POS") == "0"


def test_no_delay_stores_from_the_trigger_at_place_one() -> None:
    trio = _run("SCOPE(ON, 1, 0, 800, TICKS)\nWA(50)\nVR(1) = TICKS\nTRIGGER")
    assert _table(trio, 0) == trio.machine.vr_read(1)
    assert trio.query("?SCOPE_TRIGGER_POS") == "1"

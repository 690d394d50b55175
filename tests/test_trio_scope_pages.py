"""SCOPE's table range and SCOPE_POS as the SCOPE_DELAY page's examples use them: table_stop
is the last TABLE index filled (10001..10800 holds 4 traces of 200 starting 10001, 10201,
10401, 10601), and a program waits for `SCOPE_POS = n`, n the points of each trace, to
know its capture is complete. Our numbers; TICKS, never set by the program, reads minus
the servo tick, so a sample of it names the tick it was taken on."""

from __future__ import annotations

from maxk.controllers.trio import MC405


def _table(trio: MC405, index: int) -> float:
    return float(trio.query(f"?TABLE({index})"))


def test_a_delayed_capture_of_four_traces_ends_at_scope_pos_200() -> None:
    """SCOPE_DELAY's example 1, our numbers: 4 traces over 2001..2800 have 200 points each;
    20 ms delay at 1 ms a cycle: samples on ticks T+20 .. T+219 (T the TRIGGER's)."""
    trio = MC405()
    trio.send("TABLE(2801, -1)")
    trio.load("P", "VR(9) = 4.5\nSCOPE_DELAY = 20\n"
              "SCOPE(ON, 1, 2001, 2800, TICKS, VR(9), -TICKS, 7)\nWA(5)\n"
              "VR(1) = TICKS\nTRIGGER\nWAIT UNTIL SCOPE_POS = 200\nVR(2) = TICKS\nVR(3) = 1")
    trio.send('RUN "P"')
    trio.advance(ticks=400)
    minus_t = trio.machine.vr_read(1)
    assert trio.query("?VR(3)") == "1.0000"  # the wait ended: the example does not hang
    assert trio.query("?SCOPE_POS") == "200"
    assert _table(trio, 2001) == minus_t - 20 and _table(trio, 2200) == minus_t - 219
    assert [_table(trio, n) for n in (2201, 2400)] == [4.5, 4.5]  # trace 2 from 2201
    assert _table(trio, 2401) == -(minus_t - 20) and _table(trio, 2600) == -(minus_t - 219)
    assert [_table(trio, n) for n in (2601, 2800, 2801)] == [7.0, 7.0, -1.0]
    assert trio.machine.vr_read(2) == minus_t - 219  # seen on the last sample's own cycle


def test_a_short_pre_trigger_capture_fills_its_points_and_reports_the_trigger() -> None:
    """SCOPE_DELAY's example 2, our numbers: 2 traces over 5001..6000 are 500 points each,
    200 ms asked for before the TRIGGER, only 120 ms given: the trigger's sample is the
    121st, TABLE(5000 + 121), and the capture ends at SCOPE_POS = 500."""
    trio = MC405()
    trio.send("TABLE(6001, -1)")
    trio.load("P", "SCOPE_DELAY = -200\nSCOPE(ON, 1, 5001, 6000, -TICKS, TICKS)\nWA(120)\n"
              "VR(1) = TICKS\nTRIGGER\nWAIT UNTIL SCOPE_POS = 500\n"
              "VR(4) = 5000 + SCOPE_TRIGGER_POS")
    trio.send('RUN "P"')
    trio.advance(ticks=1000)
    t = -trio.machine.vr_read(1)  # the TRIGGER's tick
    assert trio.query("?VR(4)") == "5121.0000"
    assert _table(trio, 5121) == t  # trace 1 reads the tick itself
    assert _table(trio, 5001) == t - 120 and _table(trio, 5500) == t + 379
    assert _table(trio, 5501) == -(t - 120) and _table(trio, 6000) == -(t + 379)
    assert _table(trio, 6001) == -1.0  # past table_stop: untouched


def test_scope_pos_counts_the_samples_stored_since_trigger() -> None:
    trio = MC405()
    trio.send("SCOPE(ON, 2, 100, 109, TICKS)")  # 10 points, one every 2 cycles
    assert trio.query("?SCOPE_POS") == "0"  # armed, not triggered
    trio.send("TRIGGER")  # the first sample on TRIGGER's own cycle
    assert trio.query("?SCOPE_POS") == "1"
    trio.advance(ticks=7)  # and on the 2nd, 4th, 6th after it
    assert trio.query("?SCOPE_POS") == "4"
    trio.advance(ticks=100)
    assert trio.query("?SCOPE_POS") == "10"  # full: stays at the trace's points
    trio.send("TRIGGER")
    assert trio.query("?SCOPE_POS") == "1"  # a new capture counts again


def test_one_parameter_uses_every_index_to_the_stop_and_the_last_table_index() -> None:
    trio = MC405()
    assert trio.send("SCOPE(ON, 1, 511990, 511999, TICKS)") == []
    trio.send("TRIGGER")
    trio.advance(ticks=20)
    assert trio.query("?SCOPE_POS") == "10"
    assert _table(trio, 511999) == _table(trio, 511990) - 9
    assert trio.send("SCOPE(ON, 1, 5, 5, TICKS)") == []  # start = stop: one point
    trio.send("TRIGGER")
    trio.advance(ticks=3)
    assert trio.query("?SCOPE_POS") == "1"


def test_a_range_off_the_table_or_backwards_is_refused_and_keeps_the_old_scope() -> None:
    trio = MC405()
    trio.send("SCOPE(ON, 1, 0, 3, TICKS)")
    for line in ("SCOPE(ON, 1, 0, 512000, TICKS)", "SCOPE(ON, 1, 10, 9, TICKS)",
                 "SCOPE(ON, 1, 0, 2, TICKS, TICKS, TICKS, TICKS)"):
        assert trio.send(line) == ["! Parameter out of range"]
    trio.send("TRIGGER")
    trio.advance(ticks=10)
    assert trio.query("?SCOPE_POS") == "4"  # the first SCOPE's 0..3


def test_scopes_first_example_two_traces_over_0_to_1000_split_at_500() -> None:
    """SCOPE's example 1, period 1 here: 1001 indices for 2 parameters give 500 points
    each, 0..499 and 500..999; index 1000 is left over."""
    trio = MC405()
    trio.send("TABLE(1000, -1)")
    trio.send("SCOPE(ON, 1, 0, 1000, TICKS, -TICKS)")
    trio.send("TRIGGER")
    trio.advance(ticks=600)
    assert trio.query("?SCOPE_POS") == "500"
    assert _table(trio, 500) == -_table(trio, 0) and _table(trio, 999) == -_table(trio, 499)
    assert _table(trio, 499) == _table(trio, 0) - 499 and _table(trio, 1000) == -1.0

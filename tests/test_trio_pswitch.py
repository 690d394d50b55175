"""PSWITCH and HW_PSWITCH from their TrioBASIC help pages: outputs switched at positions,
each edge on its own servo tick.

Axis 0 runs FORWARD (or REVERSE) at SPEED 100 with ACCEL 1e6, so at servo tick k (1 ms)
it stands at 0.1 k - 0.005 units: with UNITS 10 its whole counts are k - 1, so count c
is reached on tick c + 1; with UNITS 1 count c on the first tick 0.1 k - 0.005 >= c.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405

SET_UP = "BASE(0): SPEED=100: ACCEL=1e6: DECEL=1e6"


def machine(units: float = 10) -> MC405:
    trio = MC405()
    assert trio.send(f"{SET_UP}: UNITS={units:g}") == []
    return trio


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def op(trio: MC405, n: int) -> int:
    return int(trio.query(f"?READ_OP({n})"))


def levels(trio: MC405, n: int, ticks: list[int]) -> list[int]:
    out = []
    for tick in ticks:
        at(trio, tick)
        out.append(op(trio, n))
    return out


def test_example_1_a_software_cam_switch_on_a_repeating_axis() -> None:
    """Degrees at 10 counts a degree, REP_DIST 360: on from 80 to 200 every turn."""
    trio = machine()
    assert trio.send("REP_DIST = 360: REP_OPTION = ON") == []
    assert trio.send("PSWITCH(0, ON, 0, 11, ON, 80, 200): FORWARD") == []
    # 80 degrees is count 800 (tick 801), 200 is 2000 (tick 2001); a turn is 3600 ticks
    assert levels(trio, 11, [1, 800, 801, 2000, 2001, 4400, 4401, 5600, 5601]) == \
        [0, 0, 1, 1, 0, 0, 1, 1, 0]
    assert list(trio.machine.switches.edges) == [(801, 11, True), (2001, 11, False),
                                                 (4401, 11, True), (5601, 11, False)]


def test_example_3_state_off_turns_the_output_off_inside_the_window() -> None:
    trio = machine()
    assert trio.send("PSWITCH(24, ON, 0, 11, OFF, 80, 80 + 120)") == []
    assert op(trio, 11) == 1  # at 0 degrees, outside the window: ON
    assert trio.send("FORWARD") == []
    assert levels(trio, 11, [800, 801, 2000, 2001]) == [1, 0, 0, 1]


def test_the_window_works_travelling_backwards() -> None:
    """REVERSE: count -(k - 1) on tick k; the window -20..-8 is counts -200..-81."""
    trio = machine()
    assert trio.send("PSWITCH(3, ON, 0, 5, ON, -20, -8): REVERSE") == []
    assert levels(trio, 5, [81, 82, 201, 202]) == [0, 1, 1, 0]


def test_the_output_is_the_or_of_op_and_off_keeps_or_forces_it() -> None:
    trio = machine()
    assert trio.send("PSWITCH(7, ON, 0, 14, ON, 0, 50)") == []
    assert op(trio, 14) == 1
    assert trio.send("OP(14, OFF)") == [] and op(trio, 14) == 1  # the switch holds it
    assert trio.send("PSWITCH(7, OFF, 0)") == [] and op(trio, 14) == 1  # kept (hold 0)
    assert trio.send("OP(14, OFF)") == [] and op(trio, 14) == 0  # as the page's example 2
    assert trio.send("PSWITCH(7, ON)") == [] and op(trio, 14) == 1  # enabled again
    assert trio.send("PSWITCH(7, OFF, 1)") == [] and op(trio, 14) == 0  # forced off
    assert trio.send("PSWITCH(8, ON, 0, 15, ON, 10, 20): OP(15, ON)") == []
    assert op(trio, 15) == 1  # OP can override a switch that drives nothing


def test_example_4_a_sequence_of_positions_from_the_table() -> None:
    """Positions 2.5, 9, 18.6, 20.4 (counts 25, 90, 186, 204): on, off, on, off; the
    zeros after them end the sequence."""
    trio = machine()
    assert trio.send("TABLE(1000, 2.5, 9, 18.6, 20.4)") == []
    assert trio.send("mode = 0: mode.0 = 1: mode.3 = 1") == []
    assert trio.send("PSWITCH(1, mode, 0, 14, ON, 1000, 1099): FORWARD") == []
    assert levels(trio, 14, [25, 26, 90, 91, 186, 187, 204, 205, 3000]) == \
        [0, 1, 1, 0, 0, 1, 1, 0, 0]


def test_example_5_timed_pulses_at_descending_positions() -> None:
    """From 60 backwards (DEFPOS 60, counts 600 - (k - 1)): 55, 50.5 and 48 are reached
    on ticks 51, 96 and 121; each pulse lasts 8 servo cycles."""
    trio = machine()
    assert trio.send("DEFPOS(60): TABLE(1100, 55, 50.5, 48)") == []
    assert trio.send("PSWITCH(1, 1 + 8 + 16 + 32, 0, 12, ON, 1100, 1102, 8): REVERSE") == []
    ticks = [50, 51, 58, 59, 95, 96, 103, 104, 120, 121, 128, 129]
    assert levels(trio, 12, ticks) == [0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0]


def test_hw_pswitch_toggles_output_8_plus_the_axis_at_counts() -> None:
    """UNITS 1: counts 5, 10, 15 are reached on ticks 51, 101, 151 (0.1 k - 0.005)."""
    trio = machine(units=1)
    assert trio.send("TABLE(21, 5, 10, 15)") == []
    assert trio.send("HW_PSWITCH(1, 1, ON, 21, 23): FORWARD") == []
    assert levels(trio, 8, [50, 51, 100, 101, 150, 151]) == [0, 1, 1, 0, 0, 1]
    assert trio.send("HW_PSWITCH(0)") == [] and op(trio, 8) == 0  # disabled


def test_hw_pswitch_fifo_is_cleared_by_mode_2_and_holds_512() -> None:
    trio = machine(units=1)
    assert trio.send("TABLE(0, 5, 10): HW_PSWITCH(1, 1, ON, 0, 1) AXIS(2)") == []
    assert len(trio.machine.switches.hardware[2].fifo) == 2
    assert trio.send("HW_PSWITCH(2) AXIS(2)") == []
    assert len(trio.machine.switches.hardware[2].fifo) == 0
    for k in range(513):
        trio.machine.table.write(100 + k, [float(k + 1)])
    reply = trio.send("HW_PSWITCH(1, 1, ON, 100, 612) AXIS(2)")
    assert reply and reply[0].endswith("Parameter out of range")
    assert len(trio.machine.switches.hardware[2].fifo) == 0  # nothing loaded
    assert trio.send("HW_PSWITCH(1, 1, ON, 100, 611) AXIS(2)") == []
    assert len(trio.machine.switches.hardware[2].fifo) == 512


def test_a_program_waiting_on_a_switched_output_wakes_on_its_tick() -> None:
    trio = machine()
    trio.load("P", "PSWITCH(0, ON, 0, 11, ON, 30, 40)\nFORWARD\n"
              "WAIT UNTIL READ_OP(11) = ON\nVR(1) = DPOS\nWAIT UNTIL READ_OP(11) = OFF\n"
              "VR(2) = DPOS")
    assert trio.send('RUN "P"') == []
    trio.advance(1.0)
    # on at count 300 (tick 301: 30.095), off at 400 (tick 401: 40.095)
    assert float(trio.query("?VR(1)")) == pytest.approx(30.095, abs=1e-9)
    assert float(trio.query("?VR(2)")) == pytest.approx(40.095, abs=1e-9)


@pytest.mark.parametrize("line", [
    "PSWITCH(64, ON, 0, 11, ON, 1, 2)",  # switches 0..63
    "PSWITCH(0, ON, 0, 11, ON, 5, 2)",  # setpos above resetpos without bit 1
    "PSWITCH(0, ON, 16, 11, ON, 1, 2)",  # no axis 16
    "PSWITCH(0, 1 + 8 + 64, 0, 11, ON, 0, 3)",  # the Z output
    "HW_PSWITCH(1, 1, ON, 0, 3) AXIS(5)",  # no hardware switch on axis 5
    "HW_PSWITCH(3)",
])
def test_bad_switches_are_refused_and_change_nothing(line: str) -> None:
    trio = machine()
    reply = trio.send(line)
    assert reply and ("out of range" in reply[0] or "Invalid axis" in reply[0]), reply
    assert not trio.machine.switches.switches and not trio.machine.switches.hardware
    assert op(trio, 11) == 0

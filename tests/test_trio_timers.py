"""HW_TIMER / HW_TIMER_DONE, FE_LATCH and PMOVE from their TrioBASIC help pages.

The servo cycle is 1000 us: a timer started on tick t0 shows the level it has at
(t - t0) x 1000 us on tick t.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405
from tests.test_trio_drive import _servo_run


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def op(trio: MC405, n: int) -> int:
    return int(trio.query(f"?READ_OP({n})"))


def test_example_5_ten_cycles_of_one_second_with_3500_us_on() -> None:
    trio = MC405()
    t0 = trio.tick
    assert trio.send("HW_TIMER(2, 1000000, 3500, 10, 0, 13, ON)") == []
    seen = []
    for tick in (0, 3, 4, 999, 1000, 1003, 1004, 9003, 9004):
        at(trio, t0 + tick)
        seen.append((op(trio, 13), int(trio.query("?HW_TIMER_DONE"))))
    assert seen == [(1, 1), (1, 1), (0, 1), (0, 1), (1, 1), (1, 1), (0, 1), (1, 1), (0, 1)]
    at(trio, t0 + 9999)
    assert trio.query("?HW_TIMER_DONE") == "1"
    at(trio, t0 + 10000)  # ten seconds: done, the output left off
    assert (op(trio, 13), trio.query("?HW_TIMER_DONE")) == (0, "0")


def test_example_1_a_350_us_pulse_and_waiting_for_done() -> None:
    trio = MC405()
    trio.load("P", "HW_TIMER(1, 350, 0, 14, ON)\nVR(1) = READ_OP(14)\nt = TICKS\n"
              "WAIT UNTIL HW_TIMER_DONE = 0\nVR(2) = t - TICKS\nVR(3) = READ_OP(14)")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=20)
    # on the tick it starts; done one servo cycle later (350 us < 1000 us), then off
    assert [trio.query(f"?VR({k})") for k in (1, 2, 3)] == ["1.0000", "1.0000", "0.0000"]


def test_times_are_truncated_to_10_us() -> None:
    trio = MC405()
    t0 = trio.tick
    assert trio.send("HW_TIMER(1, 2009, 0, 15, ON)") == []  # 2000 us: off on the 2nd tick
    at(trio, t0 + 1)
    assert op(trio, 15) == 1
    at(trio, t0 + 2)
    assert op(trio, 15) == 0


def test_the_timer_owns_its_output_and_then_leaves_it_to_op() -> None:
    """Example 4: output 9 (op mode 2, axis 1) OFF for 200 ms, then the opposite."""
    trio = MC405()
    t0 = trio.tick
    assert trio.send("OP(9, ON): HW_TIMER(1, 200000, 2, 1, OFF)") == []
    assert op(trio, 9) == 0
    assert trio.send("OP(9, ON)") == [] and op(trio, 9) == 0  # the timer holds it
    at(trio, t0 + 200)
    assert (op(trio, 9), trio.query("?HW_TIMER_DONE")) == (1, "0")
    assert trio.send("OP(9, OFF)") == [] and op(trio, 9) == 0
    assert trio.send("HW_TIMER(1, 5000, 0, 12, ON): HW_TIMER(0)") == []
    assert (op(trio, 12), trio.query("?HW_TIMER_DONE")) == (1, "0")  # stopped as it was


@pytest.mark.parametrize("line", [
    "HW_TIMER(1, 350, 1, 2, ON)",  # an axis's enable output
    "HW_TIMER(1, 350, 0, 7, ON)",  # outputs 8..15
    "HW_TIMER(1, 350, 2, 5, ON)",  # axes 0..4
    "HW_TIMER(2, 1000, 2000, 3, 0, 13, ON)",  # on time above the cycle time
    "HW_TIMER(3)",
    "HW_TIMER(1, 350, 0, 14)",
])
def test_bad_timers_are_refused(line: str) -> None:
    trio = MC405()
    reply = trio.send(line)
    assert reply and ("out of range" in reply[0] or "Syntax" in reply[0]), reply
    assert trio.query("?HW_TIMER_DONE") == "0"


def test_fe_latch_holds_the_error_that_raised_the_motion_error() -> None:
    """FE_LIMIT 30: FE reads 30.0 on cycle 80 and 30.22 on 81 (test_trio_drive's run);
    the error the loop compared on the cycle between passed 30."""
    runs = []
    for slicing in ("stepped", "whole"):
        trio = _servo_run(268)
        assert trio.query("?FE_LATCH") == "0"
        if slicing == "stepped":
            while trio.query("?MOTION_ERROR") == "0":
                trio.advance(ticks=1)
        trio.advance(ticks=400 - trio.machine.tick)
        runs.append(trio.machine.axis_parameter("FE_LATCH", 0))
        assert trio.send("FE_LATCH = 1")[0].endswith("read only")
        assert trio.send("DATUM(0): SERVO = ON") == []
        assert trio.query("?FE_LATCH") == "0"  # reset by SERVO = ON
    assert runs[0] == runs[1]
    assert 30 < runs[0] < 31


def test_pmove_is_true_while_a_move_waits_for_room_in_the_buffer() -> None:
    """Moves of 1000 at SPEED 1000 with ACCEL 1e6 last 1.001 s (1001 cycles); the program
    starts on tick 1, so move k ends on tick 1 + 1001 k. The axis holds 16: the 20th move
    waits until the 4th has ended (tick 4005)."""
    trio = MC405()
    trio.load("P", "BASE(0)\nSPEED=1000: ACCEL=1e6: DECEL=1e6\nFOR i = 1 TO 20\n"
              "MOVE(1000)\nNEXT i")
    assert trio.send('RUN "P", 3') == []
    at(trio, 100)
    assert trio.query("?PMOVE PROC(3)") == "-1"
    assert trio.query("?PMOVE") == "0"  # the command line's own: nothing waits
    at(trio, 4004)
    assert trio.query("?PMOVE PROC(3)") == "-1"
    at(trio, 4005)
    assert trio.query("?PMOVE PROC(3)") == "0"

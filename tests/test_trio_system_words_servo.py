"""SERVO_READ: parameters read on the next servo cycle into VRs, not scaled by UNITS
(TrioBASIC help SERVO_READ; its example reads MPOS and FE of axes 0 and 1 into VR 100..103).
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405

_PROGRAM = """MOVE(5) AXIS(0)
MOVE(2) AXIS(1)
WA(100)
SERVO_READ(100, MPOS AXIS(0), FE AXIS(0), MPOS AXIS(1), FE AXIS(1), SPEED AXIS(0), {rest})
VR(99) = 1"""


def _machine() -> MC405:
    trio = MC405()
    for line in ("UNITS AXIS(0) = 800", "UNITS AXIS(1) = 50", "SPEED AXIS(0) = 10",
                 "SPEED AXIS(1) = 10", "ACCEL AXIS(0) = 1000", "ACCEL AXIS(1) = 1000"):
        assert trio.send(line) == []
    return trio


def _vrs(trio: MC405, first: int, count: int) -> list[float]:
    return [float(trio.query(f"?VR({first + k})")) for k in range(count)]


def test_the_pages_example_stores_counts_on_the_next_servo_cycle() -> None:
    trio = _machine()
    trio.load("P", _PROGRAM.format(rest="ATYPE AXIS(0), VR(7) + 1"))
    assert trio.send('RUN "P"') == []
    t0 = trio.tick
    # the moves load on the first cycle (t0 + 1), WA(100) ends at t0 + 101, where
    # SERVO_READ starts: nothing is written yet
    trio.advance(ticks=101)
    assert _vrs(trio, 99, 9) == [0.0] * 9
    trio.advance(ticks=1)
    assert trio.tick == t0 + 102
    # read at t0 + 102, 0.101 s into each move: at 1000 units/s^2 SPEED 10 is reached in
    # 0.01 s over 0.05 units, so both axes stand at 10 x 0.101 - 0.05 = 0.96 units:
    # 0.96 x 800 = 768 counts on axis 0, 0.96 x 50 = 48 on axis 1; no following error
    # (stepper axes); SPEED 10 units/s is 8000 counts/s; ATYPE and an expression as read
    assert _vrs(trio, 100, 7) == [768.0, 0.0, 48.0, 0.0, 8000.0, 43.0, 1.0]
    assert trio.query("?DPOS AXIS(0)") == "0.9600"  # (the user-unit value, for contrast)
    assert trio.query("?VR(99)") == "1.0000"  # the program went on after it


def test_a_parameter_without_axis_reads_servo_reads_own_axis() -> None:
    trio = _machine()
    assert trio.send("DEFPOS(3) AXIS(1)") == []
    assert trio.send("SERVO_READ(20, DPOS, ENCODER AXIS(0)) AXIS(1)") == []
    assert _vrs(trio, 20, 2) == [150.0, 0.0]  # 3 units x UNITS 50


@pytest.mark.parametrize("line", ["SERVO_READ(65535, MPOS, FE)", "SERVO_READ(-1, MPOS)",
                                  "SERVO_READ(2.5, MPOS)"])
def test_a_vr_range_off_the_end_writes_nothing(line: str) -> None:
    trio = _machine()
    assert trio.send("VR(65535) = 7") == []
    assert trio.send(line) == ["! Parameter out of range"]
    assert trio.query("?VR(65535)") == "7.0000"


def test_the_last_vr_can_be_written() -> None:
    trio = _machine()
    assert trio.send("SERVO_READ(65535, UNITS AXIS(0))") == []
    assert trio.query("?VR(65535)") == "800.0000"  # UNITS itself is not scaled

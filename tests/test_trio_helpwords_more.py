"""VP_DEMAND_SPEED/ACCEL/DECEL/JERK (profile_readings.py): the demands the profiler runs the
move now in force on, in user units, 0 when idle (D on their entries). Figures by hand."""

from __future__ import annotations

import pytest

from maxk.commands.trio.keywords import KEYWORDS
from maxk.controllers.trio import MC405

DEMANDS = ("VP_DEMAND_SPEED", "VP_DEMAND_ACCEL", "VP_DEMAND_DECEL", "VP_DEMAND_JERK")


def mc405(*lines: str) -> MC405:
    trio = MC405()
    for line in lines:
        assert trio.send(line) == [], line
    return trio


def demands(trio: MC405, axis: int = 0) -> list[float]:
    return [trio.machine.axis_parameter(name, axis) for name in DEMANDS]


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def test_idle_reads_0_and_a_move_reads_its_rates_in_user_units() -> None:
    """UNITS 10: SPEED 5, ACCEL 20, DECEL 40, VP_MODE 5 with JERK 100 read back as given
    (the profiler holds 50, 200, 400, 1000 counts), not the speed now (0 at the start)."""
    trio = mc405("UNITS = 10: SPEED = 5: ACCEL = 20: DECEL = 40: VP_MODE = 5: JERK = 100")
    assert demands(trio) == [0, 0, 0, 0]
    assert trio.send("MOVE(20)") == []
    start = trio.tick
    at(trio, start + 1)
    assert demands(trio) == pytest.approx([5, 20, 40, 100])
    assert trio.query("?VP_DEMAND_SPEED") == "5"
    at(trio, start + 100_000)  # long done
    assert demands(trio) == [0, 0, 0, 0]


def test_vp_mode_0_has_no_jerk_and_the_demand_changes_with_the_move_in_force() -> None:
    """MERGE off, UNITS 1, ACCEL = DECEL = 100. MOVESP(10) at FORCE_SPEED 10: 0.1 s up and
    down (0.5 each), 9 at 10 (0.9 s): 1.1 s, 1100 servo cycles of 1 ms. Then MOVE(5) at
    SPEED 4 from rest: 0.04 s ramps (0.08 each), 4.84 / 4 = 1.21 s at 4: 1290 cycles more."""
    trio = mc405("SPEED = 4: ACCEL = 100: DECEL = 100: FORCE_SPEED = 10")
    assert trio.machine.period == pytest.approx(0.001)
    assert trio.send("MOVESP(10): MOVE(5)") == []
    start = trio.tick
    at(trio, start + 1)
    assert demands(trio) == pytest.approx([10, 100, 100, 0])
    at(trio, start + 1099)
    assert demands(trio)[0] == pytest.approx(10)
    at(trio, start + 1101)
    assert trio.machine.axis_parameter("DPOS", 0) > 10
    assert demands(trio) == pytest.approx([4, 100, 100, 0])
    at(trio, start + 1100 + 1289)
    assert demands(trio)[0] == pytest.approx(4)
    at(trio, start + 1100 + 1291)
    assert demands(trio) == [0, 0, 0, 0]


def test_speed_written_mid_move_is_the_new_demand_and_a_cancel_demands_rest() -> None:
    trio = mc405("SPEED = 10: ACCEL = 200: DECEL = 50")
    assert trio.send("MOVE(100)") == []
    start = trio.tick
    at(trio, start + 500)
    assert demands(trio) == pytest.approx([10, 200, 50, 0])
    assert trio.send("SPEED = 6") == []
    at(trio, start + 501)
    assert demands(trio)[0] == pytest.approx(6)
    assert trio.send("CANCEL") == []
    at(trio, start + 502)
    assert trio.machine.axis_parameter("VP_SPEED", 0) > 0  # still ramping down
    assert demands(trio)[0] == 0
    assert demands(trio)[2] == pytest.approx(50)


def test_a_path_reads_the_base_axis_demand_on_every_axis_of_its_group() -> None:
    """BASE(0, 1): MOVE(30, 40) at axis 0's SPEED 5 (its UNITS 2), axis 1's own SPEED 99
    and UNITS 7 not used: both axes read 5 (the path's vector speed, base user units)."""
    trio = mc405("UNITS AXIS(0) = 2: UNITS AXIS(1) = 7: SPEED AXIS(1) = 99",
                 "SPEED = 5: ACCEL = 50: DECEL = 50: BASE(0, 1)")
    assert trio.send("MOVE(30, 40)") == []
    trio.advance(ticks=10)
    assert demands(trio, 0) == pytest.approx([5, 50, 50, 0])
    assert demands(trio, 1) == pytest.approx([5, 50, 50, 0])
    assert demands(trio, 2) == [0, 0, 0, 0]


def test_their_entries_say_what_they_read() -> None:
    for name in DEMANDS:
        entry = KEYWORDS[name]
        assert not entry.note.startswith("Not modelled"), name
        assert entry.source == f"TrioBASIC help {name}"


@pytest.mark.parametrize(("setup", "move", "jerk"), [
    ("SPEED = 4", "MOVE(50)", 100 * 0.5),  # JERK x JERK_FACTOR
    ("FORCE_SPEED = 4: FORCE_JERK = 300", "MOVESP(50)", 300),  # an SP move's own jerk
])
def test_the_demand_jerk_in_vp_mode_5(setup: str, move: str, jerk: float) -> None:
    trio = mc405("VP_MODE = 5: JERK = 100: JERK_FACTOR = 0.5", setup)
    assert trio.send(move) == []
    trio.advance(ticks=5)
    assert [trio.machine.axis_parameter(n, 0) for n in ("VP_DEMAND_SPEED", "VP_DEMAND_JERK")
            ] == pytest.approx([4, jerk])

"""Robot frames on an MC405 (TrioBASIC help FRAME, AXIS_DPOS, AXIS_UNITS, WORLD_DPOS,
FRAME_TRANS, FRAME_GROUP): moves command the world position (DPOS), the motors follow the
frame's inverse transform (AXIS_DPOS, MPOS) at every servo tick.

Every expected number is hand arithmetic: the move's path distance at tick k (1 ms) with
SPEED 100 and ACCEL = DECEL 1e6 is 100 t - 0.005 once the 0.1 ms ramp is over (the ramp
loses v^2 / 2a), and the FRAME page's equations applied to it.
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405

SPEED, ACCEL = 100.0, 1e6
LOSS = SPEED * SPEED / (2 * ACCEL)  # 0.005


def path(tick: int, start: int = 0) -> float:
    """Distance a move loaded on tick `start` has gone on tick `tick` (cruising)."""
    return SPEED * (tick - start) / 1000 - LOSS


def machine(units: str = "") -> MC405:
    trio = MC405()
    if units:
        assert trio.send(units) == []
    assert trio.send(f"BASE(0, 1): SPEED = {SPEED:g}: ACCEL = {ACCEL:g}: "
                     f"DECEL = {ACCEL:g}") == []
    return trio


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def world(trio: MC405) -> list[float]:
    return [trio.machine.dpos(a) for a in (0, 1)]


def motors(trio: MC405, name: str = "AXIS_DPOS") -> list[float]:
    return [trio.machine.axis_parameter(name, a) for a in (0, 1)]


def test_frame_2_single_belt_raises_the_load_with_both_motors() -> None:
    """The page's example: DEFPOS(150, 50), FRAME = 2: the world is ((150 + 50) / 2,
    (150 - 50) / 2) = (100, 50); MOVE(0, 100) then moves both motors, motor 0 by +Y
    and motor 1 by -Y (X = (A0 + A1) / 2, Y = (A0 - A1) / 2)."""
    trio = machine()
    assert trio.send("DEFPOS(150, 50)") == []
    assert trio.send("FRAME = 2") == []
    assert world(trio) == [100.0, 50.0]
    assert motors(trio) == [150.0, 50.0]
    assert motors(trio, "MPOS") == [150.0, 50.0]
    assert trio.query("?FRAME AXIS(1)") == "2"
    start = trio.tick
    assert trio.send("MOVE(0, 100)") == []
    for tick in (start + 1, start + 250, start + 731):
        at(trio, tick)
        y = 50 + path(tick, start)
        assert world(trio) == pytest.approx([100.0, y], abs=1e-9)
        assert motors(trio) == pytest.approx([100 + y, 100 - y], abs=1e-9)
        assert motors(trio, "MPOS") == pytest.approx([100 + y, 100 - y], abs=1e-9)
        assert motors(trio, "WORLD_DPOS") == pytest.approx([100.0, y], abs=1e-9)
    assert trio.run_until_idle()
    assert motors(trio) == pytest.approx([250.0, -50.0], abs=1e-9)
    assert float(trio.query("?FE AXIS(0)")) == 0
    # FRAME = 0: DPOS becomes the motors' positions again
    assert trio.send("FRAME = 0") == []
    assert world(trio) == pytest.approx([250.0, -50.0], abs=1e-9)
    assert motors(trio) == pytest.approx([250.0, -50.0], abs=1e-9)
    assert trio.send("MOVE(-50, 50)") == [] and trio.run_until_idle()
    assert world(trio) == pytest.approx([200.0, 0.0], abs=1e-9)


def test_units_scale_the_world_and_axis_units_the_motors() -> None:
    """UNITS 10 on the world, AXIS_UNITS 4 on the motors: DEFPOS(15, 5) is raw (150, 50),
    so after FRAME = 2 DPOS = (100, 50) / 10 and AXIS_DPOS = (150, 50) / 4; MOVE(0, 2)
    is 20 raw on Y: the motors end at (170, 30) / 4."""
    trio = machine("UNITS AXIS(0) = 10: UNITS AXIS(1) = 10: AXIS_UNITS AXIS(0) = 4: "
                   "AXIS_UNITS AXIS(1) = 4")
    assert trio.send("DEFPOS(15, 5)") == []
    assert motors(trio) == [15.0, 5.0]  # FRAME 0: AXIS_DPOS is DPOS
    assert trio.send("FRAME AXIS(0) = 2") == []
    assert world(trio) == pytest.approx([10.0, 5.0])
    assert motors(trio) == pytest.approx([37.5, 12.5])
    assert motors(trio, "MPOS") == pytest.approx([37.5, 12.5])
    assert trio.send("MOVE(0, 2)") == [] and trio.run_until_idle()
    assert world(trio) == pytest.approx([10.0, 7.0])
    assert motors(trio) == pytest.approx([42.5, 7.5])
    assert trio.query("?AXIS_DPOS AXIS(0)") == "42.5000"


ROTATE = """theta = {degrees} * 2 * PI / 360
GOSUB matrix
DEFPOS(10, 0)
FRAME = 5
MOVE({dx}, {dy})
WAIT IDLE
STOP
matrix:
  TABLE(0, COS(theta), -SIN(theta), SIN(theta), COS(theta))
  det = TABLE(0) * TABLE(3) - TABLE(2) * TABLE(1)
  TABLE(4, TABLE(3) / det, -TABLE(1) / det, -TABLE(2) / det, TABLE(0) / det)
RETURN
"""


def test_frame_5_rotated_axes_from_a_program() -> None:
    """The page's FRAME 5 example shape, run as a program: the matrix and its inverse in
    TABLE, the motors at (10, 0) when the frame goes on, so the world starts at
    (10, 0) * [[T4, T5], [T6, T7]] = (10 cos, 10 sin); MOVE(40, 30) (path length 50)
    then drives the motors at (x, y) * [[cos, -sin], [sin, cos]]."""
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    trio = machine()
    trio.load("ROT", ROTATE.format(degrees=30, dx=40, dy=30))
    assert trio.send('RUN "ROT"') == []
    x0, y0 = 10 * c, 10 * s
    for _ in range(50):  # the program's first cycles: the move's first tick
        framed = trio.machine.axis_parameter("FRAME", 0) == 5
        if framed and world(trio) != pytest.approx([x0, y0], abs=1e-12):
            break
        at(trio, trio.tick + 1)
    start = trio.tick - 1  # moving on its first tick: 0.1 - 0.005 gone
    for tick in (start + 1, start + 100, start + 400):
        at(trio, tick)
        d = path(tick, start)
        x, y = x0 + 0.8 * d, y0 + 0.6 * d
        assert world(trio) == pytest.approx([x, y], abs=1e-9)
        assert motors(trio) == pytest.approx([x * c + y * s, -x * s + y * c], abs=1e-9)
    assert trio.run_until_idle()
    x, y = x0 + 40, y0 + 30
    assert world(trio) == pytest.approx([x, y], abs=1e-9)
    assert motors(trio) == pytest.approx([x * c + y * s, -x * s + y * c], abs=1e-9)


POLAR = ("UNITS AXIS(0) = 4000: AXIS_UNITS AXIS(0) = 4000: UNITS AXIS(1) = 1000000 * 2 * PI "
         "/ 360: AXIS_UNITS AXIS(1) = 4000: TABLE(0, 1000000)")


def test_frame_6_polar_programming_of_an_xy_gantry() -> None:
    """The page's examples: a gantry programmed in mm and degrees (TABLE(0) = 1e6 counts
    per radian of the world angle); MOVEABS(150, 0) takes the tool 150 mm along X,
    then MOVE 360 degrees on the angle takes it round a circle about the origin:
    X = 150 cos(angle), Y = 150 sin(angle), in mm (AXIS_UNITS 4000)."""
    trio = machine(POLAR)
    assert trio.send("FRAME = 6") == []
    assert world(trio) == [0.0, 0.0]
    assert trio.send("MOVEABS(150, 0)") == [] and trio.run_until_idle()
    assert world(trio) == pytest.approx([150.0, 0.0], abs=1e-9)
    assert motors(trio) == pytest.approx([150.0, 0.0], abs=1e-9)
    assert trio.send("SPEED AXIS(1) = 90: ACCEL AXIS(1) = 1e6: DECEL AXIS(1) = 1e6") == []
    start = trio.tick
    assert trio.send("MOVE(360) AXIS(1)") == []
    for tick in (start + 1, start + 1000, start + 2500, start + 3999):
        at(trio, tick)
        degrees = 90 * (tick - start) / 1000 - 90 * 90 / 2e6
        angle = math.radians(degrees)
        assert trio.machine.dpos(1) == pytest.approx(degrees, abs=1e-9)
        assert motors(trio) == pytest.approx([150 * math.cos(angle), 150 * math.sin(angle)],
                                             abs=1e-9)
    assert trio.run_until_idle()  # a move goes whole counts: 360 degrees is 6283185
    assert world(trio) == pytest.approx([150.0, 6283185 / (1e6 * 2 * math.pi / 360)],
                                        abs=1e-9)
    angle = 6283185 / 1e6
    assert motors(trio) == pytest.approx([150 * math.cos(angle), 150 * math.sin(angle)],
                                         abs=1e-9)


CYLINDER = ("UNITS AXIS(0) = 4000: AXIS_UNITS AXIS(0) = 4000: UNITS AXIS(1) = 4000: "
            "AXIS_UNITS AXIS(1) = 4000 / 360: TABLE(0, 4000 / (2 * PI))")


def test_frame_10_xy_programming_of_a_cylindrical_robot_counts_whole_turns() -> None:
    """The page's example: the arm's radius in mm, its rotation 4000 counts a turn
    (4000 / 2 pi per radian), AXIS_UNITS so the rotation reads degrees. Homed at radius
    100, angle 0: FRAME = 10 puts the tool at (100, 0). Two full circles about the
    origin (MOVECIRC, centre -100 from the start) turn the arm twice: the rotation motor
    ends 720 degrees round, not back at 0; on the way it stands at the circle's angle."""
    trio = machine(CYLINDER)
    assert trio.send("DEFPOS(100, 0)") == []
    assert trio.send("FRAME = 10") == []
    assert world(trio) == pytest.approx([100.0, 0.0], abs=1e-12)
    assert motors(trio) == pytest.approx([100.0, 0.0], abs=1e-12)
    start = trio.tick
    assert trio.send("MOVECIRC(0, 0, -100, 0, 1)") == []
    at(trio, start + 1)
    sign = 1 if world(trio)[1] > 0 else -1  # (which way round: MOVECIRC's direction)
    for tick in (start + 1000, start + 3000, start + 5000):
        at(trio, tick)
        phi = path(tick, start) / 100  # radians round the circle
        x, y = world(trio)
        assert [x, y] == pytest.approx([100 * math.cos(phi), sign * 100 * math.sin(phi)],
                                       abs=1e-9)
        assert motors(trio) == pytest.approx([100.0, sign * math.degrees(phi)], abs=1e-9)
    assert trio.run_until_idle()
    assert motors(trio) == pytest.approx([100.0, sign * 360.0], abs=1e-9)
    assert trio.send("MOVECIRC(0, 0, -100, 0, 1)") == [] and trio.run_until_idle()
    assert world(trio) == pytest.approx([100.0, 0.0], abs=1e-9)
    assert motors(trio) == pytest.approx([100.0, sign * 720.0], abs=1e-9)
    # FRAME = 0: the positions are the motors' again, two turns round
    assert trio.send("FRAME = 0") == []
    assert world(trio) == pytest.approx([100.0, sign * 720 * 4000 / 360 / 4000], abs=1e-9)


def test_frame_trans_runs_a_frame_on_table_values() -> None:
    """FRAME_TRANS(frame, in, out, direction[, offset]): frame 2's inverse of world
    (30, 10) is motors (40, 20), its forward back (30, 10); frame 5's matrices read at
    the offset given (a 90 degree turn: (x', y') = (x, y) [[0, -1], [1, 0]] = (y, -x))."""
    trio = machine()
    assert trio.send("TABLE(1000, 30, 10)") == []
    assert trio.send("FRAME_TRANS(2, 1000, 2000, 0)") == []
    assert [trio.machine.table_read(2000 + k) for k in range(2)] == [40.0, 20.0]
    assert trio.send("FRAME_TRANS(2, 2000, 3000, 1)") == []
    assert [trio.machine.table_read(3000 + k) for k in range(2)] == [30.0, 10.0]
    assert trio.send("TABLE(100, 0, -1, 1, 0, 0, 1, -1, 0)") == []
    assert trio.send("FRAME_TRANS(5, 1000, 4000, 0, 100)") == []
    assert [trio.machine.table_read(4000 + k) for k in range(2)] == [10.0, -30.0]
    assert trio.send("FRAME_TRANS(5, 4000, 5000, 1, 100)") == []
    assert [trio.machine.table_read(5000 + k) for k in range(2)] == [30.0, 10.0]
    assert trio.query("?FRAME_TRANS(2, 1000, 6000, 0)") == "0"
    for bad in ("FRAME_TRANS(2, 1000, 2000, 3)", "FRAME_TRANS(1, 1000, 2000, 0)",
                "FRAME_TRANS(6, 1000, 2000, 0, 900)"):  # (frame 6: TABLE(900) = 0 scale)
        assert trio.send("TABLE(2000, 7, 7)") == []
        assert trio.send(bad) == ["! Parameter out of range"]
        assert [trio.machine.table_read(2000 + k) for k in range(2)] == [7.0, 7.0]


def test_frame_group_places_a_frame_on_chosen_axes_and_table_offset() -> None:
    """FRAME_GROUP(0, 100, 2, 3): frame 2 on axes 2 and 3 (FRAME on either sets both),
    its data from TABLE(100); FRAME_GROUP(0) prints the group; FRAME_GROUP(0, -1)
    deletes it, the frame off: DPOS is MPOS again."""
    trio = machine()
    assert trio.send("FRAME_GROUP(0, 100, 2, 3)") == []
    assert trio.send("BASE(2, 3): DEFPOS(6, 2)") == []
    assert trio.send("FRAME AXIS(3) = 2") == []
    assert trio.query("?FRAME AXIS(2)") == "2" and trio.query("?FRAME AXIS(0)") == "0"
    assert [trio.machine.dpos(a) for a in (2, 3)] == [4.0, 2.0]
    assert [trio.machine.axis_parameter("AXIS_DPOS", a) for a in (2, 3)] == [6.0, 2.0]
    assert trio.send("FRAME_GROUP(0)") == [
        "0 [100] : 2, 3 {0:0.00000, 0.00000, 0.00000, 0.00000, 0.00000, 0.00000} "
        "TO={0:0.00000, 0.00000, 0.00000} VL={0, 0}"]
    assert trio.send("PRINT FRAME_GROUP(0)")[1:] == ["0"]  # (page example 3: the line, 0)
    assert trio.send("SPEED = 100: ACCEL = 1e6: DECEL = 1e6: MOVE(1, 0)") == []
    assert trio.run_until_idle()
    assert [trio.machine.axis_parameter("AXIS_DPOS", a) for a in (2, 3)] == \
        pytest.approx([7.0, 3.0])
    assert trio.send("FRAME_GROUP(0, -1)") == []
    assert trio.query("?FRAME AXIS(2)") == "0"
    assert [trio.machine.dpos(a) for a in (2, 3)] == pytest.approx([7.0, 3.0])


def test_refusals_leave_everything_as_it_was() -> None:
    """A frame the page gives no equations for, a frame change while the axes move,
    AXIS_UNITS 0, a write to AXIS_DPOS, FRAME_GROUP with axes not ascending: each is
    the controller's error, nothing changed."""
    trio = machine()
    assert trio.send("DEFPOS(150, 50)") == []
    assert trio.send("FRAME = 1") == ["! Parameter out of range"]
    assert trio.query("?FRAME") == "0" and world(trio) == [150.0, 50.0]
    assert trio.send("MOVE(10, 0)") == []
    assert trio.send("FRAME = 2") == ["! Parameter out of range"]
    assert trio.query("?FRAME") == "0"
    assert trio.run_until_idle()
    assert trio.send("AXIS_UNITS = 0") == ["! Parameter out of range"]
    assert trio.query("?AXIS_UNITS") == "1"
    assert trio.send("AXIS_DPOS = 3") == ["! Parameter is read only"]
    assert trio.send("FRAME_GROUP(1, 0, 5, 4)") == ["! Parameter out of range"]
    assert trio.send("FRAME_GROUP(8, 0, 4, 5)") == ["! Parameter out of range"]
    assert trio.send("FRAME = 2") == []
    assert world(trio) == [105.0, 55.0]


def test_a_servo_axis_in_a_frame_follows_its_motor_demand() -> None:
    """Servo axes (ATYPE 36, loop closed) in FRAME 2: MPOS reads AXIS_DPOS and FE is 0
    all along the move (D: a servo axis in a frame follows its motor demand exactly),
    and no following error trips with FE_LIMIT 1."""
    trio = machine("ATYPE AXIS(0) = 36: ATYPE AXIS(1) = 36: P_GAIN AXIS(0) = 1: "
                   "P_GAIN AXIS(1) = 1: FE_LIMIT AXIS(0) = 1: FE_LIMIT AXIS(1) = 1: "
                   "SERVO AXIS(0) = ON: SERVO AXIS(1) = ON: WDOG = ON")
    assert trio.send("DEFPOS(150, 50): FRAME = 2") == []
    start = trio.tick
    assert trio.send("MOVE(0, 100)") == []
    for tick in (start + 300, start + 900):
        at(trio, tick)
        y = 50 + path(tick, start)
        assert motors(trio, "MPOS") == pytest.approx([100 + y, 100 - y], abs=1e-9)
        assert motors(trio, "FE") == [0.0, 0.0]
    assert trio.run_until_idle()
    assert trio.query("?MOTION_ERROR") == "0"


def test_the_limit_inputs_see_the_motor_not_the_world() -> None:
    """FRAME page: FWD_IN acts on the motor's position. In FRAME 2 a world MOVE(0, 100)
    along Y drives motor 0 = 100 + Y while world X stays 100: a forward limit switch on
    motor 0 at AXIS_DPOS 200 (50 counts from power-up: DEFPOS named it 150) opens when Y
    reaches 100, path 50: on tick 501 (50.095 gone) the move is cancelled (IN reads 0,
    AXISSTATUS bit 4) though X never moved; the MOVE buffered behind is dropped."""
    trio = machine("FWD_IN AXIS(0) = 3")
    trio.machine.world.axes[0].set_plus_limit(50)
    assert trio.send("DEFPOS(150, 50): FRAME = 2") == []
    assert trio.query("?IN(3)") == "1"
    start = trio.tick
    assert trio.send("MOVE(0, 100): MOVE(0, 100)") == []
    at(trio, start + 500)
    assert trio.query("?IN(3)") == "1" and not trio.machine.queues[0][0].stopping
    at(trio, start + 501)
    assert trio.query("?IN(3)") == "0" and trio.machine.queues[0][0].stopping
    assert len(trio.machine.queues[0]) == 1
    assert trio.run_until_idle()
    assert trio.machine.dpos(0) == 100.0
    assert abs(trio.machine.dpos(1) - (50 + path(start + 501, start))) <= 0.1
    assert int(float(trio.query("?AXISSTATUS AXIS(0)"))) & 16


def test_frame_on_a_group_of_another_size_or_without_its_table_is_refused() -> None:
    """FRAME_GROUP page: the group's axes must match the frame's; a polar frame with no
    counts per radian in TABLE cannot be computed: both refused, nothing changed."""
    trio = machine()
    assert trio.send("FRAME = 6") == ["! Parameter out of range"]  # TABLE(0) is 0
    assert trio.send("FRAME = 10") == ["! Parameter out of range"]
    assert trio.query("?FRAME") == "0"
    assert trio.send("FRAME_GROUP(0)") == ["0 [-1] :"]
    assert trio.send("FRAME_GROUP(1, 0, 4, 5, 6)") == []
    assert trio.send("FRAME AXIS(5) = 2") == ["! Parameter out of range"]
    assert trio.query("?FRAME AXIS(4)") == "0"


def test_a_joint_passing_axis_fs_limit_cancels_the_groups_moves_on_that_tick() -> None:
    """AXIS_FS_LIMIT page: with a frame on, the tick AXIS_DPOS passes AXIS_FS_LIMIT every
    move of the frame group is cancelled and AXISSTATUS bit 16 is set. In FRAME 2 from
    world (100, 50), MOVE(0, 100) raises motor 0 = 100 + Y: it passes 180 when Y passes
    80, path 30: on tick 301 (30.095 gone); the path then stops (the shared path stop
    lands on a whole count, within 0.1 of there) and the MOVE buffered behind is
    dropped. A move back runs."""
    trio = machine("AXIS_FS_LIMIT AXIS(0) = 180")
    assert trio.send("DEFPOS(150, 50): FRAME = 2") == []
    start = trio.tick
    assert trio.send("MOVE(0, 100): MOVE(0, 100)") == []
    at(trio, start + 300)
    assert trio.machine.queues[0] and not trio.machine.queues[0][0].stopping
    at(trio, start + 301)
    assert trio.machine.queues[0][0].stopping
    assert len(trio.machine.queues[0]) == 1  # the buffered move is gone
    assert int(float(trio.query("?AXISSTATUS AXIS(0)"))) & (1 << 16)  # 180.095 > 180
    assert trio.run_until_idle()
    y = trio.machine.dpos(1)
    assert abs(y - (50 + path(start + 301, start))) <= 0.1
    assert motors(trio)[0] == pytest.approx(100 + y, abs=1e-9)
    assert trio.send("MOVE(0, -10)") == [] and trio.run_until_idle()
    assert trio.machine.dpos(1) == pytest.approx(y - 10, abs=1e-9)
    assert not int(float(trio.query("?AXISSTATUS AXIS(0)"))) & (1 << 16)


def test_frame_scale_reads_its_power_up_value_so_units_can_take_it() -> None:
    """FRAME_SCALE page: power-up 1000000000; its example sets UNITS = FRAME_SCALE."""
    trio = MC405()
    assert trio.query("?FRAME_SCALE AXIS(3)") == "1000000000"
    assert trio.send("BASE(3): UNITS = FRAME_SCALE") == []
    assert trio.query("?UNITS AXIS(3)") == "1000000000"


def test_the_cylindrical_robots_turning_joint_stops_at_its_reverse_limit_past_a_half_turn(
        ) -> None:
    """FRAME 10 as above with AXIS_RS_LIMIT AXIS(1) = -270 (degrees): the circle turns
    the arm the negative way (MOVECIRC direction 1 here), so the joint passes -270 when
    the path passes 100 * 3 pi / 2 = 471.239: on tick 4713 (471.295 gone, the joint at
    -270.03; atan2 alone would read +89.97 there). The circle is cancelled on that tick."""
    trio = machine(CYLINDER + ": AXIS_RS_LIMIT AXIS(1) = -270")
    assert trio.send("DEFPOS(100, 0): FRAME = 10") == []
    start = trio.tick
    assert trio.send("MOVECIRC(0, 0, -100, 0, 1)") == []
    at(trio, start + 4712)
    assert motors(trio)[1] == pytest.approx(-math.degrees(path(start + 4712, start) / 100))
    assert not trio.machine.queues[0][0].stopping
    at(trio, start + 4713)
    assert motors(trio)[1] == pytest.approx(-math.degrees(path(start + 4713, start) / 100))
    assert trio.machine.queues[0][0].stopping
    assert int(float(trio.query("?AXISSTATUS AXIS(1)"))) & (1 << 17)


def test_frame_rep_dist_folds_the_world_angle_while_the_frame_is_on() -> None:
    """FRAME_REP_DIST and REP_OPTION pages: with bit 3, the polar gantry's angle (degrees)
    reads folded at +-180 (0..180 with bit 0 too) while FRAME 6 is on; REP_DIST no
    longer folds it, AXIS_DPOS never is, and with the frame off DPOS is not folded."""
    trio = machine(POLAR)
    assert trio.send("FRAME_REP_DIST AXIS(1) = 180: REP_OPTION AXIS(1) = 8") == []
    assert trio.send("REP_DIST AXIS(1) = 100") == []  # disabled by bit 3
    assert trio.send("DEFPOS(0, 200)") == []  # the frame off: not folded at all
    assert trio.machine.axis_parameter("DPOS", 1) == pytest.approx(200, abs=1e-9)
    assert trio.send("DEFPOS(0, 0): FRAME = 6") == []
    assert trio.send("MOVEABS(150, 0)") == [] and trio.run_until_idle()
    assert trio.send("SPEED AXIS(1) = 90: ACCEL AXIS(1) = 1e6: DECEL AXIS(1) = 1e6") == []
    start = trio.tick
    assert trio.send("MOVE(360) AXIS(1)") == []
    at(trio, start + 1500)  # 135 degrees: inside the fold
    assert trio.machine.axis_parameter("DPOS", 1) == pytest.approx(90 * 1.5 - 90 * 90 / 2e6,
                                                                   abs=1e-9)
    tick = start + 2500  # 225 degrees less the ramp's loss: reads 360 less
    at(trio, tick)
    degrees = 90 * 2.5 - 90 * 90 / 2e6
    dpos = trio.machine.axis_parameter("DPOS", 1)
    assert dpos == pytest.approx(degrees - 360, abs=1e-9)
    assert trio.machine.axis_parameter("WORLD_DPOS", 1) == pytest.approx(degrees - 360,
                                                                         abs=1e-9)
    angle = math.radians(degrees)  # the motors follow the unfolded angle
    assert motors(trio) == pytest.approx([150 * math.cos(angle), 150 * math.sin(angle)],
                                         abs=1e-9)
    assert trio.send("REP_OPTION AXIS(1) = 9") == []  # 0..180: 225 - 180
    assert trio.machine.axis_parameter("DPOS", 1) == pytest.approx(degrees - 180, abs=1e-9)
    assert trio.run_until_idle()
    assert trio.send("FRAME = 0") == []  # DPOS = MPOS again, by AXIS_UNITS: not folded
    assert trio.machine.axis_parameter("DPOS", 1) == trio.machine.axis_parameter("MPOS", 1)
    assert trio.send("REP_OPTION AXIS(1) = 0") == []  # REP_DIST 100 folds again
    assert abs(trio.machine.axis_parameter("DPOS", 1)) <= 100

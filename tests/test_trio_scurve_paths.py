"""S-curves on interpolated and merged paths of the MC405 (TrioBASIC help SRAMP, JERK,
VP_MODE, MOVE, MERGE, CANCEL): the vector speed of a multi-axis move follows the S-curve
a single-axis move of the path's length would, merged moves S-ramp between their
speeds, and CANCEL S-ramps down.

Every expected position is hand arithmetic on an S-ramp: from v1 by dv with peak
acceleration A and rise r (jerk J = A / r), the distance tau seconds in is
v1 tau + J tau^3 / 6 while the acceleration rises, then the ramp's velocity and distance
at r carried at A, and over the last r the mirror image from the ramp's end; a ramp
lasts |dv| / A + r and covers (v1 + v2) / 2 of its time.
"""

from __future__ import annotations

import math

import pytest

from maxk.controllers.trio import MC405
from maxk.firmware_model import servo_kernel
from maxk.firmware_model.servo import ServoLoop


def ramp_distance(v1: float, v2: float, peak: float, rise: float, tau: float) -> float:
    """Distance tau seconds into an S-ramp from v1 to v2 (peak acceleration, rise time),
    by hand: the three stretches of constant jerk."""
    sign = 1.0 if v2 > v1 else -1.0
    jerk = peak / rise
    total_time = abs(v2 - v1) / peak + rise
    if tau <= rise:
        return v1 * tau + sign * jerk * tau ** 3 / 6
    if tau <= total_time - rise:
        p_rise = v1 * rise + sign * jerk * rise ** 3 / 6
        v_rise = v1 + sign * jerk * rise ** 2 / 2
        hold = tau - rise
        return p_rise + v_rise * hold + sign * peak * hold ** 2 / 2
    w = total_time - tau  # the mirror image, back from the ramp's end
    return (v1 + v2) / 2 * total_time - (v2 * w - sign * jerk * w ** 3 / 6)


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def xy(trio: MC405) -> tuple[float, float]:
    return trio.machine.dpos(0), trio.machine.dpos(1)


def mtype(trio: MC405) -> float:
    return float(trio.query("?MTYPE AXIS(0)"))


SET_UP = "BASE(0,1): UNITS AXIS(0)=1: UNITS AXIS(1)=1: SPEED=10: ACCEL=100: DECEL=50"


# ---- an interpolated move ------------------------------------------------------------------
def test_move_30_40_with_sramp_runs_the_single_axis_s_curve_along_its_vector() -> None:
    """SRAMP 50 ms, SPEED 10, ACCEL 100, DECEL 50: the vector (length 50) ramps up over
    10/100 + 0.05 s (0.75 units), down over 10/50 + 0.05 s (1.25 units), cruises 48/10
    s; X carries 3/5 of it, Y 4/5, and both end on the tick the sum gives."""
    up, down = 0.15, 0.25
    cruise = (50 - 0.75 - 1.25) / 10
    end = up + cruise + down  # 5.2 s
    trio = MC405()
    assert trio.send(f"{SET_UP}: SRAMP=50: MOVE(30,40)") == []

    def vector(t: float) -> float:
        if t <= up:
            return ramp_distance(0, 10, 100, 0.05, t)
        if t <= up + cruise:
            return 0.75 + 10 * (t - up)
        return 0.75 + 10 * cruise + ramp_distance(10, 0, 50, 0.05, t - up - cruise)

    for tick in (30, 100, 130, 150, 2000, 4990, 5100, 5180):
        at(trio, tick)
        s = vector(tick / 1000)
        x, y = xy(trio)
        assert x == pytest.approx(0.6 * s, abs=1e-9), tick
        assert y == pytest.approx(0.8 * s, abs=1e-9), tick
    assert math.ceil(end * 1000 - 1e-6) == 5200
    at(trio, 5199)
    assert xy(trio)[1] < 40
    assert mtype(trio) == 1
    at(trio, 5200)
    assert xy(trio) == (30, 40)
    assert mtype(trio) == 0


def test_the_vector_equals_a_single_axis_move_of_the_paths_length() -> None:
    """MOVE(30,40) and MOVE(50) on one axis, same SPEED/ACCEL/DECEL/SRAMP: at every
    tick the path's distance is the single axis's position."""
    path, single = MC405(), MC405()
    assert path.send(f"{SET_UP}: SRAMP=80: MOVE(30,40)") == []
    assert single.send("BASE(0): UNITS=1: SPEED=10: ACCEL=100: DECEL=50: SRAMP=80: "
                       "MOVE(50)") == []
    for tick in range(0, 5400, 37):
        at(path, tick)
        at(single, tick)
        x, y = xy(path)
        assert math.hypot(x, y) == pytest.approx(single.machine.dpos(0), abs=1e-9), tick


def test_jerk_in_vp_mode_6_gives_the_path_a_triangle_of_acceleration() -> None:
    """VP_MODE 6, JERK 500, SPEED 10, ACCEL = DECEL 100: ACCEL^2/JERK = 20 > 10, so the
    acceleration peaks at sqrt(10 x 500) after sqrt(10/500) s and each ramp lasts
    2 sqrt(10/500) s covering 10 x that / 2."""
    peak, rise = math.sqrt(10 * 500), math.sqrt(10 / 500)
    ramp = 2 * rise
    cruise = (50 - 10 * ramp) / 10
    trio = MC405()
    assert trio.send(f"{SET_UP}: DECEL=100: VP_MODE=6: JERK=500: MOVE(-30,40)") == []
    for tick in (100, 200, 1000, 5000):
        at(trio, tick)
        t = tick / 1000
        if t <= ramp:
            s = ramp_distance(0, 10, peak, rise, t)
        elif t <= ramp + cruise:
            s = 10 * ramp / 2 + 10 * (t - ramp)
        else:
            s = 50 - 10 * ramp / 2 + ramp_distance(10, 0, peak, rise, t - ramp - cruise)
        x, y = xy(trio)
        assert (x, y) == (pytest.approx(-0.6 * s, abs=1e-9), pytest.approx(0.8 * s, abs=1e-9))
    end = math.ceil((2 * ramp + cruise) * 1000 - 1e-6)
    at(trio, end - 1)
    assert xy(trio)[1] < 40
    at(trio, end)
    assert xy(trio) == (-30, 40)


def test_jerk_is_ignored_on_a_path_in_vp_mode_0() -> None:
    """VP_MODE 0 with SRAMP 0: JERK set or not, the path's ramps are linear."""
    trio = MC405()
    assert trio.send(f"{SET_UP}: JERK=500: MOVE(30,40)") == []
    at(trio, 50)
    assert xy(trio) == (pytest.approx(0.6 * 100 * 0.05 ** 2 / 2, abs=1e-12),
                        pytest.approx(0.8 * 100 * 0.05 ** 2 / 2, abs=1e-12))


def test_movecirc_with_sramp_runs_the_s_curve_along_its_arc() -> None:
    """A quarter circle of radius 10 (length 5 pi): the angle swept is the S-curve's
    distance over the radius; X and Y are on the circle about the centre."""
    length = 5 * math.pi
    cruise = (length - 0.75 - 1.25) / 10
    trio = MC405()
    assert trio.send(f"{SET_UP}: SRAMP=50: MOVECIRC(10,10,0,10,0)") == []
    for tick in (40, 120, 800, 1500, 1600):
        at(trio, tick)
        t = tick / 1000
        if t <= 0.15:
            s = ramp_distance(0, 10, 100, 0.05, t)
        elif t <= 0.15 + cruise:
            s = 0.75 + 10 * (t - 0.15)
        else:
            s = 0.75 + 10 * cruise + ramp_distance(10, 0, 50, 0.05, t - 0.15 - cruise)
        angle = -math.pi / 2 + s / 10  # anticlockwise from below the centre (0, 10)
        x, y = xy(trio)
        assert x == pytest.approx(10 * math.cos(angle), abs=1e-9), tick
        assert y == pytest.approx(10 + 10 * math.sin(angle), abs=1e-9), tick
    end = math.ceil((0.15 + cruise + 0.25) * 1000 - 1e-6)
    at(trio, end)
    assert xy(trio) == (10, 10)


# ---- merged moves --------------------------------------------------------------------------
def test_merged_sp_moves_s_ramp_from_one_speed_to_the_next_and_to_rest() -> None:
    """MERGE ON, MOVESP(30,40) at FORCE_SPEED 10 then MOVESP(30,40) at FORCE_SPEED 20,
    SRAMP 50, ACCEL 100: 0 -> 10 at the start of the first (0.15 s, 0.75), 10 -> 20 at
    its end (the next SP move runs at its speed from its start: 0.15 s, 2.25), 20 -> 0
    at the end of the second at ACCEL (0.25 s, 2.5)."""
    to_20 = 0.15 + (50 - 0.75 - 2.25) / 10
    seam = to_20 + 0.15
    down_from = seam + (50 - 2.5) / 20
    trio = MC405()
    assert trio.send(f"{SET_UP}: SRAMP=50: MERGE=ON: FORCE_SPEED=10: MOVESP(30,40): "
                     "FORCE_SPEED=20: MOVESP(30,40)") == []
    for tick in (100, 3000, 4860, 4900, 4990, 6000, 7400, 7500, 7600):
        at(trio, tick)
        t = tick / 1000
        if t <= 0.15:
            s = ramp_distance(0, 10, 100, 0.05, t)
        elif t <= to_20:
            s = 0.75 + 10 * (t - 0.15)
        elif t <= seam:
            s = 47.75 + ramp_distance(10, 20, 100, 0.05, t - to_20)
        elif t <= down_from:
            s = 50 + 20 * (t - seam)
        else:
            s = 97.5 + ramp_distance(20, 0, 100, 0.05, t - down_from)
        x, y = xy(trio)
        assert (x, y) == (pytest.approx(0.6 * s, abs=1e-9), pytest.approx(0.8 * s, abs=1e-9)), \
            tick
    end = math.ceil((down_from + 0.25) * 1000 - 1e-6)
    assert end == 7625
    at(trio, end - 1)
    assert xy(trio)[1] < 80
    at(trio, end)
    assert xy(trio) == (60, 80)


def test_speed_written_while_an_s_curve_path_runs_s_ramps_to_it() -> None:
    """SPEED 10 -> 20 at 1 s into MOVE(300,400) (9.25 along, cruising): the path
    S-ramps 10 -> 20 at ACCEL 100 over 0.15 s (2.25 units), then cruises at 20."""
    trio = MC405()
    assert trio.send(f"{SET_UP}: SRAMP=50: MOVE(300,400)") == []
    at(trio, 1000)
    assert trio.send("SPEED=20") == []
    for tick in (1030, 1100, 1140, 2000):
        at(trio, tick)
        tau = tick / 1000 - 1
        s = 9.25 + (ramp_distance(10, 20, 100, 0.05, tau) if tau <= 0.15
                    else 2.25 + 20 * (tau - 0.15))
        x, y = xy(trio)
        assert (x, y) == (pytest.approx(0.6 * s, abs=1e-9), pytest.approx(0.8 * s, abs=1e-9)), \
            tick


def test_a_move_merged_during_a_ramp_takes_over_when_the_ramp_ends() -> None:
    """The second move loads 50 ms into the first one's ramp up: the ramp runs to its
    end (10 at 0.15 s) as planned, then the path goes on to the end of both moves."""
    trio = MC405()
    assert trio.send(f"{SET_UP}: SRAMP=50: MERGE=ON: MOVE(3,4)") == []
    at(trio, 50)
    assert trio.send("MOVE(3,4)") == []
    at(trio, 150)  # the first ramp, unchanged: 0.75 units
    assert xy(trio) == (pytest.approx(0.45, abs=1e-9), pytest.approx(0.6, abs=1e-9))
    at(trio, 500)  # cruising at 10 in the first move, no stop at its end
    s = 0.75 + 10 * 0.35
    assert xy(trio) == (pytest.approx(0.6 * s, abs=1e-9), pytest.approx(0.8 * s, abs=1e-9))
    end = math.ceil((0.15 + (10 - 0.75 - 1.25) / 10 + 0.25) * 1000 - 1e-6)
    at(trio, end)  # (the last ramp down of a merged path: at ACCEL 100, 0.15 s, 0.75)
    assert xy(trio) == (6, 8)


# ---- CANCEL --------------------------------------------------------------------------------
def test_cancel_of_an_s_curve_path_s_ramps_down_at_decel() -> None:
    """CANCEL at 2 s into MOVE(300,400) (19.25 units along, at 10): an S-ramp at DECEL
    50 with SRAMP 50 ms, 0.25 s and 1.25 units: it rests at 20.5 along the vector (C:
    CANCEL page, at DECEL; the S-ramp starts at once, D)."""
    trio = MC405()  # (UNITS 1000: where it rests is not a whole count of a unit)
    assert trio.send(f"{SET_UP}: UNITS AXIS(0)=1000: UNITS AXIS(1)=1000: SRAMP=50: "
                     "MOVE(300,400)") == []
    at(trio, 2000)
    assert trio.send("CANCEL") == []
    for tick in (2030, 2100, 2230):
        at(trio, tick)
        s = 19.25 + ramp_distance(10, 0, 50, 0.05, tick / 1000 - 2)
        x, y = xy(trio)
        assert (x, y) == (pytest.approx(0.6 * s, abs=1e-9), pytest.approx(0.8 * s, abs=1e-9))
    at(trio, 2249)
    assert mtype(trio) != 0
    at(trio, 2250)
    assert xy(trio) == (pytest.approx(12.3, abs=1e-9), pytest.approx(16.4, abs=1e-9))
    assert mtype(trio) == 0


def test_cancel_of_a_jerk_limited_single_axis_move_ramps_down_at_jerk() -> None:
    """VP_MODE 6, JERK 2000, ACCEL = DECEL 100, SPEED 10: CANCEL at 2 s (19.25 along)
    ramps down over 10/100 + 100/2000 s, 0.75 units: at rest on 20 at 2.15 s."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: SPEED=10: ACCEL=100: DECEL=100: VP_MODE=6: "
                     "JERK=2000: MOVE(1000)") == []
    at(trio, 2000)
    assert trio.machine.dpos(0) == pytest.approx(19.25, abs=1e-9)
    assert trio.send("CANCEL") == []
    for tick in (2020, 2080, 2140):
        at(trio, tick)
        expected = 19.25 + ramp_distance(10, 0, 100, 0.05, tick / 1000 - 2)
        assert trio.machine.dpos(0) == pytest.approx(expected, abs=1e-9), tick
    at(trio, 2150)
    assert trio.machine.dpos(0) == pytest.approx(20, abs=1e-9)
    assert mtype(trio) == 0


def test_mhelical_with_jerk_rises_its_third_axis_along_the_s_curve() -> None:
    """MHELICAL: the arc's S-curve as MOVECIRC's, the third axis rising 6 over the arc's
    length in proportion to the distance along it (VP_MODE 5, JERK 2000: A^2/J = 5 < 10,
    each ramp 10/100 + 100/2000 s); mode 1: the path speed is the circle's."""
    length = 5 * math.pi
    cruise = (length - 0.75 - 0.75) / 10
    trio = MC405()
    assert trio.send("BASE(0,1,2): UNITS AXIS(0)=1: UNITS AXIS(1)=1: UNITS AXIS(2)=1: "
                     "SPEED=10: ACCEL=100: DECEL=100: VP_MODE=5: JERK=2000: "
                     "MHELICAL(10,10,0,10,0,6,1)") == []
    for tick in (30, 100, 900, 1600):
        at(trio, tick)
        t = tick / 1000
        if t <= 0.15:
            s = ramp_distance(0, 10, 100, 0.05, t)
        elif t <= 0.15 + cruise:
            s = 0.75 + 10 * (t - 0.15)
        else:
            s = 0.75 + 10 * cruise + ramp_distance(10, 0, 100, 0.05, t - 0.15 - cruise)
        angle = -math.pi / 2 + s / 10
        assert trio.machine.dpos(0) == pytest.approx(10 * math.cos(angle), abs=1e-9)
        assert trio.machine.dpos(1) == pytest.approx(10 + 10 * math.sin(angle), abs=1e-9)
        assert trio.machine.dpos(2) == pytest.approx(6 * s / length, abs=1e-9)
    at(trio, math.ceil((0.3 + cruise) * 1000 - 1e-6))
    assert [trio.machine.dpos(a) for a in range(3)] == [10, 10, 6]


# ---- a servo axis on an S-curve path: the compiled kernel steps it as the Python loop ------
# (no FE_LIMIT or soft-limit watch: the loops record nothing, so the kernel steps them)
SERVO_PATH = ("BASE(0,1): ATYPE AXIS(0)=77: ATYPE AXIS(1)=77: P_GAIN AXIS(0)=8: "
              "P_GAIN AXIS(1)=8: D_GAIN AXIS(0)=120: D_GAIN AXIS(1)=120: SERVO AXIS(0)=ON: "
              "SERVO AXIS(1)=ON: ERRORMASK AXIS(0)=0: ERRORMASK AXIS(1)=0: "
              "AXIS_MODE AXIS(0)=256: AXIS_MODE AXIS(1)=256: WDOG=ON: SPEED=20000: "
              "ACCEL=400000: DECEL=400000: SRAMP=20")


def servo_run() -> list[tuple[float, ...]]:
    trio = MC405()
    assert trio.send(SERVO_PATH) == []
    trio.advance(ticks=5)
    assert trio.send("MERGE=ON: MOVE(3000,4000): MOVECIRC(2000,0,1000,0,1)") == []
    states = []
    for _ in range(60):
        trio.advance(ticks=9)
        loops = [trio.machine.axes[a].servo for a in (0, 1)]
        states.append(tuple(x for loop in loops if loop is not None
                            for x in (loop.p, loop.w, loop.dac)))
    return states


@pytest.mark.skipif(servo_kernel.STEP is None, reason="the compiled servo kernel was not built")
def test_the_kernel_steps_an_s_curve_path_as_the_python_loop(monkeypatch) -> None:
    """The kernel evaluates the path's pieces of constant jerk (its jerked contour) with
    the Python loop's arithmetic: the same motor states, and it did the stepping."""
    kinds = []
    real = servo_kernel.STEP
    assert real is not None

    def counting(state, params, program, tick, count):  # type: ignore[no-untyped-def]
        kinds.append(program[0])
        return real(state, params, program, tick, count)

    monkeypatch.setattr(servo_kernel, "STEP", counting)
    monkeypatch.setattr(servo_kernel, "STEP_AXES", None)
    ours = servo_run()
    assert servo_kernel.KIND_CONTOUR_JERK in kinds
    with monkeypatch.context() as patch:
        def scalar(self, axis, board, matrices, friction, gains, count,  # type: ignore
                   kernel=None):
            self._cache = None
            self._scalar_python(axis, board, matrices, friction, gains, count)

        patch.setattr(ServoLoop, "_scalar", scalar)
        theirs = servo_run()
    assert len(ours[0]) == 6
    for a, b in zip(ours, theirs, strict=True):
        assert all(math.isclose(x, y, rel_tol=0.0, abs_tol=1e-9) for x, y in
                   zip(a, b, strict=True)), (a, b)


# ---- a single-axis S-curve move that becomes a path where it is -----------------------------
def test_speed_written_during_a_jerk_limited_ramp_lets_the_ramp_end_then_s_ramps() -> None:
    """VP_MODE 6, JERK 2000, ACCEL 100, SPEED 10, MOVE(100): SPEED=20 at 0.1 s, inside
    the ramp up: that ramp still ends at 10 at 0.15 s (0.75 units), then 10 -> 20 over
    10/100 + 100/2000 s (2.25 units), and the move ends at 100 on the tick the sum
    gives (down 20 -> 0 over 0.25 s, 2.5 units)."""
    trio = MC405()
    assert trio.send("BASE(0): UNITS=1: SPEED=10: ACCEL=100: DECEL=100: VP_MODE=6: "
                     "JERK=2000: MOVE(100)") == []
    at(trio, 100)
    assert trio.send("SPEED=20") == []
    for tick in (120, 150, 200, 290, 1000):
        at(trio, tick)
        t = tick / 1000
        if t <= 0.15:
            s = ramp_distance(0, 10, 100, 0.05, t)
        elif t <= 0.3:
            s = 0.75 + ramp_distance(10, 20, 100, 0.05, t - 0.15)
        else:
            s = 3.0 + 20 * (t - 0.3)
        assert trio.machine.dpos(0) == pytest.approx(s, abs=1e-9), tick
    end = math.ceil((0.3 + (100 - 3.0 - 2.5) / 20 + 0.25) * 1000 - 1e-6)
    at(trio, end - 1)
    assert trio.machine.dpos(0) < 100
    at(trio, end)
    assert trio.machine.dpos(0) == 100


def test_feed_hold_s_ramps_an_sramp_move_to_rest_and_back() -> None:
    """SRAMP 50, SPEED 10, ACCEL = DECEL 100, MOVE(100), FHOLD_IN 7 at FHSPEED 0: held
    at 1.05 s (9.75 along) it S-ramps to rest over 0.15 s (0.75 units) and waits;
    released at 3 s it S-ramps up again and ends 0.15 + (89.5 - 1.5) / 10 + 0.15 s
    later."""
    trio = MC405()
    trio.world_view().set_input(7, True)  # (active low: released)
    assert trio.send("BASE(0): UNITS=1: SPEED=10: ACCEL=100: DECEL=100: SRAMP=50: "
                     "FHOLD_IN=7: MOVE(100)") == []
    at(trio, 1050)
    assert trio.machine.dpos(0) == pytest.approx(9.75, abs=1e-9)
    trio.world_view().set_input(7, False)
    for tick in (1080, 1150, 1190, 2000, 3000):
        at(trio, tick)
        tau = min(tick / 1000 - 1.05, 0.15)
        expected = 9.75 + ramp_distance(10, 0, 100, 0.05, tau)
        assert trio.machine.dpos(0) == pytest.approx(expected, abs=1e-9), tick
    trio.world_view().set_input(7, True)
    at(trio, 3100)
    assert trio.machine.dpos(0) == pytest.approx(10.5 + ramp_distance(0, 10, 100, 0.05, 0.1),
                                                 abs=1e-9)
    end = 3000 + math.ceil((0.3 + (89.5 - 1.5) / 10) * 1000 - 1e-6)
    at(trio, end - 1)
    assert trio.machine.dpos(0) < 100
    at(trio, end)
    assert trio.machine.dpos(0) == 100


def test_interp_factor_0_on_y_runs_x_at_the_single_axis_s_curve() -> None:
    """INTERP_FACTOR AXIS(1) = 0: the vector speed holds along X alone (the path runs
    50/30 faster), so X runs exactly a single-axis MOVE(30)'s S-curve (SRAMP, ACCEL,
    DECEL) and Y goes 4/3 of X's way."""
    path, single = MC405(), MC405()
    assert path.send(f"{SET_UP}: SRAMP=50: INTERP_FACTOR AXIS(1)=0: MOVE(30,40)") == []
    assert single.send("BASE(0): UNITS=1: SPEED=10: ACCEL=100: DECEL=50: SRAMP=50: "
                       "MOVE(30)") == []
    for tick in range(0, 3300, 41):
        at(path, tick)
        at(single, tick)
        x, y = xy(path)
        assert x == pytest.approx(single.machine.dpos(0), abs=1e-9), tick
        assert y == pytest.approx(x * 4 / 3, abs=1e-9), tick


def test_the_slot_example_runs_its_s_curves_under_maxk_run(tmp_path) -> None:
    """examples/mc405_scurve_slot.maxk under `maxk run`: its replies as recorded, and
    the trace's vector speed rises over its first 0.2 s as the S-curve says (at 0.1 s,
    the middle of the ramp up: 500 x 0.1 / 2 = 25 mm/s; then 50) and never above 50."""
    from pathlib import Path

    from maxk.cli import main

    script = Path(__file__).parent.parent / "examples" / "mc405_scurve_slot.maxk"
    trace = tmp_path / "slot.csv"
    assert main(["run", str(script), "--trace", str(trace), "--trace-every", "1ms"]) == 0
    lines = trace.read_text().splitlines()[1:]
    rows = [(int(r.split(",")[0]), float(r.split(",")[2]), float(r.split(",")[3]))
            for r in lines]
    at_tick = {tick: (x, y) for tick, x, y in rows}
    start = next(tick for tick, x, _y in rows if x > 0) - 1  # the program's first move
    x0, _ = at_tick[start + 100]
    x1, _ = at_tick[start + 101]
    assert x0 == pytest.approx(5000 * 0.1 ** 3 / 6, abs=1e-6)  # J t^3 / 6 (traced to 1e-6)
    assert (x1 - x0) * 1000 == pytest.approx(25, abs=0.3)
    end = 0.4 + (80 + 20 * math.pi - 10) / 50  # 3.0566 s: on tick 3057
    assert at_tick[start + 3057] == (0, 0)
    left = end - 3.050  # the last arc ends along +X, its acceleration falling at JERK
    assert at_tick[start + 3050][0] == pytest.approx(-5000 * left ** 3 / 6, abs=2e-6)


def test_an_s_curve_move_of_no_length_ends_at_once() -> None:
    """MOVEABS to where the axes stand, with SRAMP: nothing moves, the move is done on
    the next servo tick, and the next move runs its S-curve."""
    trio = MC405()
    assert trio.send(f"{SET_UP}: SRAMP=50: MOVEABS(0,0): MOVE(3,4)") == []
    at(trio, 30)
    s = ramp_distance(0, 10, 100, 0.05, 0.03)
    assert xy(trio) == (pytest.approx(0.6 * s, abs=1e-9), pytest.approx(0.8 * s, abs=1e-9))

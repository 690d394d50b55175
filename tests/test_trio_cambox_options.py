"""CAMBOX's link options, pattern mode and multi-axis form, MOVELINK's option bits and
registration (REGIST, MARK, REG_POS, REP_OPTION), from their TrioBASIC help pages.

The link axis (axis 1) runs FORWARD at 100 units/s with ACCEL 1e6 (UNITS 1), so at
servo tick k (1 ms) it stands at 0.1 k - 0.005 (the ramp's 0.1 ms loses v^2 / 2a);
every expected position is that arithmetic and the page's description of the option.
"""

from __future__ import annotations

import numpy as np
import pytest

from maxk.controllers.trio.controller import MC405

SPEED, ACCEL = 100.0, 1e6
LOSS = SPEED * SPEED / (2 * ACCEL)  # 0.005
SHAPE = [0.0, 100.0, 300.0, 400.0]  # a 3-segment profile over a link distance of 10


def link(tick: int) -> float:
    """The FORWARD link axis's DPOS at a tick."""
    t = tick / 1000
    return SPEED * t - LOSS if t >= SPEED / ACCEL else 0.5 * ACCEL * t * t


def first_tick(position: float) -> int:
    """The first tick the link axis has reached a position."""
    k = int((position + LOSS) / SPEED * 1000)
    while link(k) < position:
        k += 1
    return k


def profile(u: float, shape: list[float] = SHAPE, span: float = 10.0) -> float:
    u = min(max(u, 0.0), span)
    return float(np.interp(u / span * (len(shape) - 1), range(len(shape)), shape))


def machine() -> MC405:
    trio = MC405()
    assert trio.send("TABLE(0, 0, 100, 300, 400)") == []
    assert trio.send(f"BASE(1): SPEED={SPEED:g}: ACCEL={ACCEL:g}: DECEL={ACCEL:g}") == []
    return trio


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def read(trio: MC405, what: str) -> float:
    if what.startswith("DPOS AXIS("):  # exact, not as PRINT rounds it
        return trio.machine.dpos(int(what[10:-1]))
    return float(trio.query(f"?{what}"))


def test_absolute_start_holds_until_the_link_position_then_follows_and_ends() -> None:
    trio = machine()
    assert trio.send("CAMBOX(0, 3, 1, 10, 1, 2, 20) AXIS(0)") == []
    assert trio.send("FORWARD AXIS(1)") == []
    end = first_tick(30.0)
    for tick in (100, 199, first_tick(20.0), 250, 275, end - 1):
        at(trio, tick)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(profile(link(tick) - 20), abs=1e-6)
        assert read(trio, "MTYPE AXIS(0)") == 20
    at(trio, end)
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (400.0, 0)


def test_table_values_are_offset_by_the_first_value() -> None:
    trio = machine()
    assert trio.send("TABLE(10, 50, 150)") == []
    assert trio.send("CAMBOX(10, 11, 2, 10, 1) AXIS(0): FORWARD AXIS(1)") == []
    at(trio, 51)  # the link at 5.095: half way, (150 - 50) x 2 x 0.5095
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(200 * link(51) / 10, abs=1e-6)


def test_repeat_runs_cycle_after_cycle_until_rep_option_bit_1() -> None:
    trio = machine()
    assert trio.send("CAMBOX(0, 3, 1, 10, 1, 4) AXIS(0): FORWARD AXIS(1)") == []
    for tick in (50, 150, 333, 777):
        at(trio, tick)
        p = link(tick)
        cycles = int(p // 10)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(400 * cycles + profile(p - 10 * cycles),
                                                         abs=1e-6)
    assert trio.send("REP_OPTION AXIS(1) = 2") == []  # (set on the link axis, as the page)
    assert read(trio, "REP_OPTION AXIS(1)") == 0  # the firmware clears it
    end = first_tick(80.0)  # the cycle 70..80 running at 77.7 is the last
    at(trio, end - 1)
    assert read(trio, "MTYPE AXIS(0)") == 20
    at(trio, end)
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (3200.0, 0)


def test_a_cambox_starts_exactly_at_the_links_registration_mark_and_repeats() -> None:
    trio = machine()
    stage = trio.machine.world.axes[1]
    stage.index_offset, stage.index_period, stage.index_width = 2500, 100000, 4
    assert trio.send("UNITS AXIS(1) = 100") == []  # marks in counts, DPOS in units
    assert trio.send("REGIST(1) AXIS(1)") == []
    assert read(trio, "MARK AXIS(1)") == 0
    assert trio.send("CAMBOX(0, 3, 1, 10, 1, 5) AXIS(0): FORWARD AXIS(1)") == []
    mark = first_tick(25.0)  # 25 units = the 2500th count
    at(trio, mark - 1)
    assert (read(trio, "MARK AXIS(1)"), read(trio, "DPOS AXIS(0)")) == (0, 0)
    at(trio, mark)
    assert (read(trio, "MARK AXIS(1)"), read(trio, "REG_POS AXIS(1)")) == (-1, 25.0)
    for tick in (mark, 300, 420, 999):
        at(trio, tick)
        u = link(tick) - 25
        cycles = int(u // 10)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(400 * cycles + profile(u - 10 * cycles),
                                                         abs=1e-6)


def test_regist_falling_z_edge_and_the_r_input() -> None:
    trio = machine()
    stage = trio.machine.world.axes[1]
    stage.index_offset, stage.index_period, stage.index_width = 1000, 4000, 4
    assert trio.send("REGIST(2) AXIS(1): FORWARD AXIS(1)") == []
    at(trio, 10500)  # the mark is counts 1000..1003: it falls at 1004 (tick 10041)
    assert read(trio, "REG_POS AXIS(1)") == 1004.0
    trio.send("REGIST(3) AXIS(1)")
    at(trio, 12000)
    view = trio.world_view()
    view.set_input(1, True)  # the R input of axis 1 rises now
    assert (read(trio, "MARK AXIS(1)"), read(trio, "REG_POS AXIS(1)")) == (
        -1, pytest.approx(link(12000), abs=1e-9))
    assert trio.send("REGIST(42) AXIS(1)")[0].endswith("Parameter out of range")


def test_offset_start_takes_the_axis_as_that_far_into_the_profile() -> None:
    trio = machine()
    assert trio.send("CAMBOX(0, 3, 1, 10, 1, 128, 0, 5) AXIS(0): FORWARD AXIS(1)") == []
    at(trio, 30)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(profile(5 + link(30)) - profile(5),
                                                      abs=1e-6)
    at(trio, first_tick(5.0))
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (200.0, 0)


def test_pattern_mode_scales_each_shape_and_counts_its_repeats() -> None:
    trio = machine()
    # shape 0..1 (a straight line), control block at 100, pattern 10, 20 at TABLE(200)
    assert trio.send("TABLE(0, 0, 1): TABLE(200, 10, 20)") == []
    assert trio.send("TABLE(100, 200, -1, 200, 201, 0, 2, -1)") == []
    assert trio.send("CAMBOX(0, 1, 100, 10, 1, 12) AXIS(0): FORWARD AXIS(1)") == []
    # shapes: 10, 20, 10, 20 (two repeats of the pattern), then it ends at 60
    starts = [0.0, 10.0, 30.0, 40.0]
    for tick in (50, 150, 250, 350):
        at(trio, tick)
        p = link(tick)
        k = int(p // 10)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(
            starts[k] + (10, 20)[k % 2] * (p - 10 * k) / 10, abs=1e-6)
    at(trio, first_tick(40.0))
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (60.0, 0)
    assert read(trio, "TABLE(104)") == 2  # REPEAT POSITION counted both


def test_the_multi_axis_form_loads_every_axis_from_the_table() -> None:
    trio = machine()
    assert trio.send("TABLE(50, 0, 30): TABLE(60, 0, 50, 80)") == []
    assert trio.send("TABLE(1000, 50, 51, 1, 10, 1, 0, 0, 0)") == []
    assert trio.send("TABLE(1008, 60, 62, 2, 20, 1, 2, 5, 0)") == []
    assert trio.send("BASE(2): CAMBOX(1000, 2): FORWARD AXIS(1)") == []
    at(trio, 80)
    p = link(80)
    assert read(trio, "DPOS AXIS(2)") == pytest.approx(30 * p / 10, abs=1e-6)
    assert read(trio, "DPOS AXIS(3)") == pytest.approx(
        2 * profile(p - 5, [0, 50, 80], 20), abs=1e-6)
    # a bad row refuses the whole group: nothing is loaded
    assert trio.send("TABLE(1016, 50, 51, 1, -1, 1, 0, 0, 0)") == []
    reply = trio.send("BASE(4): CAMBOX(1008, 2)")
    assert reply and "Parameter out of range" in reply[0]
    assert read(trio, "MTYPE AXIS(4)") == 0


def smoothstep_share(z: float, derivative) -> float:  # type: ignore[no-untyped-def]
    """The integral of a ramp's speed curve, numerically (not the model's closed form)."""
    xs = np.linspace(0.0, z, 20001)
    speed = np.array([derivative(x) for x in xs])
    return float(np.trapezoid(speed, xs))


def test_movelink_1040_ramps_on_the_power_9_polynomial() -> None:
    """1040 = bit 4 (curved ramps) + bit 10 (curve 1, power 9 polynomial speed)."""
    trio = machine()
    assert trio.send("MOVELINK(100, 100, 40, 40, 1, 1040) AXIS(0): FORWARD AXIS(1)") == []

    def speed9(x: float) -> float:  # power 9 smoothstep: 0 to 1, flat ends
        return 126 * x**5 - 420 * x**6 + 540 * x**7 - 315 * x**8 + 70 * x**9

    peak = 100 / (100 - 40)  # the ramps still average half the peak ratio
    for tick in (100, 200, 399):
        at(trio, tick)
        u = link(tick)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(
            peak * 40 * smoothstep_share(u / 40, speed9), abs=1e-6)
    at(trio, 500)  # between the ramps: the peak ratio, after the first ramp's half
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(peak * (link(500) - 20), abs=1e-6)
    at(trio, 900)
    rest = 100 - link(900)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(
        100 - peak * 40 * smoothstep_share(rest / 40, speed9), abs=1e-6)


def test_movelink_starts_on_the_mark() -> None:
    trio = machine()
    stage = trio.machine.world.axes[1]
    stage.index_offset, stage.index_period, stage.index_width = 15, 1000, 1
    assert trio.send("REGIST(1) AXIS(1): MOVELINK(10, 20, 0, 0, 1, 1) AXIS(0)") == []
    assert trio.send("FORWARD AXIS(1)") == []
    at(trio, 140)
    assert read(trio, "DPOS AXIS(0)") == 0
    at(trio, 250)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx((link(250) - 15) / 2, abs=1e-6)
    at(trio, first_tick(35.0))
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (10.0, 0)


def moving(tick: int, speed: float, accel: float) -> float:
    """A FORWARD axis's DPOS at a tick, from rest at tick 0."""
    t = tick / 1000
    ramp = speed / accel
    return speed * t - speed * ramp / 2 if t >= ramp else 0.5 * accel * t * t


def test_flexlink_waits_then_runs_a_sine_excitation_over_the_rest_of_the_cycle() -> None:
    """The page's example 1: no base move, 10000 over the last 40% of a 20000 link
    cycle, half accel, half decel (sine ramps: the default curve)."""
    trio = MC405()
    assert trio.send("BASE(1): SPEED=10000: ACCEL=1e8: DECEL=1e8") == []
    assert trio.send("FLEXLINK(0, 10000, 20000, 60, 0, 50, 50, 1) AXIS(0)") == []
    assert trio.send("FORWARD AXIS(1)") == []

    def sine(z: float) -> float:  # the ramp's speed share
        return (1 - np.cos(np.pi * z)) / 2

    peak = 2 * 10000 / 8000  # counts per link count at the window's middle
    for tick in (500, 1200, 1400, 1600, 1800, 1999):
        at(trio, tick)
        u = moving(tick, 10000, 1e8) - 12000
        if u <= 0:
            want = 0.0
        elif u <= 4000:
            want = peak * 4000 * smoothstep_share(u / 4000, sine)
        else:
            want = 10000 - peak * 4000 * smoothstep_share((8000 - u) / 4000, sine)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(want, abs=1e-6), tick
    at(trio, 2001)
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (10000.0, 0)


def test_flexlink_adds_an_advance_to_a_one_to_one_base_and_repeats() -> None:
    """The page's example 2, repeating (option 4): 1:1 plus 500 between 80% and 95%."""
    trio = MC405()
    assert trio.send("BASE(1): SPEED=10000: ACCEL=1e8: DECEL=1e8") == []
    assert trio.send("FLEXLINK(10000, 500, 10000, 80, 5, 50, 50, 1, 4) AXIS(0)") == []
    assert trio.send("FORWARD AXIS(1)") == []
    for tick in (500, 799, 1500, 2500):
        at(trio, tick)
        u = moving(tick, 10000, 1e8)
        cycles = u // 10000
        rest = u - 10000 * cycles
        extra = 0.0 if rest <= 8000 else 500.0 if rest >= 9500 else None
        if extra is not None:
            assert read(trio, "DPOS AXIS(0)") == pytest.approx(
                10500 * cycles + rest + extra, abs=1e-6), tick
    reply = trio.send("FLEXLINK(0, 1, 100, 70, 40, 50, 50, 1) AXIS(2)")
    assert reply and "Parameter out of range" in reply[0]  # 70% + 40% of the base


def test_a_repeating_axis_reads_folded_positions_and_moves_within_its_fold() -> None:
    trio = machine()
    assert read(trio, "REP_DIST AXIS(1)") == 200000  # power-up
    assert trio.send("REP_DIST AXIS(1) = 100: FORWARD AXIS(1)") == []
    at(trio, 1500)  # unfolded 149.995: -100..100 folds it to -50.005
    assert float(trio.query("?DPOS AXIS(1)")) == pytest.approx(link(1500) - 200, abs=1e-4)
    assert trio.send("REP_OPTION AXIS(1) = 1") == []  # 0..100: 49.995
    assert float(trio.query("?DPOS AXIS(1)")) == pytest.approx(link(1500) - 100, abs=1e-4)
    assert float(trio.query("?MPOS AXIS(1)")) == pytest.approx(link(1500) - 100, abs=1e-4)
    trio.send("CANCEL AXIS(1)")
    trio.advance(0.1)
    here = trio.machine.dpos(1)  # unfolded, at rest
    assert trio.send("MOVEABS(90) AXIS(1)") == []  # within the fold it reads now
    trio.advance(2.0)
    assert trio.machine.dpos(1) == pytest.approx(here - (here - 100) + 90, abs=1e-9)
    assert float(trio.query("?DPOS AXIS(1)")) == 90


@pytest.mark.parametrize(("mode", "window", "captured"), [
    (257, (33, 47), 35.0),  # inside the window: the marks at 5, 15, 25 pass by
    (769, (0, 20), 25.0),  # outside it
])
def test_a_registration_window_passes_over_the_marks_it_rejects(
        mode: int, window: tuple[float, float], captured: float) -> None:
    trio = machine()
    stage = trio.machine.world.axes[1]
    stage.index_offset, stage.index_period, stage.index_width = 500, 1000, 1
    trio.send("UNITS AXIS(1) = 100")
    trio.send(f"OPEN_WIN AXIS(1) = {window[0]}: CLOSE_WIN AXIS(1) = {window[1]}")
    assert trio.send(f"REGIST({mode}) AXIS(1): FORWARD AXIS(1)") == []
    tick = first_tick(captured)
    at(trio, tick - 1)
    assert read(trio, "MARK AXIS(1)") == 0
    at(trio, tick)
    assert (read(trio, "MARK AXIS(1)"), read(trio, "REG_POS AXIS(1)")) == (-1, captured)


def test_sramp_makes_the_ramp_last_speed_over_accel_plus_the_sramp_time() -> None:
    """SPEED 100, ACCEL 1000, SRAMP 40 ms: the acceleration rises over 0.04 s (jerk
    1000 / 0.04), holds 0.06 s, falls over 0.04 s: the ramp lasts 0.14 s and covers
    100 x 0.14 / 2 = 7 units; a 100-unit move then ends at 2 x 0.14 + (100 - 14) / 100."""
    trio = MC405()
    assert trio.send("BASE(0): SPEED=100: ACCEL=1000: DECEL=1000: SRAMP=40") == []
    assert trio.send("MOVE(100)") == []
    jerk = 1000 / 0.04
    at(trio, 40)  # end of the rise: jerk t^3 / 6
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(jerk * 0.04 ** 3 / 6, abs=1e-9)
    at(trio, 70)  # 0.03 s into the hold: v(0.04) = 20, a = 1000
    p40 = jerk * 0.04 ** 3 / 6
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(p40 + 20 * 0.03 + 500 * 0.03 ** 2,
                                                     abs=1e-9)
    at(trio, 140)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(7.0, abs=1e-9)
    end = round((2 * 0.14 + 86 / 100) * 1000)
    at(trio, end - 1)
    assert read(trio, "DPOS AXIS(0)") < 100
    at(trio, end)
    assert read(trio, "DPOS AXIS(0)") == 100


def test_a_forward_only_cambox_ignores_the_links_backward_travel() -> None:
    """Link option 32: the link goes to 6, back to 2, then to 12: the cam has seen
    6 + (12 - 2) = 16 of forward travel, so it ended (10) on the way; with 16384 only
    travel past the highest point counts: 6, then from 6 to 12: it ends at 10 too, but
    at 8 on the way out it has seen 8, not 6 + 6."""
    for option, seen_at_8 in ((32, 6 + 6), (16384, 8)):
        trio = MC405()
        assert trio.send("TABLE(0, 0, 1000): BASE(1): SPEED=10: ACCEL=1e6: DECEL=1e6") == []
        assert trio.send(f"CAMBOX(0, 1, 1, 20, 1, {option}) AXIS(0)") == []
        trio.send("MOVEABS(6): MOVEABS(2)")
        trio.advance(2.0)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(1000 * 6 / 20, abs=1e-6)
        trio.send("MOVEABS(12)")
        trio.advance(ticks=600)  # 6 of 10 units of the way out: at 8
        assert read(trio, "DPOS AXIS(1)") == pytest.approx(8, abs=0.01)
        here = trio.machine.dpos(1)
        seen = (6 + here - 2) if option == 32 else here
        assert seen_at_8 == pytest.approx(seen, abs=0.01)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(1000 * seen / 20, abs=1e-6)


def test_a_forward_only_movelink_ends_when_its_forward_travel_is_done() -> None:
    """MOVELINK option 32 over 10 of link: out to 6, back to 2, out again: it ends where
    the link has gone 4 more forward, at 6, on the first tick it gets there."""
    trio = MC405()
    assert trio.send("BASE(1): SPEED=10: ACCEL=1e6: DECEL=1e6") == []
    assert trio.send("MOVELINK(100, 10, 0, 0, 1, 32) AXIS(0)") == []
    trio.send("MOVEABS(6): MOVEABS(2)")
    trio.advance(2.0)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(60, abs=1e-6)
    start = trio.tick
    trio.send("MOVEABS(8)")
    # from rest at 2: 10 units/s after a 10 us ramp (5e-5 lost): at 6 after 0.400005 s
    end = start + 401
    at(trio, end - 1)
    assert read(trio, "MTYPE AXIS(0)") == 22
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(60 + 10 * (trio.machine.dpos(1) - 2),
                                                     abs=1e-6)
    at(trio, end)
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (100, 0)


def test_movesp_runs_at_force_speed_and_move_at_speed() -> None:
    """SPEED 10, FORCE_SPEED 40, ACCEL 1e6: MOVESP(20) takes 0.5 s (+ the 40 us ramp),
    MOVE(20) after it 2 s."""
    trio = MC405()
    assert trio.send("BASE(0): SPEED=10: FORCE_SPEED=40: ACCEL=1e6: DECEL=1e6") == []
    assert trio.send("MOVESP(20): MOVE(20)") == []
    at(trio, 250)  # 40 x 0.25 - 40 x 40 / 2e6
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(40 * 0.25 - 40 * 40 / 2e6, abs=1e-9)
    at(trio, 501)
    assert read(trio, "DPOS AXIS(0)") == 20
    at(trio, 1501)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(20 + 10 * 1.0 - 10 * 10 / 2e6, abs=1e-9)
    trio.send("MOVEABSSP(0)")
    trio.advance(3.0)
    assert read(trio, "DPOS AXIS(0)") == 0


def test_a_jog_input_jogs_at_jogspeed_while_it_is_low() -> None:
    """FWD_JOG on input 7, active low (the manual): held high, nothing; low at tick 100,
    the axis jogs at JOGSPEED 20 (ACCEL 1e6: 2e-4 lost); high at tick 600, it ramps
    down at DECEL 1e6 and stands (2e-4 more)."""
    trio = MC405()
    view = trio.world_view()
    view.set_input(7, True)
    assert trio.send("BASE(0): JOGSPEED=20: SPEED=50: ACCEL=1e6: DECEL=1e6") == []
    assert trio.send("FWD_JOG=7") == []
    at(trio, 100)
    assert read(trio, "MTYPE AXIS(0)") == 0
    view.set_input(7, False)
    assert read(trio, "MTYPE AXIS(0)") == 14
    at(trio, 600)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(20 * 0.5 - 20 * 20 / 2e6, abs=1e-9)
    view.set_input(7, True)
    trio.advance(0.1)
    assert read(trio, "MTYPE AXIS(0)") == 0
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(20 * 0.5, abs=1e-9)
    assert trio.send("FAST_JOG=6: REV_JOG=5") == []  # input 6 low: fast; 5 low: reverse
    view.set_input(7, True)
    trio.advance(ticks=200)
    assert read(trio, "DPOS AXIS(0)") == pytest.approx(10 - 50 * 0.2 + 50 * 50 / 2e6,
                                                     abs=1e-9)


def test_cam_follows_the_table_in_time_at_speed() -> None:
    """CAM(0, 3, 2, 30) with SPEED 10: the profile 0, 100, 300, 400 (x 2) over 3 s, one
    TABLE interval a second."""
    trio = MC405()
    assert trio.send("TABLE(0, 0, 100, 300, 400): BASE(0): SPEED=10") == []
    assert trio.send("CAM(0, 3, 2, 30): MOVE(5)") == []
    assert read(trio, "MTYPE AXIS(0)") == 13
    for tick in (250, 1000, 1500, 2999):
        at(trio, tick)
        assert read(trio, "DPOS AXIS(0)") == pytest.approx(
            2 * profile(tick / 1000, SHAPE, 3.0), abs=1e-9)
    at(trio, 3000)
    assert read(trio, "DPOS AXIS(0)") == 800
    assert read(trio, "MTYPE AXIS(0)") == 1  # the MOVE behind it


def test_movecircsp_runs_the_arc_at_force_speed() -> None:
    """A quarter circle of radius 100 (157.08 long) at FORCE_SPEED 100 with ACCEL 1e6:
    done on the first tick at or after 1.5708 s + 100 / 1e6 s; at SPEED 10 it would take
    ten times as long."""
    trio = MC405()
    assert trio.send("BASE(0, 1): SPEED=10: FORCE_SPEED=100: ACCEL=1e6: DECEL=1e6") == []
    assert trio.send("MOVECIRCSP(100, 100, 100, 0, 1)") == []
    end = int(np.ceil((np.pi * 50 / 100 + 100 / 1e6) * 1000 - 1e-9))
    at(trio, end - 1)
    assert read(trio, "MTYPE AXIS(0)") == 4
    at(trio, end)
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "DPOS AXIS(1)")) == (100, 100)
    assert read(trio, "MTYPE AXIS(0)") == 0


def test_a_pattern_pointing_outside_table_ends_the_cambox_and_time_goes_on() -> None:
    trio = machine()
    assert trio.send("TABLE(0, 0, 1): TABLE(200, 10, 20)") == []
    assert trio.send("TABLE(100, 200, -1, 200, 201, 0, 1, 999999999)") == []
    assert trio.send("CAMBOX(0, 1, 100, 10, 1, 12) AXIS(0): FORWARD AXIS(1)") == []
    trio.advance(1.0)  # after two shapes the next block is outside TABLE: it ends at 30
    assert (read(trio, "DPOS AXIS(0)"), read(trio, "MTYPE AXIS(0)")) == (30, 0)
    assert trio.send("?1") == ["1"]


@pytest.mark.parametrize("line", [
    "CAMBOX(0, 3, 1, 1e-300, 1, 4) AXIS(0)",  # a link distance no cycle count holds
    "CAMBOX(0, 3, 1, 10, 1, 64) AXIS(0)",  # a reserved bit
    "CAMBOX(0, 3, 1, 10, 1, 3, 5) AXIS(0)",  # two start events
    "CAMBOX(0, 3, 1, 10, 1, 128, 0, 10) AXIS(0)",  # an offset past the link distance
    "CAM(0, 3, 1, -10) AXIS(0)",  # a distance that is not positive
    "CAM(3, 0, 1, 10) AXIS(0)",
    "REGIST(5) AXIS(0)",  # reserved (REGIST page)
    "MOVELINK(1, 10, 0, 0, 1, 16 + 5 * 1024) AXIS(0)",  # curve 5: unused
    "FLEXLINK(1, 1, 10, 0, 0, 50, 50, 1, 32 + 16384) AXIS(0)",
])
def test_bad_options_are_refused_and_load_nothing(line: str) -> None:
    trio = machine()
    reply = trio.send(line)
    assert reply and "Parameter out of range" in reply[0], reply
    assert read(trio, "MTYPE AXIS(0)") == 0 and read(trio, "NTYPE AXIS(0)") == 0
    assert trio.send("?1") == ["1"]


def test_demand_speed_is_the_demands_change_over_the_last_servo_cycle() -> None:
    trio = MC405()
    assert trio.send("BASE(0): UNITS=10: SPEED=25: ACCEL=1e6: DECEL=1e6: MOVE(100)") == []
    at(trio, 500)  # cruising at 25 units/s (the move lasts 4 s)
    assert float(trio.query("?DEMAND_SPEED")) == pytest.approx(25, abs=1e-9)
    trio.advance(5.0)
    assert float(trio.query("?DEMAND_SPEED")) == 0


def test_a_linked_axis_captures_its_z_mark_to_the_tick() -> None:
    """Axis 2 CONNECTed at 3 counts per count to the FORWARD link axis: its mark at
    count 600 is met when the link is at 200 (tick 2001 at 0.1 t - 0.005)."""
    trio = machine()
    stage = trio.machine.world.axes[2]
    stage.index_offset, stage.index_period, stage.index_width = 600, 100000, 1
    assert trio.send("CONNECT(3, 1) AXIS(2): REGIST(1) AXIS(2): FORWARD AXIS(1)") == []
    tick = first_tick(200.0)
    at(trio, tick - 1)
    assert read(trio, "MARK AXIS(2)") == 0
    at(trio, tick)
    assert (read(trio, "MARK AXIS(2)"), read(trio, "REG_POS AXIS(2)")) == (-1, 600)

"""The MC405's servo output: the open-loop DAC with SERVO OFF, DAC_OUT, OUTLIMIT, DAC_SCALE
and the OV_GAIN / AFF_GAIN terms of the closed loop (TrioBASIC help DAC, DAC_OUT,
OUTLIMIT, DAC_SCALE, OV_GAIN, AFF_GAIN, SERVO).

The world's default motor (maxk/firmware_model/motor.py's MotorPlant defaults, worked out
here by hand): inertia 5e-6 kg m^2, viscous friction 2e-5 N m s/rad, Coulomb friction
0.005 N m, torque constant 0.1 N m/A on a voltage amplifier of gain 3 through 2 ohm, 2000
lines (8000 counts a turn). Under a constant output of u shared DAC counts (10 V = 32767)
it settles at w = g (u - f) / a counts/s with
    torque per count = 0.1 * 3 / 2 * 10 / 32767 N m,
    g = torque per count / 5e-6 * 8000 / (2 pi)   (counts/s^2 per count),
    a = (2e-5 + 0.1^2 / 2) / 5e-6                   (1/s: about 1 ms),
    f = 0.005 / torque per count                    (counts of output friction holds).
"""

from __future__ import annotations

import math

from tests.trio_helpers import at, mc405

TORQUE_PER_COUNT = 0.1 * 3.0 / 2.0 * 10.0 / 32767.0
G = TORQUE_PER_COUNT / 5e-6 * 8000.0 / (2.0 * math.pi)
A = (2e-5 + 0.1 ** 2 / 2.0) / 5e-6
FRICTION = 0.005 / TORQUE_PER_COUNT


def steady_speed(dac: float) -> float:
    """counts/s under an MC405 DAC value (x16 on the shared 16-bit output)."""
    u = dac * 16.0
    return G * (u - FRICTION) / A


OPEN = "ATYPE=77: WDOG=ON: SERVO=OFF: REP_DIST=1e9"


# ---- DAC with SERVO OFF: the open loop ---------------------------------------------------
def test_dac_with_servo_off_runs_the_motor_at_its_steady_speed() -> None:
    trio = mc405(OPEN, "DAC=1024")  # +5 V, as the help page's square wave
    assert trio.query("?DAC_OUT") == "1024"
    at(trio, 500)  # 500 time constants: settled
    start = float(trio.query("?MPOS"))
    at(trio, 1500)  # one second later
    travelled = float(trio.query("?MPOS")) - start
    assert abs(travelled - steady_speed(1024)) <= 1.0  # (encoder counts: +/-1)
    # DPOS is MPOS while SERVO is OFF (help DPOS): FE reads 0
    assert (trio.query("?DPOS"), trio.query("?FE")) == (trio.query("?MPOS"), "0")


def test_the_help_page_square_wave_reverses_the_motor_every_250_ms() -> None:
    trio = mc405(OPEN)
    trio.load("SQUARE", "square:\n  DAC AXIS(0) = 1024\n  WA(250)\n"
                      "  DAC AXIS(0) = -1024\n  WA(250)\nGOTO square\n")
    trio.send('RUN "SQUARE"')
    at(trio, 100)
    assert trio.query("?DAC_OUT") == "1024"
    at(trio, 200)
    high = float(trio.query("?MPOS"))
    at(trio, 240)
    assert abs(float(trio.query("?MPOS")) - high - steady_speed(1024) * 0.040) <= 1.0
    at(trio, 400)
    assert trio.query("?DAC_OUT") == "-1024"
    low = float(trio.query("?MPOS"))
    at(trio, 440)
    assert abs(float(trio.query("?MPOS")) - low + steady_speed(1024) * 0.040) <= 1.0


def test_dac_is_not_put_out_with_the_watchdog_or_the_enable_off() -> None:
    trio = mc405("ATYPE=77: SERVO=OFF: REP_DIST=1e9", "DAC=1024")  # WDOG OFF
    assert (trio.query("?DAC"), trio.query("?DAC_OUT")) == ("1024", "0")
    at(trio, 1000)
    assert trio.query("?MPOS") == "0"
    trio.send("WDOG=ON: AXIS_ENABLE=OFF")
    at(trio, 2000)
    assert (trio.query("?DAC_OUT"), trio.query("?MPOS")) == ("0", "0")
    trio.send("AXIS_ENABLE=ON")
    assert trio.query("?DAC_OUT") == "1024"
    at(trio, 2500)
    assert float(trio.query("?MPOS")) > 0.4 * steady_speed(1024)
    trio.send("WDOG=OFF")  # the output goes to 0, DPOS still follows MPOS as it coasts
    at(trio, 2502)
    assert trio.query("?DAC_OUT") == "0"
    assert (trio.query("?DPOS"), trio.query("?FE")) == (trio.query("?MPOS"), "0")


def test_outlimit_limits_the_open_loop_output() -> None:
    trio = mc405(OPEN, "OUTLIMIT=1023", "DAC=2047")
    assert (trio.query("?DAC"), trio.query("?DAC_OUT")) == ("2047", "1023")
    at(trio, 500)
    start = float(trio.query("?MPOS"))
    at(trio, 1500)
    assert abs(float(trio.query("?MPOS")) - start - steady_speed(1023)) <= 1.0
    assert trio.send("OUTLIMIT=4000") == ["! Parameter out of range"]
    assert trio.query("?OUTLIMIT") == "1023"
    trio.send("DAC=-3000")
    assert trio.query("?DAC_OUT") == "-1023"


def test_dac_scale_power_up_and_its_sign_does_not_scale_the_open_loop() -> None:
    trio = mc405(OPEN)
    assert (trio.query("?DAC_SCALE"), trio.query("?OUTLIMIT")) == ("1", "2047")
    trio.send("DAC_SCALE=-1: DAC=512")
    at(trio, 500)
    start = float(trio.query("?MPOS"))
    at(trio, 1500)
    assert abs(float(trio.query("?MPOS")) - start - steady_speed(512)) <= 1.0
    assert trio.send("DAC_SCALE=17") == ["! Parameter out of range"]


def test_servo_on_takes_the_demand_to_where_the_motor_stands() -> None:
    trio = mc405(OPEN, "DAC=300")
    at(trio, 200)
    trio.send("DAC=0")  # the motor coasts down to a stop on its friction
    at(trio, 400)
    stood = float(trio.query("?MPOS"))
    assert stood > 0
    trio.send("P_GAIN=10: D_GAIN=160: SERVO=ON")
    assert float(trio.query("?DPOS")) == stood
    at(trio, 600)
    assert abs(float(trio.query("?MPOS")) - stood) <= 1.0


# ---- the closed loop's output: OV_GAIN and AFF_GAIN terms, every servo cycle -------------
def test_ov_and_aff_gains_add_their_terms_to_the_output_every_cycle() -> None:
    """Each cycle's output, from the loop's own measured positions and the demand:
    P e + D (e - e_prev) + VFF v + AFF (v - v_prev) + OV (p - p_prev) (the pages' terms),
    in DAC_OUT's units (shared output / 16)."""
    p_gain, d_gain, vff, aff, ov = 8.0, 120.0, 3.0, 50.0, -30.0
    trio = mc405(f"ATYPE=77: P_GAIN={p_gain}: D_GAIN={d_gain}: VFF_GAIN={vff}: "
                 f"AFF_GAIN={aff}: OV_GAIN={ov}: SERVO=ON: WDOG=ON: SPEED=2000: "
                 "ACCEL=40000: DECEL=40000")
    at(trio, 10)
    trio.send("MOVE(300)")
    m = trio.machine
    loop = m.axes[0].servo
    assert loop is not None
    history = []  # (demand, measured) on each cycle before it runs
    checked = 0
    for tick in range(m.tick, m.tick + 120):
        at(trio, tick)
        history.append((m.demand(0), loop.p))
        if len(history) >= 3:
            (r2, _), (r1, p1), (r0, p0) = history[-3], history[-2], history[-1]
            at(trio, tick + 1)
            e0, e1 = r0 - p0, r1 - p1
            v0, v1 = r0 - r1, r1 - r2
            expected = (p_gain * e0 + d_gain * (e0 - e1) + vff * v0 + aff * (v0 - v1)
                        + ov * (p0 - p1)) / 16.0
            assert abs(float(trio.machine.drive.following.dac_out(0)) - expected) < 1e-6, tick
            checked += 1 if v0 != v1 else 0
    assert checked >= 5  # the acceleration ramps were among the cycles checked


def test_s_ref_and_t_ref_are_the_dac_and_their_outs_dac_out() -> None:
    trio = mc405(OPEN, "S_REF=300")
    assert (trio.query("?DAC"), trio.query("?T_REF"), trio.query("?S_REF_OUT"),
            trio.query("?T_REF_OUT")) == ("300", "300", "300", "300")
    trio.send("T_REF=-700")
    assert (trio.query("?DAC"), trio.query("?DAC_OUT")) == ("-700", "-700")
    assert trio.send("S_REF_OUT=5")[0].startswith("!")  # read only, as DAC_OUT
    assert trio.query("?DAC") == "-700"


# ---- FE_LIMIT_MODE ---------------------------------------------------------------------
SERVO = ("ATYPE=77: P_GAIN=10: D_GAIN=160: SERVO=ON: WDOG=ON: SPEED=4000: ACCEL=40000: "
         "DECEL=40000")


STEP = "SPEED=40000: ACCEL=4e7: DECEL=4e7"  # a short move is a step of the demand


def _errors_at(mode: int, limit: float, distance: int, slices: int,
               profile: str = "SPEED=4000") -> int | None:
    """The tick of the motion error of a move with FE_LIMIT `limit` (None: none by 400)."""
    trio = mc405(SERVO, profile, f"FE_LIMIT={limit}: FE_LIMIT_MODE={mode}: ERRORMASK=268")
    trio.send(f"MOVE({distance})")
    while trio.machine.tick < 400:
        trio.advance(ticks=slices)
        if trio.query("?MOTION_ERROR") != "0":
            return None if slices > 1 else trio.machine.tick
    return None if trio.query("?MOTION_ERROR") == "0" else -1


def fe_by_tick(distance: int, ticks: int, profile: str = "SPEED=4000") -> list[float]:
    trio = mc405(SERVO, profile, f"MOVE({distance})")
    out = []
    for _ in range(ticks):
        trio.advance(ticks=1)
        out.append(float(trio.query("?FE")))
    return out


def test_fe_limit_mode_1_raises_the_error_one_cycle_later_whatever_the_slicing() -> None:
    """Along the ramp FE grows every cycle: mode 1 sees the second cycle beyond the limit
    one cycle after mode 0 sees the first."""
    first = _errors_at(0, 30, 8000, 1)
    assert first is not None and first > 50
    assert _errors_at(1, 30, 8000, 1) == first + 1
    whole = mc405(SERVO, "FE_LIMIT=30: FE_LIMIT_MODE=1: ERRORMASK=268", "MOVE(8000)")
    whole.advance(ticks=400)  # one stretch: the error found inside it
    stepped = mc405(SERVO, "FE_LIMIT=30: FE_LIMIT_MODE=1: ERRORMASK=268", "MOVE(8000)")
    stepped.advance(ticks=first + 1)
    for trio in (whole, stepped):
        assert (trio.query("?MOTION_ERROR"), trio.query("?AXISSTATUS")) == ("1", "256")
    assert stepped.query("?DPOS") == whole.query("?DPOS")  # stopped on the same cycle


def test_fe_limit_mode_1_ignores_a_single_cycle_beyond_the_limit() -> None:
    """A short, steep move's error peaks once: a limit just under the peak and above both
    its neighbours is passed on one cycle only."""
    fe = [abs(v) for v in fe_by_tick(60, 200, STEP)]
    peak = max(range(len(fe)), key=fe.__getitem__)
    neighbour = max(fe[peak - 1], fe[peak + 1], *fe[peak + 2:])
    assert fe[peak] - neighbour > 5.0  # room for a limit between them
    limit = (fe[peak] + neighbour) / 2
    assert _errors_at(0, limit, 60, 1, STEP) is not None
    assert _errors_at(1, limit, 60, 1, STEP) is None
    assert _errors_at(1, limit, 60, 400, STEP) is None
    assert mc405().send("FE_LIMIT_MODE=2") == ["! Parameter out of range"]

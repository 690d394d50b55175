"""Servo axes: the PID loop on the motor plant, through the command language."""

import math

import control
import numpy as np
import pytest

from maxk import MAXk
from maxk.firmware_model.motor import MotorPlant
from maxk.firmware_model.servo import DAC_LIMIT
from maxk.personalities.maxk import flags as F

TUNED = "KP100; KD400; KI40; KU400; KV680;"  # docs/servo.md: the default motor, tuned


def servo(gains: str = "", letter: str = "X") -> MAXk:
    board = MAXk()
    board.send(f"A{letter} PSM; LP0; {gains} CL1;")
    return board


def following_errors(board: MAXk, seconds: float, step: float = 0.01,
                     letter: str = "X") -> list[int]:
    """RP - RE sampled as a host polls it."""
    out = []
    for _ in range(round(seconds / step)):
        board.advance(step)
        out.append(int(board.query(f"A{letter} RP")) - int(board.query(f"A{letter} RE")))
    return out


def record(board: MAXk, seconds: float, letter: str = "X") -> list[tuple]:
    """Per-tick samples (tick, commanded, actual, v, w, error, dac)."""
    loop = board.board.axis(letter).servo
    loop.recorder = []
    board.advance(seconds)
    samples, loop.recorder = loop.recorder, None
    return samples


def test_psm_makes_a_servo_that_starts_open_loop():
    board = MAXk()
    board.send("AX PSM;")
    assert board.query("AX PS?") == "=M"
    assert board.query("AX ?PS") == "=M"
    assert board.query("AX CL?") == "off"
    assert board.query("AX ?PM") == "=off"
    assert board.query("AX ?KP") == "10"  # factory gains, manual 2.14
    assert board.query("AX ?KA") == "0"
    board.send("AX KP2.5")
    assert board.query("AX ?KP") == "2.5"
    assert board.query("AM;?KP;") == "2.5,,,,,,,"
    board.advance(1.0)
    assert board.query("AX RE") == "0"  # KO0 and static friction: nothing moves


def test_open_loop_ko_turns_the_motor_at_a_speed_proportional_to_it():
    """Manual 2.9 step 4: KO3277 is about 1 V; the motor turns, faster with more."""
    speeds = []
    for ko in (3277, 6554, -3277):
        board = MAXk()
        board.send(f"AX PSM; KO{ko};")
        board.advance(1.0)
        before = int(board.query("AX RE"))
        board.advance(0.5)
        speeds.append((int(board.query("AX RE")) - before) / 0.5)
    assert speeds[0] > 10_000
    assert speeds[1] == pytest.approx(2 * speeds[0], rel=0.05)
    assert speeds[2] == pytest.approx(-speeds[0], rel=0.01)
    board = MAXk()
    board.send("AX PSM; KO2000; LP0;")
    board.advance(0.2)
    assert int(board.query("AX RE")) > 0  # manual 2.9 step 5: RE positive, wiring right


def test_lp0_cl1_holds_position_against_a_load():
    board = servo(TUNED + " KO1000;")  # a constant disturbance the integrator must hold
    errors = following_errors(board, 2.0)
    assert max(abs(e) for e in errors[-50:]) == 0
    assert board.query("AX RP") == "0"


def test_the_manuals_tuning_check_rp_and_re_agree():
    """Manual 2.13: `AC100000;VL5000;MR64000;GO;` then RE and RP agree for tuned gains."""
    board = servo(TUNED)
    board.send("AX AC100000; VL5000; MR64000; GO; ID;")
    errors = following_errors(board, 13.5)
    assert board.done("X")
    assert board.query("AX RP") == "64000"
    assert board.query("AX RE") == "64000"
    assert max(abs(e) for e in errors) <= 1


def slew_error(gains: str) -> int:
    board = servo(gains)
    board.send("AX AC100000; VL5000; MR64000; GO;")
    board.advance(6.0)  # mid-slew
    return int(board.query("AX RP")) - int(board.query("AX RE"))


def test_raising_kp_lowers_the_following_error():
    errors = [slew_error(f"KP{kp}; KD0; KI0;") for kp in (1, 10, 100)]
    assert errors[0] > errors[1] > errors[2] > 0
    assert errors[0] == pytest.approx(10 * errors[1], rel=0.1)  # error ~ 1/KP


def overshoot(gains: str) -> float:
    board = servo(gains)
    board.advance(0.05)
    board.send("AX AC8000000; VL400000; MR200; GO;")
    samples = record(board, 0.3)
    return max(s[2] for s in samples) - 200


def test_too_much_kp_rings_and_kd_damps_it():
    assert overshoot("KP100; KD0; KI0;") < 5
    assert overshoot("KP2000; KD0; KI0;") > 20  # unstable: rings against the DAC limits
    assert overshoot("KP2000; KD2000; KI0;") < 1


def test_ki_and_ku_remove_the_long_term_error():
    def final_error(gains: str) -> int:
        board = servo(gains)
        board.send("AX AC100000; VL5000; MR6400; GO;")
        board.advance(4.0)
        return int(board.query("AX RP")) - int(board.query("AX RE"))

    assert abs(final_error("KP10; KD160; KI0;")) >= 2  # static friction holds it off
    assert final_error("KP10; KD160; KI40; KU400;") == 0
    assert abs(final_error("KP10; KD160; KI40; KU1;")) >= 2  # KU too small to reach


def test_kv_cuts_the_slew_error_and_ka_the_ramp_error():
    assert abs(slew_error("KP100; KD400; KI0; KV680;")) < slew_error("KP100; KD400; KI0;") / 4

    def ramp_error(gains: str) -> float:
        board = servo(gains)
        board.send("AX AC1000000; VL50000; MR64000; GO;")
        return max(abs(s[5]) for s in record(board, 0.04))

    assert ramp_error("KP100; KD400; KI0; KV680; KA20000;") < ramp_error(
        "KP100; KD400; KI0; KV680;") / 2


def test_the_dac_saturates_at_its_limits():
    board = servo("KP200; KD400; KI0;")
    board.send("AX AC8000000; VL4000000; MR30000; GO;")
    samples = record(board, 0.05)
    outputs = [s[6] for s in samples]
    assert max(outputs) == DAC_LIMIT
    assert all(abs(u) <= DAC_LIMIT for u in outputs)
    board.advance(1.0)
    assert board.query("AX RE") == "30000"  # it catches up once the profile ends


def test_following_error_over_32768_disables_the_pid():
    """Manual 2.13. The trip shows as the slip flag (doorbell bit 16+i, EA 'S'), CL? off,
    the trajectory stops and the queue is flushed; LP0;CL1; re-enables it."""
    board = servo("KP1; KD0; KI0;")
    heard = []
    board.board.add_flag_listener(heard.append)
    board.send("AX AC8000000; VL4000000; MR1000000; GO; ID;")
    board.advance(1.0)
    assert board.doorbell & (1 << F.SLIP_SHIFT)
    assert F.maxnet_event_bits(0, F.AXIS_SLIP) in heard
    assert board.query("AX CL?") == "off"
    assert board.query("AX EA")[1:3] == "DS"
    assert not board.done("X")  # the ID was flushed
    rp = int(board.query("AX RP"))
    assert rp < 1_000_000  # the trajectory stopped where it was
    board.advance(2.0)
    assert board.query("AX RP") == str(rp)
    board.send("AX RA; LP0; CL1;")
    assert board.query("AX CL?") == "on"
    assert board.query("AX EA")[1:3] == "EN"
    assert max(abs(e) for e in following_errors(board, 1.0)[-20:]) <= 1


def test_an_inverted_output_runs_away_until_the_trip():
    board = servo("SVP-;")
    board.send("AX MR100; GO;")
    board.advance(2.0)
    assert board.query("AX CL?") == "off"
    assert board.doorbell & (1 << F.SLIP_SHIFT)
    assert abs(int(board.query("AX RE"))) > 32768


def test_servo_and_stepper_axes_on_one_board():
    board = MAXk()
    board.send("AX PSM; LP0; " + TUNED + " CL1; AX VL5000; AC100000; MR10000; GO; ID;")
    board.send("AY VL5000; AC100000; MR10000; GO; ID;")
    board.send("AZ PSE; VL5000; AC100000; MR-10000; GO; ID;")
    assert board.run_until_done("X", "Y", "Z", timeout=5)
    assert board.tick == board.board.axis("Y").rest_since  # same profile, same end tick
    board.advance(0.5)
    assert board.query("AA RP") == "10000,10000,-10000,0,0,0,0,0"
    assert board.query("AA RE") == "10000,10000,-10000,0,0,0,0,0"
    assert board.query("AX QA") == "PDNN"


@pytest.mark.parametrize("script", [
    "LP0; CL1; AC100000; VL5000; MR6400; GO;",
    "LP0; KP40; KD300; KI40; KU40; CL1; AC200000; VL20000; MR20000; GO; MR-5000; GO;",
    "LP0; KP10; KD160; KV500; KA2000; CL1; AC100000; VL5000; MR6400; GO;",
    "LP0; KP10; KD160; CL1; JG3000; WT2458; JG-2000;",
    "KO3277;",
    "LP0; KP1; KD0; KI0; CL1; PN; AC100000; VL5000; MR6000; GO;",
])
def test_closed_form_jumps_agree_with_tick_by_tick_stepping(script):
    """The engine jumps over linear stretches; with a recorder attached it steps every
    tick. Both must give the same motor."""
    def run(tick_by_tick: bool) -> list[tuple[float, float]]:
        board = MAXk()
        board.send("AX PSM;")
        loop = board.board.axis("X").servo
        if tick_by_tick:
            loop.recorder = []
        board.send(f"AX {script}")
        states = []
        for _ in range(30):
            board.advance(0.05)
            states.append((loop.p, loop.w))
        return states

    for (p1, w1), (p2, w2) in zip(run(False), run(True), strict=True):
        assert p1 == pytest.approx(p2, abs=1e-3)
        assert w1 == pytest.approx(w2, abs=1e-2 + 1e-6 * abs(w2))


def test_servo_runs_are_deterministic():
    def replies() -> list[str]:
        board = servo("KP40; KD300; KI40; KU40;")
        out = []
        board.send("AX AC200000; VL20000; MR20000; GO; MR-5000; GO;")
        for _ in range(50):
            board.advance(0.017)
            out += board.send("AX RE; RP; EA;")
        return out

    assert replies() == replies()


def test_plant_is_the_python_control_transfer_function_discretized():
    plant = MotorPlant()
    g, a, friction = plant.coefficients()
    tf = plant.transfer_function()
    assert sorted(np.real(control.poles(tf))) == pytest.approx(sorted([0.0, -a]))
    period = 1 / 8192
    a11, a12, a21, a22, b1, b2 = plant.discrete(period)
    sampled = control.c2d(tf, period, method="zoh")
    # same discrete poles as c2d of the transfer function: 1 and exp(-a T)
    assert sorted(np.real(control.poles(sampled))) == pytest.approx(
        sorted([a22, a11]), rel=1e-9)
    assert a22 == pytest.approx(math.exp(-a * period))
    assert friction > 0


def test_update_rate_change_keeps_the_loop_running():
    board = MAXk()
    board.send("#UR2048; AX PSM; LP0; " + TUNED + " CL1; AC100000; VL5000; MR6400; GO; ID;")
    assert board.run_until_done("X", timeout=5)
    board.advance(4.0)  # the gains act per tick: at a quarter of the rate KI is slower
    assert board.query("AX RE") == "6400"


def test_motor_parameters_come_from_the_world():
    slow = MAXk()
    slow.set_motor("X", inertia=5e-5)  # ten times the inertia: a slower start in open loop
    fast = MAXk()
    for board in (slow, fast):
        board.send("AX PSM; KO3277;")
        board.advance(0.002)
    assert int(slow.query("AX RE")) < int(fast.query("AX RE"))
    with pytest.raises(ValueError):
        slow.set_motor("X", amplifier="magic")


def test_counter_changes_do_not_kick_the_filter():
    """LP/LPE, #UR and homing move the counters, CL1 on a running loop changes nothing:
    no derivative or feed-forward kick reaches the DAC (review findings)."""
    board = servo(TUNED + " LPE1000;")
    board.advance(2.0)
    loop = board.board.axis("X").servo
    loop.recorder = []
    board.send("#UR2048")
    board.board.advance(3)
    assert max(abs(r[6]) for r in loop.recorder) < 1000
    board = servo(TUNED + " KA20000; AC100000; VL20000; JG20000;")
    board.advance(1.0)
    loop = board.board.axis("X").servo
    loop.recorder = []
    board.send("AX CL1; LP0;")
    board.board.advance(4)
    outputs = [r[6] for r in loop.recorder]
    assert max(outputs) - min(outputs) < 50


def test_homing_a_servo_loads_the_counters_without_a_kick():
    board = MAXk()
    board.set_home("X", 50_000, 50_100)
    board.send("AX PSM; LP0; " + TUNED + " CL1; AC200000; VL20000; HM-300000;")
    loop = board.board.axis("X").servo
    board.advance(2.0)
    loop.recorder = []
    board.advance(1.5)
    assert board.board.axis("X").homing is None
    assert max(abs(r[6]) for r in loop.recorder) < 5000
    assert int(board.query("AX RP")) < -300_000 + 2000  # loaded at home, then ramped down


def _open_loop_counts(setup: str) -> list[int]:
    """RE every 50 ms of an open-loop servo axis holding a constant output (KO)."""
    board = MAXk()
    board.send(f"AX PSM; LP0; {setup} CL0;")
    counts = []
    for _ in range(20):
        board.advance(0.05)
        counts.append(int(board.query("AX RE")))
    return counts


def test_an_inverted_output_driven_the_other_way_moves_the_motor_alike():
    """SVP- only inverts the DAC: the motor cannot tell SVP- with KO -u from SVP+ with
    KO +u, friction included (it opposes the motor's motion either way)."""
    normal = _open_loop_counts("SVP+; KO6000;")
    inverted = _open_loop_counts("SVP-; KO-6000;")
    assert normal[-1] > 0  # 1.8 V on the default motor moves it forward
    assert inverted == normal

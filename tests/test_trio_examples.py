"""The seed's three PWM examples, downloaded as atrio would and run on the fake machine.

The fake moves at constant speed (no ramps), so VP_SPEED is SPEED while a move runs:
enough to check every mark the examples compute and every gate toggle of example 3.
"""

from __future__ import annotations

from tests.trio_helpers import EXAMPLE_1, EXAMPLE_2, EXAMPLE_3, Rig


def start(text: str, name: str) -> Rig:
    rig = Rig()
    rig.load(name, text)
    assert rig.command(f'RUN "{name}"') == b""
    return rig


def test_example_1_mark_follows_path_speed_limited_at_500() -> None:
    rig = start(EXAMPLE_1, "EX1")
    pwm = rig.machine.pwm[4]
    assert rig.cycles(11) == b""  # WA(10): PWM_CONTROL(2,...) runs on cycle 11
    assert (pwm.mode, pwm.multiplier, pwm.offset, pwm.limit, pwm.links) == (2, 0.1, 50, 500,
                                                                           (0, None))
    rig.cycles(1)
    assert rig.machine.vp_speed[0] == 5000
    assert pwm.mark == 500  # 5000 * 0.1 + 50 = 550, limited to 500
    assert rig.command("?PWM_MARK AXIS(4)") == b"500"
    assert pwm.duty(wdog=rig.machine.system["WDOG"] != 0,
                    atype=int(rig.machine.axis_params[4]["ATYPE"])) == 0.5
    rig.cycles(8001 - rig.machine.tick)  # the square: 4 x 10000 at 5000/s from tick 2
    assert (rig.machine.dpos[0], rig.machine.dpos[1], pwm.mark) == (0.0, 0.0, 500)
    rig.cycles(1)
    assert (rig.machine.vp_speed[0], pwm.mark) == (0.0, 50)
    assert rig.command("PROCESS") == b""  # the program has ended; the link stays


def test_example_1_comment_speed_2000_gives_250() -> None:
    rig = Rig()
    rig.load("EX1", EXAMPLE_1)
    rig.command("!EX1,1RSPEED=2000")
    rig.command('RUN "EX1"')
    rig.cycles(12)
    assert rig.machine.vp_speed[0] == 2000
    assert rig.machine.pwm[4].mark == 250


def test_example_2_mark_from_speed_and_the_cambox_profile() -> None:
    rig = start(EXAMPLE_2, "EX2")
    machine, pwm = rig.machine, rig.machine.pwm[4]
    seen = []
    for _ in range(2 * 4012 + 50):  # two passes of the WHILE loop and a bit
        linked = pwm.links == (0, 9)  # before the cycle: the machine reloads the mark first
        rig.cycles(1)
        amplitude, speed = machine.dpos[9], machine.vp_speed[0]
        if linked:
            assert pwm.mark == min(500, int(speed * amplitude * (1 / 10000) + 50))
        seen.append((machine.dpos[8], amplitude, pwm.mark))
    # the profile: 0 for the first 15000 of the 40000 path, up to 1000 by 20000, ...
    by_path = {round(p): (a, m) for p, a, m in seen[:4000]}
    assert by_path[10000] == (0.0, 50)
    assert by_path[17500][0] == 500.0 and by_path[17500][1] == 500  # 550 limited
    assert by_path[25000] == (1000.0, 500)
    assert by_path[32500][0] == 500.0
    assert by_path[37500] == (0.0, 50)
    assert max(p for p, _, _ in seen) == 40000.0  # CONNPATH: axis 8 runs the path length
    assert [round(p) for p, _, _ in seen[4000:4030]].count(0) >= 1  # DEFPOS(0) AXIS(8)
    assert max(m for _, _, m in seen[4100:]) == 500  # the second pass again


def test_example_3_fifo_contents_and_gate_toggles() -> None:
    rig = start(EXAMPLE_3, "EX3")
    machine, pwm = rig.machine, rig.machine.pwm[0]
    rig.cycles(1)
    assert [e.position / 16 for e in pwm.pending_gates()] == [110, 115, 195, 220]
    assert [(e.greater, e.level) for e in pwm.pending_gates()] == [
        (True, True), (True, False), (True, True), (True, False)]
    assert (pwm.mode, pwm.gating, pwm.mark, pwm.encoder) == (1, True, 400, 0)
    duty = []
    for _ in range(620):
        rig.cycles(1)
        duty.append((machine.tick, round(machine.dpos[0], 6),
                     pwm.duty(machine.system["WDOG"] != 0, int(machine.axis_params[0]["ATYPE"]))))
    # out at SPEED 1000 units/s from tick 2 (one unit per cycle), back from tick 302
    on = [(t, d) for t, d, x in duty if x == 0.4]
    assert {d for _, d in on} == {*range(111, 116), *range(196, 221)} | {
        *range(110, 115), *range(195, 220)}
    assert machine.gate_events[:8] == [
        (112, 0, True), (117, 0, False), (197, 0, True), (222, 0, False),  # GT, out
        (382, 0, True), (407, 0, False), (487, 0, True), (492, 0, False),  # LT, back
    ]
    assert pwm.encoder == round(machine.dpos[0] * 16)
    assert rig.command("?PWM_ENCODER AXIS(0)").decode() == str(pwm.encoder)


def test_example_3_defpos_does_not_move_pwm_encoder() -> None:
    rig = start(EXAMPLE_3, "EX3")
    rig.cycles(50)
    before = rig.machine.pwm[0].encoder
    rig.command("DEFPOS(1000) AXIS(0)")
    assert rig.machine.pwm[0].encoder == before
    rig.command("PWM_CONTROL(6) AXIS(0)")
    assert rig.command("?PWM_ENCODER AXIS(0)") == b"0"

"""The compiled servo kernel against the Python loop it replaces.

The Python loop (`ServoLoop._scalar_python`) is the reference. With the kernel built, the
engine steps short pieces, arcs and nonlinear stretches through it; here the same
scenarios run once with the kernel and once with every one of those steps taken by the
Python loop instead (the same choice of stretches), and the motors must agree: the same
RE replies, positions to 1e-9 counts (they agree to the bit: the kernel does the same
arithmetic in the same order). The compiled half is skipped where no kernel was built.

The kernel also takes a profile's slews in closed form (its jump): those comparisons switch
the jumps off, and the jumps are held against the kernel's own steps (same replies, same
ticks, positions within a micro-count).
"""

from __future__ import annotations

import math
from array import array

import pytest

from maxk import MAXk
from maxk.firmware_model import servo_kernel
from maxk.firmware_model.motor import MotorPlant
from maxk.firmware_model.servo import ServoLoop

TUNED = "KP100; KD400; KI40; KU400; KV680;"  # docs/servo.md: the default motor, tuned

SCENARIOS = {
    "short moves": ("MAXk-4000", "AX PSM; LP0; " + TUNED + " CL1; AC500000; VL50000; "
                    "MR7001; GO; MR-5003; GO; MR333; GO;", "X"),
    "factory gains, ramp and slew": ("MAXk-4000", "AX PSM; LP0; CL1; AC100000; VL5000; "
                                     "MR6400; GO;", "X"),
    "feed-forward, S-curve": ("MAXk-4000", "AX PSM; LP0; KP10; KD160; KV500; KA2000; CL1; "
                              "SC; AC100000; VL5000; MR6400; GO;", "X"),
    "cosine ramps, parabolic": ("MAXk-4000", "AA PSM,M; LP0,0; KP100,100; KD400,400; "
                                "CL1,1; AX CN; AC300000; VL30000; MR20000; GO; "
                                "AY PN; AC300000; VL30000; MR-20000; GO;", "XY"),
    "jog (kernel for a second, then closed form)": ("MAXk-4000", "AX PSM; LP0; KP10; "
                                                    "KD160; CL1; AC50000; JG3000;", "X"),
    "open loop KO": ("MAXk-4000", "AX PSM; KO3277;", "X"),
    "saturated DAC": ("MAXk-4000", "AX PSM; LP0; KP200; KD400; KI0; CL1; AC8000000; "
                      "VL4000000; MR30000; GO;", "X"),
    "following-error trip": ("MAXk-4000", "AX PSM; LP0; KP1; KD0; KI0; CL1; AC8000000; "
                             "VL4000000; MR1000000; GO;", "X"),
    "three axes, one trips": ("MAXk-4000", "AA PSM,M,M; LP0,0,0; KP1,100,10; KD0,400,160; "
                              "KI0,40,1; KU400,400,400; KV0,680,0; CL1,1,1; "
                              "AC8000000,500000,100000; VL4000000,50000,5000; "
                              "MR1000000,7001,-3000; GO;", "XYZ"),
    "inverted output": ("MAXk-4000", "AX PSM; LP0; SVP-; CL1; MR100; GO;", "X"),
    "counters moved mid-move": ("MAXk-4000", "AX PSM; LP0; " + TUNED + " CL1; AC200000; "
                                "VL20000; MR20000; GO; WT200; LP5000; LPE4000;", "X"),
    "circle": ("MAXk-4000", "AA PSM,M; LP0,0; KP100,100; KD400,400; KI40,40; KU400,400; "
               "KV680,680; CL1,1; AA; VA200000; VV20000,20000; VP0,0; VC0,2000,-270; "
               "VP1000,1000; VC0,0,360; VE;", "XY"),
}


def run(scenario: str, seconds: float = 1.5, step: float = 0.02) -> tuple[list, list]:
    """RE and EA replies sampled as a host polls, and the loops' exact states."""
    model, script, letters = SCENARIOS[scenario]
    board = MAXk(model)
    board.send(script)
    replies, states = [], []
    for _ in range(round(seconds / step)):
        board.advance(step)
        replies += board.send("AA RE; AX EA;")
        states.append([(loop.p, loop.w, loop.s, loop.q, loop.dac, loop.tick)
                       for letter in letters
                       if (loop := board.board.axis(letter).servo) is not None])
    assert not board.command_error, board.last_error
    return replies, states


def python_steps(monkeypatch: pytest.MonkeyPatch) -> None:
    """Take every tick-by-tick stretch with the Python loop, keeping the compiled
    build's choice of stretches."""
    def scalar(self, axis, board, matrices, friction, gains, count, kernel=None):
        self._cache = None
        self._scalar_python(axis, board, matrices, friction, gains, count)

    monkeypatch.setattr(ServoLoop, "_scalar", scalar)
    monkeypatch.setattr(servo_kernel, "STEP_AXES", None)  # the compiled pass over a board


def refuse(*args: object) -> int:
    raise AssertionError("the reference run must not call the kernel")


compiled = pytest.mark.skipif(servo_kernel.STEP is None,
                              reason="the compiled servo kernel was not built")


@compiled
@pytest.mark.parametrize("scenario", list(SCENARIOS))
def test_the_kernel_steps_exactly_as_the_python_loop(scenario, monkeypatch):
    monkeypatch.setattr(servo_kernel, "JUMPS", False)  # every tick stepped
    replies, states = run(scenario)
    with monkeypatch.context() as patch:
        python_steps(patch)
        patch.setattr(servo_kernel, "STEP", refuse)
        reference_replies, reference_states = run(scenario)
    assert replies == reference_replies
    for ours, theirs in zip(states, reference_states, strict=True):
        for a, b in zip(ours, theirs, strict=True):
            assert a[5] == b[5]  # the same tick, the same trip
            assert all(math.isclose(x, y, rel_tol=0.0, abs_tol=1e-9) for x, y in
                       zip(a[:5], b[:5], strict=True)), (a, b)


@compiled
def test_the_scenarios_are_mostly_stepped_by_the_kernel(monkeypatch):
    """The comparison above means something only if the kernel did the stepping."""
    ticks = []
    real = servo_kernel.STEP
    assert real is not None

    def counting(state, params, program, tick, count):
        done = real(state, params, program, tick, count)
        ticks.append(done if done >= 0 else -done - 1)
        return done

    monkeypatch.setattr(servo_kernel, "STEP", counting)
    monkeypatch.setattr(servo_kernel, "STEP_AXES", None)
    run("circle")
    assert sum(ticks) > 0.9 * 2 * 1.5 * 8192


@compiled
def test_a_pacing_pass_steps_a_boards_axes_in_one_compiled_call(monkeypatch):
    """Short advances (a door's pacing) inside moves: the compiled pass steps every axis;
    the Python loop is not called for any."""
    board = MAXk("MAXk-A000")
    board.send("AA; PSM,M,M,M,M,M,M,M,M,M; LP0,0,0,0,0,0,0,0,0,0; "
               "CL1,1,1,1,1,1,1,1,1,1; VL5000,5000,5000,5000,5000,5000,5000,5000,5000,5000; "
               "MR3000,3000,3000,3000,3000,3000,3000,3000,3000,3000; GO;")
    board.advance(0.1)  # into the slew
    advanced = []
    real = ServoLoop.advance
    monkeypatch.setattr(ServoLoop, "advance", lambda self, axis, host, to: (
        advanced.append(axis.index), real(self, axis, host, to)))
    start = board.tick
    for _ in range(20):
        board.advance(ticks=8)
    assert advanced == []
    assert board.tick == start + 20 * 8
    assert {loop.tick for a in board.board.axes if (loop := a.servo)} == {board.tick}
    # the world changed under X (a heavier load): its loop remakes its decisions
    board.board.world.axes[0].motor = MotorPlant(inertia=6e-6)
    board.advance(ticks=8)
    assert advanced == [0]


def paced(scenario: str, passes: int, ticks: int) -> tuple[list, list]:
    """RE and EA replies and the loops' exact states (with trip tick and flag) after each of
    `passes` short advances of `ticks` ticks: a door's pacing, the compiled pass's case."""
    model, script, letters = SCENARIOS[scenario]
    board = MAXk(model)
    board.send(script)
    replies, states = [], []
    for _ in range(passes):
        board.advance(ticks=ticks)
        replies += board.send("AA RE; AX EA;")
        states.append([(loop.p, loop.w, loop.s, loop.q, loop.dac, loop.tick, loop.trip_tick,
                        loop.tripped)
                       for letter in letters
                       if (loop := board.board.axis(letter).servo) is not None])
    assert not board.command_error, board.last_error
    return replies, states


@compiled
def test_a_loop_tripping_inside_a_compiled_pass_stops_there_and_the_others_go_on(monkeypatch):
    """Three axes stepped together by one compiled pass (`step_axes`), X's following error
    tripping on a tick inside the pass: X stops on that tick, Y and Z are stepped to the
    pass's end, and every state after every pass is the Python loop's to the bit."""
    real = servo_kernel.STEP_AXES
    assert real is not None
    monkeypatch.setattr(servo_kernel, "JUMPS", False)  # every tick stepped
    trips = []  # (the pass's end, loops it stepped, (tick, trip tick) of each after it)

    def watching(axes, limit):
        before = [(a.servo.tick, a.servo.trip_tick) for a in axes]
        rest = real(axes, limit)
        after = [(a.servo.tick, a.servo.trip_tick) for a in axes]
        stepped = sum(b[0] != a[0] for b, a in zip(before, after, strict=True))
        if any(b[1] is None and a[1] is not None for b, a in zip(before, after, strict=True)):
            trips.append((limit, stepped, after))
        return rest

    monkeypatch.setattr(servo_kernel, "STEP_AXES", watching)
    replies, states = paced("three axes, one trips", 200, 5)
    [(limit, stepped, after)] = trips  # X tripped once, inside a compiled pass
    assert stepped == 3
    (x_tick, x_trip), (y_tick, y_trip), (z_tick, z_trip) = after
    assert x_trip == x_tick < limit  # stopped on its trip tick, mid-pass
    assert (y_tick, y_trip, z_tick, z_trip) == (limit, None, limit, None)
    with monkeypatch.context() as patch:
        python_steps(patch)
        patch.setattr(servo_kernel, "STEP", refuse)
        reference_replies, reference_states = paced("three axes, one trips", 200, 5)
    assert replies == reference_replies
    assert [loop[7] for loop in reference_states[-1]] == [True, False, False]
    for ours, theirs in zip(states, reference_states, strict=True):
        for a, b in zip(ours, theirs, strict=True):
            assert a[5:] == b[5:]  # the same tick, the same trip
            assert all(math.isclose(x, y, rel_tol=0.0, abs_tol=1e-9) for x, y in
                       zip(a[:5], b[:5], strict=True)), (a, b)


SLEWS = {
    "long slews, tuned": ("MAXk-4000", "AX PSM; LP0; " + TUNED + " CL1; AC500000; VL50000; "
                          "MR64000; GO; MR-20000; GO;", "X"),
    "long slew, factory gains": ("MAXk-4000", "AX PSM; LP0; CL1; AC100000; VL20000; "
                                 "MR30000; GO;", "X"),
    "slew saturating the DAC": ("MAXk-4000", "AX PSM; LP0; KP200; KD400; KI0; CL1; "
                                "AC4000000; VL400000; MR300000; GO;", "X"),
    "slew, the integral capped": ("MAXk-4000", "AX PSM; LP0; KP100; KD400; "
                                   "KI400; KU20; KV680; CL1; AC500000; VL50000; "
                                   "MR-40000; GO;", "X"),
}


@compiled
@pytest.mark.parametrize("scenario", list(SCENARIOS) + list(SLEWS))
@pytest.mark.parametrize("step", [0.02, 0.25])
def test_the_kernels_jumps_agree_with_its_steps(scenario, step, monkeypatch):
    """The closed form over a slew against stepping every tick of it: the same replies,
    the same ticks, the loop's state within a micro-count (rounding, not a different
    loop: the jump is taken only where a bound keeps the loop linear)."""
    monkeypatch.setitem(SCENARIOS, scenario, {**SCENARIOS, **SLEWS}[scenario])
    replies, states = run(scenario, 2.0, step)
    monkeypatch.setattr(servo_kernel, "JUMPS", False)
    stepped_replies, stepped_states = run(scenario, 2.0, step)
    assert replies == stepped_replies
    for ours, theirs in zip(states, stepped_states, strict=True):
        for a, b in zip(ours, theirs, strict=True):
            assert a[5] == b[5]
            assert all(math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-6) for x, y in
                       zip(a[:5], b[:5], strict=True)), (a, b)


@compiled
def test_the_kernel_jumps_over_a_slew(monkeypatch):
    """The jump is taken (its rounding shows in the last bits against stepping), and the
    state after it is the stepped loop's to a micro-count, mid-slew and after the move."""
    monkeypatch.setitem(SCENARIOS, "long slews, tuned", SLEWS["long slews, tuned"])
    _, states = run("long slews, tuned", 2.0, 0.25)
    monkeypatch.setattr(servo_kernel, "JUMPS", False)
    _, stepped = run("long slews, tuned", 2.0, 0.25)
    assert states[1] != stepped[1]  # 0.5 s: mid-slew, jumped
    [(p, w, *_)] = states[1]
    [(p_stepped, w_stepped, *_)] = stepped[1]
    assert abs(p - p_stepped) < 1e-6 and abs(w - w_stepped) < 1e-6
    assert 20000 < p < 30000  # 0.05 s of ramp, then 50,000 counts/s


@compiled
@pytest.mark.parametrize("scenario", ["short moves", "cosine ramps, parabolic", "circle",
                                      "following-error trip"])
def test_without_the_kernel_the_replies_are_the_same(scenario, monkeypatch):
    """A build without a compiler jumps more stretches in closed form (which rounds
    differently in the last bits) but answers the host the same."""
    replies, _ = run(scenario)
    monkeypatch.setattr(servo_kernel, "STEP", None)
    fallback, _ = run(scenario)
    assert replies == fallback


@compiled
def test_the_kernel_refuses_what_is_not_a_description():
    step = servo_kernel.STEP
    assert step is not None
    state = array("d", [0.0] * servo_kernel.STATE_SIZE)
    params = servo_kernel.params((1.0, 0.0, 0.0, 1.0, 0.0, 0.0), 0.0, 1.0, 0.0, 0.0, 0.0,
                                 0.0, 0.0, 0.0, 0.0, 0)
    rest = servo_kernel.program(None, 5, 0, None, 1 / 8192)
    assert params is not None and rest is not None
    assert step(state, params, rest, 0, 3) == 3
    with pytest.raises(ValueError):
        step(state, params, array("d", [7.0] * 20), 0, 1)  # no such kind
    with pytest.raises(ValueError):
        step(array("d", [0.0]), params, rest, 0, 1)  # state too short
    with pytest.raises(ValueError):
        step(state, params, array("f", [0.0] * 20), 0, 1)  # not doubles
    assert step(state, params, rest, 0, 0) == 0


# ---- the plant: built once per parameter set, imported only for servos --------------------
def test_a_stepper_only_session_never_imports_python_control():
    """python-control takes seconds to import; a board without servo axes never pays it."""
    import subprocess
    import sys
    from pathlib import Path

    code = ("import sys, maxk; b = maxk.MAXk('MAXk-A000'); b.send('AA; MR100,200; GO; ID;'); "
            "b.advance(1.0); print(b.query('AA RP')[:7], 'control' in sys.modules, "
            "'scipy' in sys.modules)")
    root = str(Path(__file__).resolve().parent.parent)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={"PYTHONPATH": root, "PATH": ""}, check=True, cwd=root)
    assert out.stdout.split() == ["100,200", "False", "False"]


def test_the_plant_is_discretized_once_for_every_board(monkeypatch):
    """Sixteen boards of ten servo axes with the same motor and update rate share one
    c2d: python-control runs once per parameter set, not per axis or per board."""
    import control

    from maxk.firmware_model import motor

    calls = []
    real = control.c2d
    monkeypatch.setattr(control, "c2d", lambda *a, **k: calls.append(a) or real(*a, **k))
    motor._discretize.cache_clear()
    boards = []
    for _ in range(16):
        board = MAXk("MAXk-A000")
        board.send("AA; PSM,M,M,M,M,M,M,M,M,M; LP0,0,0,0,0,0,0,0,0,0; CL1,1,1,1,1,1,1,1,1,1;")
        board.advance(0.01)
        boards.append(board)
    assert len(calls) == 1
    boards[0].send("AX #UR4096;")  # another update rate: another discretization
    boards[0].advance(0.01)
    assert len(calls) == 2

"""The compiled servo kernel: loading it, and describing a loop's inputs to it.

`_servo_kernel.c` steps a servo loop tick by tick with exactly the arithmetic of the
Python loop (`ServoLoop._scalar_python`), about 400 times faster, so the engine steps
short moves, arcs and nonlinear stretches instead of solving them in closed form. It is
built by ``pip install -e .`` where a C compiler exists; without one (or with
``MAXK_SERVO_KERNEL=python`` in the environment) `STEP` is None and the servo runs its
Python loop and closed form as before: the same commands, slower.

What the kernel reads is plain arrays of doubles: the loop's state (`STATE` slots, held
by the loop itself), its parameters (gains, plant, friction, encoder offset) and a
*program*: the commanded position as a motion's description (a profile's phases, or a
contour's pieces and segments for one axis). Anything it cannot describe (another kind
of motion, counts beyond 2**53) gets no program, and the Python loop steps it.

Given the closed loop's modes (servo.py's `_kernel_modes`, after the parameters), the
kernel also takes a profile's slews and linear ramps in closed form where a bound keeps
the loop linear (`_servo_kernel.c`, "the closed-form jump"): not the Python loop's bits
there, but within rounding of them; `JUMPS` off, it steps every tick.
"""

from __future__ import annotations

import math
import os
from array import array
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

from maxk.firmware_model.path import ContourMotion
from maxk.firmware_model.profiles import Motion, RampShape

if TYPE_CHECKING:
    from maxk.firmware_model.motion import MotionPlan

StepFunction = Callable[[array, array, array, int, int], int]
StepAxesFunction = Callable[[Sequence[Any], int], list[Any]]


def _load() -> tuple[StepFunction | None, StepAxesFunction | None]:
    if os.environ.get("MAXK_SERVO_KERNEL", "").lower() == "python":
        return None, None
    try:
        from maxk.firmware_model import _servo_kernel
    except ImportError:
        return None, None
    return _servo_kernel.step, _servo_kernel.step_axes


STEP, STEP_AXES = _load()
"""The compiled step of one loop and the compiled pass over a board's servo axes, or
None (no compiler at install time, or switched off)."""

JUMPS = os.environ.get("MAXK_SERVO_JUMPS", "1") != "0"
"""Whether the kernel takes a profile's slews in closed form (its `jump`: the closed
loop's modes ride along in the parameters) instead of stepping every tick; read when a
loop's parameters are made. The tests that compare the kernel's steps bit for bit with
the Python loop switch it off."""

# the state's slots (the C enum's order)
# annotated one by one: mypy then knows their type wherever an import cycle puts this
# module (setup.py's mypyc build checks these modules without a cache)
P: int = 0
W: int = 1
S: int = 2
Q: int = 3
DAC: int = 4
RPREV: int = 5
RPREV2: int = 6
HAS_PREV: int = 7
HAS_PREV2: int = 8
CLOSED: int = 9
TRIPPED: int = 10
STUCK: int = 11
STATE_SIZE = 12
PARAM_SIZE = 17  # the parameters before the closed loop's modes (the C enum's)

KIND_REST, KIND_PROFILE, KIND_CONTOUR, KIND_CONTOUR_JERK = 0, 1, 2, 3
_SHAPES = {RampShape.LINEAR: 0.0, RampShape.PARABOLIC: 1.0, RampShape.SCURVE: 2.0,
           RampShape.COSINE: 3.0}
_EXACT = float(2 ** 53)  # integers beyond this are not exact doubles


def params(matrices: tuple[float, ...], friction: float, kp: float, kd: float,
           ki_per_tick: float, kv: float, ka: float, kf: float, ko: float, cap: float,
           encoder_offset: int, polarity: int = 1,
           modes: Sequence[float] = ()) -> array | None:
    """The filter and plant as the kernel reads them (None: offset not exact). `polarity`
    -1: the output is inverted (the matrices' b terms negated), so a moving motor's
    friction acts along -sign(w) in drive terms. `modes`: the closed loop's modal
    decomposition as `_servo_kernel.c`'s jump reads it (servo.py's `_kernel_modes`);
    empty: the kernel steps every tick."""
    if abs(encoder_offset) >= _EXACT:
        return None
    return array("d", (*matrices, friction, kp, kd, ki_per_tick, kv, ka, kf, ko, cap,
                       float(encoder_offset), -1.0 if polarity < 0 else 1.0, *modes))


def program(motion: MotionPlan | None, base: int, motion_start: int,
            motion_end: int | None, period: float) -> array | None:
    """The commanded position ``base + motion.offset((tick - motion_start) * period)``
    (``base + final_offset`` from motion_end on) as the kernel evaluates it; None for a
    motion it does not know."""
    if abs(base) >= _EXACT or abs(motion_start) >= _EXACT:
        return None
    if motion is None:
        return array("d", (KIND_REST, base) + (0.0,) * 12)
    final = motion.final_offset
    end_time = motion.end_time
    if abs(final) >= _EXACT or abs(base + final) >= _EXACT:
        return None
    described = _described(motion)
    if described is None:
        return None
    kind, counts, body = described
    return array("d", (kind, float(base), float(motion_start),
                       float(motion_end) if motion_end is not None else 0.0,
                       1.0 if motion_end is not None else 0.0, period, float(final),
                       end_time if end_time is not None else 0.0,
                       1.0 if end_time is not None else 0.0, *counts)) + body


_DESCRIBED: dict[int, tuple[MotionPlan, tuple[float, tuple[float, ...], array] | None]] = {}
"""Profile motions' descriptions by id (the motion held, so its id is not reused while
here): a board's moves recur (their plans are memoised), and only the header changes from
one to the next. Not contours: their plan is extended as the path gets made."""
_DESCRIBED_MAX = 256


def _described(motion: MotionPlan) -> tuple[float, tuple[float, ...], array] | None:
    """(kind, the header's counts and geometry, the body) of a motion; None if the kernel
    does not know it."""
    if type(motion) is not Motion:
        return _describe(motion)  # a contour's plan grows as the path gets made: anew
    held = _DESCRIBED.get(id(motion))
    if held is not None and held[0] is motion:
        return held[1]
    if len(_DESCRIBED) >= _DESCRIBED_MAX:
        _DESCRIBED.clear()
    described = _describe(motion)
    _DESCRIBED[id(motion)] = (motion, described)
    return described


def _describe(motion: MotionPlan) -> tuple[float, tuple[float, ...], array] | None:
    kind = type(motion)
    body: list[float] = []
    if kind is Motion:
        assert isinstance(motion, Motion)
        if any(ph.param is not None for ph in motion.phases):
            return None  # PN/SS/PR curves: the kernel knows only the factory ones
        for ph in motion.phases:
            body += (ph.t0, ph.duration, ph.s0, ph.v1, ph.v2, float(ph.direction),
                     _SHAPES[ph.shape], 1.0 if ph.mirrored else 0.0)
        return (KIND_PROFILE, (float(len(motion.phases)), 0.0, 0.0, 0.0, 0.0),
                array("d", body))
    if kind is ContourMotion:
        assert isinstance(motion, ContourMotion)
        plan, k = motion.plan, motion.k
        if motion.scale != 1.0:
            return None  # a plan in user units (MM4005): the kernel knows counts only
        jerked = plan.jerked  # S-ramps (path_scurve.py): a piece has one more value
        for pc in plan.pieces:
            body += (pc.t0, pc.duration, pc.s0, pc.v0, pc.a)
            if jerked:
                body.append(pc.j)
        for seg in plan.segments:
            if seg.frame:
                return None  # an arc in 3D (MSPHERICAL): the kernel knows plane arcs only
            values = (float(seg.start[k]), seg.unit[k], float(seg.end[k]))
            if not all(math.isfinite(v) and abs(v) < _EXACT for v in values):
                return None
            body += (seg.s0, seg.length, 1.0 if seg.is_arc else 0.0, *values, seg.cx,
                     seg.cy, seg.radius, seg.theta0, seg.turn)
        if not plan.segments:
            return None
        return (KIND_CONTOUR_JERK if jerked else KIND_CONTOUR,
                (float(len(plan.pieces)), float(len(plan.segments)), float(k),
                 float(motion.origin), plan.s_end), array("d", body))
    return None

"""Stepper velocity profiles in closed form.

A motion is a short list of phases (ramp or constant velocity). Position and velocity
are functions of time, so the tick engine can jump straight to the next event instead
of stepping every tick, and a point-to-point move lands exactly on its target.

Ramp shapes: the velocity during a ramp from v1 to v2 over a time T is
``v1 + (v2 - v1) * f(t / T)`` for a normalised shape ``f`` with ``f(0) = 0`` and
``f(1) = 1``. The programmed acceleration is the *peak* acceleration of the ramp, so a
ramp lasts ``T = k * |v2 - v1| / a`` where ``k = max f'``. The manual names the shapes
(linear, parabolic, S-curve, cosine/custom) but not their curves; these are our choices,
recorded in docs/not-modelled.md and the command table:

- linear: ``f = u`` (k = 1): trapezoid or triangle;
- parabolic: ``f = 1 - (1 - u)^2`` (k = 2): the acceleration is highest at low speed and
  falls to zero at the top, the way a stepper's torque falls with speed; a deceleration
  ramp is the mirror image in time;
- S-curve: ``f = 2u^2`` then ``1 - 2(1 - u)^2`` (k = 2): jerk-limited, acceleration peaks
  mid-ramp;
- cosine: ``f = (1 - cos(pi u)) / 2`` (k = pi / 2).

Shape parameters (``param``, None for the factory curve above; our decisions, recorded
in the command table under PN, SS and PR):

- parabolic of degree n (PN#): ``f = 1 - (1 - u)^n`` (k = n, integral n / (n + 1));
  n = 2 is the factory curve, n = 1 is linear;
- S-curve with jerk share p in (0, 1] (SS#, PR# as percentages): the acceleration rises
  linearly over the first p/2 of the ramp, holds over the middle 1 - p, falls linearly
  over the last p/2 (k = 2 / (2 - p), integral 1/2); p = 1 is the factory curve, p -> 0
  tends to linear. Every piece is a polynomial, so positions stay exact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum
from functools import lru_cache


class RampShape(Enum):
    """Velocity ramp selected per axis (LA, PN, SC, CN)."""

    LINEAR = "linear"
    PARABOLIC = "parabolic"
    SCURVE = "s-curve"
    COSINE = "cosine"


# (peak slope k, integral of f over [0, 1])
_SHAPE_CONSTANTS: dict[RampShape, tuple[float, float]] = {
    RampShape.LINEAR: (1.0, 0.5),
    RampShape.PARABOLIC: (2.0, 2.0 / 3.0),
    RampShape.SCURVE: (2.0, 0.5),
    RampShape.COSINE: (math.pi / 2.0, 0.5),
}


def shape_param(shape: RampShape, param: float | None) -> float | None:
    """The parameter that changes the curve, or None for the factory curve: a parabolic
    degree other than 2, an S-curve jerk share below 1 (others take none)."""
    if param is None:
        return None
    if shape is RampShape.PARABOLIC:
        if param < 1.0:
            raise ValueError(f"a parabolic ramp's degree is at least 1, not {param:g}")
        return None if param == 2.0 else float(param)
    if shape is RampShape.SCURVE:
        if not 0.0 < param <= 1.0:
            raise ValueError(f"an S-curve's jerk share is in (0, 1], not {param:g}")
        return None if param == 1.0 else float(param)
    return None


def shape_constants(shape: RampShape, param: float | None = None) -> tuple[float, float]:
    """(peak slope k, integral of f over [0, 1]) of a shape with its parameter."""
    param = shape_param(shape, param)
    if param is None:
        return _SHAPE_CONSTANTS[shape]
    if shape is RampShape.PARABOLIC:
        return param, param / (param + 1.0)
    return 2.0 / (2.0 - param), 0.5  # S-curve with a constant-acceleration middle


def _scurve_f(u: float, p: float) -> float:
    """S-curve with jerk share p: a rising corner of length a = p/2, a straight middle,
    a falling corner (the mirror image of the rising one)."""
    a, peak = p / 2.0, 2.0 / (2.0 - p)
    if u <= a:
        return peak * u * u / (2.0 * a)
    if u < 1.0 - a:
        return peak * (u - a / 2.0)
    w = 1.0 - u
    return 1.0 - peak * w * w / (2.0 * a)


def _scurve_integral(u: float, p: float) -> float:
    a, peak = p / 2.0, 2.0 / (2.0 - p)
    if u <= a:
        return peak * u**3 / (6.0 * a)
    if u < 1.0 - a:
        return peak * (a * a / 6.0 + ((u - a / 2.0) ** 2 - a * a / 4.0) / 2.0)
    w = 1.0 - u  # f(u) = 1 - f(1 - u), so F(u) = u - 1/2 + F(1 - u)
    return u - 0.5 + peak * w**3 / (6.0 * a)


def ramp_knots(shape: RampShape, param: float | None = None) -> tuple[float, ...]:
    """Normalised times inside a ramp where its polynomial pieces meet (S-curves)."""
    if shape is not RampShape.SCURVE:
        return ()
    p = shape_param(shape, param)
    if p is None:
        return (0.5,)
    return (p / 2.0, 1.0 - p / 2.0)


def shape_f(shape: RampShape, u: float, param: float | None = None) -> float:
    """Normalised velocity fraction at normalised time u in [0, 1]."""
    if param is not None and (param := shape_param(shape, param)) is not None:
        if shape is RampShape.PARABOLIC:
            return 1.0 - (1.0 - u) ** param
        return _scurve_f(u, param)
    if shape is RampShape.LINEAR:
        return u
    if shape is RampShape.PARABOLIC:
        return 1.0 - (1.0 - u) ** 2
    if shape is RampShape.SCURVE:
        return 2.0 * u * u if u < 0.5 else 1.0 - 2.0 * (1.0 - u) ** 2
    return (1.0 - math.cos(math.pi * u)) / 2.0


def shape_integral(shape: RampShape, u: float, param: float | None = None) -> float:
    """Integral of shape_f from 0 to u."""
    if param is not None and (param := shape_param(shape, param)) is not None:
        if shape is RampShape.PARABOLIC:
            return u - (1.0 - (1.0 - u) ** (param + 1.0)) / (param + 1.0)
        return _scurve_integral(u, param)
    if shape is RampShape.LINEAR:
        return u * u / 2.0
    if shape is RampShape.PARABOLIC:
        return u * u - u**3 / 3.0
    if shape is RampShape.SCURVE:
        return 2.0 * u**3 / 3.0 if u < 0.5 else _scurve_upper(u)
    return u / 2.0 - math.sin(math.pi * u) / (2.0 * math.pi)


def _scurve_upper(u: float) -> float:
    """Integral of the S-curve for u >= 1/2: F(1/2) + (u - 1/2) - 2/3 * (1/8 - (1 - u)^3)."""
    w = 1.0 - u
    return 1.0 / 12.0 + (u - 0.5) - 2.0 * (0.125 - w**3) / 3.0


def ramp_time(shape: RampShape, dv: float, accel: float, param: float | None = None) -> float:
    """Seconds to change speed by dv at peak acceleration accel."""
    return shape_constants(shape, param)[0] * abs(dv) / accel


@dataclass(frozen=True, slots=True)
class Phase:
    """One piece of a motion: speeds are magnitudes, direction is +1 or -1."""

    t0: float  # seconds from the motion's start
    duration: float  # math.inf for an endless jog slew
    s0: float  # signed offset at t0 (steps from the motion's origin)
    v1: float  # speed at start (>= 0)
    v2: float  # speed at end (>= 0)
    direction: int
    shape: RampShape
    mirrored: bool = False  # deceleration ramps mirror the parabolic shape in time
    param: float | None = None  # the shape's parameter (None: factory curve), see top

    def speed(self, tau: float) -> float:
        if self.v1 == self.v2 or self.duration == 0.0:
            return self.v1
        u = min(max(tau / self.duration, 0.0), 1.0)
        if self.mirrored:
            return self.v2 + (self.v1 - self.v2) * shape_f(self.shape, 1.0 - u, self.param)
        return self.v1 + (self.v2 - self.v1) * shape_f(self.shape, u, self.param)

    def distance(self, tau: float) -> float:
        """Unsigned distance travelled tau seconds into the phase."""
        T = self.duration
        if self.v1 == self.v2 or T == 0.0:  # (a ramp from a denormal speed takes no time)
            return self.v1 * tau
        u = min(max(tau / T, 0.0), 1.0)
        if self.mirrored:
            full = shape_integral(self.shape, 1.0, self.param)
            return self.v2 * tau + (self.v1 - self.v2) * T * (
                full - shape_integral(self.shape, 1.0 - u, self.param)
            )
        return self.v1 * tau + (self.v2 - self.v1) * T * shape_integral(self.shape, u,
                                                                        self.param)

    @property
    def length(self) -> float:
        return self.distance(self.duration)

    @property
    def polynomial(self) -> bool:
        """Is the position a polynomial in time over this phase? (Cosine ramps are not;
        nor, for the servo's cubic pieces, parabolic ramps of a degree above 2.)"""
        if self.v1 != self.v2 and self.shape is RampShape.PARABOLIC and self.param is not None:
            return self.param <= 2.0 and self.param == int(self.param)
        return not (self.v1 != self.v2 and self.shape is RampShape.COSINE)

    @property
    def knots(self) -> tuple[float, ...]:
        """Times (s from the phase's start) where its polynomial pieces meet."""
        if self.v1 == self.v2 or math.isinf(self.duration):
            return ()
        return tuple(k * self.duration for k in ramp_knots(self.shape, self.param))


@dataclass(slots=True)
class Motion:
    """A planned motion relative to an integer origin position.

    ``end_time`` is None for a jog that slews until told otherwise. ``final_offset`` is
    the exact integer offset the motion ends on (a move's distance, or a rounded stop).
    ``ramp_end_time`` is when the last speed change completes (what a queued JG waits for).
    """

    phases: list[Phase]
    end_time: float | None
    final_offset: int
    ramp_end_time: float
    direction: int = 1
    peak_speed: float = 0.0
    _last: int = field(default=0, repr=False)
    # all phases travel one way (moves and stops; not a reversing jog): found when made,
    # as a plan is never modified once made and every motion start and end asks
    monotonic: bool = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.monotonic = all(p.direction == self.direction for p in self.phases)

    def phase_at(self, t: float) -> Phase | None:
        phases = self.phases
        if not phases:
            return None
        i = self._last
        if i >= len(phases) or phases[i].t0 > t:
            i = 0
        while i + 1 < len(phases) and phases[i + 1].t0 <= t:
            i += 1
        self._last = i
        return phases[i]

    def offset(self, t: float) -> float:
        """Signed offset from the origin at time t (exact float, not yet whole steps)."""
        if self.end_time is not None and t >= self.end_time:
            return float(self.final_offset)
        phase = self.phase_at(t)
        if phase is None:
            return float(self.final_offset)
        return phase.s0 + phase.direction * phase.distance(t - phase.t0)

    def velocity(self, t: float) -> float:
        """Signed velocity at time t, steps/s."""
        if self.end_time is not None and t >= self.end_time:
            return 0.0
        phase = self.phase_at(t)
        if phase is None:
            return 0.0
        return phase.direction * phase.speed(t - phase.t0)


def _ramp(t0: float, s0: float, v1: float, v2: float, accel: float, direction: int,
          shape: RampShape, param: float | None = None) -> Phase:
    param = shape_param(shape, param)
    duration = ramp_time(shape, v2 - v1, accel, param)
    mirrored = v2 < v1 and shape is RampShape.PARABOLIC
    return Phase(t0, duration, s0, v1, v2, direction, shape, mirrored, param)


def _append(phases: list[Phase], phase: Phase) -> tuple[float, float]:
    """Append a phase; return the time and signed offset where it ends."""
    phases.append(phase)
    return phase.t0 + phase.duration, phase.s0 + phase.direction * phase.length


@lru_cache(maxsize=4096)
def plan_move(distance: int, base: float, peak: float, accel: float, decel: float,
              shape: RampShape, up: float | None = None, down: float | None = None) -> Motion:
    """A point-to-point move from rest: jump to VB, ramp to VL, slew, ramp to VB, stop.

    Short moves become triangles: the peak speed is solved so that both ramps meet.
    ``up`` and ``down`` are the shape parameters of the acceleration and deceleration
    ramps (None: the factory curve).
    Memoised: scans repeat the same moves, and a plan is never modified once made
    (Motion's phase cursor is only a lookup hint, safe to share).
    """
    direction = 1 if distance >= 0 else -1
    d = abs(distance)
    if d == 0:
        return Motion([], 0.0, 0, 0.0, direction=direction)
    phases, t, ramp_end, peak = move_phases(float(d), direction, base, peak, accel, decel,
                                            shape, up, down)
    return Motion(phases, t, direction * d, ramp_end, direction=direction, peak_speed=peak)


def move_phases(d: float, direction: int, base: float, peak: float, accel: float,
                decel: float, shape: RampShape, up: float | None = None,
                down: float | None = None) -> tuple[list[Phase], float, float, float]:
    """The phases of a move of length d > 0 from rest (plan_move's arithmetic, for any
    length: a path's speed follows them along its length): (phases, end time, the
    first ramp's end, the peak speed)."""
    up, down = shape_param(shape, up), shape_param(shape, down)
    k, integral = shape_constants(shape, up)
    k_down, integral_down = shape_constants(shape, down)
    base = min(base, peak)
    x = peak - base
    up_length = k * x / accel * (base + integral * x)
    down_length = k_down * x / decel * (base + integral_down * x)
    if up_length + down_length > d:
        if (k, integral) == (k_down, integral_down):
            # Triangle: integral*x^2 + base*x = d / (k * (1/a + 1/d)).
            c = d / (k * (1.0 / accel + 1.0 / decel))
            x = (-base + math.sqrt(base * base + 4.0 * integral * c)) / (2.0 * integral)
        else:  # ramps of different shapes: A x^2 + B x = d
            qa = integral * k / accel + integral_down * k_down / decel
            qb = base * (k / accel + k_down / decel)
            x = 2.0 * d / (qb + math.sqrt(qb * qb + 4.0 * qa * d))
        peak = base + x
    phases: list[Phase] = []
    t, s = 0.0, 0.0
    if peak > base:
        t, s = _append(phases, _ramp(t, s, base, peak, accel, direction, shape, up))
    ramp_end = t
    down_phase = (_ramp(0.0, 0.0, peak, base, decel, direction, shape, down)
                  if peak > base else None)
    down_length = down_phase.length if down_phase else 0.0
    slew = d - abs(s) - down_length
    if slew > 1e-9 and peak > 0:
        t, s = _append(phases, Phase(t, slew / peak, s, peak, peak, direction, shape))
    if down_phase is not None:
        t, s = _append(phases, _ramp(t, s, peak, base, decel, direction, shape, down))
    if not phases:  # peak == base == 0 cannot happen (VL >= 1); guard anyway
        phases.append(Phase(0.0, d / max(peak, 1.0), 0.0, peak, peak, direction, shape))
        t = d / max(peak, 1.0)
    return phases, t, ramp_end, peak


def plan_stop(residual: float, velocity: float, base: float, decel: float,
              shape: RampShape, down: float | None = None) -> Motion:
    """Decelerate from the current signed velocity to VB, then stop; final step rounded."""
    direction = 1 if velocity >= 0 else -1
    speed = abs(velocity)
    phases: list[Phase] = []
    t, s = 0.0, residual
    if speed > base and decel > 0:
        t, s = _append(phases, _ramp(0.0, residual, speed, base, decel, direction, shape,
                                     down))
    final = round(s)
    return Motion(phases, t, final, t, direction=direction, peak_speed=speed)


def plan_jog(residual: float, velocity: float, target: float, base: float, accel: float,
             decel: float, shape: RampShape, up: float | None = None,
             down: float | None = None) -> Motion:
    """Change speed toward a signed jog velocity, then slew forever (or stop at 0)."""
    if target == 0:
        return plan_stop(residual, velocity, base, decel, shape, down)
    direction = 1 if target > 0 else -1
    phases: list[Phase] = []
    t, s = 0.0, residual
    speed = abs(velocity)
    if velocity != 0 and (velocity > 0) != (target > 0):
        # Reverse: decelerate to VB in the old direction, then stop and turn, as a
        # stepper does (it never crawls below its base velocity).
        old = 1 if velocity > 0 else -1
        if speed > base:
            t, s = _append(phases, _ramp(0.0, s, speed, base, decel, old, shape, down))
        speed = 0.0
    goal = abs(target)
    if speed == 0.0:
        speed = min(base, goal)  # a stepper starts at its base velocity
    if goal > speed:
        t, s = _append(phases, _ramp(t, s, speed, goal, accel, direction, shape, up))
    elif goal < speed:
        t, s = _append(phases, _ramp(t, s, speed, goal, decel, direction, shape, down))
    phases.append(Phase(t, math.inf, s, goal, goal, direction, shape))
    return Motion(phases, None, 0, t, direction=direction, peak_speed=max(goal, abs(velocity)))


def scaled(reference: Motion, distance: int, reference_distance: int) -> Motion:
    """The reference profile scaled to one axis's signed distance, ending exactly on it."""
    f = distance / reference_distance
    sign = 1 if f >= 0 else -1
    g = abs(f)
    phases = [
        Phase(p.t0, p.duration, p.s0 * f, p.v1 * g, p.v2 * g, p.direction * sign, p.shape,
              p.mirrored, p.param)
        for p in reference.phases
    ]
    return Motion(phases, reference.end_time, distance, reference.ramp_end_time,
                  direction=sign, peak_speed=reference.peak_speed * g)

"""Internal-controller motions in slot units, on the shared closed-form profiles.

A motion is a chain of profile segments, each started at a slot boundary from an integer
origin. The position after slot k is origin + the whole pulses of the closed-form offset
at the slot boundary (magnitude floored, so both directions count alike), so the pulses
of a slot are the difference at its two boundaries: exactly the closed-form motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...firmware_model.profiles import Motion, Phase, RampShape, plan_jog, plan_move, plan_stop
from .constants import SLOT_SECONDS

_EPS = 1e-6  # float slack so that 2500 * 0.004 counts as 10 whole pulses, not 9
_SHAPE = RampShape.LINEAR
MAX_RATE = 32767 / SLOT_SECONDS
"""The fastest an internal motion runs, pulses/s (D): the most pulses one slot entry can
carry (v2's 15 bits; v1's 7 bits are checked where its slots are filled). A maximum
speed set beyond it (1e300 pulses/ms, say) is taken at it, so a speed-mode run never
reaches positions no float holds."""


def whole_pulses(offset: float) -> int:
    """Whole pulses emitted once the closed-form offset reached `offset`."""
    if offset >= 0:
        return math.floor(offset + _EPS)
    return -math.floor(-offset + _EPS)


@dataclass(frozen=True)
class Segment:
    start: int  # slot at whose start the profile's time 0 lies
    origin: int
    motion: Motion

    def offset_at(self, slot: int) -> float:
        return self.motion.offset((slot - self.start) * SLOT_SECONDS)

    def end_slot(self) -> int | None:
        if self.motion.end_time is None:
            return None
        # The slack absorbs float noise (an "instant" ramp still lasts ~1e-8 ms).
        return self.start + max(0, math.ceil(self.motion.end_time / SLOT_SECONDS - 1e-6))


class SlotMotion:
    """One axis's internal-controller motion (a chain of segments)."""

    def __init__(self, segments: list[Segment], speed_mode: bool = False) -> None:
        self.segments = segments
        self.speed_mode = speed_mode

    def _segment(self, slot: int) -> Segment:
        seg = self.segments[0]
        for s in self.segments[1:]:
            if s.start <= slot:
                seg = s
        return seg

    def position_at(self, slot: int) -> int:
        """Axis position at the start of slot (after slots < slot were emitted)."""
        seg = self._segment(slot)
        if slot <= seg.start:
            return seg.origin
        return seg.origin + whole_pulses(seg.offset_at(slot))

    def exact_at(self, slot: int) -> tuple[int, float, float]:
        """(position, residual fraction, velocity pulses/s) at the start of slot."""
        seg = self._segment(slot)
        if slot <= seg.start:
            return seg.origin, 0.0, seg.motion.velocity(0.0) if slot == seg.start else 0.0
        t = (slot - seg.start) * SLOT_SECONDS
        offset = seg.motion.offset(t)
        whole = whole_pulses(offset)
        return seg.origin + whole, offset - whole, seg.motion.velocity(t)

    def end_slot(self) -> int | None:
        """First slot boundary from which the position no longer changes."""
        return self.segments[-1].end_slot()

    def directions(self, s0: int, s1: int) -> set[int]:
        """Directions of travel over the slot boundaries s0..s1."""
        dirs: set[int] = set()
        for i, seg in enumerate(self.segments):
            nxt = self.segments[i + 1].start if i + 1 < len(self.segments) else None
            if (nxt is not None and nxt <= s0) or seg.start >= s1:
                continue
            t0 = max(0, s0 - seg.start) * SLOT_SECONDS
            t1 = (s1 - seg.start) * SLOT_SECONDS
            for ph in seg.motion.phases:
                if ph.t0 < t1 and ph.t0 + ph.duration > t0 and max(ph.v1, ph.v2) > 0:
                    dirs.add(ph.direction)
        return dirs


def _limits(max_speed_per_ms: float, accel_per_ms2: float, decel_per_ms2: float
            ) -> tuple[float, float, float]:
    """Axis parameters in pulses/s and pulses/s^2 (a zero ramp means an instant change).
    Values the host's floats can carry but no stage can (NaN, infinities, a ramp slower
    than a pulse a day or faster than an instant change) are taken at those bounds (D),
    so an absurd setting makes an absurd motion, never a fault inside the device."""
    peak = max_speed_per_ms * 1e3 if math.isfinite(max_speed_per_ms) else 0.0
    acc = _ramp(accel_per_ms2)
    dec = _ramp(decel_per_ms2)
    return min(MAX_RATE, max(0.0, peak)), acc, dec


def _ramp(per_ms2: float) -> float:
    """A ramp in pulses/s^2: zero, negative or not a number is an instant change."""
    if not math.isfinite(per_ms2) or per_ms2 <= 0:
        return 1e18
    return min(1e18, max(1e-3, per_ms2 * 1e6))


def plan_position(current: SlotMotion | None, position: int, slot: int, target: int,
                  max_speed: float, accel: float, decel: float,
                  peak_fraction: float = 1.0) -> SlotMotion | None:
    """Move to target within the axis limits. A moving axis that can still stop in time
    carries on from its present speed; one that cannot (or runs the other way) first
    stops within its deceleration, then moves back."""
    peak, acc, dec = _limits(max_speed, accel, decel)
    peak *= peak_fraction
    if peak <= 0:
        return None
    segments: list[Segment] = []
    start, origin = slot, position
    if current is not None:
        pos, residual, velocity = current.exact_at(slot)
        if velocity != 0.0:
            onward = _continue(residual, velocity, target - pos, peak, acc, dec)
            if onward is not None:
                return SlotMotion([Segment(slot, pos, onward)])
            stop = plan_stop(residual, velocity, 0.0, dec, _SHAPE)
            seg = Segment(slot, pos, stop)
            segments.append(seg)
            start = seg.end_slot() or slot
            origin = pos + stop.final_offset
    distance = target - origin
    if distance != 0:
        segments.append(Segment(start, origin, plan_move(distance, 0.0, peak, acc, dec, _SHAPE)))
    return SlotMotion(segments) if segments else None


def _continue(residual: float, velocity: float, final: int, peak: float, acc: float,
              dec: float) -> Motion | None:
    """Linear-ramp profile from offset `residual` at `velocity` to rest at `final`:
    ramp to the peak the distance allows, slew, ramp down; None if it cannot stop there."""
    distance = final - residual
    direction = 1 if distance > 0 else -1
    speed = velocity * direction
    length = abs(distance)
    if speed <= 0 or speed * speed / (2 * dec) > length:
        return None
    top = peak if speed > peak else min(peak, math.sqrt(
        (2 * acc * dec * length + dec * speed * speed) / (acc + dec)))
    first = abs(top - speed) / (acc if top >= speed else dec)
    last = top / dec
    along = (speed + top) / 2 * first
    down = top / 2 * last
    slew = max(0.0, length - along - down) / top if top > 0 else 0.0
    phases = [Phase(0.0, first, residual, speed, top, direction, _SHAPE),
              Phase(first, slew, residual + direction * along, top, top, direction, _SHAPE),
              Phase(first + slew, last, final - direction * down, top, 0.0, direction, _SHAPE)]
    end = first + slew + last
    return Motion([p for p in phases if p.duration > 0], end, final, first,
                  direction=direction, peak_speed=top)


def plan_speed(current: SlotMotion | None, position: int, slot: int, speed: float,
               max_speed: float, accel: float, decel: float) -> SlotMotion | None:
    """Run at speed pulses/s (clamped to the axis's maximum) from the present motion."""
    peak, acc, dec = _limits(max_speed, accel, decel)
    speed = max(-peak, min(peak, speed))
    residual, velocity = 0.0, 0.0
    if current is not None:
        position, residual, velocity = current.exact_at(slot)
    if speed == 0.0 and velocity == 0.0:
        return None
    motion = plan_jog(residual, velocity, speed, 0.0, acc, dec, _SHAPE)
    return SlotMotion([Segment(slot, position, motion)], speed_mode=True)


def constant_speed(position: int, slot: int, speed_per_ms: float) -> SlotMotion | None:
    """Run at a constant signed speed from slot on, with no ramp (homing and probing)."""
    if speed_per_ms == 0.0 or not math.isfinite(speed_per_ms):
        return None
    v = max(-MAX_RATE, min(MAX_RATE, speed_per_ms * 1e3))
    return SlotMotion([Segment(slot, position, plan_jog(0.0, v, v, 0.0, 1.0, 1.0, _SHAPE))],
                      speed_mode=True)

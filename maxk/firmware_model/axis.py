"""An axis's motion in closed form: where it is and how fast at any tick, and when it
reaches a position. Every controller's axes are built on this; what an axis is told to do
(queues, modes, flags) belongs to the controller's personality.

A motion is anything with the `MotionPlan` interface: the closed-form profiles of
`profiles.py`, a linearly interpolated move (a scaled profile), one axis's view of a path
(`path.ContourMotion`), or pulses given per time slot. Positions are physical steps since
power-up (what the switches see); counters a host reads are offsets from them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

try:  # mypyc's class options (setup.py compiles this module where it can)
    from mypy_extensions import mypyc_attr
except ImportError:  # pure Python without mypy installed: the decorator does nothing
    def mypyc_attr(*_args: object, **_kwargs: object):  # type: ignore[no-redef,misc]
        return lambda cls: cls

from maxk.firmware_model.motion import Clock, MotionPlan

if TYPE_CHECKING:
    from maxk.firmware_model.servo import ServoLoop


@mypyc_attr(allow_interpreted_subclasses=True)  # each controller's axes
@dataclass
class MotionAxis:
    """The kinematic state of one axis: the physical position at rest or at the origin
    of the running motion, the motion and its ticks, the counters' offsets."""

    index: int
    letter: str
    # Physical position in steps since power-up, at rest or at the origin of the motion.
    steps: int = 0
    counter_offset: int = 0  # motor counter = steps + counter_offset
    encoder_offset: int = 0  # encoder counter = encoder counts + encoder_offset
    motion: MotionPlan | None = None
    motion_start: int = 0  # tick the motion started on
    motion_end: int | None = None  # tick it ends on (None: endless jog)
    ramp_end: int = 0  # tick the last speed change of the motion completes
    switch_tick: int | None = None  # next tick a switch or trigger may change
    direction: int = 1  # direction of the last or current motion
    rest_since: int = 0  # tick the last motion ended
    servo: ServoLoop | None = None  # the closed loop and motor of a servo axis
    # the last offset asked of the running motion: (motion, seconds into it, whole steps);
    # a poll asks the same tick for a status and a position
    _offset_memo: tuple[object, float, int] = field(default=(None, -1.0, 0), repr=False,
                                                    compare=False)

    # ---- position and velocity ------------------------------------------------------
    def steps_at_tick(self, tick: int, period: float) -> int:
        """Physical position at any tick of the running motion (or at rest): the whole
        steps the motion has made by then."""
        m = self.motion
        if m is None:
            return self.steps
        if self.motion_end is not None and tick >= self.motion_end:
            return self.steps + m.final_offset
        t = (tick - self.motion_start) * period
        memo = self._offset_memo
        if memo[0] is m and memo[1] == t:
            return self.steps + memo[2]
        whole = int(m.offset(t))
        self._offset_memo = (m, t, whole)
        return self.steps + whole

    def steps_now(self, engine: Clock) -> int:
        return self.steps_at_tick(engine.tick, engine.period)

    def velocity(self, engine: Clock) -> float:
        m = self.motion
        if m is None or (self.motion_end is not None and engine.tick >= self.motion_end):
            return 0.0
        return m.velocity((engine.tick - self.motion_start) * engine.period)

    def travel_direction(self, engine: Clock) -> int:
        """Which way the axis is travelling now: the velocity's sign, or on a motion's
        last tick (velocity 0) the way its last update cycle went. A one-way motion
        (every phase the same way: a move, a stop, a jog without reversal) has no other
        answer than its direction, which a status poll then needs no velocity for."""
        m = self.motion
        if m is None:
            return self.direction
        if m.monotonic:
            return m.direction
        v = self.velocity(engine)
        if v == 0:
            step = self.steps_now(engine) - self.steps_at_tick(engine.tick - 1, engine.period)
            if step == 0:
                return m.direction
            return 1 if step > 0 else -1
        return 1 if v > 0 else -1

    @property
    def moving(self) -> bool:
        return self.motion is not None

    # ---- starting and ending motions -------------------------------------------------
    def begin(self, motion: MotionPlan, engine: Clock) -> None:
        """Run `motion` from this tick: its end tick is `start + ceil(T / period)`, so a
        move ends exactly on its target on the first tick at or after its analytic end."""
        self.motion = motion
        now = engine.tick
        self.motion_start = now
        period = engine.period
        if motion.end_time is None:
            self.motion_end = None
        else:
            self.motion_end = now + math.ceil(motion.end_time / period - 1e-9)
        self.ramp_end = now + math.ceil(motion.ramp_end_time / period - 1e-9)
        self.direction = motion.direction
        if self.motion_end is not None and self.motion_end <= now:
            self.finish_motion()

    def freeze(self, engine: Clock) -> tuple[float, float]:
        """Stop the running motion's clock at this tick: the whole steps made so far
        become the position; return (fractional residual, velocity) for what follows."""
        m = self.motion
        if m is None:
            return 0.0, 0.0
        t = (engine.tick - self.motion_start) * engine.period
        exact = m.offset(t)
        velocity = m.velocity(t)
        if velocity:
            self.direction = 1 if velocity > 0 else -1
        whole = int(exact)
        self.steps += whole
        self.motion_ended()
        self.rest_since = engine.tick
        self.motion = None
        self.motion_end = None
        self.switch_tick = None
        return exact - whole, velocity

    def finish_motion(self) -> None:
        """The motion reached its end tick: the axis stands on its final whole step."""
        m = self.motion
        if m is not None:
            self.steps += m.final_offset
            if self.motion_end is not None:
                self.rest_since = self.motion_end
            self.motion_ended()
        self.motion = None
        self.motion_end = None
        self.switch_tick = None

    def motion_ended(self) -> None:
        """Called when a motion ends or is frozen, before it is dropped (a personality
        settles what depended on it)."""

    # ---- when a position is reached ----------------------------------------------------
    def tick_reaching(self, position: float, direction: int, engine: Clock) -> int | None:
        """The first tick after now at which the running motion, travelling in
        `direction`, has reached `position` (steps), or None if it never does.

        Each phase of a motion is monotonic, so a bisection over the ticks of every
        phase that travels the right way finds the crossing exactly, in O(log n). This
        is how limit switches, home edges, index marks and position-gated outputs all
        find their exact tick."""
        m = self.motion
        if m is None:
            return None
        # A move or a stop never goes past where it ends: most searches end here.
        if m.end_time is not None and m.monotonic and (
                m.direction != direction
                or direction * (self.steps + m.final_offset - position) < 0):
            return None
        period = engine.period
        now = engine.tick

        def reached(tick: int) -> bool:
            return direction * (self.steps_at_tick(tick, period) - position) >= 0

        for phase in m.phases:
            if phase.direction != direction or (phase.v1 == 0 and phase.v2 == 0):
                continue
            first = max(now + 1, self.motion_start + int(phase.t0 / period))
            if math.isinf(phase.duration):
                here = self.steps_at_tick(first, period)
                need = max(0.0, direction * (position - here))
                last = first + math.ceil(need / (phase.v1 * period)) + 2
            else:
                last = self.motion_start + math.ceil((phase.t0 + phase.duration) / period)
            if self.motion_end is not None:
                last = min(last, self.motion_end)
            tick = first_tick(reached, first, last) if last >= first else None
            if tick is not None:
                return tick
        return None


def first_tick(reached: Callable[[int], bool], lo: int, hi: int) -> int | None:
    """The smallest tick in [lo, hi] at which a monotone condition holds (bisection);
    None if it does not hold at hi. Every exact-to-the-tick search uses it."""
    if not reached(hi):
        return None
    while lo < hi:
        mid = (lo + hi) // 2
        if reached(mid):
            hi = mid
        else:
            lo = mid + 1
    return lo


SwitchSide = int  # +1: the plus limit, -1: the minus limit


@mypyc_attr(allow_interpreted_subclasses=True)  # Trio's limits
class MotionEnds:
    """The shared machine ends its axes' motions: an event source that, on each motion's
    end tick, stands the axis on its final step (`finish_motion`, which calls the axis's
    `motion_ended` hook) and tells the personality (`on_end(axis, tick)`: a queue moves
    on, a done flag sets). Given limit switches (`limit_at(axis, side)`: the physical
    position from which that side's limit is active, None for none; -inf/+inf for a
    switch stuck active), it also finds, exactly to the tick, where a motion reaches one,
    and calls `on_limit(axis, side, tick)` there (the personality stops the axis its
    controller's way). A new controller adds one for its axes and writes only what its
    controller does at an end or a limit.

    A limit that becomes active under a moving axis (a switch moved onto it, a fault that
    sticks it active) acts on the tick the world changed (`changed()`, then the engine's
    next pass at that tick, or `act_now()`) if the axis travels toward it then, else on
    the first tick it turns toward it. The motion a limit leaves the axis with (its stop,
    which runs on into the pressed switch) never trips that side again; a motion that
    knows its reach (`reach`: the offsets it stays within, as `path.ContourMotion` has)
    skips the limits it never gets to, without making its phases."""

    def __init__(self, axes: Sequence[MotionAxis], engine: Clock,
                 on_end: Callable[[MotionAxis, int], None] = lambda axis, tick: None, *,
                 limit_at: Callable[[MotionAxis, SwitchSide], float | None] | None = None,
                 on_limit: Callable[[MotionAxis, SwitchSide, int], None] | None = None
                 ) -> None:
        self.axes = axes
        self.engine = engine
        self.on_end = on_end
        self.limit_at = limit_at
        self.on_limit = on_limit
        self._limit: dict[int, tuple[object, int | None, SwitchSide]] = {}  # per axis:
        # (the motion it was found for, the tick it reaches a limit, which limit)
        self._braking: dict[int, tuple[object, SwitchSide]] = {}  # per axis: the motion
        # a limit left it with, and that limit's side

    def _limit_tick(self, axis: MotionAxis) -> tuple[int | None, SwitchSide]:
        found = self._limit.get(axis.index)
        motion = axis.motion
        if found is not None and found[0] is motion:
            return found[1], found[2]
        best: tuple[int | None, SwitchSide] = (None, 1)
        if self.limit_at is not None and motion is not None:
            engine = self.engine
            braking = self._braking.get(axis.index)
            reach = getattr(motion, "reach", None)
            for side in (1, -1):
                if braking is not None and braking[0] is motion and braking[1] == side:
                    continue
                edge = self.limit_at(axis, side)
                if edge is None:
                    continue
                if reach is not None and (edge > axis.steps + reach[1] if side > 0
                                          else edge < axis.steps + reach[0]):
                    continue  # (beyond where the motion ever goes)
                here = axis.steps_now(engine)
                if side * (here - edge) >= 0 and side * axis.velocity(engine) > 0:
                    tick: int | None = engine.tick  # pressed now, travelling into it
                else:
                    tick = axis.tick_reaching(edge, side, engine)
                if tick is not None and (best[0] is None or tick < best[0]):
                    best = (tick, side)
        self._limit[axis.index] = (motion, *best)
        return best

    def changed(self) -> None:
        """A switch moved or a fault was set: find the limits afresh."""
        self._limit.clear()

    def act_now(self) -> None:
        """Do at once what is due at the present tick (a world change made outside the
        engine's pass: a limit now pressed under a moving axis)."""
        due = self.next_event()
        if due is not None and due <= self.engine.tick:
            self.on_event(self.engine.tick)

    def next_event(self) -> int | None:
        soonest: int | None = None
        # the engine asks twice a pass: the cache is read here directly, unless a subclass
        # decides itself when its cache holds (it overrides _limit_tick)
        found = self._limit if type(self)._limit_tick is MotionEnds._limit_tick else None
        for axis in self.axes:
            motion = axis.motion
            if motion is None:
                continue
            known = None if found is None else found.get(axis.index)
            limit = known[1] if known is not None and known[0] is motion else (
                self._limit_tick(axis)[0])
            end = axis.motion_end
            if end is not None and (soonest is None or end < soonest):
                soonest = end
            if limit is not None and (soonest is None or limit < soonest):
                soonest = limit
        return soonest

    def on_event(self, now: int) -> None:
        for axis in self.axes:
            if axis.motion is None:
                continue
            tick, side = self._limit_tick(axis)
            if tick is not None and tick <= now and self.on_limit is not None and (
                    axis.motion_end is None or tick <= axis.motion_end):
                self._limit.pop(axis.index, None)
                self.on_limit(axis, side, now)
                self._braking[axis.index] = (axis.motion, side)
            elif axis.motion_end is not None and axis.motion_end <= now:
                axis.finish_motion()
                self.on_end(axis, now)

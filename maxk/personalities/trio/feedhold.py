"""Feed hold of the MC405: FHOLD_IN and FHSPEED (TrioBASIC help, FHOLD_IN and FHSPEED).

While the input FHOLD_IN names is active (low, as IN(n) reads it: C, so INVERT_IN
applies), the moves of a BASE group whose base axis names it run at FHSPEED without
being cancelled; when it lets go they go back to their programmed speed (C). FHSPEED 0
(its power-up value) pauses them. Links (CONNECT, CAMBOX, MOVELINK...) are not speed
controlled and go on (C).

How (D): the run's path is re-planned from where it is, at the speed it has, with the
path planner's speed scale FHSPEED / the programmed speed of the move in progress (so
that move runs at FHSPEED, the moves merged after it at the same share of theirs), the
change at the run's ACCEL (the page: ACCEL/DECEL/JERK; the path planner has one rate).
A single-axis move (a closed-form profile) becomes a path of its remaining distance
first, as MOVEMODIFY's re-plan (an S-curve move's S-ramp running going on: runs.py).
With SRAMP/JERK the changes are S-ramps (path_scurve.py). Inputs are looked at when the
world or a parameter changes and at every engine event, as the jog inputs are.
"""

from __future__ import annotations

from typing import Any

from maxk.firmware_model.path import plan_path

from .runs import Run

FEEDHOLD = 1 << 7  # AXISSTATUS bit 7 (h): the feed-hold input is active (C: AXISSTATUS)


class FeedHold:
    """The feed-hold inputs of every base axis: an every-event watcher of the machine."""

    every_event = True

    def __init__(self, machine: Any) -> None:
        self.m = machine
        self.held: set[int] = set()  # base axes whose feed-hold input is active

    def reset(self) -> None:
        self.held.clear()

    def next_event(self) -> int | None:
        return None

    def on_event(self, now: int) -> None:
        self.look()

    def _active(self, axis: int) -> bool:
        number = self.m.axes[axis].params.get("FHOLD_IN", -1.0)
        return number >= 0 and not self.m.digital_input(int(number))

    def look(self) -> None:
        m = self.m
        for axis in range(m.axis_count):
            active = self._active(axis)
            if not active and axis not in self.held:
                continue
            queue = m.queues[axis]
            run: Run | None = queue[0] if queue and queue[0].base == axis else None
            scale = 1.0
            if active:
                self.held.add(axis)
                if run is not None and run.started and not run.stopping:
                    hold = max(0.0, m.axes[axis].params.get("FHSPEED", 0.0))
                    programmed = run.speeds[_current(m, run)] / run.units
                    scale = min(1.0, hold / programmed) if programmed > 0 else 1.0
            else:
                self.held.discard(axis)
            if run is None or not run.started or run.stopping or run.scale == scale:
                continue
            if run.profile is not None:
                run = _as_path(m, run)
            run.scale = scale
            m._apply_plan(run, run.plan_new(m.tick, period=m.period))
            m.changed()


def _current(m: Any, run: Run) -> int:
    if run.plan is None or run.profile is not None:
        return 0
    s, _v = run.plan.state((m.tick - run.plan_tick) * m.period)
    return run.segment_index(s)


def _as_path(m: Any, run: Run) -> Run:
    """A running single-axis move as a path of its remaining distance from here, at the
    speed it has (its place in the queue taken by the new run)."""
    axis = run.base
    a = m.axes[axis]
    now = m.tick
    here = float(m.own_counts(axis, m._now())[0])
    assert run.profile is not None
    end = float(a.steps + run.profile.final_offset)
    velocity = abs(a.velocity(m)) if a.motion is not None else 0.0
    s_done, _v = run.distance_speed(m._now(), m.period)
    m.distance_done[axis] += float(s_done[0]) / run.units
    new = Run((axis,), [(end - here,)], run.speeds[:1],  # type: ignore[list-item]
              run.accels[:1], run.decel, run.units, single=False)
    new.kinds = {0: run.kinds.get(0, 1)}
    new.counted = run.counted  # (MOVE_COUNT counted it already)
    new.started = True
    new.start_tick = now
    new.resolve((here,))
    m.queues[axis][0] = new
    new.plan = new.continued(run, (now - run.start_tick) * m.period, float(s_done[0])) \
        or plan_path(new.segments, 0, 0.0, velocity, 1.0)  # (an S-curve's ramp goes on)
    new.plan_tick = now
    return new


__all__ = ["FeedHold"]

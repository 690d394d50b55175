"""Virtual time and events: the one loop every controller runs on.

Time is an integer tick counter at the controller's update period (the MAXk's 122.07 us,
a PoKeys 1 ms slot, a Trio servo cycle). Nothing here reads the wall clock: a door that
wants real time advances the engine to "now"; tests advance it explicitly and are exact.

Cost grows with events, not ticks. Everything that can change something at a later tick
is an *event source*: it says when it next needs attention, and is called at that tick.
The engine jumps from the earliest such tick to the next; it knows no kinds of source
(axes, paths, pollers, pulse generators all look the same to it). A personality adds what
its firmware does once a tick's events have run (`after_events`), and what runs every
tick between events (`integrate`, the servo loops).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol, Self

try:  # mypyc's class options (setup.py compiles this module where it can)
    from mypy_extensions import mypyc_attr
except ImportError:  # pure Python without mypy installed: the decorator does nothing
    def mypyc_attr(*_args: object, **_kwargs: object):  # type: ignore[no-redef,misc]
        return lambda cls: cls


class EventSource(Protocol):
    """Something that changes the machine at ticks it can predict."""

    def next_event(self) -> int | None:
        """The earliest tick at which this source needs to act (None: not before
        something else changes)."""
        ...

    def on_event(self, now: int) -> None:
        """Act at tick `now`: called when `next_event()` <= now, or at every event tick
        for a source that sets `every_event` (it watches what other events change)."""
        ...


@dataclass(slots=True)
class _Observer:
    every: int | None  # None: at every event tick
    due: int | None
    callback: Callable[[Engine], None]


@mypyc_attr(allow_interpreted_subclasses=True)  # each controller's machine
class Engine:
    """Integer virtual time, the event sources and the loop that runs them."""

    def __init__(self, update_rate_hz: int | float) -> None:
        self.tick = 0
        # `int | float`, not `float`: the rate is reported as it was given (#UR? says
        # 1024, not 1024.0), and a compiled build (mypyc) would turn a `float`'s int
        # into a float
        self.update_rate_hz = update_rate_hz
        self.period = 1.0 / update_rate_hz
        # Virtual time stays continuous across a change of update rate:
        # time = origin + (tick - tick origin) * period
        self._time_origin = 0.0
        self._tick_origin = 0
        self._sources: list[EventSource] = []
        self._watchers: list[bool] = []  # per source: acts at every event tick
        self._acting: list[tuple[EventSource, bool]] = []  # the two, zipped once
        self._observers: list[_Observer] = []
        # Seconds this engine's virtual time stands behind the time its door wants (the
        # wall clock, scaled): 0.0 while it keeps up. Only a door that paces the engine
        # against a wall clock sets it (the engine itself never reads a clock); the status
        # lines and the doors read it.
        self.behind = 0.0

    # ---- time ------------------------------------------------------------------------
    @property
    def time(self) -> float:
        """Virtual seconds since power-up (continuous across update-rate changes)."""
        return self._time_origin + (self.tick - self._tick_origin) * self.period

    def tick_at(self, seconds: float) -> int:
        """The last tick at or before a virtual time (at the present update rate)."""
        return self._tick_origin + int((seconds - self._time_origin) * self.update_rate_hz
                                       + 1e-6)

    def change_update_rate(self, rate_hz: int | float) -> None:
        """From this tick on, ticks are `1/rate_hz` long; the time so far is kept."""
        self._time_origin = self.time
        self._tick_origin = self.tick
        self.update_rate_hz = rate_hz
        self.period = 1.0 / rate_hz

    # ---- sources and observers ----------------------------------------------------------
    def add_source(self, source: EventSource) -> None:
        """Sources act in the order they were added when they fall on one tick."""
        self._sources.append(source)
        self._watchers.append(bool(getattr(source, "every_event", False)))
        self._acting = list(zip(self._sources, self._watchers, strict=True))

    def remove_source(self, source: EventSource) -> None:
        kept = [(s, w) for s, w in zip(self._sources, self._watchers, strict=True)
                if s is not source]
        self._sources = [s for s, _w in kept]
        self._watchers = [w for _s, w in kept]
        self._acting = kept

    def add_observer(self, callback: Callable[[Self], None],
                     every_ticks: int | None = None) -> None:
        """Call back at every event tick, or every N ticks (traces; never in hot paths
        unless asked for). The callback sees the machine after the tick's events ran."""
        if every_ticks is not None and every_ticks < 1:
            raise ValueError("every_ticks must be at least 1")
        due = None if every_ticks is None else self.tick + every_ticks
        self._observers.append(_Observer(every_ticks, due, callback))  # type: ignore[arg-type]

    def remove_observer(self, callback: Callable[[Self], None]) -> None:
        # == rather than `is`: a bound method (`trace._on_event`) is a new object at
        # every access, equal to the one added but never identical to it
        self._observers = [o for o in self._observers if o.callback != callback]

    def _observe(self, now: int) -> None:
        for observer in self._observers:
            if observer.every is None:
                observer.callback(self)
            elif observer.due is not None and observer.due <= now:
                observer.callback(self)
                observer.due += observer.every

    # ---- what a personality adds -----------------------------------------------------
    def settle(self) -> None:
        """Do what can be done at the present tick before time moves (a MAXk runs its
        command queues here)."""

    def after_events(self, now: int) -> None:
        """What the firmware does once the sources due at `now` have acted."""

    def integrate(self, limit: int) -> bool:
        """Run what must run every tick (servo loops) up to `limit`, the next event. True
        if it met an event of its own on the way (time then stands at its tick)."""
        return False

    # ---- the loop --------------------------------------------------------------------
    def next_event(self) -> int | None:
        best: int | None = None
        for source in self._sources:
            t = source.next_event()
            if t is not None and (best is None or t < best):
                best = t
        for observer in self._observers:
            due = observer.due
            if due is not None and (best is None or due < best):
                best = due
        return best

    def advance_to(self, tick: int, stop: Callable[[], bool] | None = None) -> bool:
        """Advance virtual time to an absolute tick, processing every event on the way.

        `stop`, when given, is asked after each event tick: True ends the advance there
        (time stands at that event's tick, everything due at it done). A door uses it to
        bound one controller's work per turn, so that a controller whose work outruns
        real time slows its own clock and never another's. Returns True when `tick` was
        reached."""
        if tick < self.tick:
            raise ValueError("time only moves forward")
        self.settle()
        next_event, integrate, after_events = self.next_event, self.integrate, self.after_events
        while True:
            event = next_event()
            limit = tick if event is None or event > tick else event
            if integrate(limit):
                if stop is not None and stop():
                    return self.tick >= tick
                continue
            if event is None or event > tick:
                break
            now = self.tick = max(event, self.tick)
            for source, watcher in self._acting:
                if watcher:
                    source.on_event(now)
                    continue
                due = source.next_event()
                if due is not None and due <= now:
                    source.on_event(now)
            after_events(now)
            if self._observers:
                self._observe(now)
            if stop is not None and now < tick and stop():
                return False
        self.tick = tick
        return True

    def advance(self, ticks: int) -> None:
        self.advance_to(self.tick + int(ticks))

    def run_until(self, predicate: Callable[[Self], bool], timeout_ticks: int) -> bool:
        """Advance event by event until predicate holds; False on timeout (time then stops
        at the timeout). Predicates are checked at events, so they should depend on
        state that changes at events (done flags, idleness, waits)."""
        deadline = self.tick + timeout_ticks
        self.settle()
        while not predicate(self):
            event = self.next_event()
            if event is None or event > deadline:
                self.advance_to(deadline)
                return predicate(self)
            self.advance_to(max(event, self.tick))
        return True

"""The control door's parts that hold state per controller: triggers (a world setting at
a tick or when an axis passes a position), traces (bounded CSV), the error log, and the
request words (the `@world` words and their JSON form). The HTTP side is control.py."""

from __future__ import annotations

import asyncio
import contextlib
import io
import ipaddress
import logging
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from itertools import count
from typing import Any

from maxk.controllers.world_settings import parse_world
from maxk.host.client import Service
from maxk.trace import TraceWriter

log = logging.getLogger("maxk.door.control")

TRACE_LIMIT = 4 * 1024 * 1024  # characters of CSV one trace keeps (then it stops itself)
TRIGGERS = 64  # armed triggers per controller
ERRORS = 200  # error log entries kept
STEP_TURN_SECONDS = 0.01  # wall time a step runs before it pauses for the door's requests
STEP_PAUSE_SECONDS = 0.001
STEP_SLICE_SECONDS = 0.05  # virtual time advanced between two looks at the other doors
HORIZON_SECONDS = 1e7  # a trigger is armed at most this far ahead (about 116 days) (D)

class BadRequest(Exception):
    """A 4xx with a reason (status 400 unless told)."""

    def __init__(self, reason: str, status: int = 400) -> None:
        super().__init__(reason)
        self.status = status


class ErrorLog(logging.Handler):
    """The server's recent warnings and faults (the `maxk` loggers), bounded."""

    def __init__(self, size: int = ERRORS) -> None:
        super().__init__(logging.WARNING)
        self.records: deque[dict[str, Any]] = deque(maxlen=size)

    def emit(self, record: logging.LogRecord) -> None:
        with contextlib.suppress(Exception):
            self.records.append({"time": record.created, "level": record.levelname,
                                 "logger": record.name, "message": record.getMessage()})


class BoundedText(io.StringIO):
    """A trace's CSV, refusing to grow past `limit` (the trace then stops itself)."""

    def __init__(self, limit: int) -> None:
        super().__init__()
        self.limit = limit
        self.full = False
        self.lines = 0

    def write(self, text: str) -> int:
        if self.full or self.tell() + len(text) > self.limit:
            self.full = True
            return 0
        self.lines += text.count("\n")
        return super().write(text)

    def read_at(self, offset: int, size: int) -> str:
        """Up to `size` characters from `offset`, the write position kept (a reader of
        the CSV takes it a chunk at a time while the trace may still be writing)."""
        end = self.tell()
        try:
            self.seek(offset)
            return self.read(max(0, min(size, end - offset)))
        finally:
            self.seek(end)


@dataclass
class Trigger:
    """A world setting armed for a virtual time or for an axis passing a position (the
    first tick the axis's reading is at or beyond it, in the direction it lay when
    armed). A board watches all its triggers with two engine observers, whatever their
    number: one due at the earliest armed tick, and one every tick while any position
    trigger is armed, reading each watched axis once a tick and holding it against the
    nearest armed position each way."""

    ident: int
    words: str
    when: dict[str, Any]
    apply: Callable[[Any], str]
    fired_tick: int | None = None
    said: str = ""
    error: str = ""
    tick: int | None = None  # armed for this tick
    axis: str | None = None  # armed for this axis passing `target`
    target: float = 0.0
    rising: bool = True

    def as_dict(self) -> dict[str, Any]:
        return {"id": self.ident, "words": self.words, "when": self.when,
                "fired_tick": self.fired_tick, "did": self.said, "error": self.error}


class Board:
    """What the door keeps per controller: its triggers and its trace."""

    def __init__(self, service: Service) -> None:
        self.service = service
        self.triggers: dict[int, Trigger] = {}
        self.trace: TraceWriter | None = None
        self.trace_text: BoundedText | None = None
        self.trace_every: int | None = None
        self._ids = count(1)
        self.paused_speed: float | None = None  # the speed to go back to after a pause
        self.clock_word = 0  # counts the clock requests: a step ends when a later one came
        self._timed: list[Trigger] = []  # armed for a tick
        self._timer_at: int | None = None  # the tick the timer observer is due at
        self._passing: list[Trigger] = []  # armed for a position, in the order armed
        self._edges: dict[str, tuple[float | None, float | None]] = {}  # per axis: the
        # nearest armed position above it and below it
        self._view: Any = None

    @property
    def controller(self) -> Any:
        return self.service.controller

    # ---- triggers ------------------------------------------------------------------
    def arm(self, words: str, when: dict[str, Any]) -> Trigger:
        apply = parse_world(words)  # ValueError: bad words, nothing armed
        engine = self.controller.engine
        view = self._view = self.controller.world_view()
        armed = [t for t in self.triggers.values() if t.fired_tick is None]
        if len(armed) >= TRIGGERS:
            raise BadRequest(f"at most {TRIGGERS} triggers armed on one controller", 409)
        trigger = Trigger(next(self._ids), words, when, apply)
        self.service.sync()
        if "axis" in when:
            axis = str(when["axis"])
            view.index(axis)  # KeyError: no such axis
            target = number_of(when.get("passes"), "passes")
            start = view.reading(axis).position
            trigger.axis, trigger.target, trigger.rising = axis, target, start < target
            trigger.when = {"axis": axis, "passes": target,
                            "direction": "up" if trigger.rising else "down"}
        else:
            if "tick" in when:
                tick = int(number_of(when["tick"], "tick"))
            elif "time" in when:
                tick = engine.tick_at(number_of(when["time"], "time"))
            elif "after" in when:
                tick = engine.tick + self.controller_ticks(number_of(when["after"], "after"))
            else:
                raise BadRequest("when: {\"time\": s}, {\"tick\": n}, {\"after\": s} or "
                                 "{\"axis\": NAME, \"passes\": position}")
            if tick <= engine.tick:
                raise BadRequest(f"tick {tick} is not in the future (now {engine.tick})")
            if (tick - engine.tick) * engine.period > HORIZON_SECONDS:
                raise BadRequest(f"a trigger is armed at most {HORIZON_SECONDS:g} virtual "
                                 "seconds ahead")
            trigger.tick = tick
            trigger.when = {"tick": tick}
        if len(self.triggers) >= TRIGGERS:  # forget the oldest that fired
            for ident in [i for i, t in self.triggers.items() if t.fired_tick is not None]:
                del self.triggers[ident]
                if len(self.triggers) < TRIGGERS:
                    break
        self.triggers[trigger.ident] = trigger
        if trigger.axis is not None:
            if not self._passing:
                engine.add_observer(self._watch, 1)
            self._passing.append(trigger)
            self._find_edges()
        else:
            self._timed.append(trigger)
            self._schedule()
        return trigger

    def _watch(self, _engine: Any) -> None:
        """Every tick while a position trigger is armed: each watched axis read once and
        held against its nearest position each way (`_edges`), however many are armed."""
        reading = self._view.reading
        for axis, (up, down) in self._edges.items():
            position = reading(axis).position
            if (up is not None and position >= up) or (down is not None and position <= down):
                for trigger in [t for t in self._passing if t.axis == axis and (
                        position >= t.target if t.rising else position <= t.target)]:
                    self._fire(trigger)

    def _find_edges(self) -> None:
        edges: dict[str, tuple[float | None, float | None]] = {}
        for trigger in self._passing:
            assert trigger.axis is not None
            up, down = edges.get(trigger.axis, (None, None))
            if trigger.rising:
                up = trigger.target if up is None else min(up, trigger.target)
            else:
                down = trigger.target if down is None else max(down, trigger.target)
            edges[trigger.axis] = (up, down)
        self._edges = edges

    def _schedule(self) -> None:
        """The timer observer, due at the earliest armed tick (none when none is)."""
        engine = self.controller.engine
        earliest = min((t.tick for t in self._timed if t.tick is not None), default=None)
        if earliest == self._timer_at:
            return
        if self._timer_at is not None:
            engine.remove_observer(self._due)
        self._timer_at = earliest
        if earliest is not None:
            engine.add_observer(self._due, max(1, earliest - engine.tick))

    def _due(self, engine: Any) -> None:
        now = engine.tick
        for trigger in [t for t in self._timed if t.tick is not None and t.tick <= now]:
            self._fire(trigger)
        self._timer_at = None  # (this observer is spent: the next is added anew)
        engine.remove_observer(self._due)
        self._schedule()

    def controller_ticks(self, seconds: float) -> int:
        engine = self.controller.engine
        if seconds < 0:
            raise BadRequest("after: seconds >= 0")
        if seconds > HORIZON_SECONDS:
            raise BadRequest(f"at most {HORIZON_SECONDS:g} virtual seconds ahead")
        return max(1, round(seconds / engine.period))

    def _let_go(self, trigger: Trigger) -> None:
        """No longer watched (fired or disarmed)."""
        engine = self.controller.engine
        if trigger in self._passing:
            self._passing.remove(trigger)
            self._find_edges()
            if not self._passing:
                engine.remove_observer(self._watch)
        if trigger in self._timed:
            self._timed.remove(trigger)

    def _fire(self, trigger: Trigger) -> None:
        engine = self.controller.engine
        self._let_go(trigger)
        trigger.fired_tick = engine.tick
        try:
            trigger.said = trigger.apply(self.controller)
        except (ValueError, KeyError) as error:
            trigger.error = reason_of(error)
            log.warning("board %d: trigger %d (%s): %s", self.service.number,
                        trigger.ident, trigger.words, trigger.error)

    def disarm(self, ident: int) -> Trigger:
        trigger = self.triggers.pop(ident, None)
        if trigger is None:
            raise BadRequest(f"no trigger {ident}", 404)
        self._let_go(trigger)
        self._schedule()
        return trigger

    # ---- traces --------------------------------------------------------------------
    def start_trace(self, every_ticks: int | None) -> None:
        self.stop_trace()
        self.service.sync()
        self.trace_text = BoundedText(TRACE_LIMIT)
        self.trace = TraceWriter(self.trace_text, self.controller, every_ticks)
        self.trace_every = every_ticks
        self.trace.attach()
        engine = self.controller.engine
        engine.add_observer(self._trace_full)

    def _trace_full(self, _engine: Any) -> None:
        if self.trace_text is not None and self.trace_text.full:
            self.stop_trace()

    def stop_trace(self) -> None:
        if self.trace is not None:
            self.trace.detach()
            self.controller.engine.remove_observer(self._trace_full)
            self.trace = None

    def trace_state(self) -> dict[str, Any]:
        text = self.trace_text
        return {"running": self.trace is not None,
                "rows": 0 if text is None else max(0, text.lines - 1),
                "chars": 0 if text is None else text.tell(),
                "full": bool(text is not None and text.full),
                "limit": TRACE_LIMIT if text is None else text.limit,
                "every_ticks": self.trace_every}


async def step_to(board: Board, target: int) -> None:
    """Advance a paused board to a tick in slices, the other doors served in between (a
    long step with a tick-by-tick trace or trigger must not stall the hosts)."""
    engine = board.controller.engine
    piece = max(1, round(STEP_SLICE_SECONDS / engine.period))
    word = board.clock_word
    turn = time.perf_counter()
    while engine.tick < target and board.clock_word == word:
        try:
            engine.advance(min(piece, target - engine.tick))
        except Exception as error:  # the controller's fault, told as the pacer tells it
            board.service._report(error, b"")
            return
        if time.perf_counter() - turn >= STEP_TURN_SECONDS:
            # a real pause, not only a turn of the loop: fast slices yielding with
            # sleep(0) alone left a request (a `run` to end this step) waiting seconds
            await asyncio.sleep(STEP_PAUSE_SECONDS)
            turn = time.perf_counter()
        else:
            await asyncio.sleep(0)


def number_of(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float | str):
        raise BadRequest(f"{what}: a number, not {value!r}")
    try:
        number = float(value)
    except ValueError:
        raise BadRequest(f"{what}: a number, not {value!r}") from None
    if number != number or number in (float("inf"), float("-inf")):
        raise BadRequest(f"{what}: a finite number, not {value!r}")
    return number


def reason_of(error: BaseException) -> str:
    if isinstance(error, KeyError) and error.args:
        return str(error.args[0])
    return str(error)


def world_words(body: dict[str, Any]) -> str:
    """A world setting's words from a request: `{"words": "X limits 5000 -5000"}`, or the
    JSON form that maps onto the same words: `{"axis": "X", "set": "limits", "values":
    [5000, -5000]}`, `{"input": 3, "level": true}`, `{"analog": 0, "volts": 2.5}`."""
    if "words" in body:
        words = body["words"]
        if not isinstance(words, str):
            raise BadRequest("words: the text of one world setting, e.g. 'X limits 5000 -5000'")
        return words
    if "input" in body:
        level = body.get("level")
        if not isinstance(level, bool | int):
            raise BadRequest("level: true or false")
        return f"input {_word(body['input'])} {'high' if level else 'low'}"
    if "analog" in body:
        return f"analog {_word(body['analog'])} {_word(body.get('volts'))}"
    if "axis" in body and "set" in body:
        values = body.get("values", [])
        if not isinstance(values, list):
            values = [values]
        return " ".join([_word(body["axis"]), _word(body["set"]), *(_word(v) for v in values)])
    raise BadRequest("give {\"words\": \"X limits 5000 -5000\"} or its JSON form "
                     "{\"axis\", \"set\", \"values\"} / {\"input\", \"level\"} / "
                     "{\"analog\", \"volts\"}")


def _word(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, int | float | str):
        text = str(value)
        if not text or any(c.isspace() for c in text):
            raise BadRequest(f"not one word: {value!r}")
        return text
    raise BadRequest(f"not a word or a number: {value!r}")


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False

"""What a script's directives do when they run, on any controller: `@wait until`,
`@expect` and `@trace`, spoken through the contracts (the engine, the world view)."""

from __future__ import annotations

import re
from typing import Any

from maxk.controllers.contract import Controller
from maxk.controllers.world_view import WorldView
from maxk.trace import TraceWriter

DURATION = re.compile(r"^(?P<value>\d+(?:\.\d*)?|\.\d+)\s*(?P<unit>s|sec|ms|us|ticks?)?$", re.I)

def parse_duration(text: str, update_rate_hz: float) -> int:
    """A duration to ticks: '0.5 s', '250 ms', '100 ticks' (a bare number is seconds)."""
    m = DURATION.match(text.strip())
    if not m:
        raise ValueError(f"not a duration: {text!r} (say e.g. 0.5 s, 250 ms or 100 ticks)")
    value = float(m["value"])
    unit = (m["unit"] or "s").lower()
    if unit.startswith("tick"):
        if not value.is_integer():
            raise ValueError(f"ticks must be whole: {text!r}")
        return int(value)
    seconds = value * {"s": 1.0, "sec": 1.0, "ms": 1e-3, "us": 1e-6}[unit]
    return int(-(-round(seconds * update_rate_hz * 1e9) // 10**9))  # ceil without float fuzz


def wait_until(controller: Controller, view: WorldView, what: tuple, timeout: int) -> bool:
    """Advance until the condition holds (False on timeout). Done and idle change only at
    events; a position is watched tick by tick while the axis moves, so the wait ends on
    the very tick it is reached."""
    engine = controller.engine
    kind, names = what[0], what[1]
    if kind == "idle" and not names:
        console = controller.console()
        return engine.run_until(lambda _e: console.is_idle(), timeout)
    names = names or view.axis_names
    for name in names:
        view.index(name)  # KeyError for an axis it does not have
    if kind == "done":
        return engine.run_until(lambda _e: all(view.reading(n).done for n in names), timeout)
    if kind == "idle":
        return engine.run_until(lambda _e: not any(view.reading(n).moving for n in names),
                                timeout)
    op, at = what[2], what[3]

    def reached() -> bool:
        p = view.reading(names[0]).position
        return p >= at if op == ">=" else p <= at if op == "<=" else p == at

    deadline = engine.tick + timeout
    engine.settle()
    while not reached():
        if engine.tick >= deadline:
            return False
        if view.reading(names[0]).moving:
            engine.advance_to(engine.tick + 1)
        else:  # nothing changes the position before the next event
            event = engine.next_event()
            engine.advance_to(deadline if event is None else
                              min(deadline, max(event, engine.tick + 1)))
    return True


def start_trace(controller: Controller, args: tuple[str, str | None],
                 traces: list[tuple[Any, Any]]) -> str | None:
    path, every = args
    try:
        ticks = None if every is None else max(
            1, parse_duration(every, controller.engine.update_rate_hz))
        stream = open(path, "w", encoding="utf-8", newline="")  # noqa: SIM115
    except (OSError, ValueError) as error:
        return str(error)
    tracer = TraceWriter(stream, controller, ticks)
    tracer.attach()
    traces.append((tracer, stream))
    return None


def check_expect(view: WorldView, text: str, args: tuple) -> str | None:
    """None when the expectation holds, else what was found instead."""
    g = dict(args)
    try:
        if not g:  # the controller's own words
            found = view.extra_expect(text.split())
            if found is False:
                return f"cannot read @expect {text!r} on this controller"
            return found  # type: ignore[return-value]
        if g["field"]:
            r = view.reading(g["axis"])
            fieldname = g["field"].lower()
            value = {"position": r.position, "encoder": r.encoder,
                     "velocity": round(r.velocity)}[fieldname]
            if value is None:
                return f"{r.name} has no {fieldname}"
            return None if value == int(g["value"]) else f"{r.name} {fieldname} {value}"
        if g["state"]:
            r = view.reading(g["axis2"])
            state = " ".join(g["state"].lower().split())
            if state in ("done", "not done"):
                return None if r.done == (state == "done") else (
                    f"{r.name} {'done' if r.done else 'not done'}")
            if state in ("moving", "not moving", "idle"):
                return None if r.moving == (state == "moving") else (
                    f"{r.name} {'moving' if r.moving else 'not moving'}")
            over = bool({"overtravel", "plus-limit", "minus-limit"} & set(r.flags))
            return None if over == (state == "overtravel") else (
                f"{r.name} {'overtravel' if over else 'no overtravel'}")
        number, io = int(g["bit"]), g["io"].lower()
        want = g["level"].lower() == "high"
        level = view.output_level(number) if io in ("bit", "output") else None
        if level is None and io != "output":
            if number not in view.inputs:
                return f"no {io} {number}"
            level = view.input_level(number)
        if level is None:
            return f"no output {number}"
        return None if level == want else f"{io} {number} {'high' if level else 'low'}"
    except KeyError as error:  # an axis the controller does not have
        return str(error.args[0])

"""Command scripts: controller commands, expected replies and waits in virtual time.

A script is plain text, one item per line (format in docs/scripts.md):

    // comment                      (blank lines too)
    @board MAXk-4000                 (before the first command; default MAXk-8000;
                                      any model: MM4005, MC405, PoKeys57CNC...;
                                      several models make one test per model)
    @rate 4096                       (update rate in Hz, one the controller runs at,
                                      before the first command; several: one test each)
    AX; VL5000; AC50000; MA10000; GO; ID;
    @wait 0.5 s                      (also: ms, ticks)
    @wait until X done within 5 s    (also: until idle, until all done, until X idle,
                                      until X position >= 5000)
    AX RP
    < 10000                          (the reply the previous command line must give)
    @expect X position 10000         (also: encoder, velocity, done, not done, moving,
                                      overtravel, input 3 high, output 9 low; a kind's
                                      own: the MAXk's error, doorbell 0x..., captures 3)
    @world X limits 5000 -5000       (the machine around the controller: switches,
                                      index, faults, inputs, analog; docs/io.md)
    @trace run.csv every 1 ms        (a CSV of every axis from here to the end)

Every directive speaks to any controller through the contracts (its console, its engine,
its world view), with axis names as that controller names them (X on a MAXk, 1 on an
MM4005, 0 on an MC405). Controller commands are sent exactly as written, each line
ended by a CR as a terminal would. Directives start with `@`, expected replies with `<`,
comments with `//`: no controller's command starts with any of these.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from maxk.controllers.contract import BuildOptions, Controller
from maxk.controllers.registry import DEFAULT_MODEL, build, canonical_model, kind_of
from maxk.controllers.world_settings import parse_world
from maxk.script_directives import (
    DURATION,
    check_expect,
    parse_duration,
    start_trace,
    wait_until,
)

CHECK_RATE_HZ = 1000  # a duration's form is checked at this rate when the script is read


class ScriptError(Exception):
    """A script line that cannot be understood (names the line)."""

    def __init__(self, path: str, line: int, message: str) -> None:
        super().__init__(f"{path}:{line}: {message}")
        self.path = path
        self.line = line
        self.message = message


@dataclass(frozen=True)
class Step:
    line: int
    kind: str  # "send", "expect-reply", "wait", "wait-until", "expect"
    text: str
    args: tuple = ()


@dataclass
class Script:
    path: str
    steps: list[Step]
    models: list[str] = field(default_factory=lambda: [DEFAULT_MODEL])
    update_rates_hz: list[int | None] = field(default_factory=lambda: [None])  # None:
    # the controller's own default rate
    lines: list[str] = field(default_factory=list)

    @property
    def model(self) -> str:
        return self.models[0]

    @property
    def update_rate_hz(self) -> int | None:
        return self.update_rates_hz[0]

    @property
    def rate_given(self) -> bool:
        return self.update_rates_hz != [None]

    @property
    def checks_replies(self) -> bool:
        """A script with any expected reply is a regression: every reply must match."""
        return any(step.kind == "expect-reply" for step in self.steps)


DEFAULT_TIMEOUT_S = 60.0


def parse_script(text: str, path: str = "<script>") -> Script:
    lines = text.splitlines()
    script = Script(path, [], lines=lines)
    seen_command = False
    for number, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line.startswith("//"):
            continue
        if line.startswith("<"):
            if not script.steps or script.steps[-1].kind not in ("send", "expect-reply"):
                raise ScriptError(path, number, "an expected reply must follow a command line")
            script.steps.append(Step(number, "expect-reply", line[1:].strip()))
            continue
        if line.startswith("@"):
            word, _, rest = line[1:].partition(" ")
            word = word.lower()
            rest = rest.strip()
            try:
                if word == "board":
                    if seen_command:
                        raise ValueError("@board must come before the first command")
                    names = rest.replace(",", " ").split()
                    if not names:
                        raise ValueError(f"@board needs a model, e.g. @board {DEFAULT_MODEL}")
                    script.models = [canonical_model(n) for n in names]
                    _check_rates(script)
                elif word == "rate":
                    if seen_command:
                        raise ValueError("@rate must come before the first command")
                    rates = rest.replace(",", " ").split()
                    if not rates or not all(r.isdigit() for r in rates):
                        raise ValueError("@rate takes update rates in Hz, e.g. @rate 4096")
                    script.update_rates_hz = [int(r) for r in rates]
                    _check_rates(script)
                elif word == "trace":
                    script.steps.append(_parse_trace(number, rest))
                elif word == "wait":
                    script.steps.append(_parse_wait(number, rest))
                elif word == "expect":
                    script.steps.append(_parse_expect(number, rest))
                elif word == "world":
                    script.steps.append(Step(number, "world", rest, (parse_world(rest),)))
                else:
                    raise ValueError(f"unknown directive @{word}")
            except ValueError as error:
                raise ScriptError(path, number, str(error)) from None
            continue
        seen_command = True
        script.steps.append(Step(number, "send", raw.rstrip("\r\n")))
    _check_against_controllers(script)
    return script


def _check_against_controllers(script: Script) -> None:
    """Directives checked when the script is read, on a fresh controller of each model
    it names: axis names, input numbers and a kind's own words (the MAXk's `capture`,
    `doorbell`) are refused now, naming the line, not half-way through a run."""
    if not any(step.kind in ("world", "expect", "wait-until") for step in script.steps):
        return
    for model in dict.fromkeys(script.models):
        view = build(model).world_view()
        for step in script.steps:
            try:
                if step.kind == "world":
                    step.args[0](view)
                elif step.kind == "wait-until":
                    for name in step.args[0][1]:
                        view.index(name)
                elif step.kind == "expect":
                    g = dict(step.args)
                    if not g:
                        if view.extra_expect(step.text.split()) is False:
                            raise ValueError(f"cannot read @expect {step.text!r} on the "
                                             f"{model}: say e.g. 'X position 1000', 'X done'"
                                             ", 'X overtravel' or 'input 3 high'")
                    elif g["axis"] or g["axis2"]:
                        view.index(g["axis"] or g["axis2"])
            except (KeyError, ValueError, OverflowError) as error:
                message = error.args[0] if error.args else str(error)
                raise ScriptError(script.path, step.line, str(message)) from None


def _check_rates(script: Script) -> None:
    """Every model of the script must run at every rate it names (checked as soon as
    both are known, so a script is refused when read, not half-way through a run)."""
    for model in script.models:
        for rate in script.update_rates_hz:
            kind_of(model).check_rate(rate)


def _axes(text: str) -> tuple[str, ...]:
    """Axis names in a wait: `X`, `XYZ` (letters run together), `1 2`, `1,2`."""
    names = text.replace(",", " ").split()
    if len(names) == 1 and names[0].isalpha():
        return tuple(names[0].upper())
    return tuple(n.upper() for n in names)


_WAIT_WHAT = re.compile(
    r"^(?:(?P<idle>idle)|all\s+done"
    r"|(?P<axes>[A-Za-z0-9][A-Za-z0-9 ,]*?)\s+(?P<state>done|idle)"
    r"|(?P<axis>[A-Za-z0-9]+)\s+position\s*(?P<op>>=|<=|=)?\s*(?P<at>-?\d+))$", re.I)


def _parse_wait(line: int, rest: str) -> Step:
    if rest.lower().startswith("until"):
        body, _, timeout = rest[5:].strip().partition(" within ")
        timeout = timeout.strip() or f"{DEFAULT_TIMEOUT_S} s"
        parse_duration(timeout, CHECK_RATE_HZ)  # ValueError now, not mid-run
        m = _WAIT_WHAT.match(body.strip())
        if m is None:
            raise ValueError(f"cannot read @wait {rest!r}: say e.g. 'until X done', "
                             "'until idle', 'until all done', 'until 1 idle' or "
                             "'until X position >= 5000'")
        if m["idle"]:
            what: tuple = ("idle", ())
        elif m["axes"]:
            what = (m["state"].lower(), _axes(m["axes"]))
        elif m["axis"]:
            what = ("position", (m["axis"].upper(),), m["op"] or ">=", int(m["at"]))
        else:
            what = ("done", ())
        return Step(line, "wait-until", rest, (what, timeout))
    if not rest:
        raise ValueError("@wait needs a duration or 'until ...'")
    if not DURATION.match(rest):
        raise ValueError(f"not a duration: {rest!r} (say e.g. 0.5 s, 250 ms, 100 ticks, "
                         "or until X done)")
    parse_duration(rest, CHECK_RATE_HZ)  # e.g. 1.5 ticks: refused now, not mid-run
    return Step(line, "wait", rest)


_EXPECT = re.compile(
    r"^(?:(?P<axis>[A-Za-z0-9]+)\s+(?P<field>position|encoder|velocity)\s+(?P<value>-?\d+)"
    r"|(?P<axis2>[A-Za-z0-9]+)\s+(?P<state>not\s+done|done|moving|not\s+moving|idle"
    r"|no\s+overtravel|overtravel)"
    r"|(?P<io>bit|input|output)\s+(?P<bit>\d+)\s+(?P<level>high|low))$",
    re.I,
)


def _parse_expect(line: int, rest: str) -> Step:
    """The shared expectations are read now; any other words are the controller's own
    (the MAXk's `error`, `doorbell 0x...`, `captures 2`) and are read when they run."""
    words = rest.split()
    if not words:
        raise ValueError("@expect needs something to check, e.g. 'X position 1000'")
    if words[0].lower() == "error" or [w.lower() for w in words] == ["no", "error"]:
        text = rest.strip()[len("error"):].strip() if words[0].lower() == "error" else None
        return Step(line, "expect-error", rest, (text,))
    m = _EXPECT.match(rest.strip())
    return Step(line, "expect", rest, () if m is None else tuple(m.groupdict().items()))


_TRACE = re.compile(r"^(?P<path>\S+)(?:\s+every\s+(?P<every>.+))?$", re.I)


def _parse_trace(line: int, rest: str) -> Step:
    m = _TRACE.match(rest.strip())
    if m is None:
        raise ValueError("@trace FILE.csv [every DURATION]")
    if m["every"]:
        parse_duration(m["every"], CHECK_RATE_HZ)
    return Step(line, "trace", rest, (m["path"], m["every"]))


# ---- running -------------------------------------------------------------------------
@dataclass
class Failure:
    line: int
    command: str
    expected: str
    actual: str
    tick: int
    state: list[str] = field(default_factory=list)  # the board when it failed

    def __str__(self) -> str:
        return (f"line {self.line} (tick {self.tick}): {self.command}\n"
                f"  expected: {self.expected}\n  actual:   {self.actual}")

    def report(self) -> str:
        """The failure with the board's state at that moment, for pytest."""
        return "\n".join([str(self), "  board state:", *("    " + s for s in self.state)])


def board_state(controller: Controller) -> list[str]:
    """A compact picture of the controller: what a failure report shows."""
    engine = controller.engine
    return [f"tick {engine.tick} ({engine.time:.6f} s), {controller.model} at "
            f"{engine.update_rate_hz:g} Hz", *controller.console().status_lines()]


@dataclass
class Transcript:
    """What a run produced: each command line with its replies, and any failures."""

    entries: list[tuple[int, int, str, list[str]]] = field(default_factory=list)
    failures: list[Failure] = field(default_factory=list)
    board: Controller | None = None
    errors: list[tuple[int, int, str]] = field(default_factory=list)  # (line, tick, the
    # controller's message): every command error the run raised, expected or not

    @property
    def replies(self) -> list[str]:
        return [r for _, _, _, replies in self.entries for r in replies]


def run_script(script: Script, *, model: str | None = None,
               update_rate_hz: int | None = None, check: bool = True,
               board: Controller | None = None,
               on_step: Callable[[Step], None] | None = None) -> Transcript:
    """Run a script on a fresh controller; the same script always gives the same
    transcript. Written against the contracts, for every controller alike: its console
    runs the command lines, its engine owns time, its world view answers `@world`,
    `@expect` and `@wait until`.

    With check=False nothing is compared (what `--record` uses). A caller may pass its
    own fresh controller, e.g. one with a trace observer attached, and an on_step
    callback that runs after every step.
    """
    if board is None:
        board = build(model or script.model,
                      BuildOptions(update_rate_hz=update_rate_hz or script.update_rate_hz))
    controller = board
    console = controller.console()
    engine = controller.engine
    view = controller.world_view()
    transcript = Transcript(board=controller)
    pending: list[str] = []  # replies of the last command line not yet matched
    last_command, last_line = "", 0
    strict = check and script.checks_replies
    traces: list[tuple[Any, Any]] = []
    unexpected: list[tuple[int, int, str, str]] = []  # errors no directive has taken yet:
    # (line, tick, what raised it, the message)
    expected_replies: list[str] = []  # the `<` lines of the last command line

    def fail(line: int, command: str, expected: str, actual: str,
             tick: int | None = None) -> None:
        transcript.failures.append(
            Failure(line, command, expected, actual, engine.tick if tick is None else tick,
                    board_state(controller)))

    def note_errors(step: Step, what: str, replies: list[str]) -> None:
        """The controller's command errors since the last look, charged to this step."""
        for message in console.refused(replies, console.new_errors()):
            text = message.removeprefix("! ")
            transcript.errors.append((step.line, engine.tick, text))
            unexpected.append((step.line, engine.tick, what, text))

    def settle_errors() -> None:
        """Before the next command line and at the end: in a regression, an error the
        script did not say it expects (`@expect error`, or its text as a `<` reply)
        fails, with the line, the tick and the controller's message."""
        for line, tick, what, text in unexpected:
            if strict and f"! {text}" not in expected_replies and text not in \
                    expected_replies:
                fail(line, what, "(no command error)", text, tick)
        unexpected.clear()

    try:
        for step in script.steps:
            if strict and pending and step.kind != "expect-reply":
                fail(last_line, last_command, "(no more replies)", pending[0])
                pending.clear()
            if step.kind == "send":
                settle_errors()
                expected_replies = []
                try:
                    replies = console.execute(step.text)
                except Exception as error:  # a fault in the emulator: a failure, not a crash
                    replies = []
                    fail(step.line, step.text, "(the line run)",
                         f"internal error: {type(error).__name__}: {error}")
                transcript.entries.append((step.line, engine.tick, step.text, replies))
                note_errors(step, step.text, replies)
                pending = list(replies)
                last_command, last_line = step.text, step.line
            elif step.kind == "expect-reply":
                expected_replies.append(step.text)
                if not check:
                    continue
                actual = pending.pop(0) if pending else "(no reply)"
                if actual != step.text:
                    fail(step.line, last_command, step.text, actual)
            elif step.kind == "wait":
                try:
                    engine.advance(parse_duration(step.text, engine.update_rate_hz))
                except Exception as error:  # a fault in the emulator: a failure, not a crash
                    fail(step.line, f"@wait {step.text}", step.text,
                         f"internal error: {type(error).__name__}: {error}")
            elif step.kind == "wait-until":
                what, timeout_text = step.args
                timeout = parse_duration(timeout_text, engine.update_rate_hz)
                try:
                    ok = wait_until(controller, view, what, timeout)
                except KeyError as error:  # an axis this controller does not have
                    fail(step.line, f"@wait {step.text}", step.text, str(error.args[0]))
                    continue
                except Exception as error:  # a fault in the emulator: a failure, not a crash
                    fail(step.line, f"@wait {step.text}", step.text,
                         f"internal error: {type(error).__name__}: {error}")
                    continue
                if not ok and check:
                    fail(step.line, f"@wait {step.text}", step.text.partition(" within ")[0],
                         f"timed out after {timeout_text}")
            elif step.kind == "world":
                try:
                    step.args[0](view)
                except (KeyError, ValueError, OverflowError) as error:
                    fail(step.line, f"@world {step.text}", step.text,
                         str(error.args[0] if error.args else error))
            elif step.kind == "trace":
                problem = start_trace(controller, step.args, traces)
                if problem is not None:
                    fail(step.line, f"@trace {step.text}", step.text, problem)
            elif step.kind == "expect-error":
                note_errors(step, last_command, [])
                problem = _take_errors(step, unexpected, view)
                if problem is not None and check:
                    fail(step.line, f"@expect {step.text}", step.text, problem)
            elif step.kind == "expect" and check:
                problem = check_expect(view, step.text, step.args)
                if problem is not None:
                    fail(step.line, f"@expect {step.text}", step.text, problem)
            if step.kind not in ("send", "expect-error"):
                note_errors(step, f"@{step.kind.partition('-')[0]} {step.text}"
                            if step.kind != "expect-reply" else last_command, [])
            for tracer, _stream in traces:
                tracer.sample(f"line {step.line}")
            if on_step is not None:
                on_step(step)
        settle_errors()
    finally:
        for tracer, stream in traces:
            tracer.detach()
            stream.close()
    if strict and pending:
        fail(last_line, last_command, "(no more replies)", pending[0])
    return transcript


def _take_errors(step: Step, unexpected: list[tuple[int, int, str, str]],
                 view: Any) -> str | None:
    """`@expect error [TEXT]`: the command lines since the last one raised an error (one
    whose message holds TEXT, in any case); they are expected now. `@expect no error`:
    none did. Either also runs the kind's own check of the same words where it has one
    (the MAXk's command-error flag, doorbell bit 24). A problem, or None."""
    (text,) = step.args
    own = view.extra_expect(step.text.split())
    own_problem = own if isinstance(own, str) else None
    if text is None:  # @expect no error
        if unexpected:
            first = unexpected[0][3]
            unexpected.clear()  # reported here, once
            return f"command error: {first}"
        return own_problem
    if not unexpected:
        if own is None:
            return None  # the kind's own word held (the MAXk's flag still set)
        return own_problem or "no command error"
    found = not text or any(text.lower() in message.lower() for *_, message in unexpected)
    problem = None if found else f"command error: {unexpected[0][3]} (not {text!r})"
    unexpected.clear()  # expected, or reported here: once either way
    return problem


def load_script(path: str | Path) -> Script:
    p = Path(path)
    return parse_script(p.read_text(encoding="utf-8"), str(p))



def record(script: Script, transcript: Transcript) -> str:
    """The script's text with every command line followed by the replies it gave.

    Existing expected replies are replaced; everything else (comments, waits,
    directives, blank lines) is kept as written. Running the result reproduces it.
    """
    replies_by_line = {line: replies for line, _tick, _text, replies in transcript.entries}
    errors_by_line: dict[int, list[str]] = {}
    for line, _tick, text in transcript.errors:
        errors_by_line.setdefault(line, []).append(text)
    out: list[str] = []
    retake = False  # after a command line that raised errors, until the next command line
    for number, raw in enumerate(script.lines, start=1):
        stripped = raw.strip()
        if stripped.startswith("<"):
            continue
        if number in replies_by_line:
            retake = number in errors_by_line
        elif retake and re.match(r"@expect\s+error\b", stripped, re.I):
            continue  # written anew from what this run raised
        out.append(raw)
        replies = replies_by_line.get(number, [])
        out.extend(f"< {reply}" for reply in replies)
        out.extend(f"@expect error {text}" for text in errors_by_line.get(number, [])
                   if f"! {text}" not in replies and text not in replies)
    return "\n".join(out) + "\n"

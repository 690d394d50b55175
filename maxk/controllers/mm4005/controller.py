"""The Newport MM4005 behind the doors, and from Python in virtual time.

    >>> from maxk.controllers.mm4005 import MM4005Controller
    >>> mm = MM4005Controller("MM4005-2")
    >>> mm.send("1VA1;1AC5;1PA2.5")
    []
    >>> mm.run_until_idle()
    True
    >>> mm.query("1TP")
    '1TP2.5000'

One machine (`personalities/mm4005/machine.py`), one interpreter and so one error
register (TE/TB read the controller's only error buffer, whoever asks), and a line
session per host with its own half-received line. Nothing here reads the wall clock.

Models: "MM4005" has the four axes an MM4005 drives; "MM4005-1".."MM4005-4" name how
many are installed (our decision: the EPICS driver counts the TP fields, and the
reference exchanges were recorded against two).
"""

from __future__ import annotations

import csv
import io
import logging
import os
import weakref
from collections import deque
from pathlib import Path
from typing import IO, Final

from maxk.commands.mm4005 import COMMANDS, Interpreter, MM4005Session
from maxk.commands.mm4005.fmt import fixed, position_decimals
from maxk.controllers.contract import ConsoleBase, Notify, Transport, VirtualTime
from maxk.controllers.world_view import AxisReading, WorldView
from maxk.firmware_model.world import AxisWorld
from maxk.personalities.mm4005 import ErrorCode, ErrorRegister
from maxk.personalities.mm4005.execution import PulseRecord
from maxk.personalities.mm4005.io import ANALOG_INPUTS, IO_BITS
from maxk.personalities.mm4005.machine import MAX_AXES, MM4005
from maxk.personalities.mm4005.programs import MEMORY, ProgramStore
from maxk.personalities.mm4005.timed import TracePoint

from .trace import MM4005Recording, PathTrace

log = logging.getLogger("maxk.mm4005")

DEFAULT_MODEL: Final = "MM4005"
MODELS: Final = (DEFAULT_MODEL, *(f"MM4005-{n}" for n in range(1, MAX_AXES + 1)))
STATUS_WIDTH: Final = 80
SEND_WAIT_S: Final = 600.0  # a line sent from Python or typed waits this long at most (D)
PULSE_CSV_HEADER: Final = ("pulse", "tick", "time_s", "distance", "element", "x_counts",
                           "y_counts", "x", "y")


def axis_count_of(model: str) -> int:
    """'MM4005' -> 4, 'MM4005-2' -> 2; ValueError for anything else."""
    for name in MODELS:
        if name.lower() == model.lower():
            return MAX_AXES if name == DEFAULT_MODEL else int(name.rsplit("-", 1)[1])
    raise ValueError(f"unknown MM4005 model {model!r} (models: {', '.join(MODELS)})")


class _NotedRegister(ErrorRegister):
    """The controller's error register, also noting each error for the console (which
    shows it without reading it, so a host's TE still sees it); the newest 200 are kept
    between two looks."""

    def __init__(self) -> None:
        super().__init__()
        self.noted: deque[ErrorCode] = deque(maxlen=200)

    def record(self, code: ErrorCode) -> None:
        super().record(code)
        self.noted.append(code)


class MM4005Controller(VirtualTime):
    """An MM4005: the door contract (controllers/contract.py) and a Python API."""

    kind = "MM4005"
    transports: tuple[Transport, ...] = ("tcp", "pty")
    packet_size = None

    def __init__(self, model: str = DEFAULT_MODEL,
                 archive: str | os.PathLike[str] | None = None) -> None:
        """`archive`: the program memory's file (stored programs survive a power cycle
        and a restart); None keeps them in memory only."""
        self.machine = MM4005(axis_count_of(model))
        self.machine.programs = ProgramStore(archive)
        if self.machine.programs.problem:
            log.error("%s", self.machine.programs.problem)
        self._model = next(m for m in MODELS if m.lower() == model.lower())
        self.interpreter = self._new_interpreter()
        self._sessions: list[MM4005Session] = []
        self._console: MM4005Console | None = None
        self._own: MM4005Session | None = None  # send()'s session

    def _new_interpreter(self) -> Interpreter:
        interpreter = Interpreter(self.machine)
        interpreter.context.errors = _NotedRegister()
        return interpreter

    # ---- the door contract -----------------------------------------------------------------
    @property
    def model(self) -> str:
        return self._model

    @property
    def engine(self) -> MM4005:
        return self.machine

    def open_session(self, notify: Notify | None = None) -> MM4005Session:
        """A host's CR-framed line session; the MM4005 never speaks unasked, so `notify`
        is never called."""
        session = MM4005Session(self.machine, self.interpreter, notify)
        self._sessions = [s for s in self._sessions if not s.closed] + [session]
        return session

    def console(self) -> MM4005Console:
        if self._console is None:
            self._console = MM4005Console(self)
        return self._console

    def reset(self) -> None:
        """Power-up again: motion stops at once, defaults back, the error register clear;
        a line half received or held by a wait is lost, as is a running program; the
        stored programs stay (read again from the archive when there is one)."""
        self.machine.reset()
        programs = self.machine.programs
        programs.load()
        if programs.problem:
            log.error("%s", programs.problem)
        self.interpreter = self._new_interpreter()
        self._sessions = [s for s in self._sessions if not s.closed]
        for session in self._sessions:
            session.power_up(self.interpreter)

    # ---- talking to it ------------------------------------------------------------------
    def send(self, line: str) -> list[str]:
        """One command line (no CR needed); its replies, without CR. A line that waits
        (WS) runs virtual time until its wait is over (at most `SEND_WAIT_S`: then it is
        given up, D); a program's replies come with the next line's."""
        session = self._own
        if session is None or session.closed:
            session = self._own = self.open_session()
        session.feed(line.rstrip("\r").encode("latin-1", "replace") + b"\r")
        if session.waiting:
            self.machine.run_until(lambda _m: not session.waiting, self.ticks(SEND_WAIT_S))
            if session.waiting:
                session.abandon()
                log.warning("%r still waiting after %g s: given up", line, SEND_WAIT_S)
        text = session.read().decode("latin-1")
        return [reply for reply in text.split("\r") if reply]

    def query(self, line: str) -> str:
        """A line that must give exactly one reply."""
        replies = self.send(line)
        if len(replies) != 1:
            raise ValueError(f"{line!r} gave {len(replies)} replies, expected 1 "
                             f"(error register: {self.errors.peek().char})")
        return replies[0]

    @property
    def errors(self) -> ErrorRegister:
        return self.interpreter.errors

    # ---- time -----------------------------------------------------------------------------
    def run_until_idle(self, timeout: float = 600.0) -> bool:
        """Advance until no axis moves and no trajectory runs; False on timeout."""
        machine = self.machine
        deadline = machine.tick + self.ticks(timeout)
        while not machine.is_idle():
            # jump to the latest end the machine knows of (a trajectory's last tick, a
            # move's end) in one pass over its events; then look again (a stop hands
            # over to a move, a home search goes on)
            end = machine.known_end()
            if end is None or end <= machine.tick:
                return machine.run_until(lambda m: m.is_idle(), deadline - machine.tick)
            machine.advance_to(min(end, deadline))
            if machine.tick >= deadline:
                return machine.is_idle()
        return True

    # ---- the world and what came out -------------------------------------------------------
    def stage(self, axis: int) -> AxisWorld:
        """Axis n's stage (switch positions in counts since power-up). Call
        `world_changed()` after changing it while something moves."""
        return self.machine.world.axes[axis - 1]

    def world_changed(self) -> None:
        self.machine.world_changed()

    def world_view(self) -> MM4005WorldView:
        """The world contract (controllers/world_view.py): axes 1..n."""
        return MM4005WorldView(self.machine)

    def trace_path(self, axes: tuple[int, int] | None = None,
                   every_ticks: int = 20) -> PathTrace:
        """Start sampling two axes (default: the trajectory's AX and AY) every N ticks
        (default 10 ms); `detach()` stops it."""
        if axes is None:
            axes = (self.machine.trajectory.x_axis, self.machine.trajectory.y_axis)
        return PathTrace(self.machine, axes, every_ticks).attach()

    def record(self, every_ticks: int = 20) -> MM4005Recording:
        """The trajectory's XY path sampled every N ticks, with the pulses marked on it
        (`maxk run --trace/--plot`)."""
        return MM4005Recording(self, self.trace_path(every_ticks=every_ticks))

    @property
    def pulses(self) -> list[PulseRecord]:
        """The XY trajectory's synchronized pulses the ring still holds."""
        return self.machine.pulse_log

    @property
    def trace_points(self) -> list[TracePoint]:
        """The time-based trajectory's pulses (TQ's trace) the ring still holds."""
        return self.machine.trace_points

    @property
    def timed_log(self) -> bool:
        """Is the pulse log the time-based trajectory's (EC) rather than the XY one's?"""
        records = self.machine.pulse_trace.records
        return bool(records) and isinstance(records[-1], TracePoint)

    def pulse_header(self) -> tuple[str, ...]:
        if not self.timed_log:
            return PULSE_CSV_HEADER
        names = range(1, self.machine.axis_count + 1)
        return ("pulse", "tick", "time_s", "element",
                *(f"{n}{kind}" for n in names for kind in ("TH", "TP")))

    def pulse_row(self, record: PulseRecord | TracePoint) -> tuple[object, ...]:
        period = self.machine.period
        if isinstance(record, TracePoint):
            values = [v for pair in zip(record.theoretical, record.actual, strict=True)
                      for v in pair]
            return (record.number, record.tick, f"{record.tick * period:.4f}",
                    record.element, *(f"{v:.6f}" for v in values))
        p = record
        return (p.index, p.tick, f"{p.tick * period:.4f}", f"{p.distance:.6f}", p.element,
                p.x_counts, p.y_counts, p.x, p.y)

    def pulse_rows(self) -> list[tuple[object, ...]]:
        return [self.pulse_row(r) for r in self.machine.pulse_trace.records]

    def pulse_csv(self, path: str | Path | None = None) -> str:
        """The pulse log the ring holds as CSV (XY runs: tick, time, path distance,
        element, X/Y; time-based runs: tick, time, element, every axis's TH and TP);
        written to `path` when given."""
        out = io.StringIO()
        writer = csv.writer(out, lineterminator="\n")
        writer.writerow(self.pulse_header())
        writer.writerows(self.pulse_rows())
        text = out.getvalue()
        if path is not None:
            Path(path).write_text(text)
        return text

    def stream_pulses(self, stream: IO[str] | None) -> None:
        """From now on every pulse, as it fires, is written to `stream` as a CSV row
        (the whole log, however long: the ring keeps only the newest); None stops."""
        trace = self.machine.pulse_trace
        if stream is None:
            trace.sink = None
            return
        writer = csv.writer(stream, lineterminator="\n")

        def sink(record: PulseRecord | TracePoint) -> None:
            if stream.closed:  # its owner went away: stop streaming
                trace.sink = None
                return
            writer.writerow(self.pulse_row(record))

        trace.sink = sink


class MM4005Console(ConsoleBase):
    """The REPL's and scripts' view of an MM4005 on the shared `ConsoleBase`: the prompt,
    the per-axis status table and idleness (no axis moving: a trajectory's axes move
    until it ends) come from the contract; the status line adds a running trajectory's
    progress (AT, or XCn/N of a time-based run) and the pulses fired."""

    controller: MM4005Controller

    def __init__(self, controller: MM4005Controller) -> None:
        super().__init__(controller)
        self._stream: IO[str] | None = None  # the file :pulses-csv streams to

    def _close_stream(self) -> None:
        if self._stream is not None:
            self.controller.stream_pulses(None)
            self._stream.close()
            self._stream = None

    def execute(self, line: str) -> list[str]:
        """The replies of one line (without CR)."""
        return self.controller.send(line)

    def new_errors(self) -> list[str]:
        """`! C Parameter out of limits` for each error since the last look (this
        console's lines and every host's), without reading the register."""
        register = self.controller.interpreter.errors
        assert isinstance(register, _NotedRegister)
        lines = [f"! {code.char} {code.text}" for code in register.noted]
        register.noted.clear()
        return lines

    def _position_text(self, axis: int) -> str:
        m = self.controller.machine
        return fixed(m.position(axis), position_decimals(m.resolution(axis)))

    def status_line(self, width: int = STATUS_WIDTH) -> str:
        m = self.controller.machine
        parts = [f"{m.time:.3f}s"]
        for axis in range(1, m.axis_count + 1):
            status = m.status(axis)
            flag = "*" if status.moving else ("o" if status.power_off else "")
            parts.append(f"{axis}:{self._position_text(axis)}{flag}")
        element = m.trajectory_element()
        timed = m.timed_run
        if timed is not None and not timed.finished:  # the time-based run: elements done
            parts.append(f"XC{m.elements_done()}/{len(timed.starts) - 1}")
        elif element:
            parts.append(f"AT{element}")
        if m.pulse_trace.total:
            parts.append(f"P{m.pulse_trace.total}")
        line = " ".join(parts)
        if len(line) > width:  # 4 long positions: drop the decimals beyond 2
            parts = [parts[0]] + [_shorten(p) for p in parts[1:]]
            line = " ".join(parts)[:width]
        return line

    def status_lines(self) -> list[str]:
        """The contract's axis table (counts), then the MM4005's own words per axis (user
        units, MS, DP, VA, AC, limits) and its trajectories, pulses, servo, register."""
        m = self.controller.machine
        lines = [f"{self.controller.model} at {m.time:.4f} s (tick {m.tick}, "
                 f"{m.update_rate_hz:g} Hz)", *super().status_lines()]
        for axis in range(1, m.axis_count + 1):
            status = m.status(axis)
            left, right = m.travel_limits(axis)
            lines.append(
                f"axis {axis}: TP {self._position_text(axis)} DP {m.target(axis):.4f} "
                f"MS {status.char} ({status.byte:#04x}) VA {m.velocity(axis):g} "
                f"AC {m.acceleration(axis):g} TU {m.resolution(axis):g} "
                f"limits {left:g}..{right:g}")
        traj = m.trajectory
        lines.append(f"trajectory: {len(traj.elements)} elements, AT{m.trajectory_element()}, "
                     f"X axis {traj.x_axis}, Y axis {traj.y_axis}, VV {traj.velocity:g}, "
                     f"VS {traj.acceleration:g}")
        timed = m.timed
        lines.append(f"time-based trajectory: {len(timed.elements)} elements, axes "
                     f"{','.join(map(str, sorted(timed.axes))) or '-'}, UC {timed.accel_time:g}, "
                     f"{'verified' if timed.verified else 'not verified'}, MB{timed.pulse_start} "
                     f"ME{timed.pulse_end} MN{timed.pulse_request}, XC{m.elements_done()}")
        trace = m.pulse_trace
        lines.append(f"pulses fired {trace.total} (the log keeps the newest {trace.capacity:,}; "
                     f"{trace.dropped:,} dropped)")
        servos = [str(n) for n in range(1, m.axis_count + 1) if m.settings[n - 1].servo_on]
        lines.append(f"servo loop on axes {','.join(servos) or 'none (factory gains: exact '}"
                     + ("" if servos else "profile-only axes)"))
        gpio, acquisition = m.gpio, m.global_trace
        lines.append(f"I/O: outputs SB{gpio.output_port()}, inputs RB"
                     f"{sum(1 << (b - 1) for b in range(1, 9) if m.input_level(b))}; "
                     f"global trace GQ{acquisition.requested} SQ{acquisition.period}, "
                     f"{acquisition.taken} taken"
                     f"{' (acquiring)' if acquisition.acquiring else ''}")
        lines.append(f"error register: {self.controller.errors.peek().char}")
        store = m.programs
        running = m.tasks.program
        where = (f", program {getattr(running, 'number', '?')} running at line "
                 f"{getattr(running, 'line', '?')}" if running is not None else "")
        lines.append(f"programs stored: {', '.join(map(str, sorted(store.programs))) or 'none'}"
                     f" ({store.used()} of {MEMORY} bytes){where}"
                     + (f"; {store.problem}" if store.problem else ""))
        run = m.timed_run
        if run is not None and not run.finished:
            lines.append(f"time-based run: XC{m.elements_done()}/{len(run.starts) - 1}, "
                         f"element {run.element_at(m.tick)}, {m.pulse_trace.total} pulses, "
                         f"ends at tick {run.end_tick}")
        return lines

    def help(self, topic: str) -> list[str] | None:
        spec = COMMANDS.get(topic.strip().upper())
        if spec is None:
            return None
        lines = [f"{spec.mnemonic}: {_plain(spec.mnemonic, spec.summary)}",
                 f"  source: {spec.source} ({spec.confidence})"]
        if spec.note:
            lines.append(f"  note: {spec.note}")
        return lines

    def words(self) -> list[str]:
        return sorted(COMMANDS)

    def summary(self, word: str) -> str:
        spec = COMMANDS.get(word.strip().upper())
        return "" if spec is None else _plain(spec.mnemonic, spec.summary)

    def repl_help(self) -> list[str]:
        return ["  :pulses      the pulse log of the running or last trajectory (CSV lines)",
                "  :pulses-csv FILE   write it to FILE and append every later pulse as it "
                "fires (the whole log; :pulses shows the newest 20,000); "
                ":pulses-csv off stops"]

    def after_reset(self) -> list[str]:
        m = self.controller.machine
        return [f"reset: {m.axis_count} axes, counters 0, trajectory cleared, "
                f"error register clear (tick {m.tick})"]

    def repl_word(self, word: str, rest: str) -> list[str] | None:
        """`:pulses` lists the pulse log; `:pulses-csv FILE` writes it as CSV."""
        word = word.lstrip(":").lower()
        if word == "pulses":
            rows = self.controller.pulse_rows()
            return [",".join(PULSE_CSV_HEADER)] + [",".join(map(str, r)) for r in rows]
        if word == "pulses-csv":
            target = rest.strip()
            if not target:
                return ["! :pulses-csv needs a file name (or 'off')"]
            self._close_stream()
            if target.lower() == "off":
                return ["pulses no longer streamed"]
            path = Path(target)
            try:
                self.controller.pulse_csv(path)
                self._stream = open(path, "a", encoding="utf-8", newline="")  # noqa: SIM115
            except (OSError, ValueError) as error:  # no such folder, a NUL in the name
                return [f"! :pulses-csv: {error}"]
            self._stream.reconfigure(line_buffering=True)
            weakref.finalize(self, self._stream.close)
            self.controller.stream_pulses(self._stream)
            count = len(self.controller.machine.pulse_trace.records)
            return [f"{count} pulses written to {path}; later pulses are appended as they "
                    "fire (:pulses-csv off stops)"]
        return None


def _shorten(part: str) -> str:
    """'1:-12345.6789*' -> '1:-12345.68*': positions to two decimals."""
    head, _, value = part.partition(":")
    flag = value[-1] if value and value[-1] in "*o" else ""
    number = value[:-1] if flag else value
    try:
        return f"{head}:{float(number):.2f}{flag}"
    except ValueError:
        return part



class MM4005WorldView(WorldView):
    """The MM4005's world behind the contract: axes named 1..n as its commands number
    them (`1PA10`), positions in encoder counts since power-up; the GPIO inputs 1..8
    that RB reads (manual 3.103), the outputs 1..8 that SB drives (the world's outputs),
    the analog inputs 1..4 that RA reads (manual 3.137)."""

    def __init__(self, machine: MM4005) -> None:
        super().__init__(machine.world, [str(n) for n in range(1, len(machine.axes) + 1)],
                         inputs=tuple(IO_BITS), analog=tuple(ANALOG_INPUTS),
                         changed=machine.world_changed, source_owner=machine)
        self.machine = machine

    def output_level(self, number: int) -> bool | None:
        """An output bit as SB drove it (None: the MM4005 has no output `number`)."""
        return self.machine.gpio.output_level(number) if number in IO_BITS else None

    def describe(self) -> list[str]:
        """`:world`: the stages and inputs, then the 8 outputs SB drives."""
        levels = " ".join(f"{bit} {'high' if self.machine.gpio.output_level(bit) else 'low'}"
                          for bit in IO_BITS)
        return [*super().describe(), f"outputs {levels}"]

    def trace_columns(self) -> list[str]:
        """The output port as SB? reads it (bit 1 least significant)."""
        return ["outputs"]

    def trace_values(self) -> list[object]:
        return [self.machine.gpio.output_port()]

    def reading(self, name: str) -> AxisReading:
        number = self.index(name) + 1
        machine = self.machine
        a = machine.axis(number)
        status = machine.status(number)
        flags = tuple(word for on, word in ((status.plus_limit, "plus-limit"),
                                            (status.minus_limit, "minus-limit"),
                                            (status.home_signal, "home"),
                                            (status.power_off, "motor-off")) if on)
        steps = a.steps_now(machine)
        return AxisReading(str(number), steps + a.counter_offset, steps + a.encoder_offset,
                           a.velocity(machine), not status.moving, status.moving, flags)


def _plain(mnemonic: str, summary: str) -> str:
    """A summary without the mnemonic its handler's docstring starts with (`TP: ...`), so
    help and completion do not say it twice."""
    return summary.removeprefix(f"{mnemonic}: ")

"""The Trio MC405 behind the doors: its TrioBASIC command line over the shared engine.

    >>> from maxk.controllers.trio import MC405
    >>> trio = MC405()
    >>> trio.send("BASE(0,1): SPEED=5000: ACC(50000): MOVE(10000,0)")
    []
    >>> trio.run_until_idle()
    True
    >>> trio.query("?DPOS AXIS(0)")
    '10000'

One machine (`MC405Machine`, an engine at the servo period), one set of programs and
processes, and a command-line session per host: every session drives the same machine,
programs print to every session, and a statement that waits (WA, WAIT IDLE) holds only
its own session's prompt. Programs are stored in a directory (`BuildOptions.archive`)
and survive a restart of the emulator, as the controller's flash does.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np

from maxk.commands.trio.interpreter import Interpreter
from maxk.commands.trio.keywords import KEYWORDS, Kind, lookup
from maxk.commands.trio.programs import ProgramStore
from maxk.commands.trio.scheduler import ProcessScheduler
from maxk.commands.trio.session import TrioCommandLine
from maxk.commands.trio.system import ProgramCommands
from maxk.controllers.contract import ConsoleBase, Notify, Transport, VirtualTime
from maxk.controllers.world_view import AxisReading, WorldView
from maxk.firmware_model.world import EncoderMount
from maxk.personalities.trio.machine import SERVO_PERIODS, MC405Machine
from maxk.personalities.trio.pwm import PwmMode
from maxk.personalities.trio.trace import PwmTrace

from .archive import FlashArchive, restore

MODEL = "MC405"
SERVO_RATES_HZ = (500, 1000, 2000, 4000)  # SERVO_PERIOD 2000, 1000, 500, 250 us
CONSOLE_WAIT_S = 600.0  # a typed WA/WAIT IDLE runs virtual time at most this long (D)
_NOT_STORED = frozenset({"DPOS", "MPOS", "VP_SPEED", "IDLE", "PWM_CYCLE", "PWM_MARK",
                         "PWM_ENCODER"})


def program_directory(archive: str | os.PathLike[str] | None) -> Path | None:
    """Where the programs live: the archive path as a directory; a `.json` file name (as
    `maxk serve` gives every board) becomes the directory beside it named `.programs`."""
    if archive is None:
        return None
    path = Path(archive)
    if path.suffix == ".json":
        stem = path.name[:-len(".params.json")] if path.name.endswith(".params.json") \
            else path.stem
        return path.with_name(stem + ".programs")
    return path


class MC405(VirtualTime):
    """A Trio MC405: the door contract, a console, and a small API in virtual time."""

    kind = "MC405"
    model = MODEL
    transports: tuple[Transport, ...] = ("tcp",)
    packet_size = None

    def __init__(self, archive: str | os.PathLike[str] | None = None,
                 update_rate_hz: float | None = None) -> None:
        """`update_rate_hz`: the servo rate to power up with (500, 1000, 2000 or 4000 Hz:
        SERVO_PERIOD 2000..250 us); None: the MC405's 1000 us."""
        axis_defaults = {k.name: k.default for k in KEYWORDS.values()
                         if k.kind is Kind.AXIS_PARAMETER and k.name not in _NOT_STORED}
        system_defaults = {k.name: k.default for k in KEYWORDS.values()
                           if k.kind is Kind.SYSTEM_PARAMETER}
        if update_rate_hz is not None:
            period = 1e6 / update_rate_hz
            if round(period) not in SERVO_PERIODS or abs(period - round(period)) > 1e-9:
                raise ValueError(f"the MC405 servo rate is one of "
                                 f"{', '.join(str(10**6 // p) for p in SERVO_PERIODS)} Hz")
            system_defaults["SERVO_PERIOD"] = float(round(period))
        self.machine = MC405Machine(axis_defaults, system_defaults)
        self.flash = FlashArchive(program_directory(archive))  # (archive.py: read before
        flash = self.flash.load()  # the store, which may set its directory aside)
        self.programs = ProgramStore(program_directory(archive))
        self.runtime = ProgramCommands(self.machine, self.programs, self._nowhere)
        self.runtime.interpreter = Interpreter(self.machine, self.runtime, self._broadcast)
        self.runtime.process_output = self._broadcast
        self.scheduler = ProcessScheduler(self.machine, self.runtime)
        self.machine.add_source(self.scheduler)
        self._console: TrioConsole | None = None
        if flash is not None:
            restore(self, flash, keep_servo_period=update_rate_hz is None)
        self.flash.started(self)
        self.runtime.start_autorun(announce=False)

    def save_archive(self, final: bool = False) -> None:
        """Keep the flash (VRs, FLASH parameters, flash pages) for the next run if it
        changed: at most once a virtual second, or now when `final` (archive.py)."""
        self.flash.keep(self, now=final)

    # ---- the door contract -------------------------------------------------------------------
    @property
    def engine(self) -> MC405Machine:
        return self.machine

    def open_session(self, notify: Notify | None = None) -> TrioCommandLine:
        """A host's telnet command line on this controller."""
        session = TrioCommandLine(self.machine, runtime=self.runtime, notify=notify,
                                  on_restart=self._restart)
        self.scheduler.sessions = [s for s in self.scheduler.sessions if not s.closed]
        self.scheduler.add(session)
        return session

    def console(self) -> TrioConsole:
        if self._console is None:
            self._console = TrioConsole(self)
        return self._console

    def reset(self) -> None:
        """Restart the controller (EX): programs stop, the machine powers up again (a new
        SERVO_PERIOD takes effect), then MC_CONFIG and the autorun programs start."""
        self.runtime.halt()
        self.machine.restart()
        self.flash.keep(self, now=True)  # (archive.py: EX writes the flash)
        self.runtime.start_autorun(announce=False)

    def _restart(self, session: TrioCommandLine) -> None:
        """EX typed on a session: that session is finished (atrio reconnects), the others
        carry on with the restarted controller (D)."""
        session.close()
        self.reset()

    def _nowhere(self, text: str) -> None:
        """Replies of program commands go to the session that asked (it sets `output`)."""

    def _broadcast(self, text: str) -> None:
        for session in self.scheduler.sessions:
            session.hear(text)

    def world_view(self) -> MC405WorldView:
        """The world contract (controllers/world_view.py): axes 0..n as AXIS(n) names them."""
        return MC405WorldView(self.machine)

    # ---- the Python API, in virtual time -----------------------------------------------------
    def send(self, line: str) -> list[str]:
        """One command line, as typed: its output lines, then `! <text>` for an error."""
        console = self.console()
        return console.execute(line) + console.new_errors()

    def query(self, line: str) -> str:
        """A line that prints exactly one line; that line."""
        lines = self.send(line)
        if len(lines) != 1 or lines[0].startswith("! "):
            raise ValueError(f"{line!r} gave {lines!r}, expected one line")
        return lines[0]

    def load(self, name: str, text: str, program_type: int = 0) -> list[str]:
        """Store a program as atrio does (SELECT, one !NAME,nR line each, COMPILE)."""
        out = self.send(f'SELECT "{name}",{program_type}')
        for n, line in enumerate(text.splitlines()):
            out += self.send(f"!{name},{n}R{line}")
        return out + self.send("COMPILE")

    def run_until_idle(self, timeout: float = 60.0) -> bool:
        """Advance until nothing moves and no program runs; False on timeout."""
        console = self.console()
        return self.machine.run_until(lambda _m: console.is_idle(), self.ticks(timeout))

    def trace(self, pwm_axes: tuple[int, ...] = (4,), xy: tuple[int, int] = (0, 1)) -> PwmTrace:
        """Record every servo cycle from now: the XY path, PWM marks, gates and duty."""
        return self.machine.trace(pwm_axes, xy)

    def record(self, every_ticks: int = 1) -> MC405Recording:
        """`maxk run --trace/--plot`: every servo cycle's path and PWM outputs (the trace
        keeps every cycle; `every_ticks` is not needed)."""
        pwm_axes = tuple(axis for axis, out in self.machine.pwm.outputs.items()
                         if out.mode != PwmMode.OFF) or (4,)
        return MC405Recording(self.trace(pwm_axes))


class MC405Recording:
    """A run's PWM trace: CSV, and the XY path with the PWM duty drawn along it."""

    def __init__(self, trace: PwmTrace) -> None:
        self.trace = trace

    def write_csv(self, path: str) -> None:
        self.trace.write_csv(path)

    def plot(self, path: str, title: str, draw: Callable[..., object]) -> None:
        self.trace.plot(path, title=title)


class TrioConsole(ConsoleBase):
    """The REPL's and scripts' view of an MC405 (the Console contract)."""

    controller: MC405

    def __init__(self, controller: MC405) -> None:
        super().__init__(controller)
        self.session = controller.open_session()
        self._errors: list[str] = []

    def execute(self, line: str) -> list[str]:
        """Run a typed line: its output lines (no echo, no prompt; an error goes to
        `new_errors`). A statement that waits runs virtual time until it ends."""
        session = self.session
        if session.closed:
            session = self.session = self.controller.open_session()
        session.feed(line.encode("latin-1", "replace") + b"\r")
        machine = self.controller.machine
        if session.waiting:
            machine.run_until(lambda _m: not session.waiting,
                              self.controller.ticks(CONSOLE_WAIT_S))
        abandoned = session.waiting
        if abandoned:  # a person cannot type a break: give up the statement (D)
            session.abandon()
        out, errors = _lines(session.read().decode("latin-1"), line)
        self._errors += errors
        if abandoned:
            self._errors.append(f"! still waiting after {CONSOLE_WAIT_S:g} s: abandoned")
        return out

    def new_errors(self) -> list[str]:
        """`! <text>` for each command-line error since the last look."""
        errors, self._errors = self._errors, []
        return errors

    def refused(self, replies: list[str], noted: list[str]) -> list[str]:
        """The command line's errors, and a program's runtime error as the controller
        prints it unasked (`%[Process 3:Line 5] - Divide by zero`)."""
        return [*noted, *(reply for reply in replies if reply.startswith("%["))]

    def prompt(self) -> str:
        return ">>"

    def status_line(self, width: int = 80) -> str:
        m = self.controller.machine
        parts = [f"MC405 {m.time:.3f}s"]
        for axis in range(m.axis_count):
            if axis < 2 or not m.axis_idle(axis) or m.dpos(axis) != 0:
                parts.append(f"{axis}:{m.dpos(axis):.6g}")
        for axis, output in m.pwm.outputs.items():
            if output.mode is not PwmMode.OFF:
                gate = "" if not output.gating else (" on" if output.gate_level else " off")
                parts.append(f"PWM{axis} {m.mark(axis)}/{output.cycle}{gate}")
        running = len(self.controller.runtime.tasks)
        if running:
            parts.append(f"{running} prog")
        line = " ".join(parts)
        return line if len(line) <= width else line[:width - 1] + "~"

    def status_lines(self) -> list[str]:
        m = self.controller.machine
        lines = [f"MC405 tick {m.tick} ({m.time:.3f} s), servo period "
                 f"{m.servo_period_us()} us, WDOG {'ON' if m.system['WDOG'] else 'OFF'}"]
        for axis in range(m.axis_count):
            a = m.axes[axis]
            link = type(a.link).__name__.upper() if a.link is not None else "-"
            lines.append(f"axis {axis}: DPOS {m.dpos(axis):.4f} VP_SPEED {m.vp_speed(axis):.4f} "
                         f"{'IDLE' if m.axis_idle(axis) else 'MOVING'} ATYPE "
                         f"{int(a.params['ATYPE'])} UNITS {a.params['UNITS']:g} link {link}")
        lines += self.pwm_lines()
        for process, task in sorted(self.controller.runtime.tasks.items()):
            lines.append(f"process {process}: {task.ctx.program} line {task.ctx.line}")
        return lines

    def pwm_lines(self) -> list[str]:
        m = self.controller.machine
        out = []
        for axis, output in m.pwm.outputs.items():
            m.outputs.sync_encoder(axis)
            out.append(f"PWM{axis}: mode {int(output.mode)} PWM_CYCLE {output.cycle} "
                       f"PWM_MARK {m.mark(axis)} duty {m.duty(axis):.4f} gating "
                       f"{'ON' if output.gating else 'OFF'} gate "
                       f"{'open' if output.gate_open else 'closed'} FIFO {len(output.fifo)} "
                       f"PWM_ENCODER {output.encoder}")
        return out

    def help(self, topic: str) -> list[str] | None:
        if not topic.strip():
            lines = ["TrioBASIC keywords (help WORD for one):"]
            for kind in Kind:
                names = sorted(k.name for k in KEYWORDS.values() if k.kind is kind)
                lines.append(f"{kind.value}: {' '.join(names)}")
            return lines
        keyword = lookup(topic.strip())
        if keyword is None:
            return None
        lines = [f"{keyword.name} ({keyword.kind.value}): {keyword.summary}",
                 f"source {keyword.source}, confidence {keyword.confidence}"]
        if keyword.note:
            lines.append(keyword.note)
        return lines

    def words(self) -> list[str]:
        return sorted(KEYWORDS)

    def program_lines(self) -> list[str]:
        """`:programs`: every process and where it stands, then the store's programs."""
        runtime = self.controller.runtime
        now = self.controller.machine.servo_tick()
        lines = []
        for process, task in sorted(runtime.tasks.items()):
            wake = task.wake
            if task.due is None and wake is not None:
                state = "waiting for the machine (WAIT IDLE, a full move buffer)"
            elif task.due is not None and task.due > now + 1:
                state = f"waiting until tick {task.due}"
            else:
                state = "running"
            lines.append(f"process {process}: {task.ctx.program} line {task.ctx.line}, "
                         f"{state}")
        if not lines:
            lines.append("no process is running")
        store = self.controller.programs
        lines.append(f"{len(store.names())} program(s) in the store, {store.total} bytes"
                     + (f" ({store.damage})" if store.damage else ""))
        if self.controller.flash.damage:
            lines.append(self.controller.flash.damage)
        return lines

    def summary(self, word: str) -> str:
        keyword = lookup(word.strip())
        return "" if keyword is None else keyword.summary

    def repl_help(self) -> list[str]:
        return ["  :pwm               the PWM outputs (mode, cycle, mark, duty, gate, FIFO)",
                "  :gates             every gate toggle so far (tick, axis, level, position)",
                "  :trace             record every servo cycle from now (XY 0,1; PWM 0-4)",
                "  :trace FILE.csv    write what was recorded",
                "  :plot FILE.png [AXIS]  the XY path coloured by that axis's PWM duty",
                "  :programs          each process: its program, line and what it waits for"]

    def after_reset(self) -> list[str]:
        m = self.controller.machine
        return [f"reset: MC405 powered up at tick {m.tick}, servo period "
                f"{m.servo_period_us()} us, {len(self.controller.runtime.tasks)} program(s) "
                "started"]

    def is_idle(self) -> bool:
        m = self.controller.machine
        return (all(m.axis_idle(a) for a in range(m.axis_count))
                and all(t.paused for t in self.controller.runtime.tasks.values())  # (a
                # paused program waits for a person: STEPLINE, TROFF)
                and not any(s.waiting for s in self.controller.scheduler.sessions))

    def repl_word(self, word: str, rest: str) -> list[str] | None:
        """`:pwm`, `:gates`, `:trace [FILE]`, `:plot FILE [AXIS]` (see repl_help)."""
        word = word.lstrip(":").lower()
        machine = self.controller.machine
        if word == "programs":
            return self.program_lines()
        if word == "pwm":
            return self.pwm_lines()
        if word == "gates":
            return [f"tick {e.tick}: axis {e.axis} gate {'ON' if e.level else 'OFF'} at "
                    f"PWM_ENCODER {e.position}" for e in machine.gate_edges]
        if word == "trace":
            if not rest:
                self.controller.trace(pwm_axes=tuple(machine.pwm.outputs))
                return [f"tracing every servo cycle from tick {machine.tick}"]
            if machine.tracer is None:
                return ["! nothing traced: say :trace first"]
            try:
                path = machine.tracer.write_csv(rest)
            except (OSError, ValueError) as error:  # no such folder, a NUL in the name
                return [f"! {error}"]
            return [f"{len(machine.tracer)} servo cycles written to {path}"]
        if word == "plot":
            name, _, axis = rest.partition(" ")
            if machine.tracer is None or not name:
                return ["! say :trace, run, then :plot FILE.png [AXIS]"]
            try:
                path = machine.tracer.plot(name, int(axis) if axis.strip() else None)
            except KeyError:
                return [f"! axis {axis.strip()} has no traced PWM output"]
            except (ImportError, ValueError, OSError) as error:
                return [f"! {error}"]
            return [f"plot written to {path}"]
        return None


def _lines(text: str, line: str) -> tuple[list[str], list[str]]:
    """A session's bytes for one typed line as (output lines, errors): the echo and the
    prompt dropped, a `%[COMMAND LINE] - text` error as `! text`. The echo is the line
    as the session keeps it: without NUL bytes (dropped as telnet sends them)."""
    echo = line.replace("\x00", "") + "\r\n"
    at = text.find(echo)
    if at >= 0:
        text = text[:at] + text[at + len(echo):]
    if text.endswith(">>"):
        text = text[:-2]
    out, errors = [], []
    for item in text.split("\r\n"):
        if item.startswith("%[COMMAND LINE] - "):
            errors.append("! " + item[len("%[COMMAND LINE] - "):])
        elif item:
            out.append(item)
    return out, errors


MC405_INPUTS = range(32)
"""Digital inputs IN(0)..IN(31): the MC405's built-in inputs and bidirectional channels
with room for an expansion (D: the contract only needs the numbers a program reads)."""


class MC405WorldView(WorldView):
    """The MC405's world behind the contract: axes named 0..n as `AXIS(n)` names them,
    positions in counts (DPOS x UNITS, DEFPOS not applied); inputs IN(n), analog AIN(n)."""

    def __init__(self, machine: MC405Machine) -> None:
        super().__init__(machine.world, [str(i) for i in range(machine.axis_count)],
                         inputs=MC405_INPUTS, analog=range(8), changed=machine.world_changed,
                         source_owner=machine)
        self.machine = machine

    def input_level(self, number: int) -> bool:
        return self.machine.digital_input(number)  # as IN(n) reads it

    def set_shaft_encoder(self, name: str, motor: str | None,
                          counts_per_step: float = 1.0) -> None:
        """The encoder input of axis `name` reads an encoder on axis `motor`'s motor
        (a stepper with a shaft encoder wired to a second axis); None: no such encoder."""
        axis = self.index(name)
        if motor is None:
            self.world.encoders.pop(axis, None)
        else:
            if not math.isfinite(counts_per_step) or counts_per_step == 0:
                raise ValueError("counts per step is a number other than 0")
            self.world.encoders[axis] = EncoderMount(self.index(motor), counts_per_step)
        self.changed()

    def extra_setting(self, name: str | None, words: list[str]) -> str | None:
        """`@world N shaft-encoder M [COUNTS_PER_STEP]`: axis N's encoder input reads an
        encoder on axis M's motor (`none`: it reads none)."""
        if name is None or not words or words[0].lower() != "shaft-encoder":
            return None
        args = words[1:]
        if len(args) == 1 and args[0].lower() == "none":
            self.set_shaft_encoder(name, None)
            return f"{name} shaft-encoder none"
        if len(args) not in (1, 2):
            raise ValueError("shaft-encoder MOTOR_AXIS [COUNTS_PER_STEP] or shaft-encoder none")
        try:
            ratio = float(args[1]) if len(args) == 2 else 1.0
        except ValueError:
            raise ValueError(f"counts per step: {args[1][:12]!r} is no number") from None
        self.set_shaft_encoder(name, args[0], ratio)
        return f"{name} shaft-encoder {' '.join(args)}"

    def output_level(self, number: int) -> bool | None:
        return self.machine.output(number) if number in MC405_INPUTS else None

    def reading(self, name: str) -> AxisReading:
        i = self.index(name)
        machine = self.machine
        # the world's motor: a FRAME's motor demand, STEP_RATIO, BACKLASH, POSI_SEQ
        now = machine.motor_steps(i)
        ahead = float(machine.motor_steps_at(i, np.array([machine.tick + 1]))[0])
        idle = machine.axis_idle(i)
        return AxisReading(str(i), math.floor(now + 1e-9), None,
                           (ahead - now) * machine.update_rate_hz, idle, not idle)

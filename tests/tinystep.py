"""TinyStep: a fifth controller written from docs/architecture.md ("Where a new controller
goes") alone, to prove that a new controller needs nothing but its own parts: a table, a
line session, a personality on the shared machine, a controller with a world view and a
console, and one registry line. Every door (serve, the REPL, scripts, the pytest plugin,
traces and plots) then takes it.

Its language (invented, as a small RS-232 stepper indexer might speak): `1MA500` move
axis 1 to 500 steps, `2MR-20` move axis 2 by -20, `1VL800` speed in steps/s, `1AC4000`
acceleration, `1ST` stop at once, `1TP` tells `1TP500`, `1MS` tells `1MSD` (done), `M`
(moving) or `L`/`l` (stopped on the plus/minus limit), `VE` tells the version. Replies end
with CR LF; an unknown or malformed command answers `E?`. The axes stop dead on a limit.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from maxk.commands.line_session import LineSession
from maxk.commands.tables import unique_table
from maxk.controllers.contract import (
    BuildOptions,
    ConsoleBase,
    ControllerKind,
    Notify,
    Transport,
    VirtualTime,
)
from maxk.controllers.world_view import AxisReading, WorldView
from maxk.firmware_model.axis import MotionAxis, MotionEnds
from maxk.firmware_model.engine import Engine
from maxk.firmware_model.profiles import RampShape, plan_move
from maxk.firmware_model.world import World


# ---- the language: its table, its session ---------------------------------------------------
@dataclass(frozen=True)
class Command:
    mnemonic: str
    summary: str
    operand: bool = False  # takes a number
    axis: bool = True  # led by an axis number
    source: str = "tests/tinystep.py (invented)"
    confidence: str = "D"


TABLE = unique_table([
    Command("MA", "move to an absolute position (steps)", operand=True),
    Command("MR", "move by a distance (steps)", operand=True),
    Command("VL", "speed for the next moves (steps/s)", operand=True),
    Command("AC", "acceleration and deceleration (steps/s2)", operand=True),
    Command("ST", "stop at once"),
    Command("TP", "tell the position: nTPx"),
    Command("MS", "motion status: D done, M moving, L/l on the plus/minus limit"),
    Command("VE", "version", axis=False),
], lambda c: c.mnemonic, "TinyStep table")
_LINE = re.compile(r"^\s*(?P<axis>[12])?(?P<m>[A-Za-z]{2})(?P<value>-?\d+)?\s*$")


class TinySession(LineSession):
    terminators = b"\r\n"  # a line ends at CR, LF or CR LF
    line_limit = 80

    def __init__(self, machine: TinyMachine) -> None:
        super().__init__()
        self.machine = machine

    def run_line(self, text: str) -> None:
        if text.strip():
            self.reply(self.machine.execute(text).encode() + b"\r\n")

    def line_too_long(self) -> None:
        self.reply(b"E?\r\n")


# ---- the personality: axes on the shared machine -----------------------------------------------
@dataclass
class TinyAxis(MotionAxis):
    speed: float = 1000.0
    accel: float = 10000.0
    at_limit: int = 0  # +1/-1: stopped on that limit


class TinyMachine(Engine):
    def __init__(self) -> None:
        super().__init__(1000.0)
        self.world = World.default(2)
        self.axes = [TinyAxis(i, str(i + 1)) for i in range(2)]
        self.ends = MotionEnds(self.axes, self, limit_at=self._limit_at,
                               on_limit=self._on_limit)
        self.add_source(self.ends)

    def _limit_at(self, axis: MotionAxis, side: int) -> float | None:
        stage = self.world.axes[axis.index]
        return stage.plus_limit.low if side > 0 else stage.minus_limit.high

    def _on_limit(self, axis: MotionAxis, side: int, tick: int) -> None:
        axis.freeze(self)
        axis.at_limit = side  # type: ignore[attr-defined]

    def execute(self, text: str) -> str:
        m = _LINE.match(text)
        command = TABLE.get(m["m"].upper()) if m else None
        if m is None or command is None or command.axis != bool(m["axis"]) or (
                command.operand != (m["value"] is not None)):
            return "E?"
        if not command.axis:
            return "TinyStep 1.0"
        axis = self.axes[int(m["axis"]) - 1]
        value = int(m["value"] or 0)
        name, here = command.mnemonic, axis.steps_now(self)
        if name in ("MA", "MR"):
            if axis.motion is not None:
                return "E?"  # busy: one move at a time
            target = value if name == "MA" else here + value
            axis.at_limit = 0
            axis.begin(plan_move(target - here, 0.0, axis.speed, axis.accel, axis.accel,
                                 RampShape.LINEAR), self)
        elif name in ("VL", "AC"):
            if value <= 0:
                return "E?"
            setattr(axis, "speed" if name == "VL" else "accel", float(value))
        elif name == "ST":
            axis.freeze(self)
        elif name == "TP":
            return f"{axis.letter}TP{here}"
        elif name == "MS":
            state = "M" if axis.motion else {1: "L", -1: "l"}.get(axis.at_limit, "D")
            return f"{axis.letter}MS{state}"
        return "OK"


# ---- the controller: the contract, its world, its console ------------------------------------
class TinyView(WorldView):
    def __init__(self, machine: TinyMachine) -> None:
        super().__init__(machine.world, ["1", "2"], inputs=(), analog=(),
                         changed=machine.ends.changed, source_owner=machine)
        self.machine = machine

    def reading(self, name: str) -> AxisReading:
        axis = self.machine.axes[self.index(name)]
        flags = {1: ("plus-limit",), -1: ("minus-limit",)}.get(axis.at_limit, ())
        return AxisReading(axis.letter, axis.steps_now(self.machine), None,
                           axis.velocity(self.machine), axis.motion is None,
                           axis.motion is not None, flags)


class TinyConsole(ConsoleBase):
    def execute(self, line: str) -> list[str]:
        return [self.controller.engine.execute(line)] if line.strip() else []  # type: ignore

    def words(self) -> list[str]:
        return list(TABLE)

    def summary(self, word: str) -> str:
        command = TABLE.get(word.upper())
        return "" if command is None else command.summary

    def help(self, topic: str) -> list[str] | None:
        c = TABLE.get(topic.upper())
        return None if c is None else [f"{c.mnemonic}: {c.summary}",
                                       f"  source: {c.source} ({c.confidence})"]


class TinyStep(VirtualTime):
    kind = "TinyStep"
    model = "TinyStep"
    transports: tuple[Transport, ...] = ("tcp", "pty")
    packet_size = None

    def __init__(self) -> None:
        self.machine = TinyMachine()

    @property
    def engine(self) -> TinyMachine:
        return self.machine

    def open_session(self, notify: Notify | None = None) -> TinySession:
        return TinySession(self.machine)

    def console(self) -> TinyConsole:
        return TinyConsole(self)

    def reset(self) -> None:
        for axis in self.machine.axes:
            axis.freeze(self.machine)

    def world_view(self) -> TinyView:
        return TinyView(self.machine)


KIND = ControllerKind("TinyStep", ("TinyStep",), lambda model, options: TinyStep(),
                      "a 2-axis stepper indexer written as a test of the contracts",
                      update_rates_hz=(1000,))


def build(model: str = "TinyStep", options: BuildOptions | None = None) -> TinyStep:
    return TinyStep()

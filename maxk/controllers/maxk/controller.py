"""The in-process door: a MAXk board you talk to from Python, in virtual time.

    >>> from maxk import MAXk
    >>> board = MAXk("MAXk-4000")
    >>> board.send("AX; VL5000; AC50000; MA10000; GO; ID;")
    []
    >>> board.run_until_done("X", timeout=5.0)
    True
    >>> board.query("AX RP")
    '10000'

Nothing here reads the wall clock: time moves only when you advance it.
"""

from __future__ import annotations

import math
import os

from maxk.commands.max.interpreter import Interpreter
from maxk.commands.max.lexer import SEPARATORS
from maxk.commands.max.session import Framing, MaxSession
from maxk.controllers.contract import Notify, Transport, VirtualTime
from maxk.controllers.maxk.console import AxisStatus, MaxConsole
from maxk.controllers.world_view import AxisReading, WorldView
from maxk.firmware_model.world import AxisWorld, InputSource
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.board import Board, CommandErrorRecord
from maxk.personalities.maxk.capture import EDGES
from maxk.personalities.maxk.models import DEFAULT_MODEL, DEFAULT_UPDATE_RATE_HZ
from maxk.personalities.maxk.parameters import ParameterArchive, default_archive_path


class MAXk(VirtualTime):
    """A board plus a command stream: the API the REPL, scripts and tests use."""

    def __init__(self, model: str = DEFAULT_MODEL,
                 update_rate_hz: int = DEFAULT_UPDATE_RATE_HZ, *,
                 archive: str | os.PathLike | bool | None = None, board_number: int = 1) -> None:
        """`archive`: the parameter archive file (the board's flash) that APP writes and
        power-up reads; True for the per-user default file, None (the default here) for
        one kept in memory, so tests and scripts never depend on a saved file."""
        if archive is True:
            archive = default_archive_path(model, board_number)
        store = ParameterArchive(None if archive in (None, False) else archive)  # type: ignore
        self.board = Board(model, update_rate_hz, archive=store)
        self.interpreter = Interpreter(self.board)
        self.framing = Framing()  # how sessions frame replies (`maxk serve --eol/--ack`)
        self._sessions: list[MaxSession] = []
        self._view: MaxWorldView | None = None

    # ---- the door contract (controllers/contract.py) ---------------------------------
    kind = "MAXk"
    transports: tuple[Transport, ...] = ("tcp", "pty")
    packet_size = None

    @property
    def model(self) -> str:
        return self.board.model.name

    @property
    def engine(self) -> Board:
        return self.board

    def console(self) -> MaxConsole:
        """A person's view: the REPL and command scripts use it."""
        return MaxConsole(self)

    def open_session(self, notify: Notify | None = None) -> MaxSession:
        """A host's line session: its own lexer, MAXnet-framed replies, notifications."""
        session = MaxSession(self.board, self.framing, notify)
        self._sessions = [s for s in self._sessions if not s.closed]  # hosts that left
        self._sessions.append(session)
        return session

    def reset(self) -> None:
        """Reset the controller (the DLL's ResetOmsController): motion stops at once,
        the power-up sequence runs again with the archived parameters. A command half
        received is lost, in every session."""
        self.board.reset()
        self.interpreter = Interpreter(self.board)
        self._sessions = [s for s in self._sessions if not s.closed]
        for session in self._sessions:
            session.lose_partial_command()

    @property
    def firmware_flags(self) -> int:
        """Shared memory 0x048: 0xFFFFFFFF while initializing, then Table 3-4's bits."""
        return self.board.firmware_flags

    # ---- talking to the board ---------------------------------------------------------
    def write(self, data: str | bytes) -> list[str]:
        """Raw bytes as a host writes them; a trailing operand waits for its terminator."""
        return self.interpreter.write(data)

    def send(self, text: str) -> list[str]:
        """A complete command line: adds a CR terminator when the text has none."""
        if text and text[-1] not in SEPARATORS:
            text += "\r"
        return self.interpreter.write(text)

    def query(self, text: str) -> str:
        """Send a line that must produce exactly one reply, and return it."""
        replies = self.send(text)
        if len(replies) != 1:
            error = self.board.last_error
            detail = f" (last command error: {error})" if error else ""
            raise ValueError(f"{text!r} gave {len(replies)} replies, expected 1{detail}")
        return replies[0]

    # ---- time -----------------------------------------------------------------------
    def run_until_idle(self, timeout: float = 60.0) -> bool:
        """Advance until no axis moves and no queue holds work; False on timeout."""
        return self.board.run_until_idle(self.ticks(timeout))

    def run_until_done(self, *letters: str, timeout: float = 60.0) -> bool:
        """Advance until the done flag of every named axis (default: all) is set."""
        axes = [self.board.axis(x) for x in letters] if letters else self.board.axes
        return self.board.run_until(
            lambda b: all(a.flags & F.AXIS_DONE for a in axes), self.ticks(timeout)
        )

    # ---- the world around the board ---------------------------------------------------
    def world_view(self) -> MaxWorldView:
        """The world contract (controllers/world_view.py): `@world`, `:world`, `@expect`."""
        if self._view is None:
            self._view = MaxWorldView(self)
        return self._view

    def stage(self, letter: str) -> AxisWorld:
        """The stage of one axis (switch positions in physical steps since power-up).
        Change it through the set_* methods so a running motion sees the change."""
        return self.board.world.axes[self.board.axis(letter).index]

    def set_limits(self, letter: str, *, plus: float | None | str = "keep",
                   minus: float | None | str = "keep") -> None:
        """Place the limit switches (None: no switch on that side)."""
        self.world_view().set_limits(letter, plus=plus, minus=minus)

    def set_home(self, letter: str, low: float | None, high: float | None) -> None:
        """The home switch is active from low to high (None, None: no home switch)."""
        self.world_view().set_home(letter, low, high)

    def set_index(self, letter: str, period: int, width: int = 4, offset: int = 0) -> None:
        """Encoder index marks every `period` counts, `width` counts wide, one at `offset`."""
        self.world_view().set_index(letter, period, width, offset)

    def fault(self, letter: str, switch: str, state: str | None) -> None:
        """Stick a switch ('plus', 'minus' or 'home') 'active' or 'inactive'; None clears."""
        self.world_view().fault(letter, switch, state)

    def bounce(self, letter: str, switch: str, steps: int) -> None:
        """Make a switch ('plus', 'minus' or 'home') chatter within `steps` of its edges."""
        self.world_view().bounce(letter, switch, steps)

    def miss_steps(self, letter: str, steps: int) -> None:
        """A stepper misses `steps` steps now (negative: the stage overshoots): its stage
        lags the motor from here on, so an encoder (PSE) sees the slip."""
        self.world_view().miss_steps(letter, steps)

    def set_backlash(self, letter: str, steps: int) -> None:
        """Give a stepper's stage `steps` of play: after the motor reverses, the stage
        does not follow its first `steps` steps (an encoder on the stage sees it; BC on
        the board compensates)."""
        self.world_view().set_backlash(letter, int(steps))

    def set_motor(self, letter: str, **parameters: object) -> None:
        """Change the motor a servo axis drives (see MotorPlant: inertia,
        viscous_friction, coulomb_friction, torque_constant, amplifier, amplifier_gain,
        resistance, encoder_lines)."""
        self.world_view().set_motor(letter, **parameters)

    def capture(self, letter: str, *, home: str | None | bool = False, index: bool | None = None,
                inputs_rising: int | None = None, inputs_falling: int | None = None) -> None:
        """Configure real-time position capture for an axis (docs/io.md). home: 'rising',
        'falling', 'both' or None (off); False leaves it as it is."""
        config = self.board.capture_config[self.board.axis(letter).index]
        if home is not False:
            if home not in (None, "rising", "falling", "both"):
                raise ValueError("home capture is 'rising', 'falling', 'both' or None")
            config.home = home  # type: ignore[assignment]
        if index is not None:
            config.index = index
        if inputs_rising is not None:
            config.io_rising = inputs_rising & 0xFFFF
        if inputs_falling is not None:
            config.io_falling = inputs_falling & 0xFFFF
        self.board.world_changed()

    def set_input(self, bit: int, level: bool | InputSource) -> None:
        """A general purpose input's level: a constant, or a function of the board."""
        if not 0 <= bit <= 15:
            raise ValueError("general purpose bits are 0..15")
        self.world_view().set_input(bit, level)

    def set_analog(self, channel: int, volts: float | InputSource) -> None:
        """An analog input (0..3) in volts (+/-10 V), constant or a function of the board."""
        if not 0 <= channel <= 3:
            raise ValueError("analog inputs are 0..3")
        if not callable(volts) and not math.isfinite(volts):
            raise ValueError(f"volts must be a finite number, not {volts}")
        self.board.world.analog[channel] = volts
        self.board.world_changed()

    # ---- observing -------------------------------------------------------------------
    def position(self, letter: str) -> int:
        return self.board.axis(letter).motor_position(self.board)

    def encoder(self, letter: str) -> int:
        return self.board.axis(letter).encoder_position(self.board)

    def velocity(self, letter: str) -> float:
        return self.board.axis(letter).velocity(self.board)

    def done(self, letter: str) -> bool:
        return bool(self.board.axis(letter).flags & F.AXIS_DONE)

    @property
    def doorbell(self) -> int:
        return self.board.doorbell

    @property
    def command_error(self) -> bool:
        return self.board.command_error

    @property
    def last_error(self) -> CommandErrorRecord | None:
        return self.board.last_error

    def status(self) -> list[AxisStatus]:
        board = self.board
        return [
            AxisStatus(
                a.letter,
                a.motor_position(board),
                a.encoder_position(board),
                round(a.velocity(board)),
                bool(a.flags & F.AXIS_DONE),
                a.motion is not None,
                len(a.queue),
                a.status_string(board),
            )
            for a in board.axes
        ]


class MaxWorldView(WorldView):
    """The MAXk's world behind the contract: axes X..K, general purpose inputs 0..15,
    analog inputs 0..3; the capture set-up and the doorbell as its own words."""

    def __init__(self, maxk: MAXk) -> None:
        board = maxk.board
        super().__init__(board.world, board.model.axis_letters, inputs=range(16),
                         analog=range(4), changed=board.world_changed, source_owner=board)
        self.maxk = maxk

    def reading(self, name: str) -> AxisReading:
        board = self.maxk.board
        axis = board.axis(self.axis_names[self.index(name)])
        flags = axis.flags
        words = tuple(word for bit, word in ((F.AXIS_DONE, "done"),
                                             (F.AXIS_OVERTRAVEL, "overtravel"),
                                             (F.AXIS_SLIP, "slip")) if flags & bit)
        return AxisReading(axis.letter, axis.motor_position(board),
                           axis.encoder_position(board), axis.velocity(board),
                           bool(flags & F.AXIS_DONE), axis.motion is not None, words)

    def set_backlash(self, name: str, steps: int) -> None:
        self.maxk.board.axis(self.axis_names[self.index(name)]).backlash_now(self.maxk.board)
        super().set_backlash(name, steps)  # a past motion counted at the old play first

    def output_level(self, number: int) -> bool | None:
        if not 0 <= number <= 15:
            return None
        return self.maxk.board.io.level(number, self.maxk.board)

    def input_level(self, number: int) -> bool:
        return self.maxk.board.io.level(number, self.maxk.board)

    def extra_setting(self, name: str | None, words: list[str]) -> str | None:
        if name is None or not words or words[0].lower() != "capture":
            return None
        letter = self.axis_names[self.index(name)]
        args = words[1:]
        kind = args[0].lower() if args else ""
        if kind == "home" and len(args) == 2 and args[1].lower() in (*EDGES, "off"):
            edge = None if args[1].lower() == "off" else args[1].lower()
            self.maxk.capture(letter, home=edge)
        elif kind == "index" and len(args) == 2 and args[1].lower() in ("on", "off"):
            self.maxk.capture(letter, index=args[1].lower() == "on")
        elif kind == "inputs" and len(args) == 3:
            try:
                rising, falling = int(args[1], 0), int(args[2], 0)
            except ValueError:
                raise ValueError(f"not bit masks: {args[1][:12]!r} {args[2][:12]!r}") from None
            if not (0 <= rising <= 0xFFFF and 0 <= falling <= 0xFFFF):
                raise ValueError("the input masks are 16-bit: 0 to 0xFFFF")
            self.maxk.capture(letter, inputs_rising=rising, inputs_falling=falling)
        else:
            raise ValueError("capture home rising|falling|both|off, capture index on|off, "
                             "or capture inputs RISING_MASK FALLING_MASK")
        return f"{letter} capture {' '.join(args)}"

    def extra_expect(self, words: list[str]) -> str | None | bool:
        board = self.maxk.board
        text = " ".join(words).lower()
        if text in ("error", "no error"):
            error = board.command_error
            if error == (text == "error"):
                return None
            return f"error (last: {board.last_error})" if error else "no error"
        if len(words) == 2 and words[0].lower() == "captures" and words[1].isdigit():
            waiting = len(board.capture_ring)
            return None if waiting == int(words[1]) else f"captures {waiting}"
        if len(words) == 2 and words[0].lower() == "doorbell":
            try:
                want = int(words[1], 0)
            except ValueError:
                return f"not a doorbell word: {words[1]!r}"
            word = board.doorbell
            return None if word == want else f"doorbell 0x{word:08x}"
        return False

    def trace_axis_columns(self, after_done: bool = False) -> list[str]:
        return ["queued"] if after_done else ["status"]

    def trace_axis_values(self, name: str, after_done: bool = False) -> list[object]:
        board = self.maxk.board
        axis = board.axis(self.axis_names[self.index(name)])
        return [len(axis.queue)] if after_done else [axis.status_string(board)]

    def trace_columns(self) -> list[str]:
        return ["doorbell", "command_error"]

    def trace_values(self) -> list[object]:
        board = self.maxk.board
        return [f"0x{board.doorbell:08x}", int(board.command_error)]

    def describe(self) -> list[str]:
        b = self.maxk.board
        lines = []
        for line, cap in zip(super().describe(), b.capture_config, strict=False):
            capture = []
            if cap.home:
                capture.append(f"home {cap.home}")
            if cap.index:
                capture.append("index")
            if cap.on_inputs:
                capture.append(f"inputs {cap.io_rising:#x}/{cap.io_falling:#x}")
            lines.append(line + (f"; capture {', '.join(capture)}" if capture else ""))
        inputs = "".join("1" if b.world.digital_level(i, b) else "0" for i in range(15, -1, -1))
        lines.append(f"inputs (15..0): {inputs}; analog: " + ", ".join(
            f"{b.world.analog_volts(c, b):g} V" for c in range(4)))
        lines.append(f"capture ring: {len(b.capture_ring)} waiting, {b.capture_ring.lost} lost")
        return lines

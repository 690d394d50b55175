"""The PoKeys for a person: a small command language for the REPL and command scripts
(the `Console` contract), since the wire protocol is binary.

Each line is one word and its arguments; the word turns into the device's own requests
through the Python API (`maxk.controllers.pokeys.PoKeys`), so a console line and a
PoKeysLib call exercise the same bytes. Commands that set something answer nothing (as
the device's empty replies carry nothing); queries answer decoded lines; a line the
console cannot read, or a request the device ignores, answers `! ...`. Axes are named
X Y Z A B C U V or 1..8.

Long module: each console word is a handler beside its help line, and the words cover the
whole request table (set-up, pulse engine, I/O, the REPL's slot words); split by word
group, every half would import the other's parsing of axes and values.
"""

from __future__ import annotations

import re
import struct
from collections.abc import Callable, Sequence
from typing import Any, overload

from maxk.commands.pokeys.table import ENTRIES
from maxk.controllers.contract import ConsoleBase
from maxk.controllers.glance import short_position
from maxk.controllers.pokeys.console_io import IO_WORDS, IOWords
from maxk.controllers.pokeys.status import (
    STATE_SHORT,
    SWITCH_WORDS,
    V1_STATES,
    V2_STATES,
    ConsoleError,
    PoKeysControls,
    PoKeysError,
    axis_index,
    letters_of,
    on_off,
    show_number,
)
from maxk.controllers.pokeys.trace import SlotRecorder
from maxk.firmware_model.world import axis_position_source
from maxk.personalities.pokeys import AXIS_LETTERS
from maxk.personalities.pokeys.engine import PulseEngine

WORDS: dict[str, tuple[str, str]] = {
    "status": ("status", "engine state, buffer fill, each axis's position and state"),
    "pos": ("pos", "the position counters on one line"),
    "setup": ("setup N", "v2: axes 1..N take part in the pulse engine (PulseEngineSetup)"),
    "axis": ("axis X [buffer|internal] [position|speed] [max V] [accel A] [decel D] "
             "[switches lim- lim+ home|none] [soft MIN MAX] [homing PCT RET] [invert]",
             "configure an axis (speeds pulses/ms, accelerations pulses/ms^2)"),
    "state": ("state stopped|running|jogging (v1: stopped|internal|buffer|jogging)",
              "set the pulse engine's state"),
    "move": ("move X 1000 [Y -500 ...] [at F]",
             "internal-controller axes to positions (speed-mode axes: pulses/s)"),
    "set": ("set X 0 [Y 100 ...]", "load position counters (the stage does not move)"),
    "fill": ("fill P1 [P2 ...] [x N] [16bit] [large]",
             "offer N slots of pulses for axes 1.. to the buffer; says how many it took"),
    "clear": ("clear", "empty the slot buffer"),
    "home": ("home X [Y ...] | home finish [stopped|running]",
             "start homing the axes (v2: then finish to leave HOME)"),
    "probe": ("probe Z -5000 [speed F] [input N] [polarity 0|1] | probe finish",
              "v2: run toward max positions until the probe input changes"),
    "world": ("world [X limits PLUS MINUS|none] [X home LOW HIGH|none]",
              "the stage: switch positions in physical pulses"),
    "estop": ("estop on|off", "press or release the e-stop (world input 0)"),
    "input": ("input N on|off | input N when Z <= -1234",
              "a world digital input (probe input N), constant or by an axis's position"),
    "request": ("request CMD [P1 P2 P3 P4] [: PAYLOAD HEX]",
                "send one raw request frame; the reply in hex (and whether the device refused it)"),
    "reboot": ("reboot", "v2: PulseEngineReboot"),
    **IO_WORDS,
    "requests": ("requests", "every request the device answers, with source and confidence"),
}

REPL_WORDS = """\
  :slots N     run N slots and show each (pulses per axis, state, buffer fill)
  :trace FILE  write a CSV slot trace from now (:trace off to stop)
  :plot FILE   draw the traced slots: position, pulse rate, buffer fill (PNG)
  :plan X      the axis's motion as a plan (phases)
  :requests    the device's requests with source and confidence (also: help requests)"""


SHOWN_SLOTS_MAX = 100_000
"""`:slots N` prints a line a slot: more than this is not for reading (D)."""

_EVENTS = {"limit": "a limit switch stopped the engine",
           "estop": "the e-stop stopped the engine", "probe_error": "probing missed"}


class _Repeated(Sequence[list[int]]):
    """One slot row offered `count` times, built only as far as the device takes it
    (`fill 1 x 100000000` must not build a hundred million rows for 128 slots)."""

    def __init__(self, row: list[int], count: int) -> None:
        self.row, self._n = row, count

    def __len__(self) -> int:
        return self._n

    @overload
    def __getitem__(self, index: int) -> list[int]: ...

    @overload
    def __getitem__(self, index: slice) -> list[list[int]]: ...

    def __getitem__(self, index: int | slice) -> list[int] | list[list[int]]:
        if isinstance(index, slice):
            return [list(self.row) for _ in range(*index.indices(self._n))]
        if not -self._n <= index < self._n:
            raise IndexError(index)
        return list(self.row)


class PoKeysConsole(IOWords, ConsoleBase):
    """The `Console` of a PoKeys device."""

    def __init__(self, dev: PoKeysControls) -> None:
        ConsoleBase.__init__(self, dev)  # type: ignore[arg-type]
        self.dev = dev
        self._events: list[str] = []
        self._listening: PulseEngine | None = None
        self.recorder: SlotRecorder | None = None
        self._listen()

    def _listen(self) -> None:
        pulse = self.dev.pulse_engine
        if pulse is not self._listening:
            pulse.listeners.append(self._event)
            self._listening = pulse

    def _event(self, slot: int, event: str, axis: int) -> None:
        if event in _EVENTS:
            where = f" ({AXIS_LETTERS[axis]})" if axis >= 0 else ""
            self._events.append(f"! slot {slot}: {_EVENTS[event]}{where}")

    # ---- the Console contract ----------------------------------------------------------
    def execute(self, line: str) -> list[str]:
        words = line.split()
        if not words:
            return []
        word, args = words[0].lower(), words[1:]
        handler = getattr(self, "_do_" + word, None)
        if word not in WORDS or handler is None:
            return [f"! unknown word {words[0]!r}; try help"]
        try:
            return list(handler(args))
        except (ConsoleError, PoKeysError) as error:
            return [f"! {error}"]
        except (ValueError, KeyError, IndexError) as error:
            return [f"! {word}: {error}; say {WORDS[word][0]}"]
        except (OverflowError, struct.error) as error:  # a value the request cannot carry
            return [f"! {word}: a value out of the request's range ({error}); "
                    "that request was not sent"]

    def new_errors(self) -> list[str]:
        self._listen()
        out, self._events = self._events, []
        return out

    def refused(self, replies: list[str], noted: list[str]) -> list[str]:
        """A refusal is a `! ...` reply (`new_errors` notes the engine's own stops)."""
        return [reply for reply in replies if reply.startswith("! ")]

    def prompt(self) -> str:
        return f"{self.dev.model}> "

    def status_line(self, width: int = 80) -> str:
        """Time, engine state, buffer fill, each axis's counter (~ while it moves). In
        full when it fits; else positions in at most four characters (-2G, 123k) and a
        shorter head (D), so 8 axes fit 80 columns (`status` has them exact)."""
        e = self.dev.pulse_engine
        t = self.dev.engine.time
        marks = []
        for a in e.axes:
            if e.active(a) or self.dev.version == 1:
                moving = e.moving(a) or (e.consumes_buffer() and e.buffered(a)
                                         and e.buffer.count > 0)
                marks.append((AXIS_LETTERS[a.index], a.position, "~" if moving else ""))
        fill = f"{e.buffer.count}/{e.buffer.depth}"
        full = f"t={t:.3f}s {e.state.name} buf {fill} " + " ".join(
            f"{x}{p}{m}" for x, p, m in marks)
        if len(full) <= width:
            return full.rstrip()
        axes = " ".join(f"{x}{short_position(p)}{m}" for x, p, m in marks)
        for head in (f"t={t:.3f}s {e.state.name} buf {fill}", f"t={t:.1f}s {e.state.name} {fill}",
                     f"t={t:.0f}s {STATE_SHORT.get(e.state.name, e.state.name)} {fill}"):
            line = f"{head} {axes}"
            if len(line) <= width:
                return line
        return line[:width]

    def status_lines(self) -> list[str]:
        return self._do_status([])

    def help(self, topic: str) -> list[str] | None:
        if topic.lower() == "requests":
            return self._do_requests([])
        entry = WORDS.get(topic.lower())
        if entry is None:
            return None
        return [entry[0], "  " + entry[1]]

    def words(self) -> list[str]:
        return list(WORDS)

    def summary(self, word: str) -> str:
        entry = WORDS.get(word.lower())
        return "" if entry is None else entry[1]

    def is_idle(self) -> bool:
        return self.dev.is_idle()

    def repl_help(self) -> list[str]:
        return REPL_WORDS.splitlines()

    def after_reset(self) -> list[str]:
        self._listen()
        return [f"reset: {self.dev.model} powered up, pulse engine STOPPED, buffer empty"]

    def repl_word(self, word: str, rest: str) -> list[str] | None:
        if word == "slots":
            return self._slots(rest)
        if word == "trace":
            return self._trace(rest)
        if word == "plot":
            if self.recorder is None or not self.recorder.slots:
                return ["nothing traced: :trace FILE first"]
            try:
                return [f"plot: {self.recorder.plot(rest or 'pokeys.png')}"]
            except ImportError as error:
                return [str(error)]
        if word == "plan":
            try:
                return self._plan(rest)
            except ValueError as error:
                return [f"! plan: {error}"]
        if word == "requests":
            return self._do_requests([])
        return None

    def _do_requests(self, args: list[str]) -> list[str]:
        return [f"{e.command:#04x} {'*' if e.sub < 0 else f'{e.sub:#04x}'} {e.name} "
                f"[{e.confidence}] {e.source}" for e in ENTRIES]

    # ---- queries ---------------------------------------------------------------------
    def _do_status(self, args: list[str]) -> list[str]:
        s = self.dev.status()
        e = self.dev.pulse_engine
        count = s.enabled_axes if self.dev.version == 2 else 3
        lines = [f"state {s.state_name}, buffer {e.buffer.count}/{e.buffer.depth}"]
        if not count:
            lines.append("no axes enabled (setup N)")
        for i in range(count):
            lines.append(f"{AXIS_LETTERS[i]} {s.positions[i]} {s.axis_state_name(i)}")
        switches = [f"{name} {letters_of(bits)}" for name, bits in (
            ("limit+", s.limit_plus), ("limit-", s.limit_minus), ("home", s.home),
            ("soft", s.soft_limit)) if bits]
        if switches:
            lines.append("switches: " + ", ".join(switches))
        return lines + self._io_status()

    def _do_pos(self, args: list[str]) -> list[str]:
        s = self.dev.status()
        count = s.enabled_axes if self.dev.version == 2 else 3
        if not count:
            return ["no axes enabled (setup N)"]
        return [" ".join(f"{AXIS_LETTERS[i]} {s.positions[i]}" for i in range(count))]

    # ---- settings ----------------------------------------------------------------------
    def _do_setup(self, args: list[str]) -> list[str]:
        (n,) = args
        self.dev.setup(int(n))
        return []

    def _do_state(self, args: list[str]) -> list[str]:
        (name,) = args
        names = V1_STATES if self.dev.version == 1 else V2_STATES
        if name.lower() not in names:
            raise ConsoleError(f"state is one of {', '.join(names)} on the {self.dev.model}")
        self.dev.set_state(name.lower())
        return []

    def _do_axis(self, args: list[str]) -> list[str]:
        axis = self._axis(args[0])
        fields: dict[str, Any] = {}
        rest = [a.lower() for a in args[1:]]
        i = 0
        while i < len(rest):
            w = rest[i]
            if w in ("buffer", "internal"):
                fields["internal"] = w == "internal"
            elif w in ("position", "speed"):
                fields["position_mode"] = w == "position"
            elif w in ("max", "accel", "decel"):
                fields[{"max": "max_speed"}.get(w, w)] = float(rest[i + 1])
                i += 1
            elif w == "soft":
                fields["soft_limits"] = (int(rest[i + 1]), int(rest[i + 2]))
                i += 2
            elif w == "homing":
                fields["homing"] = (int(rest[i + 1]), int(rest[i + 2]))
                i += 2
            elif w == "invert":
                fields["invert"] = True
            elif w == "switches":
                bits = 0
                while i + 1 < len(rest) and rest[i + 1] in SWITCH_WORDS:
                    bits |= SWITCH_WORDS[rest[i + 1]]
                    i += 1
                fields["switches"] = bits
            else:
                raise ConsoleError(f"axis: cannot read {w!r}; say {WORDS['axis'][0]}")
            i += 1
        if self.dev.version == 1:
            fields.pop("internal", None)
            fields.pop("position_mode", None)
            if "soft_limits" in fields or "homing" in fields:
                raise ConsoleError("the v1 engine has no soft limits or per-axis homing speeds")
        else:
            current = self.dev.pulse_engine.axes[axis].settings
            fields.setdefault("internal", current.internal)
            fields.setdefault("position_mode", current.position_mode)
        self.dev.configure_axis(axis, **fields)
        return []

    def _do_set(self, args: list[str]) -> list[str]:
        self.dev.set_positions(self._pairs(args))
        return []

    def _do_clear(self, args: list[str]) -> list[str]:
        self.dev.clear_buffer()
        return []

    def _do_reboot(self, args: list[str]) -> list[str]:
        self.dev.reboot()
        return []

    # ---- motion ------------------------------------------------------------------------
    def _do_move(self, args: list[str]) -> list[str]:
        fraction = 1.0
        if len(args) >= 2 and args[-2].lower() == "at":
            fraction = float(args[-1])
            args = args[:-2]
        self.dev.move(self._pairs(args), fraction)
        return []

    def _do_fill(self, args: list[str]) -> list[str]:
        flags = {a.lower() for a in args if a.lower() in ("16bit", "large")}
        values = [a for a in args if a.lower() not in flags]
        repeat = 1
        if len(values) >= 2 and values[-2].lower() == "x":
            repeat = int(values[-1])
            values = values[:-2]
        row = [int(v) for v in values]
        if not row or repeat < 1:
            raise ConsoleError(f"fill: say {WORDS['fill'][0]}")
        wide = "16bit" in flags or any(abs(v) > 127 for v in row)
        taken = self.dev.fill(_Repeated(row, repeat), wide=wide, large="large" in flags)
        e = self.dev.pulse_engine
        return [f"accepted {taken} of {repeat}, buffer {e.buffer.count}/{e.buffer.depth}"]

    def _do_home(self, args: list[str]) -> list[str]:
        if args and args[0].lower() == "finish":
            self.dev.homing_finish(args[1].lower() if len(args) > 1 else "stopped")
            return []
        if not args:
            raise ConsoleError("home: name the axes, e.g. home X Y")
        self.dev.home([self._axis(a) for a in args])
        return []

    def _do_probe(self, args: list[str]) -> list[str]:
        if args and args[0].lower() == "finish":
            positions, status = self.dev.probing_finish()
            if status == 0:
                return ["no probe result"]
            if status == 2:
                return ["probe missed: max position reached"]
            count = self.dev.status().enabled_axes
            return ["probed: " + " ".join(f"{AXIS_LETTERS[i]} {positions[i]}"
                                          for i in range(count))]
        options = {"speed": 0.5, "input": 1, "polarity": 1}
        targets: dict[int, int] = {}
        i = 0
        while i < len(args):
            key = args[i].lower()
            if key in options:
                options[key] = float(args[i + 1]) if key == "speed" else int(args[i + 1])
            else:
                targets[self._axis(args[i])] = int(args[i + 1])
            i += 2
        if not targets:
            raise ConsoleError("probe: name an axis and its max position, e.g. probe Z -5000")
        self.dev.probe(targets, float(options["speed"]), int(options["input"]),
                       int(options["polarity"]))
        return []

    # ---- the world ---------------------------------------------------------------------
    def _do_world(self, args: list[str]) -> list[str]:
        if not args:
            return self._describe_world()
        axis = self._axis(args[0])
        what = args[1].lower()
        values = [None if v.lower() == "none" else float(v) for v in args[2:]]
        if not 1 <= len(values) <= 2:
            raise ConsoleError(f"world: say {WORDS['world'][0]}")
        first, second = values[0], values[-1]  # one `none` stands for both
        if what == "limits":
            self.dev.set_limits(axis, plus=first, minus=second)
        elif what == "home":
            self.dev.set_home(axis, first, second)
        else:
            raise ConsoleError(f"world: say {WORDS['world'][0]}")
        return []

    def _describe_world(self) -> list[str]:
        out = []
        for i, stage in enumerate(self.dev.world.axes[:self.dev.axes]):
            plus, minus, home = stage.plus_limit.low, stage.minus_limit.high, stage.home
            out.append(f"{AXIS_LETTERS[i]} limits {show_number(plus)} {show_number(minus)} "
                       f"home {show_number(home.low)} {show_number(home.high)}, "
                       f"stage at {self.dev.pulse_engine.axes[i].stage}")
        return out

    def _do_estop(self, args: list[str]) -> list[str]:
        (level,) = args
        self.dev.press_estop(on_off(level))
        return []

    def _do_input(self, args: list[str]) -> list[str]:
        number = int(args[0])
        if len(args) == 2:
            self.dev.set_input(number, on_off(args[1]))
            return []
        m = re.fullmatch(r"when\s+(\w)\s*(<=|>=)\s*(-?\d+)", " ".join(args[1:]), re.I)
        if m is None:
            raise ConsoleError(f"input: say {WORDS['input'][0]}")
        letter, op, at = m[1].upper(), m[2], int(m[3])
        self._axis(letter)
        test: Callable[[float], float] = (
            (lambda p: float(p <= at)) if op == "<=" else (lambda p: float(p >= at)))
        self.dev.set_input(number, axis_position_source(letter, test))
        return []

    def _do_request(self, args: list[str]) -> list[str]:
        text = " ".join(args)
        head, _, tail = text.partition(":")
        fields = [int(x, 16) for x in head.split()]
        if not 1 <= len(fields) <= 5 or any(not 0 <= f <= 255 for f in fields):
            raise ConsoleError("request: a command byte and up to 4 parameters, in hex")
        payload = bytes.fromhex(tail)
        c, p1, p2, p3, p4 = fields + [0] * (5 - len(fields))
        reply = self.dev.request(c, p1, p2, p3, p4, payload=payload)
        if reply is None:
            return ["no reply"]
        return [reply.hex(" ") + (f"  (refused: status {reply[2]})" if self.dev.last_refused
                                  else "")]

    # ---- helpers -----------------------------------------------------------------------
    def _axis(self, name: str) -> int:
        try:
            return axis_index(name, self.dev.axes)
        except ValueError as error:
            raise ConsoleError(str(error)) from None

    def _pairs(self, args: list[str]) -> dict[int, int]:
        if not args or len(args) % 2:
            raise ConsoleError("name each axis and its value, e.g. X 1000 Y -500")
        return {self._axis(args[i]): int(args[i + 1]) for i in range(0, len(args), 2)}

    def _slots(self, rest: str) -> list[str]:
        try:
            n = int(rest.strip() or "1")
        except ValueError:
            n = -1
        if not 0 <= n <= SHOWN_SLOTS_MAX:
            return [f"! say :slots N with N from 0 to {SHOWN_SLOTS_MAX} (a line a slot); "
                    ":advance moves time without showing it"]
        lines: list[str] = []
        e = self.dev.pulse_engine
        axes = [a.index for a in e.axes if e.active(a)] or list(range(len(e.axes)))

        def show(record: Any) -> None:
            if before is not None:
                before(record)
            pulses = " ".join(f"{AXIS_LETTERS[i]}{record.pulses[i]:+d}" for i in axes)
            lines.append(f"slot {record.slot}: {pulses} {e.state.name} buf {e.buffer.count}")

        before = e.trace
        e.trace = show
        try:
            self.dev.engine.advance(n)
        finally:
            e.trace = before
        return lines

    def _trace(self, rest: str) -> list[str]:
        if rest.lower() == "off":
            if self.recorder is None:
                return ["no trace running"]
            self.recorder.detach()
            return [f"trace: {self.recorder.slots} slots written"]
        if not rest:
            return ["say :trace FILE.csv or :trace off"]
        try:
            stream = open(rest, "w", encoding="utf-8", newline="")  # noqa: SIM115
        except (OSError, ValueError) as error:  # no such folder, a NUL in the name
            return [f"trace: {error}"]
        out = []
        if self.recorder is not None and self.recorder.stream is not None:
            # one trace at a time: the running one ends (its file closed) as a new one starts
            self.recorder.detach()
            out.append(f"trace: the previous trace ended, {self.recorder.slots} slots written")
        self.recorder = SlotRecorder(self.dev.pulse_engine, stream, device=self.dev.device)
        self.recorder.attach()
        return [*out, f"trace: {rest}"]

    def _plan(self, rest: str) -> list[str]:
        axis = self._axis(rest.strip() or "X")
        found = self.dev.engine.motion_plan(axis)
        if found is None:
            return [f"{AXIS_LETTERS[axis]} stands still"]
        plan = found.plan
        head = (f"{AXIS_LETTERS[axis]} from slot {found.start} at {found.origin}: "
                f"ends {show_number(plan.end_time)} s, {plan.final_offset:+d} pulses")
        return [head] + [f"  t0 {p.t0:.3f} s  {p.duration:.3f} s  dir {p.direction:+d}  "
                         f"{p.v1:g}..{p.v2:g} pulses/s" for p in plan.phases]

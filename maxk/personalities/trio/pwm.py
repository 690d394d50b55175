"""The MC405 PWM output of one axis, as the PWM application note defines it.

Each of axes 0-4 has its own PWM circuit on the axis's third (enable / Z) output, clocked
at 20 MHz: PWM_CYCLE clocks per period, PWM_MARK clocks on. PWM_CONTROL picks where the
mark comes from (off, PWM_MARK, path speed, path speed times a profile axis) and runs a
position-gating FIFO compared against a 29-bit PWM_ENCODER register that follows the
axis but ignores DEFPOS/OFFPOS.

Pure logic: the engine calls :meth:`PwmOutput.servo_cycle` once per servo cycle with the
link axes' VP_SPEED (and the amplitude axis's DPOS), and moves the encoder with
:meth:`PwmOutput.move_encoder`; :meth:`PwmOutput.next_gate` and
:meth:`GateEntry.counts_to_pass` tell it where the next gate toggle is, so it can find
the exact tick the axis passes it. Where the seed leaves a question open the choice is
in :data:`DECISIONS` with its confidence (C certain, I inferred, D our decision).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from enum import IntEnum
from typing import Final, NamedTuple

from .memory import TableMemory

PWM_CLOCK_HZ: Final = 20_000_000
PWM_REGISTER_MAX: Final = 65535
PWM_ENCODER_BITS: Final = 29
PWM_ENCODER_MODULUS: Final = 1 << PWM_ENCODER_BITS
GATE_FIFO_DEPTH: Final = 512
PWM_AXES: Final = (0, 1, 2, 3, 4)
PWM_ATYPES: Final = frozenset({35, 36})
DEFAULT_PWM_CYCLE: Final = 1000

# PWM_CONTROL mode -> number of arguments including the mode itself
_ARITY: Final = {0: 1, 1: 1, 2: 5, 3: 5, 4: 1, 5: 1, 6: 1, 7: 1, 8: 6}


class Decision(NamedTuple):
    topic: str
    choice: str
    confidence: str  # C / I / D
    source: str


DECISIONS: Final = (
    Decision("clock", "20 MHz base clock; frequency = 20e6 / PWM_CYCLE", "C",
             "seed: PWM Generation"),
    Decision("PWM_CYCLE range", "1..65535; 0, negatives and larger values are refused, "
             "nothing changes; fractions truncate", "D",
             "seed gives the 65535 maximum; a period of 0 clocks has no meaning"),
    Decision("PWM_MARK range", "0..65535, refused outside; fractions truncate", "D",
             "seed gives the 65535 maximum"),
    Decision("continuous on", "PWM_MARK >= PWM_CYCLE gives a continuously on output; "
             "PWM_MARK 0 is off even when PWM_CYCLE is also 0", "C",
             "seed, last sentence; the 0/0 case is D"),
    Decision("default PWM_CYCLE", "1000 (20 kHz) at power-up, PWM_MARK 0, mode 0", "D",
             "every seed example sets PWM_CYCLE=1000"),
    Decision("PWM_MARK readback in modes 2/8", "reads the mark loaded on the last servo "
             "cycle (the computed value); it stays there after leaving the mode", "I",
             "seed: 'The value loaded into the PWM_MARK is given by ...'"),
    Decision("computed mark", "speed*mult(+amplitude)+offset, limited to the limit value, "
             "then to 0..65535, truncated to an integer clock count", "D",
             "seed states the upper limit only; a register cannot hold negatives"),
    Decision("servo cycle", "modes 2 and 8 recompute the mark once per servo cycle "
             "(SERVO_PERIOD, MC405 default 1000 us)", "C", "seed: 'adjusted on each servo "
             "cycle'; period from the MC405 default"),
    Decision("gate positions", "TABLE values are axis positions in user units, converted "
             "to PWM_ENCODER counts with the axis's UNITS when PWM_CONTROL(3) runs, rounded "
             "to the nearest count", "I", "seed example 3: MOVEABS(300) with UNITS=16 passes "
             "positions 110..220"),
    Decision("gate compare", "the FIFO head only is compared; GT fires when PWM_ENCODER "
             "is above the position, LT when below; an entry already passed when it "
             "reaches the head fires at once; several can fire in one cycle, in order", "I",
             "seed: 'As the axis moves past the positions the gating output is toggled'"),
    Decision("gate levels", "the first position of a PWM_CONTROL(3) gets the ON/OFF "
             "argument, each next one the opposite; non-zero means ON (and GT)", "I",
             "seed: 'The ON/OFF bit is toggled as the positions are loaded'"),
    Decision("gate state", "the gate starts closed; PWM_CONTROL(4) empties the FIFO and "
             "leaves the gate as it is; PWM_CONTROL(0) switches output and gating off", "D",
             "not stated by the seed"),
    Decision("FIFO overflow", "a PWM_CONTROL(3) that would take the FIFO past 512 entries "
             "is refused whole: nothing loaded", "D", "seed: 'up to 512 positions deep'"),
    Decision("table run", "table start must not exceed table end", "D", "not stated"),
    Decision("PWM_ENCODER wrap", "29-bit register read unsigned 0..536870911; moving "
             "below 0 wraps to the top; compares use the signed 29-bit difference", "D",
             "seed: 'dedicated 29 bit encoder hardware register'"),
    Decision("mode 7", "PWM_CONTROL(7) is refused", "D", "seed: 'Reserved'"),
    Decision("output conditions", "output only with WDOG=ON and ATYPE 35 or 36", "I",
             "seed: 'the WDOG must be ON for PWM generation'; ATYPE table"),
    Decision("PWM axes", "axes 0-4 have a PWM circuit", "C",
             "seed: 'works with axes 0, 1, 2, 3 and 4'"),
    Decision("PWM keywords on other axes", "PWM_CYCLE, PWM_MARK, PWM_ENCODER and "
             "PWM_CONTROL on axes 5 and up are refused ('Axis n has no PWM output')", "D",
             "a virtual axis has no Z output to drive"),
)


class PwmError(ValueError):
    """A PWM request the firmware refuses; nothing has changed."""


class PwmMode(IntEnum):
    """Where the mark comes from (PWM_CONTROL 0, 1, 2, 8)."""

    OFF = 0
    MARK = 1
    SPEED = 2
    SPEED_PROFILE = 8


def signed_counts(value: int) -> int:
    """A 29-bit register difference as a signed count (-2^28 .. 2^28-1)."""
    value %= PWM_ENCODER_MODULUS
    return value - PWM_ENCODER_MODULUS if value >= PWM_ENCODER_MODULUS // 2 else value


@dataclass(frozen=True)
class GateEntry:
    """One position in the gating FIFO."""

    position: int  # PWM_ENCODER value, 0 .. 2^29-1
    greater: bool  # GT comparison (else LT)
    level: bool  # the gate state once the axis passes the position

    def passed(self, encoder: int) -> bool:
        d = signed_counts(encoder - self.position)
        return d > 0 if self.greater else d < 0

    def counts_to_pass(self, encoder: int) -> int:
        """Signed counts the encoder must still move to pass (0: passed already)."""
        if self.passed(encoder):
            return 0
        target = self.position + (1 if self.greater else -1)
        return signed_counts(target - encoder)


def _whole(value: float, what: str) -> int:
    if not math.isfinite(value):
        raise PwmError(f"{what} out of range")
    return int(value)  # truncation toward zero, as a register write does


class PwmOutput:
    """The PWM circuit of one axis."""

    def __init__(self, axis: int) -> None:
        self.axis = axis
        self.cycle = DEFAULT_PWM_CYCLE
        self._mark = 0
        self.mode = PwmMode.OFF
        self.multiplier = 0.0
        self.offset = 0.0
        self.limit = 0.0
        self.velocity_axis: int | None = None
        self.amplitude_axis: int | None = None
        self.gating = False
        self.gate_level = False
        self.fifo: deque[GateEntry] = deque()
        self.encoder = 0
        # told of every FIFO entry as it fires (the engine logs the gate edges)
        self.on_gate: Callable[[int, GateEntry], None] | None = None

    # ---- registers ------------------------------------------------------------------
    @property
    def mark(self) -> int:
        return self._mark

    def set_cycle(self, value: float) -> None:
        cycle = _whole(value, "PWM_CYCLE")
        if not 1 <= cycle <= PWM_REGISTER_MAX:
            raise PwmError("PWM_CYCLE out of range")
        self.cycle = cycle

    def set_mark(self, value: float) -> None:
        mark = _whole(value, "PWM_MARK")
        if not 0 <= mark <= PWM_REGISTER_MAX:
            raise PwmError("PWM_MARK out of range")
        self._mark = mark

    @property
    def frequency_hz(self) -> float:
        return PWM_CLOCK_HZ / self.cycle

    # ---- PWM_CONTROL --------------------------------------------------------------------
    def control(self, args: Sequence[float], table: TableMemory, units: float,
                axis_count: int) -> None:
        """PWM_CONTROL(mode, ...): everything is checked before anything changes."""
        if not args:
            raise PwmError("PWM_CONTROL needs a mode")
        mode = args[0]
        if mode != int(mode) or int(mode) not in _ARITY:
            raise PwmError("PWM_CONTROL mode out of range")
        m = int(mode)
        if len(args) != _ARITY[m]:
            raise PwmError(f"PWM_CONTROL({m}) takes {_ARITY[m]} parameters")
        if m == 7:
            raise PwmError("PWM_CONTROL(7) is reserved")
        if m in (2, 8):
            links = [self._link_axis(a, axis_count) for a in args[4:]]
            self.multiplier, self.offset, self.limit = args[1], args[2], args[3]
            self.velocity_axis = links[0]
            self.amplitude_axis = links[1] if m == 8 else None
            self.mode = PwmMode(m)
        elif m == 3:
            self._load_gates(args, table, units)
        elif m in (0, 1):
            self.mode = PwmMode(m)
            if m == 0:
                self.gating = False
        elif m == 4:
            self.fifo.clear()
        elif m == 5:
            self.gating = True
        elif m == 6:
            self.encoder = 0

    @staticmethod
    def _link_axis(value: float, axis_count: int) -> int:
        if value != int(value) or not 0 <= int(value) < axis_count:
            raise PwmError("PWM_CONTROL link axis out of range")
        return int(value)

    def _load_gates(self, args: Sequence[float], table: TableMemory, units: float) -> None:
        greater, level = args[1] != 0, args[2] != 0
        start, end = args[3], args[4]
        if start != int(start) or end != int(end) or start > end:
            raise PwmError("PWM_CONTROL table range out of range")
        try:
            positions = table.read_run(int(start), int(end))
        except ValueError as exc:
            raise PwmError(str(exc)) from None
        if len(self.fifo) + len(positions) > GATE_FIFO_DEPTH:
            raise PwmError("PWM gating FIFO full")
        entries = []
        for value in positions:
            counts = value * units
            if not math.isfinite(counts):
                raise PwmError("PWM gate position out of range")
            entries.append(GateEntry(round(counts) % PWM_ENCODER_MODULUS, greater, level))
            level = not level
        self.fifo.extend(entries)
        self._fire()  # an entry the axis is already past fires at once

    # ---- per servo cycle ------------------------------------------------------------
    @property
    def links(self) -> tuple[int | None, int | None]:
        """(velocity link axis, amplitude link axis) the engine must supply each cycle."""
        if self.mode in (PwmMode.SPEED, PwmMode.SPEED_PROFILE):
            return self.velocity_axis, self.amplitude_axis
        return None, None

    @property
    def computed(self) -> bool:
        """The mark is recomputed every servo cycle (modes 2 and 8)."""
        return self.mode in (PwmMode.SPEED, PwmMode.SPEED_PROFILE)

    def computed_mark(self, link_speed: float, amplitude: float = 1.0) -> int:
        """The mark modes 2 and 8 load from a servo cycle's VP_SPEED (and DPOS)."""
        if self.mode is PwmMode.SPEED_PROFILE:
            value = link_speed * amplitude * self.multiplier + self.offset
        else:
            value = link_speed * self.multiplier + self.offset
        value = min(value, self.limit)
        value = min(max(value, 0.0), float(PWM_REGISTER_MAX)) if math.isfinite(value) else 0.0
        return int(value)

    def load_mark(self, mark: int) -> None:
        """A servo cycle loaded a computed mark into the register."""
        self._mark = mark

    def servo_cycle(self, link_speed: float = 0.0, amplitude: float = 1.0) -> None:
        """Reload PWM_MARK from the link axis's VP_SPEED (modes 2 and 8)."""
        if self.computed:
            self._mark = self.computed_mark(link_speed, amplitude)

    # ---- the gating FIFO ------------------------------------------------------------------
    def move_encoder(self, counts: int) -> list[GateEntry]:
        """The axis moved `counts`: update PWM_ENCODER and fire the entries now passed."""
        self.encoder = (self.encoder + counts) % PWM_ENCODER_MODULUS
        return self._fire()

    def _fire(self) -> list[GateEntry]:
        fired = []
        while self.fifo and self.fifo[0].passed(self.encoder):
            entry = self.fifo.popleft()
            self.gate_level = entry.level
            fired.append(entry)
            if self.on_gate is not None:
                self.on_gate(self.axis, entry)
        return fired

    def next_gate(self) -> GateEntry | None:
        return self.fifo[0] if self.fifo else None

    def pending_gates(self) -> list[GateEntry]:
        return list(self.fifo)

    # ---- the output ---------------------------------------------------------------------
    @property
    def gate_open(self) -> bool:
        return self.gate_level if self.gating else True

    def duty(self, wdog: bool, atype: int) -> float:
        """Fraction of each period the combined output is on (0 off, 1 continuously on)."""
        if not wdog or atype not in PWM_ATYPES or self.mode is PwmMode.OFF:
            return 0.0
        if not self.gate_open or self._mark == 0:
            return 0.0
        if self._mark >= self.cycle:
            return 1.0
        return self._mark / self.cycle


class PwmBank:
    """The PWM circuits of the MC405's axes 0-4."""

    def __init__(self, axis_count: int) -> None:
        self.axis_count = axis_count
        self.outputs = {axis: PwmOutput(axis) for axis in PWM_AXES if axis < axis_count}

    def __getitem__(self, axis: int) -> PwmOutput:
        try:
            return self.outputs[axis]
        except KeyError:
            raise PwmError(f"axis {axis} has no PWM output") from None

    def servo_cycle(self, vp_speed: Callable[[int], float], dpos: Callable[[int], float]) -> None:
        """Reload every speed-linked mark from this cycle's VP_SPEED and DPOS readings."""
        for output in self.outputs.values():
            speed_axis, amplitude_axis = output.links
            if speed_axis is None:
                continue
            amplitude = dpos(amplitude_axis) if amplitude_axis is not None else 1.0
            output.servo_cycle(vp_speed(speed_axis), amplitude)

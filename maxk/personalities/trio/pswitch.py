"""Position switches of the MC405: PSWITCH and HW_PSWITCH (their TrioBASIC help pages).

An output a switch drives is ON while any switch drives it ON or OP set it (the page: the
output is the OR of every switch on it and the OP setting), read through the machine's
`output`. Every level is a function of the axis's whole counts at the tick it is read
(a computed output: exact at any tick), and every change is an engine event found on
the axis's motion (the shared `tick_reaching` bisection, or on a linked axis a bisection
of its demand up to the next motion event, as registration does), so the edge log and
the programs waiting on an output see it on its own servo tick.

- **Cyclic PSWITCH(switch, enable, axis, output, state, setpos, resetpos)**: inside the
  window setpos <= position < resetpos (user units, as DPOS reads: REP_DIST folded) the
  switch drives `state`, outside it the opposite (C: the page's example 3, state OFF,
  gives an output off only inside the window). Enable bit 1 lets setpos exceed resetpos:
  the window then runs from setpos over the fold to resetpos (I). Bit 2 compares DPOS;
  MPOS is the demand too (D: the switch compares the demand's whole counts).
- **Sequence PSWITCH(switch, mode, axis, output, state, start, end[, pulse time])** (mode
  bit 3): the TABLE positions start..end fire in turn as the axis reaches each in the
  direction mode bit 5 gives; the first sets the output to `state`, each next one
  toggles it, or with mode bit 4 (timer) each gives a pulse of `state` for pulse time
  servo cycles.
- **HW_PSWITCH(mode, direction, opstate, start, end) AXIS(n)**: the MC405's hardware
  switch of axis n (0..4) on output 8 + n (C: page note 1); a FIFO of at most 512 counts
  (MPOS x UNITS) toggling the output from opstate as the axis passes each in the given
  direction; mode 0 disables it, 2 clears the FIFO.

- **HW_TIMER(mode, cycle time[, on time, reps], op mode, op sel, op state)**: the
  hardware timer drives a digital output (8..15; op mode 2: 8 + op sel) at op state for
  cycle time us (mode 1), or for on time us of each of reps cycles of cycle time us
  (mode 2), times truncated to 10 us (C: page); HW_TIMER_DONE reads 1 while it runs. An
  output level is read at servo ticks: a pulse shorter than a servo cycle shows on its
  first tick only.

Decisions (D): a sequence ends at the first TABLE value that does not go on in its
direction (the page's example 4 names 100 entries and fills 16); a position already
passed when loaded fires at once, several in one cycle in order; before its first
position a sequence drives nothing; an axis with a negative UNITS is refused. While
the hardware timer runs it owns its output (OP and the switches do not change it); when
it ends the output stays at the timer's last level as if OP had set it, and HW_TIMER(0)
leaves it where it is; axis enable outputs (op mode 1) are not modelled and refused.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from maxk.firmware_model.axis import first_tick

SWITCHES = 64  # PSWITCH numbers 0..63 (C: page)
FIFO_DEPTH = 512  # HW_PSWITCH positions held (C: page)
HW_OUTPUT = 8  # axis n's HW_PSWITCH output is 8 + n (C: page note 1, the MC405)
HW_AXES = 5  # axes 0..4 have one (C: page note 1)
SEQUENCE_LENGTH = 4096  # TABLE values one sequence takes at most (D: a bound)
EDGE_LOG = 1024  # the newest output edges kept (D)
OUTPUTS = 1024  # output numbers a switch may drive (as OP: IO_SPACE)


@dataclass
class Window:
    """A cyclic PSWITCH: `state` inside setpos..resetpos, the opposite outside."""

    axis: int
    output: int
    state: bool
    setpos: float
    resetpos: float
    wrap: bool  # enable bit 1: setpos above resetpos, the window runs over the fold
    enabled: bool = True


@dataclass
class Sequence_:
    """A TABLE sequence (PSWITCH mode bit 3) or a HW_PSWITCH FIFO: thresholds in whole
    counts, each fired when the axis's counts reach it travelling `direction`."""

    axis: int
    output: int
    state: bool
    direction: int
    fifo: deque[int] = field(default_factory=deque)
    pulse: int | None = None  # timer mode: servo cycles each pulse lasts
    level: bool = False
    pulse_end: int | None = None
    fired: int = 0
    enabled: bool = True


Switch = Window | Sequence_


@dataclass
class Timer:
    """HW_TIMER: `output` at `state` for `on` us of each `cycle` us, `reps` times, from
    servo tick `start` (mode 1: on = cycle, reps 1)."""

    output: int
    state: bool
    start: int
    cycle: int  # us
    on: int  # us
    reps: int

    def end_us(self) -> int:
        return self.cycle * self.reps

    def level(self, elapsed_us: float) -> bool:
        if elapsed_us >= self.end_us():
            return not self.state
        return self.state if elapsed_us % self.cycle < self.on else not self.state


class PositionSwitches:
    """The machine's PSWITCHes and HW_PSWITCHes: an event source of the engine."""

    def __init__(self, machine: Any) -> None:
        self.m = machine
        self._cache: tuple[int, int | None] = (-1, None)
        self.reset()

    def reset(self) -> None:
        self.switches: dict[int, Switch] = {}
        self.hardware: dict[int, Sequence_] = {}
        self.edges: deque[tuple[int, int, bool]] = deque(maxlen=EDGE_LOG)
        self._seen: dict[int, bool] = {}  # each driven output's level at the last event
        self.timer: Timer | None = None

    # ---- the program's side ------------------------------------------------------------
    def pswitch(self, args: Sequence[float]) -> None:
        """PSWITCH in any of its three forms; every argument checked before any change."""
        if len(args) < 2:
            raise ValueError("Syntax error")
        number, enable = _whole(args[0], 0, SWITCHES - 1), args[1]
        if enable != int(enable) or not 0 <= enable < 128:
            raise ValueError("Parameter out of range")
        mode = int(enable)
        if mode & 1 == 0:  # PSWITCH(switch, OFF[, hold])
            if len(args) > 3:
                raise ValueError("Syntax error")
            hold = _whole(args[2], 0, 1) if len(args) == 3 else 0
            self._disable(number, forced_off=hold == 1)
            return
        if len(args) == 2:  # enable again what was set up (D)
            if number not in self.switches:
                raise ValueError("Parameter out of range")
            self.switches[number].enabled = True
            self._acted()
            return
        if len(args) < 7:
            raise ValueError("Syntax error")
        axis = self._axis(args[2])
        output = _whole(args[3], 0, OUTPUTS - 1)
        state = args[4] != 0
        if mode & 64:
            raise ValueError("Parameter out of range")  # Z output: not modelled (D)
        if mode & 8:
            if len(args) > 8 or (mode & 16 and len(args) != 8):
                raise ValueError("Syntax error")
            pulse = _whole(args[7], 1, 2 ** 31) if mode & 16 else None
            direction = -1 if mode & 32 else 1
            first, last = _whole(args[5], 0, 2 ** 31), _whole(args[6], 0, 2 ** 31)
            positions = self._table(first, last, direction)
            sequence = Sequence_(axis, output, state, direction, pulse=pulse)
            self.switches[number] = sequence
            self._load(sequence, [self._threshold(axis, p * self.m.axes[axis].units,
                                                direction) for p in positions])
            return
        if len(args) != 7 or mode & 48:
            raise ValueError("Parameter out of range" if len(args) == 7 else "Syntax error")
        setpos, resetpos = args[5], args[6]
        wrap = bool(mode & 2)
        if not wrap and setpos > resetpos:
            raise ValueError("Parameter out of range")
        self.switches[number] = Window(axis, output, state, setpos, resetpos, wrap)
        self._acted()

    def hw_pswitch(self, axis: int, args: Sequence[float]) -> None:
        """HW_PSWITCH(mode[, direction, opstate, table start, table end]) AXIS(n)."""
        if not 0 <= axis < HW_AXES:
            raise ValueError("Invalid axis number")
        mode = _whole(args[0], 0, 2) if args else -1
        if mode in (0, 2):
            if len(args) != 1:
                raise ValueError("Syntax error")
            switch = self.hardware.get(axis)
            if switch is not None and mode == 0:
                switch.enabled = False
            elif switch is not None:
                switch.fifo.clear()
            self._acted()
            return
        if len(args) != 5:
            raise ValueError("Syntax error")
        direction = 1 if _whole(args[1], 0, 1) else -1
        state = args[2] != 0
        first, last = _whole(args[3], 0, 2 ** 31), _whole(args[4], 0, 2 ** 31)
        positions = self._table(first, last, direction)
        switch = self.hardware.get(axis)
        held = len(switch.fifo) if switch is not None else 0
        if held + len(positions) > FIFO_DEPTH:
            raise ValueError("Parameter out of range")
        if switch is None or (not switch.fifo and switch.direction != direction):
            switch = Sequence_(axis, HW_OUTPUT + axis, state, direction,
                               level=switch.level if switch is not None else False)
            self.hardware[axis] = switch
        switch.enabled = True
        if not switch.fifo:  # the first of a new load gets opstate (page)
            switch.state, switch.fired = state, 0
        self._load(switch, [self._threshold(axis, p, direction, units=False)
                            for p in positions])

    def hw_timer(self, args: Sequence[float]) -> None:
        """HW_TIMER(0) / (1, cycle, op mode, op sel, state) / (2, cycle, on, reps, op mode,
        op sel, state): every argument checked before any change."""
        mode = _whole(args[0], 0, 2) if args else -1
        if mode == 0:
            if len(args) != 1:
                raise ValueError("Syntax error")
            self._timer_end(keep=True)
            return
        if len(args) != (5 if mode == 1 else 7):
            raise ValueError("Syntax error")
        cycle = _whole(args[1], 10, 2 ** 31) // 10 * 10  # 10 us resolution (C)
        on, reps = cycle, 1
        if mode == 2:
            on = _whole(args[2], 0, cycle) // 10 * 10
            reps = _whole(args[3], 1, 2 ** 31)
        op_mode, op_sel = _whole(args[-3], 0, 2), _whole(args[-2], 0, 15)
        if op_mode == 1:
            raise ValueError("Parameter out of range")  # enable outputs: not modelled (D)
        if op_mode == 0 and not 8 <= op_sel <= 15 or op_mode == 2 and not op_sel <= 4:
            raise ValueError("Parameter out of range")
        output = op_sel if op_mode == 0 else HW_OUTPUT + op_sel
        self._timer_end(keep=True)
        self.timer = Timer(output, args[-1] != 0, self.m.tick, cycle, on, reps)
        self._acted()

    def timer_done(self) -> float:
        """HW_TIMER_DONE: 1 while the timer runs, else 0 (C: page)."""
        return 0.0 if self.timer is None else 1.0

    def level(self, output: int, op: bool) -> bool:
        """The output's level: the running timer's, else OP's OR the switches'."""
        timer = self._timer_level(output)
        if timer is not None:
            return timer
        return op or self.drives(output)

    def _timer_level(self, output: int) -> bool | None:
        timer = self.timer
        if timer is None or (output >= 0 and timer.output != output):
            return None
        return timer.level((self.m.tick - timer.start) * self.m.period * 1e6)

    def _timer_end(self, keep: bool) -> None:
        """The timer ends: its output stays at the level it has now (as OP's)."""
        timer = self.timer
        if timer is not None and keep:
            self.m.digital_outputs[timer.output] = bool(self._timer_level(timer.output))
        self.timer = None
        self._acted()

    def drives(self, output: int) -> bool:
        """Does any switch drive this output ON now?"""
        now = self.m.tick
        return any(s.enabled and s.output == output and self._level(s, now)
                   for s in self._all())

    # ---- the machine's side ------------------------------------------------------------
    def next_event(self) -> int | None:
        m = self.m
        if self._cache[0] == m.revision:
            return self._cache[1]
        best: int | None = None
        if self._changed_since_event():
            best = m.tick
        if self.timer is not None:  # its end: the output is OP's again, DONE reads 0
            end = self.timer.start + math.ceil(self.timer.end_us() / (m.period * 1e6) - 1e-9)
            best = end if best is None else min(best, end)
        horizon: int | None = -1
        for switch in self._all():
            if not switch.enabled:
                continue
            if horizon == -1:
                horizon = m.motion_horizon()
            for tick in self._ticks(switch, horizon):
                if best is None or tick < best:
                    best = tick
        if best is not None:
            best = max(best, m.tick)
        self._cache = (m.revision, best)
        return best

    def on_event(self, now: int) -> None:
        timer = self.timer
        if timer is not None and (now - timer.start) * self.m.period * 1e6 >= \
                timer.end_us() - 1e-6:
            self._timer_end(keep=True)
        for switch in self._all():
            if isinstance(switch, Sequence_) and switch.enabled:
                self._fire(switch, now)
        self._log(now)
        self._cache = (-1, None)
        self.m.changed()

    # ---- inside --------------------------------------------------------------------------
    def _all(self) -> list[Switch]:
        return [*self.switches.values(), *self.hardware.values()]

    def _axis(self, value: float) -> int:
        axis = value
        if axis != int(axis) or not 0 <= axis < self.m.axis_count:
            raise ValueError("Invalid axis number")
        if not self.m.axes[int(axis)].units > 0:
            raise ValueError("Parameter out of range")  # negative UNITS: refused (D)
        return int(axis)

    def _table(self, first: int, last: int, direction: int) -> list[float]:
        """TABLE(first..last) up to the first value that does not go on in `direction`
        (D: the sequence's end)."""
        if last < first or last - first >= SEQUENCE_LENGTH:
            raise ValueError("Parameter out of range")
        values: list[float] = []
        for index in range(first, last + 1):
            value = self.m.table.read(index)
            if values and direction * (value - values[-1]) <= 0:
                break
            values.append(value)
        return values

    def _threshold(self, axis: int, position: float, direction: int,
                   units: bool = True) -> int:
        """The whole count (physical) a comparison with `position` (counts as MPOS x
        UNITS reads them, DEFPOS applied) turns true at, travelling `direction`."""
        a = self.m.axes[axis]
        raw = position - a.datum
        here = self.m.demand(axis)
        if units:  # a position in the fold the axis reads now (as MOVEABS)
            raw = self.m.unwrapped(axis, position / a.units, (here + a.datum) / a.units) \
                * a.units - a.datum
        return math.ceil(raw - 1e-9) if direction > 0 else math.floor(raw + 1e-9)

    def _load(self, switch: Sequence_, thresholds: list[int]) -> None:
        switch.fifo.extend(thresholds)
        self._fire(switch, self.m.tick)  # positions already passed fire at once
        self._acted()

    def _fire(self, switch: Sequence_, now: int) -> None:
        """Every head position the axis has reached by `now`, in order; a pulse ends."""
        if switch.pulse_end is not None and switch.pulse_end <= now:
            switch.level, switch.pulse_end = False, None
        counts = self.m.counts_at(switch.axis, now)
        while switch.fifo and switch.direction * (counts - switch.fifo[0]) >= 0:
            switch.fifo.popleft()
            if switch.pulse is not None:
                switch.level, switch.pulse_end = switch.state, now + switch.pulse
            else:
                switch.level = switch.state if switch.fired % 2 == 0 else not switch.state
            switch.fired += 1

    def _level(self, switch: Switch, tick: int) -> bool:
        if isinstance(switch, Sequence_):
            return switch.level
        return self._window_level(switch, self.m.counts_at(switch.axis, tick))

    def _window_level(self, switch: Window, counts: int) -> bool:
        a = self.m.axes[switch.axis]
        u = self.m.wrapped(switch.axis, (counts + a.datum) / a.units)
        if switch.wrap and switch.setpos > switch.resetpos:
            inside = u >= switch.setpos or u < switch.resetpos
        else:
            inside = switch.setpos <= u < switch.resetpos
        return switch.state if inside else not switch.state

    def _ticks(self, switch: Switch, horizon: int | None) -> list[int]:
        """The ticks the switch may change at next (each way along its axis)."""
        m = self.m
        if isinstance(switch, Sequence_):
            out = [switch.pulse_end] if switch.pulse_end is not None else []
            if switch.fifo and switch.direction * (
                    m.counts_at(switch.axis, m.tick) - switch.fifo[0]) >= 0:
                out.append(m.tick)  # already there (a move that ended on it): due now
            elif switch.fifo:
                tick = self._reaching(switch.axis, switch.fifo[0], switch.direction, horizon)
                if tick is not None:
                    out.append(tick)
            return out
        here = m.counts_at(switch.axis, m.tick)
        up: int | None = None
        down: int | None = None
        for edge in self._edges(switch, here):
            if edge > here and (up is None or edge < up):
                up = edge
            if edge <= here and (down is None or edge > down):
                down = edge
        found = []
        for target, direction in ((up, 1), (None if down is None else down - 1, -1)):
            if target is not None:
                tick = self._reaching(switch.axis, target, direction, horizon)
                if tick is not None:
                    found.append(tick)
        return found

    def _edges(self, switch: Window, here: int) -> list[int]:
        """Counts e where the window's level may differ between e - 1 and e, near here:
        its two positions and the fold's boundary, repeated every fold."""
        m = self.m
        a = m.axes[switch.axis]
        params = a.params
        rep = params.get("REP_DIST", 0.0)
        u_here = (here + a.datum) / a.units
        values = [switch.setpos, switch.resetpos]
        if not rep > 0:
            return [math.ceil(v * a.units - a.datum - 1e-9) for v in values]
        span, origin = (rep, 0.0) if int(params.get("REP_OPTION", 0.0)) & 1 else \
            (2 * rep, -rep)
        out = []
        for v in [*values, origin]:
            folds = (u_here - v) / span
            if not math.isfinite(folds):  # a fold finer than a float step: every count
                return [here, here + 1]
            k0 = math.floor(folds)
            for k in range(k0 - 1, k0 + 3):
                out.append(math.ceil((v + k * span) * a.units - a.datum - 1e-9))
        return out

    def _reaching(self, axis: int, count: int, direction: int,
                  horizon: int | None) -> int | None:
        """The first tick after now the axis's whole counts reach `count` travelling
        `direction`: on its own motion exactly (`tick_reaching`); on a linked axis by
        bisection up to the horizon, its demand taken as monotonic till then (D)."""
        m = self.m
        a = m.axes[axis]
        if a.motion is not None and a.link is None and axis not in m.links.addax:
            return a.tick_reaching(count, direction, m)  # type: ignore[no-any-return]
        if horizon is None or horizon <= m.tick:
            return None

        def reached(tick: int) -> bool:
            return direction * (m.counts_at(axis, tick) - count) >= 0

        return _first(reached, m.tick, horizon)

    def _changed_since_event(self) -> bool:
        return any(self.m.output(o) != level for o, level in self._seen.items()) or any(
            s.enabled and s.output not in self._seen for s in self._all())

    def _log(self, now: int) -> None:
        outputs = {s.output for s in self._all()} | set(self._seen)
        if self.timer is not None:
            outputs.add(self.timer.output)
        for output in sorted(outputs):
            level = self.m.output(output)
            if self._seen.get(output, False) != level:
                self.edges.append((now, output, level))
            self._seen[output] = level

    def _disable(self, number: int, forced_off: bool) -> None:
        switch = self.switches.get(number)
        if switch is None:
            return
        if forced_off:
            self.m.digital_outputs[switch.output] = False
        elif switch.enabled and self._level(switch, self.m.tick):
            self.m.digital_outputs[switch.output] = True  # it stays as it was (page)
        switch.enabled = False
        self._acted()

    def _acted(self) -> None:
        self._cache = (-1, None)
        self.m.changed()


def _whole(value: float, low: int, high: int) -> int:
    if value != int(value) or not low <= value <= high:
        raise ValueError("Parameter out of range")
    return int(value)


def _first(reached: Callable[[int], bool], now: int, horizon: int) -> int | None:
    """The first tick after `now`, up to the horizon, the switch's position is reached."""
    return first_tick(reached, now + 1, horizon)


__all__ = ["FIFO_DEPTH", "HW_OUTPUT", "SWITCHES", "PositionSwitches", "Timer"]

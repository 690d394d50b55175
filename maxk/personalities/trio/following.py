"""Servo axes of the MC405 on the shared servo loop: following error and FE_LIMIT.

An axis is a servo when its ATYPE is a servo type (`axistypes.SERVO_ATYPES`: 44, the
flexible axis's analogue servo, 36, 77, the absolute-feedback 46/47/48/92, ...) and
P_GAIN is above 0: the shared loop (`firmware_model/servo.py`, the PID the MAXk and
MM4005 run) then drives the world's motor plant of the axis every servo cycle, MPOS reads
the plant's encoder and FE is DPOS - MPOS. With the factory gains (P_GAIN 0) the axis
stays the exact, profile-only axis it always was (MPOS = DPOS, FE = 0), so every exact
figure keeps its meaning.

What is superimposed on an axis's own moves (ADDAX, what an ended ADDAX or a SYNC left:
links.py) is in its loop's command too (`superimposed`), so a servo motor follows DPOS
as a stepper does (the loop is then stepped in Python, as with BACKLASH).

The gains map onto the shared filter as DAC = P_GAIN e + D_GAIN (e - e_prev) + I_GAIN
sum(e) + VFF_GAIN v + AFF_GAIN a + OV_GAIN dPm (counts, counts per servo cycle: D, the
MC405's own scaling is not published here), the integral limited to the whole DAC, all
times |DAC_SCALE| (its sign inverts the output: the loop's polarity). OV_GAIN's term, the
gain times the change of the measured position dPm, is exact without a term of its own
in the shared filter: dPm = v - (e - e_prev) on every cycle, so it is OV_GAIN added to
the velocity feed-forward and taken from the derivative gain. The loop is closed while
the axis's drive is enabled (`Drive.enabled`); when it closes again the demand is set to
where the motor stands; while it is open DPOS reads MPOS and FE 0 (help DPOS: DPOS is
set to MPOS while SERVO or WDOG is OFF).

With SERVO OFF, WDOG ON and AXIS_ENABLE ON the output is the open-loop DAC value
(TrioBASIC help DAC, SERVO), limited to +/-OUTLIMIT: the MC405's 12-bit value (2047 =
10 V) times 16 on the shared 16-bit output (D); the world's motor runs under it, MPOS
reads its encoder. A servo axis gets its loop (and the world's motor) when P_GAIN is
above 0 or when such an output is first put out; it keeps it from then on (D). DAC_OUT
reads the output in the same 12-bit units.

FE_LIMIT is compared on every servo cycle: each stretch the engine integrates is run
with the loops recording every cycle; if |FE| passes FE_LIMIT x UNITS counts on some
cycle (and ERRORMASK holds bit 8), the loops go back to where the stretch began
(`ServoLoop.snapshot`/`restore`) and run only to that cycle, and the drive raises the
motion error there, so the error's tick does not depend on how
time is sliced. A loop whose own error passes 32768 counts trips (the shared rule) and
raises the same error.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from functools import partial
from typing import Protocol

import numpy as np

from maxk.firmware_model.servo import DAC_LIMIT, Gains, ServoLoop, SwitchedTerms
from maxk.firmware_model.world import World

from . import encoders
from .add_dac import AddedFilter, target
from .axismode import first_reached, mpos_bounds, mpos_compared
from .axistypes import SERVO_ATYPES
from .runs import ServoGains, TrioAxis


class MotorHost(Protocol):
    """The motor's demand: the axis's, or with a FRAME on its inverse transform."""

    def motor(self, axis: int, tick: int | None = None) -> float: ...

    def framed(self, axis: int) -> bool: ...


class _Syncs(Protocol):
    @property
    def running(self) -> Mapping[int, object]: ...


class _Links(Protocol):
    @property
    def addax(self) -> Mapping[int, object]: ...
    @property
    def shift(self) -> Sequence[float]: ...
    @property
    def syncs(self) -> _Syncs: ...


class ServoHost(MotorHost, Protocol):
    """What the loops need of the machine: its axes, time, world and demand."""

    axes: list[TrioAxis]
    tick: int
    period: float
    world: World
    system: dict[str, float]


class SuperHost(Protocol):
    """The machine's demand split: its own moves and what is superimposed on them."""

    @property
    def links(self) -> _Links: ...

    def demand_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...
    def own_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...


def superimposed(machine: SuperHost, axis: int) -> Callable[[int], float] | None:
    """What is superimposed on an axis's own moves at a tick (ADDAX, an ended ADDAX's or
    SYNC's shift: links.py), counts; None: nothing now."""
    links = machine.links
    if axis not in links.addax and not links.shift[axis] and not links.syncs.running:
        return None

    def part(tick: int) -> float:
        ticks = np.array([tick])
        return float(machine.demand_counts(axis, ticks)[0]
                     - machine.own_counts(axis, ticks)[0])
    return part


FE_EXCEEDED = 1 << 8
DAC_STEP = 16.0
"""Shared 16-bit output counts per MC405 DAC count (a 12-bit DAC, 2047 = 10 V: help DAC;
the factor is ours, D)."""


def gains_of(params: dict[str, float], open_output: float = 0.0,
             keep: bool = False) -> Gains | None:
    """The loop's gains for an axis's parameters and its open-loop output (shared DAC
    counts, 0 unless SERVO is off with its drive on); None: not a servo (profile-only)."""
    if int(params["ATYPE"]) not in SERVO_ATYPES:
        return None
    if not (params["P_GAIN"] > 0 or open_output or keep):
        return None
    scale = abs(int(params["DAC_SCALE"]))
    ov = params["OV_GAIN"]
    return Gains(kp=params["P_GAIN"] * scale, ki=params["I_GAIN"] * 1024.0 * scale,
                 kd=(params["D_GAIN"] - ov) * scale, ku=DAC_LIMIT / 4.0,
                 kv=(params["VFF_GAIN"] + ov) * scale, ka=params["AFF_GAIN"] * scale,
                 ko=open_output)


def switched(params: dict[str, float]) -> SwitchedTerms | None:
    """D_ZONE_MIN/D_ZONE_MAX (user units of following error, as FE: counts x UNITS, D)
    and POS_OFFSET/NEG_OFFSET (MC405 DAC counts, as DAC: x DAC_STEP on the shared
    output) as the shared filter's switched terms (help D_ZONE_MIN, POS_OFFSET); None
    when all are 0 (the linear loop, compiled and in closed form)."""
    units = abs(params["UNITS"])
    dead = max(0.0, params["D_ZONE_MIN"]) * units
    terms = SwitchedTerms(dead, max(dead, params["D_ZONE_MAX"] * units),
                          params["POS_OFFSET"] * DAC_STEP, params["NEG_OFFSET"] * DAC_STEP)
    return terms if terms.active else None


def polarity(params: dict[str, float]) -> int:
    """DAC_SCALE's sign: a negative one inverts the closed loop's output."""
    return -1 if params["DAC_SCALE"] < 0 else 1


class Following:
    """The servo loops of one MC405's servo axes."""

    def __init__(self, machine: ServoHost, enabled: Callable[[int], bool],
                 in_error: Callable[[int], bool]) -> None:
        self.m = machine
        self.enabled = enabled  # is the axis's drive enabled (the loop closed)?
        self.in_error = in_error  # is the axis in motion error (FE no longer watched)?
        # axis -> what the machine adds to a loop's command at a tick (BACKLASH's
        # compensation, a POSI_SEQ delay: `MC405Machine.command_offset`), None: nothing
        self.command: Callable[[int], Callable[[int], float] | None] = lambda axis: None
        # axis -> what is superimposed on its own moves at a tick (`superimposed`, set by
        # the machine), None: nothing
        self.superimposed: Callable[[int], Callable[[int], float] | None] = \
            lambda axis: None
        self.over: list[int] = []  # axes whose following error stopped the last stretch
        self.soft: dict[int, int] = {}  # axis -> the side of a software limit its MPOS met
        # (AXIS_MODE bit 8 clear) that stopped the last stretch
        self.latch: dict[int, float] = {}  # FE_LATCH: the FE (counts) that raised the error
        self.driven: set[int] = set()  # axes an open-loop output gave a loop (kept, D)
        self.adds: dict[int, int] = {}  # ADD_DAC: base axis -> the axis whose output it
        # adds (add_dac.py)
        self.filters: dict[int, AddedFilter] = {}  # base axis -> the added axis's filter

    def reset(self) -> None:
        """Power-up: no stretch stopped, no loop kept for an open-loop output."""
        self.over = []
        self.driven = set()
        self.adds = {}
        self.filters = {}

    def add_dac(self, axis: int, args: list[float] | tuple[float, ...]) -> None:
        """ADD_DAC(added) on a base axis; -1 ends it (add_dac.py). A chain (the added
        axis a base, or the base added to another) is 'Parameter out of range' (D)."""
        if len(args) != 1:
            raise ValueError("Syntax error")
        added = target(args[0], axis, len(self.m.axes))
        if added is None:
            self.adds.pop(axis, None)
        else:
            if added in self.adds or axis in self.adds.values():
                raise ValueError("Parameter out of range")
            for base in [b for b, a in self.adds.items() if a == added]:
                del self.adds[base]  # (an axis is added to one base at a time)
            self.adds[axis] = added
            self.driven.add(axis)  # (the base keeps its loop from then on, D)
        self.configure()

    def open_output(self, axis: int) -> float:
        """The open-loop output in MC405 DAC counts: DAC within +/-OUTLIMIT while SERVO
        is OFF and WDOG and AXIS_ENABLE are ON, else 0 (help DAC)."""
        params = self.m.axes[axis].params
        if (params["SERVO"] != 0 or params["AXIS_ENABLE"] == 0 or self.m.system["WDOG"] == 0
                or int(params["ATYPE"]) not in SERVO_ATYPES):
            return 0.0
        limit = abs(params["OUTLIMIT"])
        return max(-limit, min(limit, params["DAC"]))

    def _open_counts(self, axis: int) -> float:
        """The open-loop output on the shared 16-bit output (DAC counts x DAC_STEP)."""
        return self.open_output(axis) * DAC_STEP

    def dac_out(self, axis: int) -> float:
        """DAC_OUT: the output put out on the last servo cycle, MC405 DAC counts."""
        a = self.m.axes[axis]
        loop = a.servo
        if loop is None or loop.tripped:
            return 0.0
        if not loop.closed and axis not in self.filters:  # (ADD_DAC: the sum put out)
            return self.open_output(axis)
        return loop.dac * a.config.servo_polarity / DAC_STEP


    @property
    def servos(self) -> list[TrioAxis]:
        return [a for a in self.m.axes if a.servo is not None]

    def configure(self) -> None:
        """Gains, enables or ATYPE changed: make, update or drop each axis's loop and close
        or open it with its drive."""
        m = self.m
        for i, a in enumerate(m.axes):
            out = self.open_output(i)
            sign = polarity(a.params) if not out else 1  # (the open loop is not scaled)
            if out and a.params["P_GAIN"] <= 0:
                self.driven.add(i)
            gains = gains_of(a.params, out * DAC_STEP, i in self.driven or i in self.adds)
            if gains is None:
                a.servo = None
                continue
            if a.config.gains != gains or a.config.servo_polarity != sign:
                a.config = ServoGains(gains, sign)
            loop = a.servo
            if loop is None:
                loop = a.servo = ServoLoop(m.motor(i), m.tick)
                loop.closed = False
                loop.feedback_scale = encoders.ratio(a.params)  # (MPOS counts: p is)
            terms = switched(a.params)
            if loop.switched != terms:
                loop.switched, loop.clamped = terms, False
            enabled = self.enabled(i)
            if enabled and not loop.closed:
                self._close(a, loop)
            elif not enabled and loop.closed:
                loop.closed = False
        self._configure_adds()

    def _configure_adds(self) -> None:
        """Give each ADD_DAC base loop its added axis's filter (the added axis a servo
        with a loop), or none."""
        axes = self.m.axes
        for i, a in enumerate(axes):
            loop = a.servo
            added = self.adds.get(i)
            other = None if added is None else axes[added]
            if loop is None or other is None or other.servo is None:
                self.filters.pop(i, None)
                if loop is not None:
                    loop.set_added(None)
                continue
            assert added is not None
            gains, sign = other.config.gains, other.config.servo_polarity
            held = self.filters.get(i)
            if (held is None or held.added != added or held.gains != gains
                    or held.polarity != sign
                    or held.base_polarity != a.config.servo_polarity):
                held = AddedFilter(self.m, i, added, gains, sign, a.config.servo_polarity,
                                   partial(self.enabled, added),
                                   partial(self._open_counts, added))
                self.filters[i] = held
            loop.set_added(held)

    def _close(self, a: TrioAxis, loop: ServoLoop) -> None:
        """Close the loop on an idle axis: the demand first moves to the encoder."""
        if a.motion is None and a.link is None:
            here = float(loop.encoder_counts())
            delta = here - (a.steps + a.fraction)
            a.steps, a.fraction = int(here), 0.0
            loop.counters_moved(delta, 0.0)
        loop.reset_filter(self.m.motor(a.index) - loop.p)
        loop.closed = True

    def rearm(self) -> None:
        """DATUM(0): a loop its own following error tripped runs again."""
        for a in self.servos:
            loop = a.servo
            assert loop is not None
            if loop.tripped or loop.trip_tick is not None:
                loop.tripped = False
                loop.trip_tick = None
                loop.reset_filter(self.m.motor(a.index) - loop.p)

    # ---- readings ---------------------------------------------------------------------
    def measured(self, axis: int) -> float | None:
        """MPOS in counts without DEFPOS (None: not a servo, MPOS = DPOS)."""
        loop = self.m.axes[axis].servo
        return None if loop is None else encoders.measured(loop)  # (ENCODER_RATIO)

    def error_counts(self, axis: int) -> float:
        """FE in counts: demand - encoder (0 for a profile-only axis)."""
        measured = self.measured(axis)
        if measured is None:
            return 0.0  # (the loop's own error: BACKLASH's compensation is in its command)
        offset = self.command(axis)
        comp = 0.0 if offset is None else offset(self.m.tick)
        return self.m.motor(axis) + comp - measured

    def open_error(self, axis: int) -> float:
        """Demand less encoder, counts, while the axis's loop is open (0 otherwise): DPOS
        reads MPOS while SERVO or WDOG is OFF (help DPOS), so DPOS is read this much
        less than the demand kept (which takes MPOS when the loop closes again)."""
        loop = self.m.axes[axis].servo
        return 0.0 if loop is None or loop.closed else self.error_counts(axis)

    def shown(self, axis: int, fe: float) -> float:
        """FE as read: 0 while the loop is open (DPOS = MPOS then)."""
        loop = self.m.axes[axis].servo
        return 0.0 if loop is not None and not loop.closed else fe

    def checked_error(self, axis: int) -> float:
        """FE as FE_LIMIT and FE_RANGE see it: 0 while the loop is open (SERVO OFF: no
        position loop whose error could be exceeded, D)."""
        loop = self.m.axes[axis].servo
        return 0.0 if loop is None or not loop.closed else self.error_counts(axis)

    # ---- every servo cycle -------------------------------------------------------------
    def integrate(self, limit: int) -> int | None:
        """Run the loops to `limit`; the tick of a following error that stops them on the
        way (the loops then stand there, `over` names the axes), or None. An ADD_DAC
        added axis's loop then reads where the base loop's motor brought its encoder."""
        first = self._integrate(limit)
        axes = self.m.axes
        for base, f in self.filters.items():
            base_loop, loop = axes[base].servo, axes[f.added].servo
            if base_loop is not None and loop is not None:
                f.follow(loop, base_loop)
        return first

    def _integrate(self, limit: int) -> int | None:
        m = self.m
        servos = self.servos
        if not servos:
            return None
        filters = self.filters
        following = {f.added for f in filters.values()}  # (ADD_DAC: no motor of their own)
        if following:
            servos = [a for a in servos if a.index not in following]
        free = [a for a in servos if a.link is None and not m.framed(a.index)]
        held = {base: f.snapshot() for base, f in filters.items()}
        watched = {a.index for a in free if self._watched(a)}
        soft = {a.index for a in free if self._soft_watched(a)}  # (AXIS_MODE bit 8 clear)
        added_watched = self._watch_added()
        saved = {a.index: a.servo.snapshot() for a in free  # type: ignore[union-attr]
                 if a.servo is not None} if watched or soft or added_watched else {}
        found: dict[int, int] = {}  # axis -> the tick its error passed
        errors: dict[int, float] = {}  # axis -> its FE (counts) on that tick
        reached: dict[int, tuple[int, int]] = {}  # axis -> (tick, side) MPOS met a limit
        for a in servos:
            loop = a.servo
            assert loop is not None
            if a.link is not None or m.framed(a.index):  # a linked servo axis, or one
                # in a FRAME, follows its (motor) demand (D)
                framed = limit if m.framed(a.index) else None  # (its demand at the end)
                loop.p, loop.w, loop.tick = m.motor(a.index, framed), 0.0, limit
                continue
            before = loop.q  # the error of the cycle before the stretch
            start = encoders.measured(loop)
            loop.command_offset = self._command(a.index)  # (BACKLASH, POSI_SEQ, ADDAX)
            if a.index in watched or a.index in soft:
                loop.recorder = []
            loop.advance(a, m, limit)  # type: ignore[arg-type]
            passed = self._first_over(a, loop, before) if a.index in watched else None
            over = None if passed is None else passed[0]
            if a.index in soft and loop.recorder:  # (each sample: the state before its
                # tick's step; the stretch's last state is the loop's now)
                eo = a.encoder_offset
                positions = [(int(x[0]), x[2] - eo) for x in loop.recorder[1:]]
                positions.append((loop.tick, loop.p))
                meets = first_reached(positions, mpos_bounds(a.params, a.units, a.datum),
                                      loop.feedback_scale, start)
                if meets is not None:
                    reached[a.index] = meets
            loop.recorder = None
            ticks = [t for t in (over, loop.trip_tick) if t is not None]
            if ticks:
                found[a.index] = min(ticks)
            if passed is not None and over == found[a.index]:
                errors[a.index] = passed[1]
        for f in filters.values():  # (an ADD_DAC added axis's FE, on its cycle)
            if f.over is not None:
                found[f.added], errors[f.added] = f.over
                f.bound = None
        if not found and not reached:
            return None
        first = min([*found.values(), *(tick for tick, _side in reached.values())])
        self.over = [axis for axis, tick in found.items() if tick == first]
        self.soft = {axis: side for axis, (tick, side) in reached.items() if tick == first}
        if first < limit and saved:  # run the loops again, only as far as the error
            for a in free:
                loop = a.servo
                assert loop is not None
                loop.restore(saved[a.index])
                if a.index in held:
                    filters[a.index].restore(held[a.index])
                loop.advance(a, m, first)  # type: ignore[arg-type]
        for axis in self.over:  # FE_LATCH: the error compared with FE_LIMIT (C: its page)
            if axis in errors:
                self.latch[axis] = errors[axis]
        return first

    def _command(self, axis: int) -> Callable[[int], float] | None:
        """What the axis's loop adds to its own moves' command at a tick: the machine's
        offset (`command`) and what is superimposed on its demand (ADDAX, an ended
        ADDAX's or SYNC's shift: links.py), so that the motor follows DPOS as a
        stepper's does (None: nothing, the loop runs compiled)."""
        inner = self.command(axis)
        part = self.superimposed(axis)
        if part is None or inner is None:
            return inner if part is None else part

        def offset(tick: int) -> float:
            return part(tick) + inner(tick)
        return offset

    def _watch_added(self) -> bool:
        """Set each ADD_DAC added axis's FE_LIMIT watch for the stretch (any watched?)."""
        watched = False
        for f in self.filters.values():
            a = self.m.axes[f.added]
            loop = a.servo
            if loop is not None and self._watched(a):
                bound = a.params["FE_LIMIT"] * a.units
                f.watch(bound, int(a.params["FE_LIMIT_MODE"]) == 1, abs(loop.q) > bound)
                watched = True
            else:
                f.watch(None, False, False)
        return watched

    def _watched(self, a: TrioAxis) -> bool:
        """Is the axis's following error compared with FE_LIMIT now?"""
        loop = a.servo
        assert loop is not None
        return (loop.closed and not loop.tripped and a.link is None
                and not self.in_error(a.index)
                and int(a.params["ERRORMASK"]) & FE_EXCEEDED != 0)

    def _soft_watched(self, a: TrioAxis) -> bool:
        """Is the axis's MPOS compared with its software limits on every cycle now (a
        servo axis with AXIS_MODE bit 8 clear, closed loop, on its own motion; a limit it
        is beyond already is not watched, `first_reached`)?"""
        loop = a.servo
        assert loop is not None
        return (loop.closed and not loop.tripped and a.link is None and a.motion is not None
                and not self.in_error(a.index) and mpos_compared(a.params, True))

    @staticmethod
    def _first_over(a: TrioAxis, loop: ServoLoop, before: float) -> tuple[int, float] | None:
        """The first recorded cycle whose |FE| passes FE_LIMIT, and that FE (counts); with
        FE_LIMIT_MODE 1 the second of two such cycles in a row (help FE_LIMIT_MODE), the
        cycle before the stretch counting as the first of them."""
        samples = loop.recorder
        if not samples:
            return None
        bound = a.params["FE_LIMIT"] * a.units
        twice = int(a.params["FE_LIMIT_MODE"]) == 1
        previous = abs(before) > bound
        for sample in samples:
            over = abs(sample[5]) > bound
            if over and (previous or not twice):
                return int(sample[0]), float(sample[5])
            previous = over
        return None

    def fe_latch(self, axis: int) -> float:
        """FE_LATCH: the FE (user units) that raised the axis's motion error; 0 before it
        and from SERVO = ON (C: page)."""
        return self.latch.get(axis, 0.0) / self.m.axes[axis].units

    def beyond_limit(self, axis: int, fe: float) -> bool:
        """Does AXISSTATUS show FE_LIMIT exceeded for this FE (user units)? With
        FE_LIMIT_MODE 1 only when the last cycle's error was beyond it too."""
        a = self.m.axes[axis]
        limit = a.params["FE_LIMIT"]
        if not abs(fe) > limit:
            return False
        loop = a.servo
        if int(a.params["FE_LIMIT_MODE"]) != 1 or loop is None:
            return True
        return abs(loop.q) > limit * abs(a.units)

    def tripped(self, axis: int) -> bool:
        loop = self.m.axes[axis].servo
        return loop is not None and (loop.tripped or loop.trip_tick is not None)


__all__ = ["DAC_STEP", "SERVO_ATYPES", "Following", "gains_of", "polarity"]

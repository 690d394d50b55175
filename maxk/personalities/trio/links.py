"""Linked motion of the MC405: CONNECT, MOVELINK and ADDAX on the shared engine.

A linked axis has no motion of its own: its demand position is a closed-form function
of another axis's demand position (counts, DEFPOS not applied), evaluated on arrays of
servo ticks like every other position of the machine (`kinematics.py`):

- CONNECT(ratio, link axis): electronic gearing. The axis moves `ratio` counts per count
  of the link axis from where both were when it took effect (C: the ratio is in
  encoder counts, not user units), until CANCEL or RAPIDSTOP. A second CONNECT on the
  same link axis changes the ratio from where both are (no jump), at the axis's
  CLUTCH_RATE (`clutch.py`); one on another link axis is ignored while the first runs
  (C, manual).
- MOVELINK(distance, link distance, link acc, link dec, link axis[, options[, link
  pos]]): the axis moves `distance` while the link axis travels `link distance`; over
  the first `link acc` of it the axis's share of the link's speed ramps up from zero,
  over the last `link dec` down to zero (so its position is a parabola in the link's
  travel there, a straight line between). It ends on the servo tick the link has
  travelled the whole link distance (found in closed form between events, an event of
  the engine); a MOVELINK buffered behind it on the same link axis takes over at the
  exact link position the first ended on, so a repeated cycle (a flying shear) never
  drifts by the servo cycle's rounding.
- ADDAX(axis): the demand of another axis is superimposed on this one's own motion,
  count for count, from where it was when ADDAX took effect; ADDAX(-1) ends it and the
  axis keeps what was added (a constant shift of its demand).

Linked moves are buffered moves: they queue per axis behind the moves and links loaded
before them (NTYPE reports the next), and a move loaded after a link waits for it to end
(the machine's rule for every link).

MOVELINK_MODIFY reshapes the rest of a running MOVELINK (`links_modify.py`); SYNC adds
its synchronising offset to the axes' demand here too (`sync.py`).

Everything here is pure arithmetic on numpy arrays; `LinkedMoves` is the machine's event
source for MOVELINK ends and keeps the per-axis queues and ADDAX state.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from maxk.firmware_model.axis import first_tick

from . import clutch, links_modify
from .link_kinds import Cambox, Connect, Flexlink, Follow, Link, Movelink
from .runs import Run, TrioAxis
from .sync import Syncs


class Host(Protocol):
    """What linked moves need of the machine (MC405Machine)."""

    axes: list[TrioAxis]
    queues: list[deque[Run]]
    revision: int
    tick: int
    period: float
    outputs: Any  # its sync_all(): the PWM encoders see the motion before it changes
    registration: Any  # registration.Registration: MARK/REG_POS per axis

    @property
    def axis_count(self) -> int: ...
    def changed(self) -> None: ...
    def motion_horizon(self) -> int | None: ...
    def _now(self) -> np.ndarray: ...
    def _buffered(self, axis: int) -> int: ...
    def _attach(self, axis: int, link: Link, handover: Link | None = None) -> None: ...
    def _unlink(self, axis: int) -> None: ...
    def _cambox_done(self, axis: int) -> None: ...
    def dpos(self, axis: int) -> float: ...
    def demand(self, axis: int) -> float: ...
    def demand_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...
    def own_counts(self, axis: int, ticks: np.ndarray) -> np.ndarray: ...


REACHED = 1e-6
"""How close (counts of the link axis) counts as having travelled a MOVELINK's link
distance (D: float rounding of a position computed exactly on a whole count)."""
MIN_SPAN = 1e-6
"""The shortest link distance, counts (D: shorter, a repeating MOVELINK's cycle count
would overflow a double)."""
MOVELINK_MODELLED = 1 | 2 | 4 | 16 | 32 | 256 | 512 | 7 << 10 | 8192 | 16384
"""MOVELINK link option bits modelled (the MOVELINK help page): 1, 256 and 512 start on
the link axis's MARK / MARKB / R_MARK(link pos), 2 at an absolute link position, 4
repeats, 16 shapes the ramps as the curve bits 10..12 name, 8192 follows DPOS (what the
model follows anyway); 32 and 16384 are active only while the link moves forward; the
reserved bits are refused (D)."""


def start_event(bits: int, args: list[float], at: int) -> str | None:
    """The registration event a link option starts on: MARK (bit 0), MARKB (bit 8) or
    R_MARK of the channel in the link position argument `args[at]` (bit 9); two start
    events at once are refused (D)."""
    if sum(1 for b in (1, 2, 256, 512) if bits & b) > 1:
        raise ValueError("Parameter out of range")
    if not bits & 512:
        return "MARK" if bits & 1 else "MARKB" if bits & 256 else None
    channel = args[at] if len(args) > at else -1.0
    if channel != int(channel) or not 0 <= channel < 8:
        raise ValueError("Parameter out of range")  # R_MARK channels 0..7 (C)
    return f"R_MARK{int(channel)}"


def movelink_from(args: list[float], units: float, link_units: float) -> Movelink:
    """A MOVELINK from its arguments (user units; counts from here on). Refusals:
    'Parameter out of range' for a link distance that is not positive, negative ramps,
    options not modelled (see MOVELINK_MODELLED)."""
    distance, span, accel, decel, link = args[:5]
    options = args[5] if len(args) > 5 else 0.0
    if any(a != 0 for a in args[8:]) or (len(args) > 7 and args[7] != 0):
        raise ValueError("Parameter out of range")  # base_dist: not modelled (D)
    if not (span > 0 and accel >= 0 and decel >= 0) or options != int(options) \
            or not 0 <= options < 1 << 15 or int(options) & ~MOVELINK_MODELLED:
        raise ValueError("Parameter out of range")
    bits = int(options)
    curve = (bits >> 10) & 7 if bits & 16 else None
    if curve is not None and curve > 4:
        raise ValueError("Parameter out of range")  # 5..7 unused (C)
    wait = start_event(bits, args, 6)
    if accel + decel > span:  # both shortened in proportion to fit (C: MOVELINK page)
        scale = span / (accel + decel)
        accel, decel = accel * scale, decel * scale
    counts = [v * link_units for v in (span, accel, decel)]
    if not counts[0] >= MIN_SPAN:
        raise ValueError("Parameter out of range")
    start = args[6] * link_units if bits & 2 and len(args) > 6 else None
    if bits & 2 and start is None:
        raise ValueError("Parameter out of range")  # option 2 needs its link position
    if not all(math.isfinite(v) and abs(v) < 2.0 ** 53 for v in (*counts, distance * units)):
        raise ValueError("Parameter out of range")
    return Movelink(distance * units, counts[0], counts[1], counts[2], int(link),
                    repeat=bool(bits & 4), start_at=start, wait=wait,
                    curve=None if curve == 4 else curve, follow=follow_of(bits))


def follow_of(bits: int) -> Follow | None:
    """Link option bits 5 (forward movement only) and 14 (forward past the highest
    position reached); both at once is refused (D)."""
    if bits & 32 and bits & 16384:
        raise ValueError("Parameter out of range")
    if bits & 32:
        return Follow("forward")
    return Follow("threshold") if bits & 16384 else None


FLEXLINK_MODELLED = 1 | 2 | 4 | 32 | 256 | 512 | 7 << 10 | 8192 | 16384
"""FLEXLINK link option bits modelled (the FLEXLINK help page): as MOVELINK's, with the
curve bits 10..12 acting without bit 4 (0, sine, by default)."""


def flexlink_from(args: list[float], units: float, link_units: float) -> Flexlink:
    """FLEXLINK(base dist, excite dist, link dist, base in %, base out %, excite acc %,
    excite dec %, link axis[, options[, start pos]]): refusals as MOVELINK's, and
    percentages outside 0..100 or base in + base out, excite acc + excite dec above 100
    (D)."""
    base, excite, span, base_in, base_out, acc, dec, link = args[:8]
    options = args[8] if len(args) > 8 else 0.0
    if options != int(options) or not 0 <= options < 1 << 15 \
            or int(options) & ~FLEXLINK_MODELLED or not span > 0:
        raise ValueError("Parameter out of range")
    shares = (base_in, base_out, acc, dec)
    if not all(0 <= v <= 100 for v in shares) or base_in + base_out > 100 \
            or acc + dec > 100:
        raise ValueError("Parameter out of range")
    bits = int(options)
    curve = (bits >> 10) & 7
    if curve > 4:
        raise ValueError("Parameter out of range")
    wait = start_event(bits, args, 9)
    counts = span * link_units
    if not counts >= MIN_SPAN or not all(
            math.isfinite(v) and abs(v) < 2.0 ** 53 for v in (counts, (base + excite) * units)):
        raise ValueError("Parameter out of range")
    w0, w1 = counts * base_in / 100, counts * (1 - base_out / 100)
    start = args[9] * link_units if bits & 2 and len(args) > 9 else None
    if bits & 2 and start is None:
        raise ValueError("Parameter out of range")
    return Flexlink((base + excite) * units, counts, (w1 - w0) * acc / 100,
                    (w1 - w0) * dec / 100, int(link), repeat=bool(bits & 4), start_at=start,
                    wait=wait, curve=None if curve == 4 else curve, base=base * units,
                    window=(w0, w1), follow=follow_of(bits))


@dataclass
class Addax:
    """ADDAX(link) on an axis: the link axis's demand change since `origin` is added."""

    link: int
    origin: float  # the link axis's demand (counts) when ADDAX took effect


class LinkedMoves:
    """The machine's linked moves: per-axis queues behind the running link, ADDAX, and the
    engine events where a MOVELINK ends."""

    def __init__(self, machine: Host, depth: int) -> None:
        self.machine = machine
        self.depth = depth  # moves an axis holds, running and buffered
        self.syncs = Syncs(machine, self.keep)  # type: ignore[arg-type]  # (sync.Host)
        self._cache: tuple[int, int | None] = (-1, None)
        self.reset()

    def reset(self) -> None:
        count = self.machine.axis_count
        self.chains: list[deque[Connect | Movelink]] = [deque() for _ in range(count)]
        self.addax: dict[int, Addax] = {}
        self.shift = [0.0] * count  # what ended ADDAXes left on each axis (counts)
        self.syncs.reset()

    # ---- loading ----------------------------------------------------------------------
    def check_axis(self, value: float, axis: int) -> int:
        """A link axis argument: a whole axis number other than the axis itself."""
        if value != int(value) or not 0 <= value < self.machine.axis_count or value == axis:
            raise ValueError("Invalid axis number")
        return int(value)

    def can_load(self, axis: int) -> bool:
        """Room in the axis's move buffer for one more linked move."""
        m = self.machine
        a = m.axes[axis]
        held = (m._buffered(axis) + (a.link is not None) + (a.pending_link is not None)
                + len(self.chains[axis]))
        return held < self.depth

    def load(self, axis: int, link: Connect | Movelink) -> None:
        """A linked move behind whatever the axis runs or holds (it starts at once on an
        idle axis)."""
        m = self.machine
        leader = getattr(link, "link", None)
        if isinstance(leader, int) and self.depends(leader, axis):
            raise ValueError("Parameter out of range")  # a loop of links has no position (D)
        a = m.axes[axis]
        if a.link is None and a.pending_link is None:
            if m.queues[axis]:
                a.pending_link = link  # it starts when the buffered moves are done
            else:
                m._attach(axis, link)
        else:
            self.chains[axis].append(link)
        m.changed()

    def connect(self, axis: int, args: list[float]) -> None:
        ratio, link = args[0], self.check_axis(args[1], axis)
        if not abs(ratio) < 2.0 ** 53 or len(args) > 2 and args[2] not in (0, 1):
            raise ValueError("Parameter out of range")  # mode 0 MPOS, 1 DPOS (CONNECT page)
        m = self.machine
        running = m.axes[axis].link
        if isinstance(running, Connect):
            if running.link == link:  # a new ratio from here on, at CLUTCH_RATE (no jump)
                clutch.change_ratio(m, axis, running, ratio)
            return  # another link axis: ignored while this CONNECT runs (C)
        self.load(axis, Connect(ratio, link))

    def movelink(self, axis: int, args: list[float]) -> None:
        if len(args) < 5:
            raise ValueError("Syntax error")
        link = self.check_axis(args[4], axis)
        m = self.machine
        self.load(axis, movelink_from(args, m.axes[axis].units, m.axes[link].units))

    def flexlink(self, axis: int, args: list[float]) -> None:
        if len(args) < 8:
            raise ValueError("Syntax error")
        link = self.check_axis(args[7], axis)
        m = self.machine
        self.load(axis, flexlink_from(args, m.axes[axis].units, m.axes[link].units))

    def set_addax(self, axis: int, value: float) -> None:
        """ADDAX(n): superimpose axis n's demand from now; ADDAX(-1): stop adding."""
        m = self.machine
        if value != -1:
            link = self.check_axis(value, axis)
            if self.depends(link, axis):
                raise ValueError("Parameter out of range")  # each would add the other (D)
        now = m._now()
        old = self.addax.pop(axis, None)
        if old is not None:
            self.shift[axis] += float(m.demand_counts(old.link, now)[0]) - old.origin
        if value != -1:
            self.addax[axis] = Addax(int(value), m.demand(int(value)))
        m.changed()

    def depends(self, axis: int, leader: int) -> bool:
        """Does `axis`'s demand follow `leader`'s, through links running or buffered
        (CAMBOX, CONNECT, MOVELINK) or ADDAX? Linking `leader` to `axis` would then make a
        position depend on itself."""
        m = self.machine
        seen: set[int] = set()
        todo = [axis]
        while todo:
            a = todo.pop()
            if a == leader:
                return True
            if a in seen:
                continue
            seen.add(a)
            ax = m.axes[a]
            for link in (ax.link, ax.pending_link, *self.chains[a]):
                for name in ("link", "link_y"):  # (link_y: COMPENSATE_XY's Y axis)
                    target = getattr(link, name, None)
                    if isinstance(target, int):
                        todo.append(target)
            if a in self.addax:
                todo.append(self.addax[a].link)
        return False

    def keep(self, axis: int, counts: float) -> None:
        """What an ended SYNC moved the axis stays on it (as an ended ADDAX's)."""
        self.shift[axis] += counts
        self.machine.changed()

    # ---- positions ----------------------------------------------------------------------
    def superimpose(self, axis: int, ticks: np.ndarray, own: np.ndarray) -> np.ndarray:
        """The axis's demand: its own plus ADDAX's (and what ended ADDAXes left) and
        SYNC's (sync.py)."""
        if self.syncs.running:
            own = own + self.syncs.counts(axis, ticks)
        shift = self.shift[axis]
        added = self.addax.get(axis)
        if added is None:
            return own + shift if shift else own
        return own + shift + (self.machine.demand_counts(added.link, ticks) - added.origin)

    def attach(self, axis: int, link: Link, handover: Link | None = None) -> bool:
        """Start a CONNECT or MOVELINK on the axis now (False: not one of ours). Behind a
        MOVELINK that just ended on the same link axis, it starts from that one's exact
        end (slave and link), not from the servo tick's positions."""
        if not isinstance(link, Connect | Movelink):
            return False
        m = self.machine
        now = m._now()
        link.origin = float(m.own_counts(axis, now)[0])
        link.link_origin = float(m.demand_counts(link.link, now)[0])
        if isinstance(handover, Movelink) and handover.link == link.link:
            link.origin = handover.origin + handover.distance
            link.link_origin = handover.link_end
        if isinstance(link, Movelink) and link.wait is not None:
            pos = m.registration.captured(link.link, link.wait)  # already captured (D)
            if pos is not None:
                link.link_origin = pos * m.axes[link.link].units - m.axes[link.link].datum
                link.wait = None
        if isinstance(link, Movelink) and link.follow is not None:
            link.follow.rebase(float(m.demand_counts(link.link, now)[0]))
        if isinstance(link, Movelink) and link.start_at is not None:
            # option 2: from the absolute link position (its DPOS), once the link gets
            # there; already past it: from where it is (D)
            start = link.start_at - m.axes[link.link].datum
            link.link_origin = max(link.link_origin, start)
        m.axes[axis].link = link
        if isinstance(link, Movelink):
            links_modify.attempt(m, axis)  # an offset kept from before (links_modify.py)
        return True

    def cancelled(self, axis: int) -> None:
        """The running link ended (CANCEL, a CAMBOX done): the next one buffered takes
        over from here."""
        m = self.machine
        a = m.axes[axis]
        if a.link is None and a.pending_link is None and self.chains[axis]:
            link = self.chains[axis].popleft()
            if m.queues[axis]:
                a.pending_link = link
            else:
                m._attach(axis, link)

    def registered(self, axis: int, event: str, counts: float) -> None:
        """A registration event on `axis` (its position, demand counts): the links
        waiting for it on that link axis start from there (the MARK link options)."""
        m = self.machine
        for a in m.axes:
            link = a.link
            if isinstance(link, Movelink) and link.link == axis and link.wait == event:
                link.link_origin, link.wait = counts, None
                if link.follow is not None:
                    link.follow.rebase(m.demand(axis))
            elif isinstance(link, Cambox) and link.link == axis and link.wait == event:
                la = m.axes[axis]
                if link.follow is not None:
                    link.follow.rebase(m.dpos(axis))
                link.start_at((counts + la.datum) / la.units, link.origin)
                link.held, link.wait = True, None
        m.changed()

    def stop_repeating(self, axis: int) -> None:
        """REP_OPTION bit 1 on `axis`: the repeating CAMBOXes and MOVELINKs running on it,
        or linked to it, end at the end of the cycle they are in (D: the page's example
        sets it on the link axis)."""
        m = self.machine
        for i, a in enumerate(m.axes):
            link = a.link
            if not isinstance(link, Cambox | Movelink) or axis not in (i, link.link):
                continue
            if isinstance(link, Cambox):
                link.stop_repeating(m.dpos(link.link))
            elif link.repeat:
                u = m.demand(link.link) - link.link_origin
                cycles = math.floor(u / link.span)
                link.origin += cycles * link.distance
                link.link_origin += cycles * link.span
                link.repeat = False
        m.changed()

    def rebase(self) -> None:
        """Forward-only links take in their link's travel up to now (every event)."""
        m = self.machine
        for a in m.axes:
            link = a.link
            follow = getattr(link, "follow", None)
            if follow is None or follow.anchor is None:
                continue
            assert isinstance(link, Cambox | Movelink)
            if isinstance(link, Cambox):
                follow.rebase(m.dpos(link.link))
            else:
                follow.rebase(m.demand(link.link))

    def clear(self) -> None:
        """RAPIDSTOP: every buffered linked move goes."""
        for chain in self.chains:
            chain.clear()

    # ---- the engine's events: a MOVELINK ends (and a CAMBOX on a linked axis) ----------
    def ends_here(self, link: Link) -> bool:
        """A link whose end this source finds: a MOVELINK, or a CAMBOX whose link axis is
        itself linked or has ADDAX (the machine's CAMBOX search follows moves only)."""
        if isinstance(link, Movelink):
            return not link.repeat
        if isinstance(link, Cambox):
            if link.end_position() is None:
                return False
            leader = link.link
            return (isinstance(self.machine.axes[leader].link, Connect | Movelink | Cambox)
                    or leader in self.addax or self.shift[leader] != 0)
        return False

    def _done(self, link: Link, tick: int) -> bool:
        m = self.machine
        if isinstance(link, Movelink):
            if link.wait is not None:
                return False
            position = m.demand_counts(link.link, np.array([tick]))
            if link.follow is not None:
                position = link.follow.effective(position)
            return float(position[0]) >= link.link_end - REACHED
        assert isinstance(link, Cambox)
        la = m.axes[link.link]
        dpos = (m.demand_counts(link.link, np.array([tick])) + la.datum) / la.units
        if link.follow is not None:
            dpos = link.follow.effective(dpos)
        end = link.end_position()
        return end is not None and float(dpos[0]) >= end - 1e-9

    def end_tick(self, link: Link, horizon: int | None) -> int | None:
        """The first servo tick the link axis has travelled the link distance, up to the
        horizon (the next tick the motion changes by itself: until then the link axis's
        position is one closed form, taken as monotonic, D); None: not by then."""
        m = self.machine
        now = m.tick
        if self._done(link, now):
            return now
        if horizon is None or horizon <= now:
            return None
        return first_tick(lambda tick: self._done(link, tick), now + 1, horizon)

    def next_event(self) -> int | None:
        m = self.machine
        if self._cache[0] == m.revision:
            return self._cache[1]
        horizon = m.motion_horizon()
        best: int | None = None
        for a in m.axes:
            link = a.link
            if link is not None and self.ends_here(link):
                tick = self.end_tick(link, horizon)
                if tick is not None and (best is None or tick < best):
                    best = tick
        self._cache = (m.revision, best)
        return best

    def on_event(self, now: int) -> None:
        m = self.machine
        m.outputs.sync_all()  # the encoders see the motion before it changes
        for axis, a in enumerate(m.axes):
            link = a.link
            if link is None or not self.ends_here(link) or not self._done(link, now):
                continue
            if isinstance(link, Movelink):
                self.finish(axis, link)
            else:  # a CAMBOX: the machine's own end of one, then what is buffered
                m._cambox_done(axis)
        m.changed()

    def finish(self, axis: int, link: Movelink) -> None:
        """The MOVELINK is done: the axis rests exactly at its end; the next buffered
        linked move starts."""
        m = self.machine
        a = m.axes[axis]
        end = link.origin + link.distance
        a.link = None
        a.steps = math.floor(end)
        a.fraction = end - a.steps
        if self.chains[axis]:
            m._attach(axis, self.chains[axis].popleft(), link)


__all__ = ["Addax", "Host", "LinkedMoves", "flexlink_from", "movelink_from"]

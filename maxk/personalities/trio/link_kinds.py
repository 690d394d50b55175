"""The MC405's linked axes: what each kind of link (CONNPATH, CAMBOX, CONNECT, MOVELINK,
FLEXLINK) keeps, and its demand as a closed-form function of the axis it follows.

A linked axis has no motion of its own; its demand position is computed on arrays of
ticks from the link axis's demand (links.py applies them, kinematics.py reads them).
Kept apart from runs.py, the buffered moves, so that each concern reads on its own.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .compensate import Compensation


@dataclass
class Connpath:
    """CONNPATH(base[, ratio]) AXIS(n): n moves by ratio x the path distance of the group
    based on `base` (in the base axis's user units, converted with n's UNITS)."""

    base: int
    ratio: float
    origin: float  # n's demand position (counts) when linked
    distance0: float  # the base group's path distance (user units) when linked


@dataclass
class Follow:
    """Which of the link's movement a link follows (link option bits 5 and 14): only
    its forward movement ("forward": each stretch of forward travel adds, backward
    travel is ignored), or only forward movement past the highest position it reached
    ("threshold"). `effective` maps the link's position to the position the link acts
    on; `rebase` takes in the link's travel up to a point (the machine calls it at every
    event and change, between which the link's motion is one monotonic closed form, D)."""

    mode: str  # "forward" or "threshold"
    acc: float = 0.0  # the effective position at `anchor` (threshold: the high water)
    anchor: float | None = None  # the link position `acc` was taken at

    def effective(self, link: np.ndarray) -> np.ndarray:
        if self.anchor is None:
            return link
        if self.mode == "threshold":
            return np.maximum(link, self.acc)
        return self.acc + np.maximum(link - self.anchor, 0.0)

    def rebase(self, link: float) -> None:
        if self.anchor is None:
            self.acc = self.anchor = link
            return
        self.acc = float(self.effective(np.array([link]))[0])
        self.anchor = link

    def raw(self, effective: float) -> float:
        """The link position at which, moving forward from here, the effective position
        reaches `effective`."""
        if self.anchor is None:
            return effective
        if self.mode == "threshold":
            return effective
        return self.anchor + (effective - self.acc)


@dataclass
class Cambox:
    """CAMBOX(start, end, multiplier, link distance, link axis[, options[, link pos[,
    offset start]]]) AXIS(n): while the link axis travels `distance` user units from
    `link_origin`, n follows the TABLE values start..end, offset by the first value
    (counts, times the multiplier), interpolated linearly.

    Options (the CAMBOX help page): `repeat` (bit 2) runs the profile again and again,
    both ways, each cycle going on from where the last ended; `wait` names the start
    event a MARK (bit 0), MARKB (bit 8) or R_MARK (bit 9) start waits for, and until it
    comes `link_origin` is None and the axis holds; `held` (bit 1 or a registration
    start) keeps the axis at its start while the link is short of the start point;
    `pattern` (bit 3) is the TABLE index of the control block whose pattern values
    scale each cycle in turn (runs `pattern_cycle` and the machine's events)."""

    values: np.ndarray  # TABLE(start..end)
    multiplier: float
    distance: float  # link axis user units
    link: int
    link_origin: float | None  # the link axis's DPOS where the profile's 0 is
    origin: float  # n's demand position (counts) at the profile's 0
    repeat: bool = False
    wait: str | None = None  # "MARK", "MARKB", "R_MARK": the start event not yet come
    held: bool = False  # holds at its start until the link reaches it
    offset: float = 0.0  # bit 7: where in the link distance the profile starts
    pattern: int | None = None  # bit 3: the control block's TABLE index
    channel: int = 0  # bit 9: the R_MARK channel
    start_pos: float | None = None  # bit 1: the link DPOS it starts at
    follow: Follow | None = None  # bits 5/14: only the link's forward movement counts
    table_start: int = 0  # the TABLE index of values[0] (TABLE_POINTER)

    def __post_init__(self) -> None:
        self.values = np.asarray(self.values, dtype=float) - float(self.values[0])

    def pointer(self, link_dpos: float) -> float:
        """TABLE_POINTER: the TABLE index of the interval the link is in, plus the share
        of it done (help TABLE_POINTER); at its first value until the start comes (D)."""
        if self.link_origin is None:
            return float(self.table_start)
        link = np.array([link_dpos])
        if self.follow is not None:
            link = self.follow.effective(link)
        u = float(link[0]) - self.link_origin
        if self.repeat:
            u -= np.floor(u / self.distance) * self.distance
        x = min(max(u / self.distance, 0.0), 1.0) * (len(self.values) - 1)
        return self.table_start + x

    @property
    def span(self) -> float:
        """Counts moved over one whole profile."""
        return self.multiplier * float(self.values[-1])

    def shape(self, u: np.ndarray) -> np.ndarray:
        """Counts after u (0..distance) of link travel, from the profile's start."""
        n = len(self.values)
        x = np.clip(u / self.distance, 0.0, 1.0) * (n - 1)
        return self.multiplier * np.interp(x, np.arange(n), self.values)

    def counts(self, link_dpos: np.ndarray) -> np.ndarray:
        if self.link_origin is None:
            return np.full(np.shape(link_dpos), self.origin)
        if self.follow is not None:
            link_dpos = self.follow.effective(link_dpos)
        u = link_dpos - self.link_origin
        if self.repeat:
            cycles = np.floor(u / self.distance)
            out = self.origin + cycles * self.span + self.shape(u - cycles * self.distance)
            if self.held:
                out = np.where(u < 0, self.origin, out)
            return out
        return self.origin + self.shape(u)

    def slope(self, link_dpos: np.ndarray) -> np.ndarray:
        """d(counts)/d(link travel) of the profile."""
        if self.link_origin is None:
            return np.zeros(np.shape(link_dpos))
        if self.follow is not None:
            link_dpos = self.follow.effective(link_dpos)
        u = link_dpos - self.link_origin
        if self.repeat:
            u = u - np.floor(u / self.distance) * self.distance
        n = len(self.values)
        x = np.clip(u / self.distance, 0.0, 1.0) * (n - 1)
        j = np.minimum(x.astype(int), n - 2)
        step = self.values[j + 1] - self.values[j]
        inside = (u >= 0) & (u < self.distance)
        return np.where(inside, self.multiplier * step * (n - 1) / self.distance, 0.0)

    def start_at(self, link_dpos: float, here: float) -> None:
        """The profile starts now with the link at `link_dpos` and the axis at `here`;
        with an offset start (bit 7) the axis is taken as being `offset` into it."""
        self.link_origin = link_dpos - self.offset
        self.origin = here - float(self.shape(np.array([self.offset]))[0])

    def end_position(self) -> float | None:
        """The link axis DPOS the profile ends at (None: repeating or not started)."""
        if self.link_origin is None or self.repeat:
            return None
        return self.link_origin + self.distance

    def stop_repeating(self, link_dpos: float) -> None:
        """REP_OPTION bit 1: the cycle running now is the last."""
        if not self.repeat or self.link_origin is None:
            return
        cycles = math.floor((link_dpos - self.link_origin) / self.distance)
        if self.held:
            cycles = max(cycles, 0)
        self.origin += cycles * self.span
        self.link_origin += cycles * self.distance
        self.repeat = False


@dataclass
class Connect:
    """CONNECT(ratio, link axis): ratio counts of this axis per count of the link axis."""

    ratio: float
    link: int
    origin: float = 0.0  # this axis's own demand (counts) when it took effect
    link_origin: float = 0.0  # the link axis's demand (counts) then
    ramp_from: float | None = None  # CLUTCH_RATE: the ratio of the cycle ending at `since`
    since: int = 0  # the tick `origin` is at while the ratio ramps (clutch.py)

    def counts(self, link_counts: np.ndarray) -> np.ndarray:
        return self.origin + self.ratio * (link_counts - self.link_origin)


@dataclass
class Movelink:
    """MOVELINK: `distance` counts over `span` counts of the link axis's travel, ramping
    over `accel` and `decel` of it (all counts; see the module docstring)."""

    distance: float
    span: float
    accel: float
    decel: float
    link: int
    repeat: bool = False  # option 4: runs again and again (both ways) until CANCEL
    start_at: float | None = None  # option 2: the link position (counts) it starts at
    wait: str | None = None  # options 1/256: the registration event not yet come
    curve: int | None = None  # option 16: the ramps' curve (bits 10..12), None linear
    follow: Follow | None = None  # bits 5/14: only the link's forward movement counts
    origin: float = 0.0
    link_origin: float = 0.0
    shaped: float | None = None  # MOVELINK_MODIFY: the distance its ramps were shaped for
    adjust: list[tuple[float, float, float]] = field(default_factory=list)
    # MOVELINK_MODIFY's offsets, each added over a stretch of link travel (links_modify.py)

    def ramp(self, z: np.ndarray) -> np.ndarray:
        """The distance share of a ramp after the fraction z of it (the integral of its
        speed curve, 1/2 at the end for every curve: so the peak ratio is the trapezoid's).
        Curves (MOVELINK page, bits 10..12): 0 sine, 1 power 9, 2 power 7, 3 power 5
        polynomial speed (the smoothstep polynomials: peak accelerations 1.57, 2.46,
        2.19, 1.88 times the linear ramp's, the page's 1.55, 2.42, 2.16, 1.86: I)."""
        c = self.curve
        if c is None:
            return z * z / 2.0
        if c == 0:
            return z / 2.0 - np.sin(np.pi * z) / (2.0 * np.pi)
        if c == 3:
            return z ** 4 * (2.5 - 3.0 * z + z * z)
        if c == 2:
            return z ** 5 * (7.0 - 14.0 * z + 10.0 * z * z - 2.5 * z ** 3)
        return z ** 6 * (21.0 - 60.0 * z + 67.5 * z * z - 35.0 * z ** 3 + 7.0 * z ** 4)

    def ramped(self, x: np.ndarray, a: float, d: float) -> np.ndarray:
        """The share (0..1) of a ramped move after the fraction x of its link travel,
        ramping up over the first fraction a and down over the last d (at most twice
        the mean ratio: no overflow for any span)."""
        peak = 1.0 / (1.0 - (a + d) / 2.0)  # the share of the link's speed between ramps
        shape = peak * (x - a / 2.0)
        with np.errstate(over="ignore", invalid="ignore"):  # (branches not taken)
            if a > 0:
                shape = np.where(x < a, peak * a * self.ramp(np.clip(x / a, 0.0, 1.0)),
                                 shape)
            if d > 0:
                rest = np.clip((1.0 - x) / d, 0.0, 1.0)
                shape = np.where(x > 1.0 - d, 1.0 - peak * d * self.ramp(rest), shape)
        return shape

    def profile(self, u: np.ndarray) -> np.ndarray:
        """Counts moved after `u` counts of link travel, 0 <= u <= span (with what
        MOVELINK_MODIFY added: links_modify.py)."""
        distance = self.distance if self.shaped is None else self.shaped
        moved = distance * self.ramped(u / self.span, self.accel / self.span,
                                       self.decel / self.span)
        for offset, start, end in self.adjust:
            z = np.clip((u - start) / (end - start), 0.0, 1.0)
            moved = moved + offset * np.where(z < 0.5, 2.0 * z * z,
                                              1.0 - 2.0 * (1.0 - z) ** 2)
        return moved

    def counts(self, link_counts: np.ndarray) -> np.ndarray:
        if self.wait is not None:
            return np.full(np.shape(link_counts), self.origin)
        if self.follow is not None:
            link_counts = self.follow.effective(link_counts)
        u = link_counts - self.link_origin
        if self.repeat:
            cycles = np.floor(u / self.span)
            return self.origin + cycles * self.distance + self.profile(u - cycles * self.span)
        return self.origin + self.profile(np.clip(u, 0.0, self.span))

    @property
    def link_end(self) -> float:
        return self.link_origin + self.span


@dataclass
class Flexlink(Movelink):
    """FLEXLINK: `base` counts at a constant ratio over the whole link span, plus
    `distance - base` counts of an excitation move over the window from `window[0]` to
    `window[1]` (counts of link travel), ramping over its first `accel` and last `decel`
    counts on the option's curve (sine unless bits 10..12 say otherwise)."""

    base: float = 0.0
    window: tuple[float, float] = (0.0, 0.0)

    def profile(self, u: np.ndarray) -> np.ndarray:
        w0, w1 = self.window
        width = w1 - w0
        excite = self.distance - self.base
        moved = self.base * u / self.span
        if width <= 0:
            return moved + np.where(u >= w0, excite, 0.0)
        x = np.clip((u - w0) / width, 0.0, 1.0)
        return moved + excite * self.ramped(x, self.accel / width, self.decel / width)


Link = Connpath | Cambox | Connect | Movelink | Compensation  # (COMPENSATE_XY: compensate.py)

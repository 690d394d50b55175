"""Exact trajectory primitives: a line from p0 to p1 and an arc (centre, radius, start
angle, sweep), each with its length, a point and tangent at any curvilinear distance, and
its extent for the travel-limit check.

Angles are in degrees, as the MM4005 takes them (FA, CA, AD). Sine and cosine are exact
at multiples of 90 degrees so that the manual's right-angle examples land on exact
coordinates (cos(90) is 0, not 6e-17), which keeps the pulse positions reproducible.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

Point = tuple[float, float]


def cos_deg(angle: float) -> float:
    """cos of an angle in degrees, exact at multiples of 90."""
    quarter = angle / 90.0
    if quarter.is_integer():
        return (1.0, 0.0, -1.0, 0.0)[int(quarter) % 4]
    return math.cos(math.radians(angle))


def sin_deg(angle: float) -> float:
    """sin of an angle in degrees, exact at multiples of 90."""
    quarter = angle / 90.0
    if quarter.is_integer():
        return (0.0, 1.0, 0.0, -1.0)[int(quarter) % 4]
    return math.sin(math.radians(angle))


def direction_deg(dx: float, dy: float) -> float:
    """Polar angle of a vector in degrees, in (-180, 180]."""
    return math.degrees(math.atan2(dy, dx))


def wrap_deg(angle: float) -> float:
    """An angle difference brought into [-180, 180)."""
    return (angle + 180.0) % 360.0 - 180.0


@dataclass(frozen=True, slots=True)
class Line:
    """A straight element from ``start`` to ``end``."""

    start: Point
    end: Point

    @property
    def length(self) -> float:
        return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])

    @property
    def entry_angle(self) -> float:
        return direction_deg(self.end[0] - self.start[0], self.end[1] - self.start[1])

    @property
    def exit_angle(self) -> float:
        return self.entry_angle

    def point_at(self, s: float) -> Point:
        """The point s units along the line from its start (clamped to the line)."""
        length = self.length
        if length == 0.0:
            return self.start
        u = min(max(s / length, 0.0), 1.0)
        if u == 1.0:
            return self.end
        return (self.start[0] + u * (self.end[0] - self.start[0]),
                self.start[1] + u * (self.end[1] - self.start[1]))

    def extent(self) -> tuple[float, float, float, float]:
        """(min x, max x, min y, max y) covered by the line."""
        xs, ys = (self.start[0], self.end[0]), (self.start[1], self.end[1])
        return min(xs), max(xs), min(ys), max(ys)


@dataclass(frozen=True, slots=True)
class Arc:
    """An arc of circle: ``start_angle`` is the polar angle of its first point seen from
    ``centre``; ``sweep`` is signed, positive counter-clockwise (trigonometric).

    The end points are kept as given rather than recomputed from the centre, so that an
    element starts exactly where the previous one ended and a CY arc ends exactly on
    (CX, CY) even when its radius is huge."""

    centre: Point
    radius: float
    start_angle: float
    sweep: float
    start: Point
    end: Point

    @property
    def length(self) -> float:
        return self.radius * math.radians(abs(self.sweep))

    @property
    def end_angle(self) -> float:
        return self.start_angle + self.sweep

    def _polar(self, angle: float) -> Point:
        return (self.centre[0] + self.radius * cos_deg(angle),
                self.centre[1] + self.radius * sin_deg(angle))

    @property
    def entry_angle(self) -> float:
        return self.start_angle + (90.0 if self.sweep > 0 else -90.0)

    @property
    def exit_angle(self) -> float:
        return self.end_angle + (90.0 if self.sweep > 0 else -90.0)

    def point_at(self, s: float) -> Point:
        """The point s units along the arc from its start (clamped to the arc)."""
        length = self.length
        u = min(max(s / length, 0.0), 1.0) if length else 0.0
        if u == 0.0:
            return self.start
        if u == 1.0:
            return self.end
        return self._polar(self.start_angle + u * self.sweep)

    def extent(self) -> tuple[float, float, float, float]:
        """(min x, max x, min y, max y): the end points and every axis crossing swept."""
        points = [self.start, self.end]
        low, high = sorted((self.start_angle, self.end_angle))
        k = math.ceil(low / 90.0)
        while k * 90.0 <= high:
            points.append(self._polar(k * 90.0))
            k += 1
        xs = [p[0] for p in points]
        ys = [p[1] for p in points]
        return min(xs), max(xs), min(ys), max(ys)


Geometry = Line | Arc


def line_along(start: Point, angle: float, length: float) -> Line:
    """The line leaving ``start`` in direction ``angle`` for ``length`` units."""
    return Line(start, (start[0] + length * cos_deg(angle), start[1] + length * sin_deg(angle)))


def arc_by_sweep(start: Point, entry_angle: float, radius: float, sweep: float) -> Arc:
    """CR/CA: the arc tangent to ``entry_angle`` at ``start``; its centre lies on the left
    of the direction of travel for a positive (counter-clockwise) sweep, on the right for
    a negative one."""
    side = 90.0 if sweep > 0 else -90.0
    centre = (start[0] + radius * cos_deg(entry_angle + side),
              start[1] + radius * sin_deg(entry_angle + side))
    start_angle = entry_angle - side
    end = (centre[0] + radius * cos_deg(start_angle + sweep),
           centre[1] + radius * sin_deg(start_angle + sweep))
    return Arc(centre, radius, start_angle, sweep, start, end)


def arc_to_point(start: Point, entry_angle: float, end: Point) -> Arc | None:
    """CX/CY: the one arc tangent to ``entry_angle`` at ``start`` that ends at ``end``.

    The centre lies on the normal at ``start``, at signed distance
    rho = |d|^2 / (2 n.d) (d = end - start, n the left normal): rho > 0 turns
    counter-clockwise, rho < 0 clockwise. None when ``end`` lies on the tangent line
    (no circle) or equals ``start``.
    """
    dx, dy = end[0] - start[0], end[1] - start[1]
    nx, ny = -sin_deg(entry_angle), cos_deg(entry_angle)
    n_dot_d = nx * dx + ny * dy
    d2 = dx * dx + dy * dy
    if d2 == 0.0 or abs(n_dot_d) <= 1e-12 * math.sqrt(d2):
        return None
    rho = d2 / (2.0 * n_dot_d)
    centre = (start[0] + rho * nx, start[1] + rho * ny)
    a0 = direction_deg(start[0] - centre[0], start[1] - centre[1])
    a1 = direction_deg(end[0] - centre[0], end[1] - centre[1])
    sweep = (a1 - a0) % 360.0 if rho > 0 else -((a0 - a1) % 360.0)
    if sweep == 0.0:
        return None
    return Arc(centre, abs(rho), a0, sweep, start, end)

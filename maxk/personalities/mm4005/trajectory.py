"""The MM4005 trajectory as chapter 5.7 defines it: setup (NT, FA, AD, AX/AY, VV/VS),
elements (LX/LY lines along the current tangent, MX/MY lines to a point, CR/CA arcs by
radius and sweep, CX/CY arcs tangent to the path ending at a point, EL), the ET
verification and the run handed to the machine.

Elements are numbered from 1 and "seamed together automatically": each starts where the
previous one ends and, except MX/MY lines, leaves in the previous exit direction (the
first one in the FA direction). Coordinates are relative to the trajectory's start point
(our decision): ET runs the path from wherever the X and Y axes stand.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Final

from .errors import (
    ANGLE_DISCONTINUITY,
    PARAMETER,
    TRAJECTORY_ELEMENT,
    TRAJECTORY_EMPTY,
    TRAVEL_LIMITS,
    ErrorCode,
    MM4005Error,
)
from .geometry import (
    Geometry,
    Line,
    Point,
    arc_by_sweep,
    arc_to_point,
    cos_deg,
    sin_deg,
    wrap_deg,
)
from .pulses import PulsePlan, PulseSettings, plan_pulses

MAX_ELEMENTS: Final = 2000  # MM4005_trajectoryScan.st: "The MM4005 allows 2000" (I)
AD_RANGE: Final = (0.001, 10.0)  # MM4006 manual 5.4: 0.001 to 10 degrees
_TANGENT_EPS: Final = 1e-12


@dataclass(frozen=True, slots=True)
class Element:
    """A defined element: its number, the command that built it and its exact shape."""

    number: int
    command: str
    geometry: Geometry


@dataclass(frozen=True, slots=True)
class VerifiedTrajectory:
    """What ET found: the elements, the pulse plan when NS was armed, and a warning
    (the MPN substitution) that does not stop the run."""

    elements: tuple[Element, ...]
    pulses: PulsePlan | None
    warning: ErrorCode | None

    @property
    def geometries(self) -> tuple[Geometry, ...]:
        return tuple(e.geometry for e in self.elements)


@dataclass(frozen=True, slots=True)
class TrajectoryRun:
    """A verified trajectory placed at ``origin`` (where X and Y stood at ET)."""

    x_axis: int
    y_axis: int
    origin: Point
    elements: tuple[Geometry, ...]
    velocity: float
    acceleration: float
    pulses: PulsePlan | None

    @property
    def length(self) -> float:
        return sum(g.length for g in self.elements)

    def locate(self, path_distance: float) -> tuple[int, Point]:
        """Element number (1-based) and absolute X/Y point at a path distance."""
        start = 0.0
        for number, geometry in enumerate(self.elements, start=1):
            if path_distance <= start + geometry.length or number == len(self.elements):
                x, y = geometry.point_at(path_distance - start)
                return number, (self.origin[0] + x, self.origin[1] + y)
            start += geometry.length
        return 0, self.origin


def path_extent(elements: tuple[Geometry, ...]) -> tuple[float, float, float, float]:
    """(min x, max x, min y, max y) of the whole path, arcs' bulges included."""
    boxes = [g.extent() for g in elements]
    return (min(b[0] for b in boxes), max(b[1] for b in boxes),
            min(b[2] for b in boxes), max(b[3] for b in boxes))


def check_travel(elements: tuple[Geometry, ...], origin: Point,
                 x_limits: tuple[float, float], y_limits: tuple[float, float]) -> None:
    """Refuse a path that would leave the X or Y software travel limits (SL/SR)."""
    x0, x1, y0, y1 = path_extent(elements)
    if (origin[0] + x0 < x_limits[0] or origin[0] + x1 > x_limits[1]
            or origin[1] + y0 < y_limits[0] or origin[1] + y1 > y_limits[1]):
        raise MM4005Error(TRAVEL_LIMITS)


@dataclass
class Trajectory:
    """The trajectory being defined plus its setup and synchronized-pulse settings."""

    entry_angle: float = 0.0  # FA, degrees (D: default 0, kept across NT)
    max_discontinuity: float = 0.001  # AD, degrees (D: default the smallest allowed)
    x_axis: int = 1  # AX (D: axis 1 by default)
    y_axis: int = 2  # AY (D: axis 2 by default)
    velocity: float = 1.0  # VV, units/s (D default)
    acceleration: float = 10.0  # VS, units/s^2 (D default)
    elements: list[Element] = field(default_factory=list)
    radius: float | None = None  # CR, kept until changed or NT
    arc_x: float | None = None  # CX, kept until changed or NT
    line_x_end: float | None = None  # MX, kept until changed or NT
    pulses: PulseSettings = field(default_factory=PulseSettings)

    # --- setup -------------------------------------------------------------------
    def new(self) -> None:
        """NT: forget the elements and the pending CR/CX/MX values."""
        self.elements.clear()
        self.radius = self.arc_x = self.line_x_end = None

    def set_max_discontinuity(self, degrees: float) -> None:
        if not AD_RANGE[0] <= degrees <= AD_RANGE[1]:
            raise MM4005Error(PARAMETER, "AD outside 0.001..10 degrees")
        self.max_discontinuity = degrees

    # --- where the next element starts -------------------------------------------
    @property
    def end_point(self) -> Point:
        return self.elements[-1].geometry.end if self.elements else (0.0, 0.0)

    @property
    def tangent(self) -> float:
        """Exit direction of the last element, or FA before the first."""
        return self.elements[-1].geometry.exit_angle if self.elements else self.entry_angle

    def _append(self, command: str, geometry: Geometry) -> Element:
        if len(self.elements) >= MAX_ELEMENTS:
            raise MM4005Error(TRAJECTORY_ELEMENT, "too many elements")
        if geometry.length <= 0.0:
            raise MM4005Error(TRAJECTORY_ELEMENT, "zero-length element")
        element = Element(len(self.elements) + 1, command, geometry)
        self.elements.append(element)
        return element

    # --- lines ---------------------------------------------------------------------
    def line_to_x(self, x: float) -> Element:
        """LX: a line along the current tangent until X reaches ``x``."""
        (x0, y0), angle = self.end_point, self.tangent
        c = cos_deg(angle)
        if abs(c) < _TANGENT_EPS:
            raise MM4005Error(TRAJECTORY_ELEMENT, "LX along a vertical tangent")
        distance = (x - x0) / c
        if distance <= 0.0:
            raise MM4005Error(TRAJECTORY_ELEMENT, "LX behind the tangent")
        return self._append("LX", Line((x0, y0), (x, y0 + distance * sin_deg(angle))))

    def line_to_y(self, y: float) -> Element:
        """LY: a line along the current tangent until Y reaches ``y``."""
        (x0, y0), angle = self.end_point, self.tangent
        s = sin_deg(angle)
        if abs(s) < _TANGENT_EPS:
            raise MM4005Error(TRAJECTORY_ELEMENT, "LY along a horizontal tangent")
        distance = (y - y0) / s
        if distance <= 0.0:
            raise MM4005Error(TRAJECTORY_ELEMENT, "LY behind the tangent")
        return self._append("LY", Line((x0, y0), (x0 + distance * cos_deg(angle), y)))

    def set_line_end_x(self, x: float) -> None:
        """MX: remember the X of the next MY line's end point."""
        self.line_x_end = x

    def line_to_point(self, y: float) -> Element:
        """MY: a line to (MX, ``y``); its direction is the user's (checked against AD by ET)."""
        if self.line_x_end is None:
            raise MM4005Error(TRAJECTORY_ELEMENT, "MY without MX")
        return self._append("MY", Line(self.end_point, (self.line_x_end, y)))

    # --- arcs ----------------------------------------------------------------------
    def set_radius(self, radius: float) -> None:
        """CR: the radius of the next CA arcs."""
        if radius <= 0.0:
            raise MM4005Error(PARAMETER, "CR must be positive")
        self.radius = radius

    def arc_by_sweep(self, sweep: float) -> Element:
        """CA: an arc of radius CR tangent to the path, sweeping ``sweep`` degrees
        (positive counter-clockwise)."""
        if self.radius is None:
            raise MM4005Error(TRAJECTORY_ELEMENT, "CA without CR")
        if sweep == 0.0 or abs(sweep) > 360.0:
            raise MM4005Error(PARAMETER, "CA outside -360..360 or zero")
        return self._append("CA", arc_by_sweep(self.end_point, self.tangent, self.radius, sweep))

    def set_arc_end_x(self, x: float) -> None:
        """CX: remember the X of the next CY arc's end point."""
        self.arc_x = x

    def arc_to_point(self, y: float) -> Element:
        """CY: the arc tangent to the path that ends at (CX, ``y``)."""
        if self.arc_x is None:
            raise MM4005Error(TRAJECTORY_ELEMENT, "CY without CX")
        arc = arc_to_point(self.end_point, self.tangent, (self.arc_x, y))
        if arc is None:
            raise MM4005Error(TRAJECTORY_ELEMENT, "end point on the tangent line")
        return self._append("CY", arc)

    def erase_last(self) -> None:
        """EL: remove the last element."""
        if not self.elements:
            raise MM4005Error(TRAJECTORY_EMPTY)
        self.elements.pop()

    # --- ET ------------------------------------------------------------------------
    def verify(self, resolution: float, base_period: float) -> VerifiedTrajectory:
        """ET's checks on the definition alone (nothing is changed): at least one element,
        every seam within AD, and the pulse conditions when NS is armed."""
        if not self.elements:
            raise MM4005Error(TRAJECTORY_EMPTY)
        for previous, element in zip(self.elements, self.elements[1:], strict=False):
            jump = wrap_deg(element.geometry.entry_angle - previous.geometry.exit_angle)
            if abs(jump) > self.max_discontinuity + 1e-9:
                raise MM4005Error(ANGLE_DISCONTINUITY, f"element {element.number}")
        elements = tuple(self.elements)
        if not self.pulses.armed:
            return VerifiedTrajectory(elements, None, None)
        plan, warning = plan_pulses(self.pulses, [e.geometry for e in elements], resolution,
                                    self.velocity, base_period)
        return VerifiedTrajectory(elements, plan, warning)

    def commit(self, verified: VerifiedTrajectory, origin: Point) -> TrajectoryRun:
        """ET accepted: apply the MPN substitution, disarm NS and build the run."""
        if verified.warning is not None and verified.pulses is not None:
            self.pulses.apply_substitution(verified.pulses.count)
        self.pulses.armed = False
        return TrajectoryRun(self.x_axis, self.y_axis, origin, verified.geometries,
                             self.velocity, self.acceleration, verified.pulses)

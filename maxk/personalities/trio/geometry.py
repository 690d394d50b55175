"""The MC405's geometric moves beyond MOVECIRC: MSPHERICAL and MSPHERICALSP.

MSPHERICAL(x, y, z, u, v, w, mode[, gtpi[, rotau[, rotav[, rotaw]]]]) moves the first
three BASE axes along an arc of a circle anywhere in their space (TrioBASIC help
MSPHERICAL), one segment of the shared path planner (`path.Segment` kind "sphere"), its
path speed the base axis's SPEED (MSPHERICALSP: FORCE_SPEED). Every position is relative
to where the move starts (I: as MOVECIRC; the page's examples start at 0). The modes
(page, C):

- 0: end (x, y, z) and a point (u, v, w) on the arc: the circle through start, mid and
  end, travelled start -> mid -> end;
- 1: end and the centre: the shorter way round; centre and end in line with the start:
  refused (page: a RUN_ERROR; here "Parameter out of range", D);
- 2: two points on a full circle, (u, v, w) first then (x, y, z), back to the start;
- 3: a point on the circle and its centre: a full circle, leaving the short way toward
  the point.

gtpi not 0 takes modes 0 and 1 the other way round to the same end (page). rotau, rotav,
rotaw: distances (user units of their axes) the 4th, 5th and 6th BASE axes move in
proportion along the arc, the path length the arc's alone (page; that they are distances
is I). The mode bits 8..12 (MOVETURN in place of MOVE) are refused (D: MOVETURN is not
modelled). Geometry is in counts of each axis, as MOVECIRC's; ends land on whole counts
(D, as MOVECIRC), and mode 1's end must lie within a count of the circle (D).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Protocol

from maxk.firmware_model.path import SegmentDef


class Host(Protocol):
    """What MSPHERICAL needs of the machine (runs.py imports this module: no import of
    the machine's modules here)."""

    def _counts(self, axis: int, value: float) -> float: ...
    def _load(self, axes: tuple[int, ...], deltas: list[int],
              arc: tuple[float, ...] | None = None, kind: int = 1) -> None: ...


MSPHERICAL, MSPHERICALSP = 31, 40  # MTYPE (C: the MTYPE page)
NAMES = frozenset({"MSPHERICAL", "MSPHERICALSP", "MOVETANG"})  # (MOVETANG: tangential.py)
Vector = tuple[float, float, float]


def _sub(a: Sequence[float], b: Sequence[float]) -> Vector:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _cross(a: Sequence[float], b: Sequence[float]) -> Vector:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _dot(a: Sequence[float], b: Sequence[float]) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _norm(a: Sequence[float]) -> float:
    return math.sqrt(_dot(a, a))


def _unit(a: Sequence[float], scale: float) -> Vector:
    """a / |a|; refused when a is (within rounding of `scale`) nothing: points in line."""
    n = _norm(a)
    if not n > 1e-9 * max(1.0, scale):
        raise ValueError("Parameter out of range")
    return (a[0] / n, a[1] / n, a[2] / n)


def _circumcentre(a: Vector, b: Vector) -> Vector:
    """The centre of the circle through the origin, a and b."""
    n = _cross(a, b)
    nn = _dot(n, n)
    scale = max(_norm(a), _norm(b), 1.0)
    if not nn > 1e-18 * scale ** 4:
        raise ValueError("Parameter out of range")  # in line: no circle
    w = tuple(_dot(a, a) * b[i] - _dot(b, b) * a[i] for i in range(3))
    c = _cross(w, n)
    return (c[0] / (2 * nn), c[1] / (2 * nn), c[2] / (2 * nn))


def sphere_arc(mode: int, first: Vector, second: Vector, other_way: bool
               ) -> tuple[Vector, Vector, Vector, float]:
    """(centre, e2: the way the arc leaves the start, end, turn in degrees), all relative
    to the start (counts), for MSPHERICAL's mode with its two points."""
    origin = (0.0, 0.0, 0.0)
    scale = max(_norm(first), _norm(second), 1.0)
    if mode in (0, 2):  # through the start, a point and another: start -> mid -> end
        mid, end = second, first  # (mode 2: the first point, then the second)
        centre = _circumcentre(mid, end)
        normal = _unit(_cross(mid, end), scale ** 2)
    else:  # mode 1: end and centre; mode 3: a point and the centre
        point, centre = first, second
        normal = _unit(_cross(_sub(origin, centre), _sub(point, centre)), scale ** 2)
        end = point
    radius = _norm(centre)
    if not radius > 0:
        raise ValueError("Parameter out of range")
    e1 = (-centre[0] / radius, -centre[1] / radius, -centre[2] / radius)
    e2 = _cross(normal, e1)
    if mode in (2, 3):
        return centre, e2, origin, 360.0
    if mode == 1 and abs(_norm(_sub(end, centre)) - radius) > 1.0:
        raise ValueError("Parameter out of range")  # the end is not on the circle (D)
    to_end = _sub(end, centre)
    turn = math.degrees(math.atan2(_dot(to_end, e2), _dot(to_end, e1))) % 360.0
    if other_way:
        e2 = (-e2[0], -e2[1], -e2[2])
        turn = 360.0 - turn
    return centre, e2, end, turn


def group_size(args: Sequence[float]) -> int:
    """The BASE axes an MSPHERICAL moves: three, and one per rota* up to the last given
    that is not 0 (D: a zero rota adds no axis)."""
    rota = list(args[8:11])
    while rota and rota[-1] == 0:
        rota.pop()
    return 3 + len(rota)


def mspherical(m: Host, axes: tuple[int, ...], args: Sequence[float], kind: int) -> None:
    """Check MSPHERICAL's arguments, make its arc and load it (nothing loaded on error)."""
    if not 6 <= len(args) <= 11:
        raise ValueError("Parameter out of range")
    mode = args[6] if len(args) > 6 else 0.0
    if mode not in (0, 1, 2, 3):
        raise ValueError("Parameter out of range")  # (bits 8..12, MOVETURN: D)
    other_way = len(args) > 7 and args[7] != 0
    counts = [m._counts(a, v) for a, v in zip(axes[:3] * 2, args[:6], strict=True)]
    first = (counts[0], counts[1], counts[2])
    second = (counts[3], counts[4], counts[5])
    if mode in (0, 1):  # the end lands on whole counts (D, as MOVECIRC)
        first = (float(round(first[0])), float(round(first[1])), float(round(first[2])))
    centre, e2, end, turn = sphere_arc(int(mode), first, second, other_way)
    rise = [round(m._counts(a, v)) for a, v in zip(axes[3:], args[8:], strict=False)]
    deltas = [round(end[0]), round(end[1]), round(end[2]), *rise]
    m._load(axes, deltas, arc=(*centre, *e2, *end, turn), kind=kind)


def sphere_definition(arc: tuple[float, ...], start: tuple[float, ...],
                      rise: tuple[float, ...], defn: SegmentDef) -> SegmentDef:
    """The planner's "sphere" segment of an MSPHERICAL loaded as `arc` (relative), from
    `start` (counts of the group's axes)."""
    c, e2, end, turn = arc[0:3], arc[3:6], arc[6:9], arc[9]
    values = (*(start[i] + c[i] for i in range(3)), *e2,
              *(start[i] + end[i] for i in range(3)), *rise)
    return SegmentDef("sphere", values, True, turn, defn.v_start, defn.v_end, defn.accel,
                      None)




# ---- TABLE geometry: SPHERE_CENTRE, FILLET -------------------------------------------
TABLE_NAMES = frozenset({"SPHERE_CENTRE", "FILLET"})
Read = Callable[[int], float]


def _point(read: Read, start: int) -> Vector:
    return (read(start), read(start + 1), read(start + 2))


def _index(value: float) -> int:
    if value != int(value) or value < 0:
        raise ValueError("Parameter out of range")
    return int(value)


def sphere_centre(args: Sequence[float], read: Read) -> tuple[int, list[float]]:
    """SPHERE_CENTRE(mid, end, out): the centre (relative to the start), the angle of the
    arc start -> mid -> end (radians, D), its radius, and 1 (points in line: the rest 0,
    D) or 0 (TrioBASIC help SPHERE_CENTRE)."""
    mid, end = _point(read, _index(args[0])), _point(read, _index(args[1]))
    try:
        centre, _e2, _end, turn = sphere_arc(0, end, mid, False)
    except ValueError:
        return _index(args[2]), [0.0] * 5 + [1.0]
    return _index(args[2]), [*centre, math.radians(turn), _norm(centre), 0.0]


def _fillet_lines(a: Vector, b: Vector, radius: float) -> list[float]:
    """FILLET option 0: the arc of `radius` blending the line a into the line b."""
    la, lb = _norm(a), _norm(b)
    out = [0.0] * 19
    if la == 0 or lb == 0:
        out[12] = 1.0
        return out
    ua = (a[0] / la, a[1] / la, a[2] / la)
    ub = (b[0] / lb, b[1] / lb, b[2] / lb)
    cosine = max(-1.0, min(1.0, _dot(ua, ub)))
    across = _sub(ub, tuple(cosine * x for x in ua))
    if _norm(across) < 1e-12:
        out[12] = 2.0  # in line (either way)
        return out
    angle = math.acos(cosine)
    half = math.tan(angle / 2)
    if radius * half > min(la, lb):  # the largest radius whose ends fit both lines (D)
        radius = min(la, lb) / half
    t = radius * half  # from the corner to each end of the arc
    n = _unit(across, 1.0)
    centre = tuple(radius * x for x in n)
    end = tuple(t * (x + y) for x, y in zip(ua, ub, strict=True))
    spoke = _unit(tuple(e - 2 * c for e, c in zip(end, centre, strict=True)), 1.0)
    mid = tuple(c + radius * s for c, s in zip(centre, spoke, strict=True))
    out[0:3] = [x * (la - t) / la for x in a]
    out[3:6], out[6:9], out[9:12] = end, mid, centre
    out[13] = radius
    out[14:17] = [x * (lb - t) / lb for x in b]
    out[17], out[18] = angle, radius * angle
    return out


def _fillet_dot(a: Vector, b: Vector) -> list[float]:
    """FILLET option 2: the mid vector, both unit vectors, their dot product, lengths."""
    la, lb = _norm(a), _norm(b)
    if la == 0 or lb == 0:
        return [0.0] * 9 + [0.0, la, lb, 1.0]
    ua = [x / la for x in a]
    ub = [x / lb for x in b]
    return [0.5 * (x + y) for x, y in zip(ua, ub, strict=True)] + ua + ub + [
        _dot(ua, ub), la, lb, 0.0]


def fillet(args: Sequence[float], read: Read) -> tuple[int, list[float]]:
    """FILLET(in, out, option): options 0 and 2 (TrioBASIC help FILLET); 1 and 3 are
    refused (D: not modelled)."""
    start, out, option = _index(args[0]), _index(args[1]), args[2]
    a, b = _point(read, start), _point(read, start + 3)
    if option == 0:
        radius = read(start + 6)
        if not radius > 0:
            raise ValueError("Parameter out of range")
        return out, _fillet_lines(a, b, radius)
    if option == 2:
        return out, _fillet_dot(a, b)
    raise ValueError("Parameter out of range")


def table_function(name: str, args: Sequence[float], read: Read) -> tuple[int, list[float]]:
    """One of TABLE_NAMES: where its values go in TABLE and the values (nothing written)."""
    if len(args) != 3:
        raise ValueError("Syntax error")
    return (sphere_centre if name == "SPHERE_CENTRE" else fillet)(args, read)


__all__ = ["MSPHERICAL", "MSPHERICALSP", "NAMES", "TABLE_NAMES", "fillet", "group_size",
           "mspherical", "sphere_arc", "sphere_centre", "sphere_definition", "table_function"]

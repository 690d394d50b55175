"""MOVEABSSEQ and MOVESEQ: a sequence of TABLE points loaded as straight moves with a
fillet arc of a given radius at each corner (TrioBASIC help MOVEABSSEQ, MOVESEQ).

The sequence is worked out whole, from where the group's buffered moves end, as the list
of the ordinary moves it loads: MOVEABS to each arc's start, then MOVECIRC (2 axes) or
MSPHERICAL mode 0 through the arc's mid point (3 axes), and MOVEABS to the last point
(page, C: "loaded into the move buffers as a sequence of MOVEABS -> MOVECIRC ->" moves; a
straight move of no length is left out, page). The interpreter loads them one by one,
waiting for room in the move buffer as for any move. Each fillet is FILLET option 0's arc
(geometry.py); its radius is reduced to the largest that fits when the points are too
close (page), a corner taking at most half of a side it shares with another corner (D).
Points in line: no arc. MOVESEQ's points are increments from the point before (I).
Options other than 0, an output area, a transition angle and more than 3 axes are
refused (D: not modelled).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

NAMES = frozenset({"MOVEABSSEQ", "MOVESEQ"})
Move = tuple[str, list[float]]  # ("MOVEABS" | "MOVECIRC" | "MSPHERICAL", arguments)


def _sub(a: Sequence[float], b: Sequence[float]) -> list[float]:
    return [x - y for x, y in zip(a, b, strict=True)]


def _norm(a: Sequence[float]) -> float:
    return math.sqrt(sum(x * x for x in a))


def axes_of(args: Sequence[float]) -> int:
    """The group size MOVE(ABS)SEQ names (its second argument): 2 or 3 here."""
    if len(args) < 5 or args[1] not in (2, 3):
        raise ValueError("Parameter out of range")
    return int(args[1])


def plan(name: str, args: Sequence[float], start: Sequence[float],
         read: Callable[[int], float]) -> list[Move]:
    """The moves MOVEABSSEQ / MOVESEQ(table, axes, npoints, options, radius[, output[,
    transition]]) loads, from `start` (user units of the group's axes)."""
    count = axes_of(args)
    index, points, options, radius = args[0], args[2], args[3], args[4]
    if (index != int(index) or index < 0 or points != int(points) or not points >= 1
            or options != 0 or not radius >= 0 or any(a != 0 for a in args[5:])):
        raise ValueError("Parameter out of range")
    path = [list(start)]
    for i in range(int(points)):
        p = [read(int(index) + i * count + k) for k in range(count)]
        path.append([x + y for x, y in zip(path[-1], p, strict=True)]
                    if name == "MOVESEQ" else p)
    sides = [_norm(_sub(b, a)) for a, b in zip(path, path[1:], strict=False)]
    moves: list[Move] = []
    here = list(start)
    for j in range(1, len(path) - 1):  # the corner at path[j]
        a, b = _sub(path[j], path[j - 1]), _sub(path[j + 1], path[j])
        la, lb = sides[j - 1], sides[j]
        if la == 0 or lb == 0 or radius == 0:
            continue
        cosine = max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b, strict=True)) / la / lb))
        angle = math.acos(cosine)
        if angle < 1e-9 or math.pi - angle < 1e-9:
            continue  # in line: no arc
        half = math.tan(angle / 2)
        room_a = la if j == 1 else la / 2  # the first side is this corner's alone
        room_b = lb if j == len(path) - 2 else lb / 2
        r = min(radius, min(room_a, room_b) / half)
        t = r * half
        ua, ub = [x / la for x in a], [x / lb for x in b]
        arc_start = [c - t * u for c, u in zip(path[j], ua, strict=True)]
        if _norm(_sub(arc_start, here)) > 1e-9:
            moves.append(("MOVEABS", arc_start))
        end = [t * (x + y) for x, y in zip(ua, ub, strict=True)]  # from the arc's start
        across = [y - cosine * x for x, y in zip(ua, ub, strict=True)]
        n = _norm(across)
        centre = [r * x / n for x in across]
        if count == 2:
            turn_left = ua[0] * ub[1] - ua[1] * ub[0] > 0
            moves.append(("MOVECIRC", [*end, *centre, 0.0 if turn_left else 1.0]))
        else:
            spoke = _sub(end, [2 * c for c in centre])
            s = _norm(spoke)
            mid = [c + r * x / s for c, x in zip(centre, spoke, strict=True)]
            moves.append(("MSPHERICAL", [*end, *mid, 0.0]))
        here = [x + y for x, y in zip(arc_start, end, strict=True)]
    if _norm(_sub(path[-1], here)) > 1e-9:
        moves.append(("MOVEABS", path[-1]))
    return moves


__all__ = ["NAMES", "axes_of", "plan"]

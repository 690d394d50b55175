"""The TABLE splines of the MC405: B_SPLINE, C_SPLINE and A_SPLINE expand a run of TABLE
points into a finer one (for CAMBOX, CAM or a sequence of MOVEABS).

Each is a pure function of the TABLE: it reads its input points, computes every output
value, and only then writes them in one TABLE write, so bad arguments or an output that
does not fit change nothing. What each page fixes and what we decided (D) where it does not
(TrioBASIC help B_SPLINE, C_SPLINE, A_SPLINE):

- B_SPLINE(1, in, points, out, expansion): a uniform cubic B-spline; the page gives
  (points + 1) * expansion values, and a real machine's program (a palletising cell's)
  lays its outputs (points + 1) * expansion + 1 apart and cams over every one of them: so
  the closing point follows them (I). (D) The control polygon is the points with the
  first and the last taken three times (points + 1 spans: the curve starts exactly on
  the first point and ends exactly on the last); each span gives `expansion` values at
  t = j / expansion, then the last point.
- B_SPLINE(2, 3, 3, weight_op, points, knots, expansion, in, out): a NURBS curve of XYZ
  points; the knot vector follows the points in TABLE (I: the page's example stores it
  there); its degree is knots - points - 1; weight_op 0 (every weight 1) is the only one
  the page describes (others refused, D). points * expansion XYZ triples, at parameters
  evenly spaced over the whole curve, both ends included (D).
- C_SPLINE(mode, in, points, dims, expansion, out[, tension, bias]): cubic Hermite
  segments with the cardinal (tension, bias) tangents, Catmull-Rom when both are 0 (modes
  1, 3: always 0); (points - 1) * expansion + 1 values per dimension (page); modes 3 and 4
  write the dimensions of a point together, 1 and 2 one block per dimension (page). (D) At
  each end the missing neighbour is the end point itself.
- A_SPLINE(in, points, out, expansion): Akima's interpolation of values at unit spacing,
  with Akima's own extrapolated end slopes; points * expansion values (I: the page's
  example cams over that many), evenly spaced from the first point to the last (D).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

Read = Callable[[int], float]
NAMES = frozenset({"B_SPLINE", "C_SPLINE", "A_SPLINE"})
MAX_OUTPUT = 512_000  # never more values than TABLE holds


def _whole(value: float, low: int, high: int) -> int:
    """An argument that must be a whole number in low..high."""
    if value != int(value) or not low <= value <= high:
        raise ValueError("Parameter out of range")
    return int(value)


def _read(read: Read, start: int, count: int) -> np.ndarray:
    return np.array([read(start + i) for i in range(count)], dtype=float)


def _hermite(p0: np.ndarray, p1: np.ndarray, m0: np.ndarray, m1: np.ndarray,
             mu: np.ndarray) -> np.ndarray:
    """Cubic Hermite points between p0 and p1 (rows), tangents m0, m1, at fractions mu."""
    mu = mu[:, None]
    mu2, mu3 = mu * mu, mu * mu * mu
    return ((2 * mu3 - 3 * mu2 + 1) * p0 + (mu3 - 2 * mu2 + mu) * m0
            + (-2 * mu3 + 3 * mu2) * p1 + (mu3 - mu2) * m1)


def b_spline(args: Sequence[float], read: Read) -> tuple[int, list[float]]:
    """B_SPLINE(mode, ...): (where to write, the values)."""
    mode = _whole(args[0], 1, 2)
    if mode == 1:
        if len(args) != 5:
            raise ValueError("Syntax error")
        start = _whole(args[1], 0, MAX_OUTPUT)
        points = _whole(args[2], 2, MAX_OUTPUT)
        out = _whole(args[3], 0, MAX_OUTPUT)
        expansion = _whole(args[4], 1, MAX_OUTPUT)
        if (points + 1) * expansion + 1 > MAX_OUTPUT:
            raise ValueError("Parameter out of range")
        p = _read(read, start, points)
        q = np.concatenate(([p[0]] * 2, p, [p[-1]] * 2))
        t = np.arange(expansion) / expansion
        basis = np.stack(((1 - t) ** 3, 3 * t ** 3 - 6 * t ** 2 + 4,
                          -3 * t ** 3 + 3 * t ** 2 + 3 * t + 1, t ** 3)) / 6.0
        values = [basis.T @ q[s:s + 4] for s in range(points + 1)]
        return out, [float(v) for v in np.concatenate(values)] + [float(p[-1])]
    if len(args) != 9:
        raise ValueError("Syntax error")
    if args[1] != 3 or args[2] != 3 or args[3] != 0:
        raise ValueError("Parameter out of range")
    points = _whole(args[4], 2, MAX_OUTPUT)
    knots = _whole(args[5], points + 2, MAX_OUTPUT)
    expansion = _whole(args[6], 1, MAX_OUTPUT)
    start, out = _whole(args[7], 0, MAX_OUTPUT), _whole(args[8], 0, MAX_OUTPUT)
    count = points * expansion
    if count * 3 > MAX_OUTPUT or count < 2:
        raise ValueError("Parameter out of range")
    control = _read(read, start, points * 3).reshape(points, 3)
    knot = _read(read, start + points * 3, knots)
    degree = knots - points - 1
    low, high = knot[degree], knot[points]
    if np.any(np.diff(knot) < 0) or not high > low:
        raise ValueError("Parameter out of range")
    u = low + (high - low) * np.arange(count) / (count - 1)
    u[-1] = high
    return out, [float(v) for v in np.ravel([_de_boor(knot, control, degree, x)
                                              for x in u])]


def _de_boor(knot: np.ndarray, control: np.ndarray, degree: int, u: float) -> np.ndarray:
    """The B-spline curve's point at parameter u (de Boor's algorithm, weights 1)."""
    points = len(control)
    span = int(np.searchsorted(knot, u, side="right")) - 1
    span = min(max(span, degree), points - 1)  # the last span holds the curve's end
    d = [control[j + span - degree].copy() for j in range(degree + 1)]
    for r in range(1, degree + 1):
        for j in range(degree, r - 1, -1):
            i = j + span - degree
            width = knot[i + degree + 1 - r] - knot[i]
            alpha = (u - knot[i]) / width if width else 0.0
            d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j]
    return d[degree]


def c_spline(args: Sequence[float], read: Read) -> tuple[int, list[float]]:
    """C_SPLINE(mode, in, points, dims, expansion, out[, tension, bias])."""
    if len(args) < 6:
        raise ValueError("Syntax error")
    mode = _whole(args[0], 1, 4)
    start = _whole(args[1], 0, MAX_OUTPUT)
    points = _whole(args[2], 2, MAX_OUTPUT)
    dims = _whole(args[3], 2, 8)
    expansion = _whole(args[4], 2, 100)
    out = _whole(args[5], 0, MAX_OUTPUT)
    tension, bias = (list(args[6:8]) + [0.0, 0.0])[:2] if mode in (2, 4) else (0.0, 0.0)
    if not (-1 <= tension <= 1 and -1 <= bias <= 1):
        raise ValueError("Parameter out of range")
    count = (points - 1) * expansion + 1
    if count * dims > MAX_OUTPUT:
        raise ValueError("Parameter out of range")
    p = _read(read, start, points * dims).reshape(points, dims)
    padded = np.concatenate((p[:1], p, p[-1:]))  # each end its own neighbour (D)
    back, ahead = (1 + bias) * (1 - tension) / 2, (1 - bias) * (1 - tension) / 2
    mu = np.arange(expansion) / expansion
    rows = []
    for i in range(points - 1):
        p_1, p0, p1, p2 = padded[i:i + 4]
        m0 = (p0 - p_1) * back + (p1 - p0) * ahead
        m1 = (p1 - p0) * back + (p2 - p1) * ahead
        rows.append(_hermite(p0, p1, m0, m1, mu))
    rows.append(p[-1:])
    curve = np.concatenate(rows)  # count rows of dims
    flat = curve.ravel() if mode in (3, 4) else curve.T.ravel()
    return out, [float(v) for v in flat]


def a_spline(args: Sequence[float], read: Read) -> tuple[int, list[float]]:
    """A_SPLINE(in, points, out, expansion)."""
    if len(args) != 4:
        raise ValueError("Syntax error")
    start = _whole(args[0], 0, MAX_OUTPUT)
    points = _whole(args[1], 3, MAX_OUTPUT)
    out = _whole(args[2], 0, MAX_OUTPUT)
    expansion = _whole(args[3], 1, MAX_OUTPUT)
    count = points * expansion
    if count > MAX_OUTPUT or count < 2:
        raise ValueError("Parameter out of range")
    y = _read(read, start, points)
    m = np.diff(y)  # slopes of the points - 1 intervals (unit spacing)
    m = np.concatenate(([3 * m[0] - 2 * m[1], 2 * m[0] - m[1]], m,
                        [2 * m[-1] - m[-2], 3 * m[-1] - 2 * m[-2]]))
    slope = np.empty(points)
    for i in range(points):  # m[i + 2] is the slope of interval i
        w1, w2 = abs(m[i + 3] - m[i + 2]), abs(m[i + 1] - m[i])
        slope[i] = ((w1 * m[i + 1] + w2 * m[i + 2]) / (w1 + w2) if w1 + w2
                    else (m[i + 1] + m[i + 2]) / 2)
    u = (points - 1) * np.arange(count) / (count - 1)
    index = np.minimum(np.floor(u).astype(int), points - 2)
    mu = u - index
    values = _hermite(y[index][:, None], y[index + 1][:, None], slope[index][:, None],
                      slope[index + 1][:, None], mu)
    values[-1, 0] = y[-1]
    return out, [float(v) for v in values[:, 0]]


def expand(name: str, args: Sequence[float], read: Read) -> tuple[int, list[float]]:
    """One of NAMES: where its values go in TABLE, and the values (nothing written)."""
    if not args:
        raise ValueError("Syntax error")
    if name == "B_SPLINE":
        return b_spline(args, read)
    if name == "C_SPLINE":
        return c_spline(args, read)
    return a_spline(args, read)


__all__ = ["NAMES", "a_spline", "b_spline", "c_spline", "expand"]

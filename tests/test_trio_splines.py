"""The TABLE splines (B_SPLINE, C_SPLINE, A_SPLINE), driven through an MC405's command line
and a program: the counts and layouts their help pages give, and values worked out by hand
from the spline's own formula (a Hermite or B-spline basis at a known fraction)."""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405


def table(trio: MC405, index: int) -> float:
    """The stored value, whole (PRINT shows 4 decimals)."""
    return trio.machine.table_read(index)


def values(trio: MC405, start: int, count: int) -> list[float]:
    return [table(trio, start + i) for i in range(count)]


# ---- C_SPLINE --------------------------------------------------------------------------------
def test_c_spline_page_example_two_dimensions_interleaved() -> None:
    """Mode 4 (cardinal, tension and bias 0 = Catmull-Rom) of 4 XY points, expansion 40:
    (4 - 1) * 40 + 1 = 121 XY pairs. Half way along the first span (mu = 0.5: Hermite
    weights 0.5, 0.125, 0.5, -0.125): x has tangents 0 and (150 - 136) / 2 = 7, so
    136 - 0.875; y has tangents (206 - 170) / 2 = 18 and (220 - 170) / 2 = 25."""
    trio = MC405()
    assert trio.send("TABLE(1000, 136, 170, 136, 206, 150, 220, 152, 220)") == []
    assert trio.send("C_SPLINE(4, 1000, 4, 2, 40, 2000, 0, 0)") == []
    assert values(trio, 2000, 2) == [136, 170]  # the first point
    assert values(trio, 2040, 2) == [135.125, 187.125]
    assert trio.query("?TABLE(2040)") == "135.1250"
    assert values(trio, 2080, 2) == [136, 206]  # each input point is on the curve
    assert values(trio, 2240, 2) == [152, 220]  # the 121st pair: the last point
    assert table(trio, 2242) == 0  # nothing written past it


def test_c_spline_block_modes_and_tension() -> None:
    """Mode 1 writes X1..Xn then Y1..Yn; mode 2 with tension 1 has zero tangents, so the
    mid-span value is the plain mean; tension -0.5, bias 0.5 scales the back difference by
    (1.5)(1.5)/2 and the forward one by (0.5)(1.5)/2."""
    trio = MC405()
    trio.send("TABLE(0, 0, 0, 10, 100, 30, 100)")  # (0,0) (10,100) (30,100)
    assert trio.send("C_SPLINE(1, 0, 3, 2, 2, 100)") == []
    # x: span 0 tangents 0 + 10 * 0.5 = 5 and (30 - 0) / 2 = 15
    x_mid = 0.5 * 0 + 0.125 * 5 + 0.5 * 10 - 0.125 * 15
    # y: span 0 tangents 50 and 50; span 1 tangents 50 and 0
    assert values(trio, 100, 10) == [0, x_mid, 10, 20 + 0.125 * 15 - 0.125 * 10, 30,
                                     0, 50, 100, 100 + 0.125 * 50, 100]
    assert trio.send("C_SPLINE(2, 0, 3, 2, 2, 200, 1, 0)") == []
    assert values(trio, 200, 5) == [0, 5, 10, 20, 30]
    assert trio.send("C_SPLINE(2, 0, 3, 2, 2, 300, -0.5, 0.5)") == []
    back, ahead = 1.5 * 1.5 / 2, 0.5 * 1.5 / 2
    m0 = 0 * back + 10 * ahead
    m1 = 10 * back + 20 * ahead
    assert table(trio, 301) == pytest.approx(5 + 0.125 * m0 - 0.125 * m1, abs=1e-12)
    # y (0, 100, 100): tangents 100 * ahead and 100 * back: 50 + 12.5 * (0.375 - 1.125)
    assert table(trio, 306) == pytest.approx(40.625, abs=1e-12)


@pytest.mark.parametrize("line", [
    "C_SPLINE(5, 0, 3, 2, 2, 100)",  # no mode 5
    "C_SPLINE(1, 0, 3, 1, 2, 100)",  # one dimension
    "C_SPLINE(1, 0, 3, 9, 2, 100)",  # nine
    "C_SPLINE(1, 0, 3, 2, 1, 100)",  # expansion below 2
    "C_SPLINE(1, 0, 3, 2, 101, 100)",  # above 100
    "C_SPLINE(2, 0, 3, 2, 2, 100, 1.5, 0)",  # tension past 1
    "C_SPLINE(1, 0, 1, 2, 2, 100)",  # one point
    "B_SPLINE(3, 0, 3, 100, 2)",
    "B_SPLINE(1, 0, 3, 100, 0)",
    "B_SPLINE(2, 3, 3, 1, 3, 5, 3, 0, 100)",  # weights from elsewhere: not described
    "B_SPLINE(2, 2, 3, 0, 3, 5, 3, 0, 100)",  # dimensions must be 3
    "A_SPLINE(0, 2, 100, 5)",  # Akima needs 3 points
])
def test_bad_spline_arguments_are_refused_and_write_nothing(line: str) -> None:
    trio = MC405()
    trio.send("TABLE(0, 1, 2, 3, 4, 5, 6, 7, 8, 9)")
    reply = trio.send(line)
    assert len(reply) == 1 and "Parameter out of range" in reply[0], reply
    assert all(v == 0 for v in values(trio, 100, 30))


def test_a_spline_that_does_not_fit_in_table_writes_nothing() -> None:
    trio = MC405()
    trio.send("TABLE(0, 1, 2, 3, 4)")
    reply = trio.send("B_SPLINE(1, 0, 4, 511990, 10)")  # 51 values from 511990
    assert len(reply) == 1 and "out of range" in reply[0], reply
    assert table(trio, 511990) == 0


# ---- B_SPLINE --------------------------------------------------------------------------------
def test_b_spline_mode_1_count_and_values() -> None:
    """Points 0, 6, 12, expansion 2: (3 + 1) * 2 = 8 values and the last point. The
    control polygon is
    0 0 0 6 12 12 12; the uniform cubic basis at t = 0 is (1, 4, 1, 0) / 6 and at
    t = 0.5 is (1, 23, 23, 1) / 48."""
    trio = MC405()
    trio.send("TABLE(0, 0, 6, 12)")
    assert trio.send("B_SPLINE(1, 0, 3, 100, 2)") == []
    expected = [0, 6 / 48,  # span 0 0 0 6
                6 / 6, (23 * 6 + 12) / 48,  # 0 0 6 12
                (6 * 4 + 12) / 6, (23 * 6 + 24 * 12) / 48,  # 0 6 12 12
                (6 + 5 * 12) / 6, (6 + 47 * 12) / 48]  # 6 12 12 12
    assert values(trio, 100, 10) == pytest.approx(expected + [12, 0], abs=1e-12)


def test_b_spline_page_example_ten_points_give_110() -> None:
    """The page: a 10 point profile expanded by 10 gives (10 + 1) * 10 = 110 values, and
    the closing point (a real cell's program cams over 111), from a program."""
    trio = MC405()
    trio.load("SPL", "\n".join([
        "FOR i = 0 TO 9",
        "  TABLE(i, i * i)",
        "NEXT i",
        "B_SPLINE(1, 0, 10, 200, 10)",
        "VR(0) = 1",
    ]))
    trio.send('RUN "SPL"')
    trio.advance(ticks=50)
    assert float(trio.query("?VR(0)")) == 1
    out = values(trio, 200, 112)
    assert out[0] == 0 and out[110] == 81 and out[111] == 0  # 111 values, then untouched
    assert all(b >= a for a, b in zip(out[:111], out[1:111], strict=False))  # i*i rises


def test_b_spline_mode_2_nurbs_degree_1_and_2() -> None:
    """Degree = knots - points - 1. Degree 1 on knots 0 0 1 2 2 is the polyline through the
    points; 3 points * expansion 3 = 9 XYZ triples at u = 0, 0.25, ... 2. Degree 2 on knots
    0 0 0 1 1 1 is the quadratic Bezier: at u = 0.5, (P0 + 2 P1 + P2) / 4."""
    trio = MC405()
    trio.send("TABLE(0, 0, 0, 0, 8, 4, 0, 8, 12, 4)")
    trio.send("TABLE(9, 0, 0, 1, 2, 2)")
    assert trio.send("B_SPLINE(2, 3, 3, 0, 3, 5, 3, 0, 100)") == []
    got = values(trio, 100, 28)
    assert got[:27] == pytest.approx([0, 0, 0, 2, 1, 0, 4, 2, 0, 6, 3, 0, 8, 4, 0,
                                      8, 6, 1, 8, 8, 2, 8, 10, 3, 8, 12, 4], abs=1e-12)
    assert got[27] == 0
    trio.send("TABLE(9, 0, 0, 0, 1, 1, 1)")
    assert trio.send("B_SPLINE(2, 3, 3, 0, 3, 6, 3, 0, 200)") == []
    # 9 triples at u = i / 8: the fifth is u = 0.5
    assert values(trio, 212, 3) == pytest.approx([6, 5, 1], abs=1e-12)
    assert values(trio, 224, 3) == pytest.approx([8, 12, 4], abs=1e-12)


def test_b_spline_mode_2_page_example_starts_and_ends_on_its_points() -> None:
    """The page's 9 XYZ points with 13 clamped knots (cubic), expansion 5: 45 triples,
    the first on the first point and the last on the last (the same point)."""
    trio = MC405()
    trio.send("TABLE(100, 150.709, 353.8857, 0, 104.5196, 337.7142, 0, 320.1131, 499.4647, 0)")
    trio.send("TABLE(109, 449.4824, 396.4945, 0, 595.335, 136.491, 0, 156.816, 96.3351, 0)")
    trio.send("TABLE(118, 429.4556, 313.7982, 0, 213.3019, 375.8004, 0, 150.709, 353.8857, 0)")
    trio.send("TABLE(127, 0, 0, 0, 0, 146.8154, 325.6644, 536.0555, 763.4151, 910.1338)")
    trio.send("TABLE(136, 1109.0886, 1109.0886, 1109.0886, 1109.0886)")
    assert trio.send("B_SPLINE(2, 3, 3, 0, 9, 13, 5, 100, 1000)") == []
    assert values(trio, 1000, 3) == pytest.approx([150.709, 353.8857, 0], abs=1e-9)
    assert values(trio, 1132, 3) == pytest.approx([150.709, 353.8857, 0], abs=1e-9)
    assert table(trio, 1135) == 0


# ---- A_SPLINE --------------------------------------------------------------------------------
def test_a_spline_akima_values() -> None:
    """Values 0 0 0 1 1, expansion 5: 25 values evenly from 0 to 4, u = j / 6. Akima's
    slope at point 2 is 0 (its left side is flat) and at point 3, with the extrapolated
    slope -1 after the last interval, (1 * 1 + 1 * 0) / 2 = 0.5; at u = 2.5 (j = 15) the
    Hermite weights give 0.5 * 1 - 0.125 * 0.5."""
    trio = MC405()
    trio.send("TABLE(0, 0, 0, 0, 1, 1)")
    assert trio.send("A_SPLINE(0, 5, 100, 5)") == []
    got = values(trio, 100, 26)
    assert got[15] == pytest.approx(0.4375, abs=1e-12)
    assert got[0] == 0 and got[24] == 1 and got[25] == 0
    assert got[:12] == pytest.approx([0] * 12, abs=1e-12)  # flat until point 2


def test_a_spline_keeps_a_straight_line_straight() -> None:
    """The page's example's shape: 6 values, expansion 10 = 60 values (its CAMBOX reads
    100..159); on a straight line Akima is the line itself: 3 * 5 * j / 59 at j."""
    trio = MC405()
    trio.send("TABLE(0, 0, 3, 6, 9, 12, 15)")
    assert trio.send("A_SPLINE(0, 6, 100, 10)") == []
    assert values(trio, 100, 61) == pytest.approx([15 * j / 59 for j in range(60)] + [0],
                                                  abs=1e-9)

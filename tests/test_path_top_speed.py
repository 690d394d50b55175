"""The shared path planner's per-segment top speed (`SegmentDef.v_top`): a segment cruises
at its own top whatever its ends, and its end (the seam) may be above its top: it then
ramps up at its end (the Trio's SP moves, docs/trio.md). Hand arithmetic at ACCEL 100."""

from __future__ import annotations

import pytest

from maxk.firmware_model.path import Segment, SegmentDef, plan_path


def line(length: float, seam: float, top: float | None) -> SegmentDef:
    return SegmentDef("line", (length, 0.0), True, 0.0, None, seam, 100.0, None, top)


def resolve(defs: list[SegmentDef]) -> list[Segment]:
    segments: list[Segment] = []
    for defn in defs:
        if segments:
            last = segments[-1]
            segments.append(Segment(defn, last.end, last.s0 + last.length, last.v_end))
        else:
            segments.append(Segment(SegmentDef(defn.kind, defn.values, True, 0.0, 0.0,
                                               defn.v_end, defn.accel, None, defn.v_top),
                                    (0.0, 0.0), 0.0, None))
    return segments


def test_a_slow_segment_ramps_up_at_its_end_to_a_faster_seam() -> None:
    """Top 5 then top 10, seam 10: 0 -> 5 (0.05 s, 0.125), cruise 9.5 at 5, 5 -> 10 at
    the end (0.05 s, 0.375); then 10 from the start, 9.5 at 10, 10 -> 0 (0.1 s, 0.5)."""
    plan = plan_path(resolve([line(10, 10, 5), line(10, 0, 10)]), 0, 0.0, None, 1.0)
    assert plan.end_time == pytest.approx(0.05 + 1.9 + 0.05 + 0.95 + 0.1, abs=1e-12)
    assert plan.state(1.0) == pytest.approx((0.125 + 5 * 0.95, 5.0), abs=1e-12)
    seam = 0.05 + 1.9 + 0.05
    assert plan.state(seam) == pytest.approx((10.0, 10.0), abs=1e-12)


def test_entered_above_its_top_and_left_above_it_a_segment_dips_to_its_top() -> None:
    """Top 10, seam 10; top 5, seam 10; top 10: the middle one enters at 10, slows to 5
    (0.05 s, 0.375), cruises 9.25 at 5, climbs back to 10 (0.05 s, 0.375)."""
    plan = plan_path(resolve([line(10, 10, 10), line(10, 10, 5), line(10, 0, 10)]), 0,
                     0.0, None, 1.0)
    first = 0.1 + 9.5 / 10
    assert plan.state(first) == pytest.approx((10.0, 10.0), abs=1e-12)
    middle = 0.05 + 9.25 / 5 + 0.05
    assert plan.state(first + 0.05 + 1.0)[1] == pytest.approx(5.0, abs=1e-12)
    assert plan.state(first + 0.05 + 1.0)[0] == pytest.approx(10 + 0.375 + 5.0, abs=1e-12)
    assert plan.state(first + middle) == pytest.approx((20.0, 10.0), abs=1e-12)


def test_without_a_top_the_segment_keeps_the_vv_ceiling() -> None:
    """No v_top: a segment's ceiling stays max(start, end) (the MAXk's VV), unchanged."""
    plan = plan_path(resolve([line(10, 10, None), line(10, 5, None)]), 0, 0.0, None, 1.0)
    # the second starts at 10 and holds it (ceiling max(10, 5)) until it must stop
    assert plan.state(0.1 + 0.95 + 0.5)[1] == pytest.approx(10.0, abs=1e-12)


def test_too_short_to_reach_its_top_a_segment_dips_as_far_as_its_length_allows() -> None:
    """Top 1 over 0.5 between two top-10 segments, seams 10: down at 100 and up again,
    the lowest speed sqrt((10^2 + 10^2) / 2 - 100 x 0.5) = sqrt(50), at its middle."""
    plan = plan_path(resolve([line(10, 10, 10), line(0.5, 10, 1), line(10, 0, 10)]), 0,
                     0.0, None, 1.0)
    first = 0.1 + 9.5 / 10
    half = (10 - 50 ** 0.5) / 100
    assert plan.state(first + half) == pytest.approx((10.25, 50 ** 0.5), abs=1e-12)
    assert plan.state(first + 2 * half) == pytest.approx((10.5, 10.0), abs=1e-12)

"""The shared planner's S-ramps (firmware_model/path_scurve.py) on many merged paths, as
the MC405's merged moves give them: every plan ends at rest exactly on the end of the
known path, its acceleration, speed and distance are continuous across every piece
(each S-ramp starts and ends at zero acceleration), the speed is never negative nor
above the highest SPEED, also where a plan is re-made in the middle of a ramp (a move
merged in: the ramp running finishes first)."""

from __future__ import annotations

import math
import random

import pytest

from maxk.firmware_model.path import Piece, Segment, SegmentDef
from maxk.firmware_model.path_scurve import SRamp, level_point, plan_shaped


def merged(rng: random.Random) -> tuple[list[Segment], list[float]]:
    """Straight moves as an MC405 merges them: each cruises at its own SPEED (its top)
    and hands over at its own speed (two plain moves join at the first one's speed)."""
    segments: list[Segment] = []
    start, s0 = (0.0, 0.0), 0.0
    speeds = [rng.choice([1.0, 5.0, 10.0, 40.0]) for _ in range(rng.randint(1, 6))]
    for j, speed in enumerate(speeds):
        delta = (rng.choice([0.01, 0.3, 2.0, 7.0, 50.0]), rng.choice([0.0, 0.5, 4.0]))
        defn = SegmentDef("line", delta, True, 0.0, 0.0 if j == 0 else None, speed,
                          rng.choice([50.0, 100.0, 1000.0]), None, speed)
        segment = Segment(defn, start, s0, segments[-1].v_end if segments else None)
        segments.append(segment)
        start, s0 = segment.end, s0 + segment.length
    return segments, speeds


def joined(pieces: list[Piece]) -> None:
    for a, b in zip(pieces, pieces[1:], strict=False):
        end_a = a.a + a.j * a.duration
        assert b.t0 == pytest.approx(a.t0 + a.duration, abs=1e-9)
        assert b.a == pytest.approx(end_a, abs=1e-6 * max(1.0, abs(end_a)))
        assert b.v0 == pytest.approx(a.v(a.duration), abs=1e-6)
        assert b.s0 == pytest.approx(a.s(a.duration), abs=1e-6)


@pytest.mark.parametrize("seed", range(4))
def test_s_ramped_merged_paths_end_at_rest_on_their_end(seed: int) -> None:
    rng = random.Random(seed)
    for _ in range(150):
        segments, speeds = merged(rng)
        ramp = rng.choice([SRamp(jerk=rng.choice([200.0, 2000.0, 5e4])),
                           SRamp(rise=rng.choice([0.01, 0.05, 0.2]))])
        plan = plan_shaped(segments, 0, 0.0, 0.0, 1.0, ramp)
        end = segments[-1].s0 + segments[-1].length
        if rng.random() < 0.5:  # a move merged in at a random time: re-made there
            assert plan.end_time is not None
            head, s, v = level_point(plan, rng.uniform(0.0, plan.end_time))
            i = next(k for k, g in enumerate(segments) if g.s0 + g.length > s - 1e-9
                     or k == len(segments) - 1)
            plan = plan_shaped(segments, i, s, v, 1.0, ramp, head)
        pieces = plan.pieces
        joined(pieces)
        last = pieces[-1]
        assert last.v(last.duration) == pytest.approx(0.0, abs=1e-6)
        assert last.s(last.duration) == pytest.approx(end, abs=1e-6)
        assert plan.s_end == pytest.approx(end, abs=1e-9)
        for p in pieces:
            for k in range(5):
                assert -1e-9 <= p.v(p.duration * k / 4) <= max(speeds) + 1e-6


def test_a_ramp_to_a_low_speed_may_be_as_long_as_one_to_rest() -> None:
    """SRAMP 10 ms at ACCEL 100: from 10 the ramp to rest covers 10/2 (0.1 + 0.01) =
    0.55, the one to 1 covers 11/2 (0.09 + 0.01) = 0.55 too; within 0.55 the lowest
    speed reached is rest, within a hair less it is 1 (not a speed near 0)."""
    ramp = SRamp(rise=0.01)
    assert ramp.distance(10.0, 0.0, 100.0) == pytest.approx(0.55, abs=1e-12)
    assert ramp.distance(10.0, 1.0, 100.0) == pytest.approx(0.55, abs=1e-12)
    assert ramp.reach_down(10.0, 0.55, 100.0) == 0.0
    # 0.55 + 0.005 w - w^2 / 200 = 0.5499: w^2 - w - 0.02 = 0
    assert ramp.reach_down(10.0, 0.5499, 100.0) == pytest.approx((1 + math.sqrt(1.08)) / 2,
                                                                 abs=1e-9)

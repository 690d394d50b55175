"""Re-plans that look ahead only as far as braking needs (issue 19): a lazily made plan
answers exactly what the whole plan answers, and a long streamed contour with velocity
overrides reads the same positions as one whose every re-plan is made whole."""

from __future__ import annotations

import random

import pytest

from maxk import MAXk
from maxk.firmware_model import path as P
from maxk.personalities.maxk import contouring as C


def _segments(n: int, seed: int) -> list[P.Segment]:
    rng = random.Random(seed)
    segments: list[P.Segment] = []
    start: tuple[float, ...] = (0.0, 0.0)
    for _ in range(n):
        speed = rng.choice([0.0, 200.0, 1000.0, 4000.0, 30000.0])
        accel = rng.choice([5000.0, 100000.0, 2e6])
        if rng.random() < 0.15:
            values: tuple[float | None, ...] = (start[0] + rng.randint(-300, 300),
                                                start[1] + rng.randint(-300, 300))
            defn = P.SegmentDef("arc", values, False, rng.choice([90.0, -45.0, 360.0]),
                                None, speed, accel, None)
        else:
            step = rng.choice([0, 1, 3, 50, 400, 5000])
            defn = P.SegmentDef("line", (rng.randint(-step, step), rng.randint(-step, step)),
                                True, 0.0, rng.choice([None, speed / 2]), speed, accel, None)
        last = segments[-1] if segments else None
        seg = P.Segment(defn, start, last.s0 + last.length if last else 0.0,
                        last.v_end if last else None)
        segments.append(seg)
        start = seg.end
    return segments


@pytest.mark.parametrize("seed", range(12))
def test_a_lazy_plan_answers_what_the_whole_plan_answers(seed):
    rng = random.Random(seed)
    segments = _segments(200, seed)
    for _ in range(6):
        i0 = rng.randrange(len(segments))
        seg = segments[i0]
        s_now = seg.s0 + rng.random() * seg.length
        v_now = rng.choice([None, 0.0, 500.0, 5000.0])
        scale = rng.choice([0.0, 0.5, 1.0, 1.37, 2.0])
        whole = P.plan_path(segments, i0, s_now, v_now, scale)
        lazy = P.plan_path(segments, i0, s_now, v_now, scale, lazy=True)
        probe = P.plan_path(segments, i0, s_now, v_now, scale, lazy=True)
        span = whole.end_time if whole.end_time is not None else 100.0
        for t in sorted(rng.uniform(0, span * 1.1) for _ in range(40)):
            assert lazy.state(t) == whole.state(t)
        for s in sorted(rng.uniform(s_now, whole.s_end + 10) for _ in range(40)):
            assert probe.time_at(s) == whole.time_at(s)
        assert lazy.end_time == whole.end_time and probe.s_end == whole.s_end
        assert lazy.pieces == whole.pieces and probe.pieces == whole.pieces


def test_a_re_plan_makes_only_the_segments_braking_needs():
    segments = _segments(2000, 99)
    plan = P.plan_path(segments, 0, 0.0, None, 1.0, lazy=True)
    plan.state(0.001)
    assert not plan.done and len(plan._pieces) < 200  # (the whole plan: thousands)


def _streamed(monkeypatch: pytest.MonkeyPatch | None) -> list[str]:
    """A long path streamed while it runs (segments arriving as the EPICS trajectory scan
    sends them), polled and nudged by VO; every re-plan made whole if monkeypatched."""
    if monkeypatch is not None:
        def whole(*args, **kwargs):
            kwargs["lazy"] = False
            return P.plan_path(*args, **kwargs)

        def whole_stop(*args, **kwargs):
            kwargs["lazy"] = False
            return P.plan_stop(*args, **kwargs)

        monkeypatch.setattr(C, "plan_path", whole)
        monkeypatch.setattr(C, "plan_stop", whole_stop)
    rng = random.Random(5)
    board = MAXk("MAXk-4000")
    board.board.world.axes[1].set_plus_limit(40000)
    board.send("AA; VV2000,3000; VA60000; VID1; VP0,0;")
    x = y = 0
    out: list[str] = []
    for i in range(600):
        x += rng.randint(-200, 400)
        y += rng.randint(-100, 150)
        speed = rng.choice([500, 2000, 3000, 8000])
        board.send(f"VV{speed}; VA{rng.choice([20000, 60000, 400000])}; VP{x},{y};")
        if i > 40 and rng.random() < 0.5:
            board.advance(ticks=rng.randint(1, 900))
            out += [str(board.tick), board.query("AA RP"), board.query("QA"),
                    board.query("AA RI")]
        if rng.random() < 0.05:
            board.send(f"VO={rng.choice([40, 95, 100, 150, 200])};")
        if rng.random() < 0.01:
            board.send("VH1;")
            board.advance(ticks=500)
            board.send("VG;")
    board.send("VE;")
    while not board.done("X") and board.time < 5000:
        board.advance(ticks=2000)
        out += [str(board.tick), board.query("AA RP"), board.query("AA RI")]
    out.append(board.query("AA RP"))
    return out


def test_a_streamed_path_reads_what_whole_re_plans_read(monkeypatch):
    lazy = _streamed(None)
    whole = _streamed(monkeypatch)
    assert len(lazy) > 1000
    assert lazy == whole

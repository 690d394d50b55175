"""Vector contouring: the manual's hole-cutting example, paths sampled every update
cycle, blending, velocity override, segment I/O, the trajectory scan's vector tasks."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk import MAXk

HOLE = ("AA; VOA0,5; VV1000,1000; VP0,0; VIO0100,,0100; VC0,5000,-180; VC0,0,-360; "
        "VIO0,,0100; VV1000,0; VP-1000,0; VE;")
SQRT2 = math.sqrt(2.0)


class Samples:
    """Every update cycle: tick, X, Y (whole counts, as RP reads them), output latch, and
    the path's exact vector speed (what VRV rounds)."""

    def __init__(self, board: MAXk, every: int = 1, task: int = 1) -> None:
        self.rows: list[tuple[int, int, int, int]] = []
        self.speed: list[float] = []
        self.board = board.board
        self.task = task
        self.board.add_observer(self._sample, every)
        self._sample(self.board)

    def _sample(self, b) -> None:
        self.rows.append((b.tick, b.axes[0].motor_position(b), b.axes[1].motor_position(b),
                          b.io.outputs))
        task = b.tasks.get(self.task)
        head = task.running if task is not None else None
        self.speed.append(head.where(b)[1] if head is not None else 0.0)

    def accelerations(self) -> list[float]:
        """|d speed / dt| between consecutive samples, counts/s^2, after the start (where a
        stepper takes the start velocity at once, as it takes VB)."""
        rate = self.board.update_rate_hz
        return [abs(b - a) * rate / max(1, t1 - t0)
                for (t0, *_), (t1, *_), a, b in zip(self.rows[1:], self.rows[2:],
                                                     self.speed[1:], self.speed[2:],
                                                     strict=False)]


def _off_circle(x: float, y: float, cx: float, cy: float, r: float) -> float:
    return abs(math.hypot(x - cx, y - cy) - r)


def _off_line(x, y, a, b) -> float:
    (ax, ay), (bx, by) = a, b
    length = math.hypot(bx - ax, by - ay)
    return abs((bx - ax) * (ay - y) - (ax - x) * (by - ay)) / length


# ---- the manual's example ----------------------------------------------------------------
def test_hole_cutting_example_runs_as_written():
    board = MAXk("MAXk-4000")
    samples = Samples(board, every=4)
    assert board.send(HOLE) == []
    board.send("AA ID")
    assert not board.command_error
    assert board.run_until_done("X", "Y", timeout=200)
    rate = board.board.update_rate_hz
    half, full = math.pi * 5000, 2 * math.pi * 10000
    line = math.hypot(1000, 10000)
    # 1000 counts/s all the way (a stepper takes the start velocity at once), and the
    # stop at the end at VA (none given: X's AC, 2,000,000), which costs v/2A: to the tick
    assert board.board.tick == math.ceil(((half + full + line) / 1000 + 1000 / 4e6) * rate)
    assert board.query("AA RP") == "-1000,0,0,0"  # exactly on the last point
    assert board.query("AA RE") == "-1000,0,0,0"
    on_half = on_full = 0
    for tick, x, y, _io in samples.rows:
        s = tick / rate * 1000.0
        if s < half:
            assert _off_circle(x, y, 0, 5000, 5000) < SQRT2
            on_half += 1
        elif s < half + full:
            assert _off_circle(x, y, 0, 0, 10000) < SQRT2
            on_full += 1
        elif s < half + full + line:
            assert _off_line(x, y, (0, 10000), (-1000, 0)) < SQRT2
    assert on_half > 25_000 and on_full > 125_000
    # clockwise: the half circle passes left of its centre, the full circle's first
    # quarter right of the hole's centre (from the top)
    quarter = next(r for r in samples.rows if r[0] >= (half / 2) / 1000 * rate)
    assert abs(quarter[1] + 5000) <= 1 and abs(quarter[2] - 5000) <= 2
    later = next(r for r in samples.rows if r[0] >= (half + full / 4) / 1000 * rate)
    assert abs(later[1] - 10000) <= 1 and abs(later[2]) <= 2


def test_hole_cutting_torch_line_is_missing_on_a_small_board():
    """Table 6-2: a MAXk-4000 has lines 0-7; the example's mask 0100 (line 8) names
    none of them, so the contour runs and no line switches."""
    board = MAXk("MAXk-4000")
    board.send(HOLE)
    board.run_until_done("X", timeout=200)
    assert not board.command_error
    assert list(board.board.io.changes) == []


def test_hole_cutting_torch_switches_at_the_segment_starts():
    board = MAXk("MAXk-8000")  # line 8 exists on boards of six axes or more
    board.send(HOLE)
    board.run_until_done("X", timeout=200)
    rate = board.board.update_rate_hz
    changes = list(board.board.io.changes)
    # on at the centre when the half circle starts (tick 0), off when the full circle is
    # done: the first tick at which the path has passed it
    end_of_circle = math.ceil((math.pi * 5000 + 2 * math.pi * 10000) / 1000 * rate - 1e-9)
    assert changes == [(0, 0x0100), (end_of_circle, 0)]


def test_hole_cutting_speed_follows_the_analog_override():
    board = MAXk("MAXk-4000")
    board.set_analog(0, 2.5)  # VOA0,5: 0 V is 100 %, +5 V 200 %
    board.send(HOLE)
    board.advance(0.5)
    assert board.query("VRV") == "1500"
    board.set_analog(0, -5.0)  # 0 %: the path holds where it is, still on the circle
    board.advance(0.5)
    assert board.query("VRV") == "0"
    x, y = board.position("X"), board.position("Y")
    board.advance(2.0)
    assert (board.position("X"), board.position("Y")) == (x, y)
    assert _off_circle(x, y, 0, 5000, 5000) < SQRT2
    assert board.query("AX QA")[1] == "N"
    board.set_analog(0, 0.0)
    board.send("AA ID")
    assert board.run_until_done("X", timeout=200)
    assert board.query("AA RP") == "-1000,0,0,0"


def test_the_hole_cutting_example_file_passes():
    from pathlib import Path

    from maxk.script import load_script, run_script

    script = load_script(Path(__file__).parent.parent / "examples" / "hole_cutting.maxk")
    transcript = run_script(script)
    assert not transcript.failures, transcript.failures


# ---- straight segments, blending, limits on speed and acceleration -----------------------
def test_straight_segments_stay_straight_and_blend_without_stopping():
    board = MAXk("MAXk-4000")
    samples = Samples(board)
    board.send("AA; VA50000; VV2000,2000; VP0,0; VP8000,6000; VP8000,0; VV2000,0; VP0,0; VE; ID")
    assert board.run_until_done("X", timeout=100)
    assert board.query("AA RP") == "0,0,0,0"
    legs = [((0, 0), (8000, 6000)), ((8000, 6000), (8000, 0)), ((8000, 0), (0, 0))]
    for _tick, x, y, _io in samples.rows:
        assert min(_off_line(x, y, a, b) for a, b in legs) < SQRT2
    # never above VV; through the corners without slowing down (no stop between
    # segments: their end velocity says so); the last one ends at rest
    assert max(samples.speed) <= 2000
    assert max(samples.accelerations()) <= 50000 * (1 + 1e-9)
    for corner in (10000, 16000):
        tick = math.ceil(corner / 2000 * 8192)
        assert min(samples.speed[tick - 40: tick + 40]) == 2000


def test_a_zero_end_velocity_stops_at_the_segment_end():
    board = MAXk("MAXk-4000")
    samples = Samples(board)
    board.send("AA; VA10000; VV1000,0; VP1000,0; VV0,1000; VP1000,1000; VV1000,0; VP0,1000; "
               "VE; ID")
    assert board.run_until_done("X", timeout=20)
    assert board.query("AA RP") == "0,1000,0,0"
    # the first corner ends a segment at 0 (VV1000,0): the path stands still there and
    # starts again (VV0,1000); the second ends at 1000: no stop
    def near(cx, cy):
        return [v for (_t, x, y, _io), v in zip(samples.rows, samples.speed, strict=True)
                if abs(x - cx) <= 1 and abs(y - cy) <= 1]

    # zero between two update cycles: within one cycle's worth of VA of it at a tick
    assert min(near(1000, 0)) <= 10000 / 8192
    assert min(near(1000, 1000)) == 1000
    assert max(samples.accelerations()) <= 10000 * (1 + 1e-9)
    assert max(samples.speed) <= 1000


def test_speed_changes_stay_within_va():
    board = MAXk("MAXk-4000")
    samples = Samples(board)
    board.send("AA; VA20000; VV0,4000; VP3000,4000; VV4000,500; VP6000,0; VV0; VP9000,4000; "
               "VE; ID")
    assert board.run_until_done("X", timeout=20)
    assert max(samples.speed) <= 4000
    assert max(samples.accelerations()) <= 20000 * (1 + 1e-9)
    assert board.query("AA RP") == "9000,4000,0,0"


def test_a_tight_arc_is_slowed_to_keep_the_centripetal_acceleration_within_va():
    board = MAXk("MAXk-4000")
    # radius 100 at VA 10000: sqrt(VA R) = 1000 counts/s, below the programmed 5000
    board.send("AA; VA10000; VV5000,5000; VP0,0; VC100,0,360; VE")
    board.advance(0.5)
    assert int(board.query("VRV")) == 1000
    board.send("AA ID")
    assert board.run_until_done("X", timeout=10)
    assert board.query("AA RP") == "0,0,0,0"


def test_arc_directions_and_angles():
    board = MAXk("MAXk-4000")
    # +90: counter-clockwise, from the first axis toward the second
    board.send("AA; VV1000,1000; VP1000,0; VC0,0,90; VE; ID")
    board.run_until_done("X", timeout=20)
    assert board.query("AA RP") == "0,1000,0,0"
    board.send("AA CA; VP1000,0; VC0,0,-90; VE; ID")  # clockwise
    board.run_until_done("X", timeout=20)
    assert board.query("AA RP") == "0,-1000,0,0"
    board.send("AA CA; VP1000,0; VC0,0,720; VE; ID")  # two whole turns close exactly
    board.run_until_done("X", timeout=60)
    assert board.query("AA RP") == "1000,0,0,0"


# ---- velocity override --------------------------------------------------------------------
def test_override_mid_path_changes_speed_on_the_path():
    board = MAXk("MAXk-4000")
    samples = Samples(board)
    board.send("AA; VA10000; VV2000,2000; VP20000,10000; VE")
    board.advance(1.0)
    assert board.query("VRV") == "2000"
    board.send("VO50")
    board.advance(0.5)
    assert board.query("VRV") == "1000"
    board.send("VO[1]=150")  # the trajectory scan's form, same task
    board.advance(0.5)
    assert board.query("VRV") == "3000"
    board.send("VO0")
    board.advance(1.0)
    assert board.query("VRV") == "0"
    held = board.query("AA RP")
    board.advance(1.0)
    assert board.query("AA RP") == held
    board.send("VO100; AA ID")
    assert board.run_until_done("X", timeout=60)
    assert board.query("AA RP") == "20000,10000,0,0"
    for _tick, x, y, _io in samples.rows:
        assert _off_line(x, y, (0, 0), (20000, 10000)) < SQRT2
    assert max(samples.speed) <= 3000  # never above 150 % of VV
    assert max(samples.accelerations()) <= 10000 * (1 + 1e-9)


def test_override_is_range_checked_and_a_bad_value_changes_nothing():
    board = MAXk()
    board.send("VO150")
    board.send("VO250")
    assert board.command_error and "range" in str(board.last_error)
    assert board.board.contour_task(1).override == 150


# ---- definitions that stream in, holds, stops ---------------------------------------------
def test_segments_streamed_while_running_extend_the_path():
    board = MAXk("MAXk-4000")
    board.send("AA; VA100000; VV1000,1000; VP1000,0;")
    board.advance(0.5)
    assert board.query("VRV") == "1000"
    board.send("VP1000,1000;")  # arrives in time: no slow-down at the corner
    board.advance(0.6)
    assert board.query("VRV") == "1000"
    board.advance(2.0)  # the known path is used up: the axes wait at its end
    assert board.query("AA RP") == "1000,1000,0,0" and board.query("VRV") == "0"
    board.send("AA ID")
    board.advance(0.1)
    assert board.query("AX QA")[1] == "N"  # the queued ID waits behind the contour
    board.send("AA; VP0,1000; VE")
    assert board.run_until_done("X", timeout=10)
    assert board.query("AA RP") == "0,1000,0,0"


def test_segments_hold_queue_units_until_the_path_passes_them():
    board = MAXk("MAXk-4000")
    board.send("AA; VH0; VV1000,1000; VP100,0; VP200,0; VP300,0; VE")
    assert board.query("AA RQC") == "2556,2556,2559,2559"  # anchor + two segments
    board.send("VG")
    board.advance(0.15)
    assert board.query("AA RQC") == "2557,2557,2559,2559"
    board.advance(1.0)
    assert board.query("AA RQC") == "2559,2559,2559,2559"


def test_vh1_holds_on_the_path_and_vg_resumes_to_the_exact_end():
    board = MAXk("MAXk-4000")
    board.send("AA; VA5000; VV1000,1000; VP3000,4000; VE")
    board.advance(1.0)
    board.send("VH1")
    board.advance(1.0)
    assert board.query("VRV") == "0"
    x, y = board.position("X"), board.position("Y")
    assert _off_line(x, y, (0, 0), (3000, 4000)) < SQRT2
    board.advance(1.0)
    assert (board.position("X"), board.position("Y")) == (x, y)
    board.send("VG; AA ID")
    assert board.run_until_done("X", timeout=20)
    assert board.query("AA RP") == "3000,4000,0,0"


def test_st_ramps_the_contour_down_on_its_path_and_frees_the_queues():
    board = MAXk("MAXk-4000")
    board.send("AA; VA4000; VV2000,2000; VP20000,20000; VE; AA ID")
    board.advance(2.0)
    board.send("AA ST")
    board.advance(0.2)
    moving = board.query("VRV")
    assert 0 < int(moving) < 2000
    board.advance(1.0)
    x, y = board.position("X"), board.position("Y")
    assert x == y and 0 < x < 20000  # stopped on the line, short of its end
    assert board.query("AA RQC") == "2559,2559,2559,2559"
    board.send("AA; MR100,100; GO; ID")  # the queues work again
    assert board.run_until_done("X", timeout=5)
    assert board.position("X") == x + 100


def test_a_hard_limit_on_one_axis_stops_the_whole_contour():
    board = MAXk("MAXk-4000")
    board.set_limits("X", plus=3000)
    board.send("AA; VV1000,1000; VP0,0; VP5000,5000; VE")
    board.advance(6.0)
    assert board.query("VRV") == "0"
    assert board.position("X") == board.position("Y") == 3000
    assert board.doorbell & (1 << 8)  # X overtravel


# ---- errors -------------------------------------------------------------------------------
@pytest.mark.parametrize("text, reason", [
    ("VC0,0,90", "open the contour"),
    ("VP[9]A100", "vector tasks are 1-8"),
    ("VP[1", "malformed task index"),
    ("VIO12345,,1", "out of range"),
    ("AA; VP100; VC0,0,90", "at least two axes"),
    ("VC0,0,0", "nonzero"),
    ("VOA7", "no analog input"),
])
def test_bad_vector_commands_are_command_errors_and_change_nothing(text, reason):
    board = MAXk("MAXk-4000")
    board.send(text + "; AA; RQC;")
    assert board.command_error
    assert reason in str(board.last_error), board.last_error
    board.send("IC")
    assert board.query("AA RQC") in ("2559,2559,2559,2559", "2558,2559,2559,2559")


def test_a_segment_naming_an_axis_outside_the_contour_is_refused():
    board = MAXk("MAXk-4000")
    board.send("AA; VH0; VP100,100; VP200,200,300")
    assert board.command_error and "not in the contour" in str(board.last_error)
    assert len(board.board.contour_task(1).contours[0].defs) == 1
    board.send("VE; VG; AA ID")
    assert board.run_until_done("X", timeout=5)
    assert board.query("AA RP") == "100,100,0,0"


# ---- the MAXv vector tasks as the EPICS trajectory scan uses them -------------------------
def _trajectory_scan_load() -> list[str]:
    """What MAX_trajectoryScan.st's loadTrajectory sends for two motors (X: task 1, Y:
    task 2), output pulses on bit 7 from task 1 (a MAXk-4000 has lines 0-7), start on
    input bit 3."""
    out = ["AM;", "BD0080;", "BL7;", "IO3,0;", "AM; SI1,1,,,,,,;", "AX; #UR?;"]
    x = [(10000, 1, 1000, 50), (1, 1000, 1000, 1050), (1, 1000, 1000, 2050),
         (10000, 1000, 0, 2100)]
    y = [(20000, 1, 2000, 100), (1, 2000, 2000, 4100), (20000, 2000, 0, 4200)]
    for task, segments, pulses in ((1, x, True), (2, y, False)):
        out.append(f"AM; VIO[{task}]0080,0000,0080;" if pulses else f"AM; VIO[{task}]0,0,0;")
        out += [f"AM; VID[{task}]1;", f"AM; VH[{task}]0;", f"A{'XY'[task - 1]}; SW3;"]
        for i, (accel, v0, v1, p) in enumerate(segments):
            slots = "," * (task - 1) + str(p) + "," * (8 - task)
            vv = f"{v0},{v1}" if i in (0, len(segments) - 1) else f"{v1}"
            out.append(f"AM; VA[{task}]{accel};VV[{task}]{vv};VP[{task}]A{slots};")
        out.append(f"AM; VE[{task}];")
    return out


def test_trajectory_scan_sequence_polled_with_qi():
    board = MAXk("MAXk-4000")
    replies = []
    for line in _trajectory_scan_load():
        replies += board.send(line)
    assert replies == ["8192"]  # #UR?
    board.send("AM;VO[1]=100;VO[2]=100;")
    board.send("AM;VG[1];VG[2];")
    assert not board.command_error, board.last_error
    board.advance(1.0)
    assert board.query("AM RP") == "0,0,0,0"  # armed: waiting for the trigger on input 3
    board.set_input(3, True)
    start = board.board.tick
    polls = []
    for _ in range(50):  # poll as the sequencer does, every 0.2 s
        board.advance(0.2)
        qi = board.query("QI")
        polls.append(qi)
        if qi[1] == "D" and qi[6] == "D":
            break
    assert polls[0][1] == "N" and polls[0][6] == "N"
    assert polls[-1][1] == "D" and polls[-1][6] == "D"
    assert board.query("AM RP") == "2100,4200,0,0"
    # task 1 pulses bit 7 at each of its four segment starts, one update cycle long
    rises = [(t - start) for t, word in board.board.io.changes if word & 0x80]
    falls = [(t - start) for t, word in board.board.io.changes if not word & 0x80]
    assert len(rises) == 4 and len(falls) == 4
    assert all(f - r == 1 for r, f in zip(rises, falls, strict=True))
    assert rises[0] == 0


def test_trajectory_scan_abort_with_vh1_and_ks():
    board = MAXk("MAXk-4000")
    for line in _trajectory_scan_load():
        board.send(line)
    board.send("AM;VO[1]=100;VO[2]=100;AM;VG[1];VG[2];")
    board.set_input(3, True)
    board.advance(0.8)
    board.send("AM; VH[1]1;")
    board.send("AM; VH[2]1;")
    board.send("KS1,1,,,,,,;")
    board.advance(0.5)
    assert board.query("VRV[1]") == board.query("VRV[2]") == "0"
    assert board.query("QI")[1] == "N"  # stopped, not finished: no done flag
    assert board.query("AM RQC").startswith("2559,2559")
    board.send("AM; MR10,10; GO; ID")
    assert board.run_until_done("X", "Y", timeout=5)


def test_trajectory_scan_over_tcp():
    """The same sequence through the TCP door, polled with QI as the sequencer does, with
    the wall clock (a manual one) moving between polls."""
    from tests.hosting import HostedBoards

    hosted = HostedBoards(models=("MAXk-4000",))
    try:
        c = hosted.connect()
        for line in _trajectory_scan_load():
            if "?" in line:
                assert c.query(line) == "8192"
            else:
                c.command(line)
        c.command("AM;VO[1]=100;VO[2]=100;")
        c.command("AM;VG[1];VG[2];")
        hosted.call(lambda: hosted.services[0].controller.set_input(3, True))
        polls = []
        for _ in range(30):
            hosted.advance(0.2)
            polls.append(c.query("QI"))
            if polls[-1][1] == "D" and polls[-1][6] == "D":
                break
        assert polls[0][:10] == "PNNN,PNNN,"
        assert polls[-1][:10] == "PDNN,PDNN,"
        assert c.query("AM RP") == "2100,4200,0,0"
        assert c.query("AM; VRV[1]") == "0"
        assert c.nothing_pending(hosted)
    finally:
        hosted.close()


# ---- properties ---------------------------------------------------------------------------
_points = st.tuples(st.integers(-20000, 20000), st.integers(-20000, 20000))


@settings(max_examples=25, deadline=None)
@given(points=st.lists(_points, min_size=1, max_size=5),
       speeds=st.lists(st.integers(100, 5000), min_size=5, max_size=5),
       accel=st.integers(2000, 2_000_000),
       arc=st.one_of(st.none(), st.tuples(_points, st.integers(-400, 400).filter(bool))))
def test_any_path_ends_exactly_on_its_last_point_within_speed(points, speeds, accel, arc):
    board = MAXk("MAXk-4000")
    samples = Samples(board, every=256)
    text = [f"AA; VA{accel}; VP0,0;"]
    for (x, y), v in zip(points, speeds, strict=False):
        text.append(f"VV{v},{v}; VP{x},{y};")
    end = points[-1]
    if arc is not None:
        (cx, cy), angle = arc
        text.append(f"VC{cx},{cy},{angle};")
        r = math.hypot(end[0] - cx, end[1] - cy)
        theta = math.atan2(end[1] - cy, end[0] - cx) + math.radians(angle)
        end = (cx + r * math.cos(theta), cy + r * math.sin(theta))
    text.append("VE; ID")
    board.send(" ".join(text))
    assert not board.command_error, board.last_error
    assert board.run_until_done("X", timeout=4000)
    assert not board.board.tasks[1].contours
    assert abs(board.position("X") - end[0]) <= 0.5 + 1e-6
    assert abs(board.position("Y") - end[1]) <= 0.5 + 1e-6
    assert max(samples.speed) <= max(speeds[: len(points)]) * (1 + 1e-12)
    assert max(samples.accelerations(), default=0.0) <= accel * (1 + 1e-9)


def test_relative_segments_back_to_back_contours_on_another_task():
    board = MAXk("MAXk-4000")
    board.send("AM; VV[3]1000,1000; VP[3]R,100,200,,; VP[3]R,100,-50,,; VE[3]; "
               "VP[3]R,-200,,,; VE[3]; AA ID")
    assert not board.command_error, board.last_error
    assert board.run_until_done("X", "Y", "Z", timeout=20)
    assert board.query("AA RP") == "0,0,150,0"
    assert board.query("VRV[3]") == "0"


def test_sa_and_reset_end_a_running_contour():
    board = MAXk("MAXk-4000")
    board.send("AA; VV1000,1000; VP5000,5000; VE")
    board.advance(1.0)
    board.send("SA")
    board.advance(1.0)
    x = board.position("X")
    assert x == board.position("Y") and 0 < x < 1000
    assert board.board.tasks[1].contours == []
    board.send("AA; VP0,0; VE; AA CA; ID")
    assert board.run_until_done("X", timeout=20)
    assert board.query("AA RP") == "0,0,0,0"
    board.send("AA; VV1000,1000; VP5000,5000; VE")
    board.advance(1.0)
    board.reset()
    board.advance(1.0)
    assert board.query("AA RP") == "0,0,0,0" and board.board.tasks == {}


def test_segments_sent_while_held_run_after_vg():
    board = MAXk("MAXk-4000")
    board.send("AA; VA10000; VV2000,2000; VP0,0; VP10000,0")
    board.advance(1.0)
    board.send("VH1")
    board.advance(1.0)
    board.send("AA; VP10000,10000; VP0,10000; VE; AA ID; VG")
    assert board.run_until_done("X", timeout=30)
    assert board.query("AA RP") == "0,10000,0,0"


def test_vh1_on_a_starved_contour_holds_and_vo_still_acts():
    board = MAXk("MAXk-4000")
    board.send("AA; VA100000; VV1000,1000; VP0,0; VP1000,0")
    board.advance(2.0)
    board.send("VH1; AA; VP20000,0")
    board.advance(1.0)
    assert board.query("VRV") == "0" and board.query("AA RP") == "1000,0,0,0"
    board.send("VG")
    board.advance(1.0)
    assert board.query("VRV") == "1000"
    board.send("VO0")
    board.advance(0.1)
    assert board.query("VRV") == "0"


def test_vg_during_the_vh1_ramp_goes_on_from_there():
    board = MAXk("MAXk-4000")
    board.send("AA; VA1000; VV2000,2000; VP0,0; VP20000,0; VE; AA ID")
    board.advance(1.0)
    board.send("VH1")
    board.advance(0.5)
    assert 0 < int(board.query("VRV")) < 2000
    board.send("VG")
    board.advance(2.0)
    assert board.query("VRV") == "2000"
    assert board.run_until_done("X", timeout=30)
    assert board.query("AA RP") == "20000,0,0,0"


def test_queue_units_stay_within_capacity_after_a_stop():
    board = MAXk("MAXk-4000")
    board.send("AA; VV1000,1000; VP0,0; VP20000,0; VP0,0; VE")
    board.advance(1.0)
    board.send("AX ST; AX MR100; GO; WT4096; MR100; GO")
    board.advance(5.0)
    assert board.query("AA RQC") == "2559,2559,2559,2559"


def test_voa_follows_an_analog_input_that_changes_with_time():
    board = MAXk("MAXk-4000")
    board.set_analog(0, lambda b: 2.5 if b.time > 1 else 0.0)
    board.send("AA; VOA0,5; VV1000,1000; VP0,0; VP20000,0; VE")
    board.advance(0.5)
    assert board.query("VRV") == "1000"
    board.advance(1.5)
    assert board.query("VRV") == "1500"


def test_a_bad_vv_changes_nothing():
    board = MAXk("MAXk-4000")
    board.send("VV1000,2000; VV500,")
    assert board.command_error
    # the next contour starts at 1000 and rises to 2000, as the good VV said (a half
    # applied VV500 would start it at 500)
    board.send("AA; VA100000; VP100000,0; VE")
    board.advance(ticks=1)
    assert board.query("VRV") == "1012"  # 1000 + 100000 counts/s^2 over one cycle
    board.advance(1.0)
    assert board.query("VRV") == "2000"


def test_a_contour_into_a_pressed_limit_is_refused_even_after_a_zero_length_start():
    board = MAXk("MAXk-4000")
    board.set_limits("X", plus=0)
    board.send("AA; VV1000,1000; VP0,0; VP20000,10000")
    board.advance(1.0)
    assert board.query("AA RP") == "0,0,0,0"
    assert board.doorbell & (1 << 8)
    assert board.board.tasks[1].contours == []

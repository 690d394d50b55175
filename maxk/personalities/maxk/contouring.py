"""Vector contouring: paths of straight lines and circular arcs at a vector velocity.

The manual's hole-cutting example (Appendix C) and the MAXv vector tasks the EPICS
trajectory scan drives (evidence 2.8) share one machine, modelled here:

- A *task* (1-8; the MAXk form without ``[n]`` is task 1) holds the definition state the
  commands set: vector acceleration (VA), start and end vector velocity (VV), the output
  action at segment starts (VIO), the velocity override (VO, or an analog input by VOA),
  hold (VH), done-on-finish (VID).
- A *contour* is what one task runs from its first VP or VC to its VE. The first VP names
  its axes. The contour takes one entry (its anchor) in each of its axes' queues, so it
  starts when every one of them is idle and has reached it, like an AA-mode GO, and the
  commands queued after it run when it has finished. Segments (VP/VC) are kept in the
  contour and hold one queue unit on each of its axes until the path has passed them
  (about 2559 segments fit, as the trajectory scan's comment says of the MAXv).
- The path is planned along its length ``s``: each segment's speed rises toward its end
  velocity (or stays at its start velocity and falls to a lower end velocity) at the
  segment's VA, never above max(start, end) x override, on arcs never above sqrt(VA R)
  (so the centripetal acceleration stays within VA too), and always able to stop at the
  end of the known path. Segments blend without stopping; the path is exact (arc points
  are computed from the centre and angle, never accumulated), each axis stands on the
  whole count its position has passed (under one count from the ideal path), and the
  contour ends on its last point exactly.
- Appending segments, changing the override, VH1 (hold) and stops re-plan from where the
  path is, at the speed it has: the path is never left, speed changes stay within VA.

Decisions (D) and inferences (I) are listed with the commands in the command table and in
docs/contouring.md.

Long module: a task, its contours and their lazily made plans (segment starts found as
the path nears them, the axes' ends set when the plan completes) are one life cycle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum
from typing import Protocol

from maxk.firmware_model.outputs import path_tick
from maxk.firmware_model.path import (
    EPS,
    ContourMotion,
    PathPlan,
    Segment,
    SegmentDef,
    plan_path,
    plan_stop,
)
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.axis import Axis, AxisHost
from maxk.personalities.maxk.waits import WAIT_REST_RETRY, Wait


class ContourHost(AxisHost, Protocol):
    """What a contour asks of the board beyond what its axes do: the done flags."""

    def set_axis_flag(self, axis: Axis, bit: int) -> None: ...
    def clear_axis_flags(self, axis: Axis, bits: int) -> None: ...


Board = ContourHost  # the contour's board, as the annotations below name it


class ContourState(Enum):
    """Where a contour is in its life."""

    WAITING = "waiting"  # defined, its axes' queues have not all reached its anchor (or VH0)
    RUNNING = "running"  # moving along the path (or ramping down for a stop or a hold)
    STARVED = "starved"  # at rest at the end of the known path, waiting for segments or VE
    HELD = "held"  # at rest after VH1, waiting for VG
    FINISHED = "finished"  # ended (done, stopped or killed): its axes' queues go on

TASKS = range(1, 9)
DEFAULT_TASK = 1
MAX_VECTOR_VELOCITY = 4_194_303.0  # VV's range: the trajectory scan clamps to this
OVERRIDE_MAX = 200.0
DEFAULT_VOA_SPAN = 5.0  # volts from 0 V to 0% or 200% (VOA channel[,span])
PULSE_TICKS = 1  # a VIO pulse (off-mask given) lasts one update cycle

# Module constants: the states are compared on every event, and a module global is read
# several times faster than an enum member through its class.
WAITING, RUNNING, STARVED, HELD, FINISHED = (
    ContourState.WAITING, ContourState.RUNNING, ContourState.STARVED, ContourState.HELD,
    ContourState.FINISHED)


# ---- tasks and contours ---------------------------------------------------------------
@dataclass
class ContourTask:
    """One vector task's definition state and its contours (the running one first)."""

    index: int
    accel: float | None = None  # VA; None: the first contour axis's AC
    v_start: float | None = None  # VV start; None: go on at the previous end velocity
    v_end: float | None = None  # VV end; None: the first contour axis's VL
    io: tuple[int, int | None, int] | None = None  # VIO on, off, mask
    hold: bool = False  # VH0: the next contour waits for VG
    done_on_finish: bool = False  # VID1
    override: float = 100.0  # VO, percent
    override_input: tuple[int, float] | None = None  # VOA channel, span (volts)
    contours: list[Contour] = field(default_factory=list)
    pulse: tuple[int, int, int] | None = None  # a VIO pulse's end: (tick, off bits, mask)

    @property
    def defining(self) -> Contour | None:
        """The contour that VP/VC/VE add to (opened by a VP, closed by VE)."""
        if self.contours and not self.contours[-1].closed:
            return self.contours[-1]
        return None

    @property
    def running(self) -> Contour | None:
        head = self.contours[0] if self.contours else None
        return head if head is not None and head.state is not WAITING else None

    def scale(self, board: Board) -> float:
        """The override as a factor: VO, or VOA's input with 0 V at 100% and the span
        either side reaching 0% and 200% (D)."""
        if self.override_input is None:
            return self.override / 100.0
        channel, span = self.override_input
        volts = board.world.analog_volts(channel, board)
        percent = 100.0 * (1.0 + volts / span)
        return min(OVERRIDE_MAX, max(0.0, percent)) / 100.0

    def next_event(self, board: Board) -> int | None:
        head = self.running
        best = head.next_event(board) if head is not None else None
        if self.pulse is not None and (best is None or self.pulse[0] < best):
            best = self.pulse[0]
        return best

    def on_event(self, board: Board) -> list[Axis]:
        if self.pulse is not None and self.pulse[0] <= board.tick:
            _tick, off, mask = self.pulse
            self.pulse = None
            Contour.drive(board, off, mask)
        head = self.running
        return head.on_event(board) if head is not None else []

    def override_changed(self, board: Board) -> None:
        head = self.running
        if head is not None and head.state is RUNNING and not head.stopping:
            head.replan(board)

    def go(self, board: Board) -> None:
        """VG: start the waiting contour, or resume a held one."""
        self.hold = False
        if not self.contours:
            return
        head = self.contours[0]
        if head.state is HELD or (head.state is RUNNING and head.stopping
                                    and not head.aborted):
            head.resume(board)  # (also during the VH1 ramp-down: it goes on from there)
        else:
            head.maybe_start(board)

    def hold_now(self, board: Board) -> None:
        """VH1: a running contour ramps down on its path and waits for VG."""
        self.hold = True
        head = self.running
        if head is not None and head.state is STARVED:
            head.state = HELD  # at rest already: it waits for VG, segments or not
        elif head is not None and head.state is RUNNING and not head.stopping:
            head.hold(board)


class ContourWait:
    """The queue wait of a contour axis standing at the contour's anchor."""

    __slots__ = ("contour",)

    def __init__(self, contour: Contour) -> None:
        self.contour = contour

    def ready(self, board: Board) -> bool:
        return self.contour.state is FINISHED


class Contour:
    """One contour of a task: its axes, its segments and where its path is."""

    def __init__(self, task: ContourTask, axes: tuple[int, ...]) -> None:
        self.task = task
        self.axes = axes
        self.defs: list[SegmentDef] = []
        self.closed = False
        # waiting (for its axes or VG) -> running / starved / held -> finished
        self.state = WAITING
        self.arrived: set[int] = set()
        self.segments: list[Segment] = []
        self.starts: list[float] = []  # the segments' s0 (the plans bisect them)
        self.last_arc = -1  # the index of the last arc among the segments (-1: none)
        self.reach: list[list[float]] = []  # per axis: the lowest and highest point
        self.current = 0  # the segment the path is in
        self.plan: PathPlan | None = None
        self.plan_tick = 0
        self.plan_end_tick: int | None = None
        self.from_rest = False
        self.stopping = False  # a hold or an abort ramp-down is running
        self.aborted = False
        # (tick, segment index), ascending: the segment starts ahead, found as the
        # path gets near them (the next to find: _bnext, up to _bstop)
        self.boundaries: list[tuple[int, int]] = []
        self._bnext = 0
        self._bstop = 0
        self._period = 0.0  # the update period the present plan was scheduled with
        self.reserved: dict[int, int] = {}  # queue units held per axis
        self.done_flag = False
        self.scale_used = 1.0  # the override the present plan was made with
        self._origin: tuple[float, ...] = ()
        self.next_poll: int | None = None  # next reading of a time-varying VOA input

    # ---- definition ------------------------------------------------------------------
    def add(self, defn: SegmentDef, board: Board) -> None:
        """A VP/VC. Every one after the first holds a unit on each axis's queue."""
        if self.defs:
            for i in self.axes:
                board.axes[i].queue.used_units += 1
                self.reserved[i] = self.reserved.get(i, 0) + 1
        self.defs.append(defn)
        if self.state is WAITING:
            return
        self._resolve_more()  # held or ramping down too: resume will plan with them
        if self.state is STARVED:
            self.state = RUNNING
            self.replan(board, from_rest=True)
        elif self.state is RUNNING and not self.stopping:
            self.replan(board)
        else:
            return
        self._refuse_if_blocked(board)

    def close(self, board: Board) -> None:
        """VE: no more segments. A contour starved at the end of its path is done."""
        self.closed = True
        if self.state is STARVED:
            self.finish(board)

    def _resolve_more(self) -> None:
        while len(self.segments) < len(self.defs):
            defn = self.defs[len(self.segments)]
            if self.segments:
                last = self.segments[-1]
                seg = Segment(defn, last.end, last.s0 + last.length, last.v_end)
            else:
                seg = Segment(defn, self._origin, 0.0, None)
                self.reach = [[x, x] for x in self._origin]
            if seg.is_arc:
                self.last_arc = len(self.segments)
                for k, c in ((0, seg.cx), (1, seg.cy)):
                    if k < len(self.reach):
                        self.reach[k][0] = min(self.reach[k][0], c - seg.radius)
                        self.reach[k][1] = max(self.reach[k][1], c + seg.radius)
            for k, x in enumerate(seg.end):
                self.reach[k][0] = min(self.reach[k][0], x)
                self.reach[k][1] = max(self.reach[k][1], x)
            self.segments.append(seg)
            self.starts.append(seg.s0)

    # ---- start -----------------------------------------------------------------------
    def arrive(self, axis: Axis, board: Board) -> Wait | None:
        """The anchor's queue action: wait for rest, then for the other axes."""
        if axis.motion is not None:
            return WAIT_REST_RETRY
        if self.state is FINISHED:
            return None
        self.arrived.add(axis.index)
        self.maybe_start(board)
        return ContourWait(self)

    def maybe_start(self, board: Board) -> None:
        task = self.task
        if (self.state is not WAITING or task.hold or not self.defs
                or task.contours[0] is not self or len(self.arrived) < len(self.axes)):
            return
        axes = [board.axes[i] for i in self.axes]
        self._origin = tuple(float(a.steps_now(board) + a.counter_offset) for a in axes)
        self._resolve_more()
        self.done_flag = task.done_on_finish
        if self.done_flag:
            for axis in axes:
                board.clear_axis_flags(axis, F.AXIS_DONE)
        self.state = RUNNING
        self.replan(board, from_rest=True)
        if self._refuse_if_blocked(board):
            return
        for axis in axes:
            axis.linked = [a for a in axes if a is not axis]
        self._segment_start(board, 0, board.tick)
        self._enter_segments(board, board.tick)

    # ---- planning --------------------------------------------------------------------
    def where(self, board: Board) -> tuple[float, float]:
        """(s, speed) of the path now (speed 0 once its axes were killed)."""
        if self.plan is None:
            return 0.0, 0.0
        s, v = self.plan.state((board.tick - self.plan_tick) * board.period)
        return (s, v) if self.followed(board) else (s, 0.0)

    def followed(self, board: Board) -> bool:
        """Does any axis still follow the present plan? (KS/KL kill them off it.)"""
        plan = self.plan
        return any(getattr(board.axes[i].motion, "plan", None) is plan for i in self.axes)

    def _index_at(self, s: float) -> int:
        i = self.current
        while (i + 1 < len(self.segments)
               and self.segments[i].s0 + self.segments[i].length <= s + EPS):
            i += 1
        return i

    def replan(self, board: Board, *, from_rest: bool = False, stop: bool = False) -> None:
        s, v = self.where(board)
        if self.plan is not None and self.plan_tick == board.tick and self.from_rest:
            from_rest = True  # nothing has moved yet: plan the start again
        i = self._index_at(s)
        scale = self.task.scale(board)
        self.scale_used = scale
        # lazy: the plan is made as far as the path gets (see _keep_ahead)
        if stop:
            plan = plan_stop(self.segments, i, s, v, scale, lazy=True, starts=self.starts,
                             last_arc=self.last_arc)
        else:
            plan = plan_path(self.segments, i, s, None if from_rest else v, scale,
                             lazy=True, starts=self.starts, last_arc=self.last_arc)
        self.plan = plan
        self.plan_tick = board.tick
        self.from_rest = from_rest and not stop
        self._period = board.period
        self.plan_end_tick = None
        # segment starts ahead (VIO, queue units): path triggers at their distances
        self.boundaries = []
        self._bnext, self._bstop = self.current + 1, len(self.segments)
        self._keep_ahead(board.tick)
        followers: list[tuple[Axis, ContourMotion]] = []
        if not plan.done:
            plan.on_complete.append(lambda: self._plan_complete(plan, followers))
        for k, index in enumerate(self.axes):
            axis = board.axes[index]
            axis._rebase(board)
            origin = float(axis.steps + axis.counter_offset)
            motion = ContourMotion(plan, k, origin)
            if self.reach:  # the whole contour's box: no switch outside it can be met
                motion.reach = (self.reach[k][0] - origin, self.reach[k][1] - origin)
            followers.append((axis, motion))
            axis.start_motion(motion, board, stopping=True)  # type: ignore[arg-type]
        if plan.done:
            self._plan_complete(plan, followers)
        self._fill_boundaries()

    def _plan_complete(self, plan: PathPlan, followers: list[tuple[Axis, ContourMotion]]
                       ) -> None:
        """The present plan is complete (made lazily, it completes as the path nears its
        end, or when something asks for all of it): the contour's and its axes' ends are
        what planning it whole at once gives."""
        if self.plan is not plan:
            return
        period = self._period
        end = plan.end_time
        self.plan_end_tick = None if end is None else (
            self.plan_tick + math.ceil(end / period - 1e-9))
        for axis, motion in followers:
            motion._set_end()
            if axis.motion is motion:
                axis.motion_end = None if motion.end_time is None else (
                    axis.motion_start + math.ceil(motion.end_time / period - 1e-9))
                axis.ramp_end = axis.motion_start + math.ceil(
                    motion.ramp_end_time / period - 1e-9)

    def _fill_boundaries(self) -> bool:
        """Find the next segment start's tick if none is pending. False: none is left."""
        if self.boundaries:
            return True
        j = self._bnext
        if j >= self._bstop or self.plan is None:
            return False
        tick = path_tick(self.plan, self.plan_tick, self._period, self.segments[j].s0)
        if tick is None:
            self._bnext = self._bstop  # the plan stops short of it, and of the rest
            return False
        self.boundaries.append((tick, j))
        self._bnext = j + 1
        return True

    def _keep_ahead(self, now: int) -> None:
        """Make the plan (lazily made) at least past the contour's next event: it cannot
        end before then, so its axes' ends are known in time (the next event makes it
        further). A plan with no segment start ahead is made to its end."""
        plan = self.plan
        if plan is None or self.state is FINISHED:
            return
        period = self._period
        while not plan.done:
            if self._fill_boundaries():
                due = max(self.boundaries[0][0], now)
                horizon = plan.horizon
                if math.isinf(horizon) or (
                        self.plan_tick + math.ceil(horizon / period - 1e-9) > due):
                    return
            plan.extend()

    def _refuse_if_blocked(self, board: Board) -> bool:
        """A path that would start an axis into a pressed limit is refused whole (as an
        MT/ML move is): the axes stay, the overtravel flag is set, the contour ends."""
        axes = [board.axes[i] for i in self.axes]
        # the cheap test first: only an axis standing on a pressed switch needs its phases
        blocked = [a for a in axes if a.motion is not None
                   and board.limit_blocks(a, a.motion.direction)
                   and a.motion.phases and a.motion.phases[0].t0 == 0.0]
        if not blocked:
            return False
        for axis in axes:
            axis.kill(board)
        for axis in blocked:
            board.refuse_into_limit(axis)
        self.aborted = True
        self.closed = True
        self.finish(board)
        return True

    def hold(self, board: Board) -> None:
        self.stopping = True
        self.replan(board, stop=True)

    def resume(self, board: Board) -> None:
        moving = self.state is RUNNING and self.where(board)[1] > 0
        self.stopping = False
        self.state = RUNNING
        self.replan(board, from_rest=not moving)
        if self._refuse_if_blocked(board):
            return
        self._enter_segments(board, board.tick)

    # ---- events ----------------------------------------------------------------------
    def next_event(self, board: Board) -> int | None:
        if self.aborted and self.state is RUNNING and not self.followed(board):
            return board.tick  # killed: finish now
        best = self.plan_end_tick if self.state is RUNNING else None
        if self._bnext < self._bstop:
            self._fill_boundaries()
        if self.boundaries and (best is None or self.boundaries[0][0] < best):
            best = self.boundaries[0][0]
        if self.state is RUNNING and self.task.override_input is not None \
                and callable(board.world.analog.get(self.task.override_input[0])):
            if self.next_poll is None or self.next_poll < board.tick:
                self.next_poll = board.tick + 1  # the analog override, every update cycle
            if best is None or self.next_poll < best:
                best = self.next_poll
        return best

    def on_event(self, board: Board) -> list[Axis]:
        now = board.tick
        if self.aborted and self.state is RUNNING and not self.followed(board):
            self.finish(board)
            return [board.axes[i] for i in self.axes]
        self._enter_segments(board, now)
        self._keep_ahead(now)
        if self.state is RUNNING and self.plan_end_tick is not None \
                and now >= self.plan_end_tick:
            self.plan_end_tick = None
            s, _v = self.where(board)
            at_end = self.segments and s >= self.segments[-1].s0 + self.segments[-1].length - 1e-6
            if self.aborted or (at_end and self.closed):
                self.finish(board)
            elif self.stopping:
                self.state = HELD
            else:
                self.state = STARVED  # waiting for more segments (or VE)
            return [board.axes[i] for i in self.axes]
        if self.next_poll is not None and self.next_poll <= now:
            self.next_poll = None
            if self.state is RUNNING and not self.stopping \
                    and abs(self.task.scale(board) - self.scale_used) > 1e-12:
                self.replan(board)
        return []

    def _enter_segments(self, board: Board, now: int) -> None:
        """Every segment start reached by now: VIO actions, queue units."""
        while self._fill_boundaries() and self.boundaries[0][0] <= now:
            _tick, j = self.boundaries.pop(0)
            for _passed in range(self.current, j):
                self._release_unit(board)
            self.current = j
            self._segment_start(board, j, now)

    def _segment_start(self, board: Board, j: int, now: int) -> None:
        io = self.segments[j].defn.io if j < len(self.segments) else None
        if io is None:
            return
        on, off, mask = io
        self.drive(board, on, mask)
        if off is not None:
            self.task.pulse = (now + PULSE_TICKS, off, mask)

    @staticmethod
    def drive(board: Board, bits: int, mask: int) -> None:
        io = board.io
        io.latch((io.outputs & ~mask) | (bits & mask), board.tick)
        board.cross_axis_event = True  # an SW may wait on an output level

    def _release_unit(self, board: Board) -> None:
        """The path has passed a segment: its queue unit is free again."""
        for i, n in self.reserved.items():
            if n > 0:
                self.reserved[i] = n - 1
                queue = board.axes[i].queue
                queue.used_units = max(0, queue.used_units - 1)

    # ---- the end -----------------------------------------------------------------------
    def withdraw(self, axis: Axis, board: Board) -> None:
        """A member's queue was flushed (ST, SA, FL, KS, SI, a limit, a reset): the
        contour is abandoned. Running, it ramps down on its path at VA (a kill after
        this stops the axes at once); not yet started, it is dropped."""
        self.reserved.pop(axis.index, None)  # the flush empties that queue's units
        if self.state is FINISHED or self.aborted:
            return
        self.aborted = True
        self.closed = True  # later VPs open a new contour
        if self.state is RUNNING:
            if not self.stopping:
                self.stopping = True
                self.replan(board, stop=True)
            board.cross_axis_event = True
            return
        self.finish(board)

    def finish(self, board: Board) -> None:
        self.state = FINISHED
        self.plan_end_tick = None
        self.boundaries = []
        self._bnext = self._bstop
        for i, n in self.reserved.items():
            queue = board.axes[i].queue
            queue.used_units = max(0, queue.used_units - n)
        self.reserved = {}
        axes = [board.axes[i] for i in self.axes]
        for axis in axes:
            axis.linked = []
        if self.done_flag and not self.aborted:
            for axis in axes:
                board.set_axis_flag(axis, F.AXIS_DONE)
        task = self.task
        if self in task.contours:
            task.contours.remove(self)
        board.cross_axis_event = True
        if task.contours:
            task.contours[0].maybe_start(board)

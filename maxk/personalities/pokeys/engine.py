"""The pulse engine's slot loop, shared by v1 and v2.

Every 1 ms slot: the limit, home, e-stop (and probe) inputs are read at the slot's start;
an enabled tripped limit or the e-stop hard-stops the engine in that very slot (no pulse
is emitted in it); otherwise each axis gets its slot's pulses from the slot buffer, from
its internal-controller motion (closed form), or from an MPG. Position counters count
exactly the pulses emitted.

``run_to`` is cheap: a stretch of slots over which no input can change (no switch edge
is crossed at a slot boundary, no timed input changes, no motion ends, the buffer does
not run dry) is emitted at once, buffered slots as one numpy block. With a slot trace
hook set, slots are emitted one by one.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import NamedTuple

import numpy as np

from maxk.firmware_model.axis import first_tick

from .axis import Axis
from .constants import GENERATING, AxisConfigBits, AxisState, EngineSpec, EngineState, SwitchBits
from .motion import SlotMotion, constant_speed
from .plans import AxisPlan, pulse_plan, segment_plan
from .slot_buffer import SlotBuffer
from .world import BenchWorld, PulseEngineWorld

HORIZON = 1 << 40
_LIMIT_N, _LIMIT_P = int(SwitchBits.LIMIT_N), int(SwitchBits.LIMIT_P)
_HOME_N, _HOME_P = int(SwitchBits.HOME_ON_LIMIT_N), int(SwitchBits.HOME_ON_LIMIT_P)
_LIMITS = _LIMIT_N | _LIMIT_P
_INVERTED, _INVERTED_HOME = int(AxisConfigBits.INVERTED), int(AxisConfigBits.INVERTED_HOME)


class SlotRecord(NamedTuple):
    """One slot as the trace sees it: pulses are signed counts, directions the pins."""

    slot: int
    pulses: tuple[int, ...]
    directions: tuple[bool, ...]
    engine_state: int
    axis_states: tuple[int, ...]


Listener = Callable[[int, str, int], None]
"""Called with (slot, event, axis or -1): 'state', 'limit', 'estop', 'homed', 'home',
'probed', 'probe_error', 'move_done', 'buffer_empty'."""


class PulseEngine:
    def __init__(self, spec: EngineSpec, world: PulseEngineWorld | None = None) -> None:
        self.spec = spec
        self.world: PulseEngineWorld = world if world is not None else BenchWorld()
        self.slot = 0
        self.state = EngineState.STOPPED
        self.axes = [Axis(i) for i in range(spec.axes)]
        self.buffer = SlotBuffer(spec.axes, spec.max_pulses_per_slot)
        self.limit_override = 0
        self.estop_polarity = 0
        self.estop_tripped = False
        self.probe_input = 0
        self.probe_polarity = 0
        self.probe_positions = [0] * spec.axes
        self.probe_status = 0
        self.state_before_probe = EngineState.STOPPED
        self.trace: Callable[[SlotRecord], None] | None = None
        self.listeners: list[Listener] = []
        # synced fast outputs (v2 0x85 0x0B): this axis's buffer column drives outputs
        self.sync_outputs_axis: int | None = None
        self.on_sync_outputs: Callable[[int], None] | None = None

    # ---- what the two engines answer differently ------------------------------------
    def active(self, axis: Axis) -> bool:
        """Does the axis generate pulses at all?"""
        raise NotImplementedError

    def consumes_buffer(self) -> bool:
        """Does the present engine state take one buffer entry per slot?"""
        raise NotImplementedError

    def buffered(self, axis: Axis) -> bool:
        """Does the axis take its pulses from the slot buffer (when it is consumed)?"""
        raise NotImplementedError

    def limits_checked(self) -> bool:
        return self.state in GENERATING

    def homing_speeds(self, axis: Axis) -> tuple[float, float]:
        """(search, return) speeds in pulses/ms."""
        raise NotImplementedError

    def mode_axis_state(self, axis: Axis) -> AxisState:
        raise NotImplementedError

    # ---- time ------------------------------------------------------------------------
    def run_to(self, slot: int) -> None:
        """Emit slots until `slot` slots have been emitted since power-up."""
        while self.slot < slot:
            self._sample()
            n = 1 if self.trace is not None else self._quiet_span(slot - self.slot)
            self._emit(n)

    def next_event(self) -> int | None:
        """Earliest slot at which something may change (a switch is reached, a move
        ends, the buffer runs dry, a timed input changes); None if nothing ever will."""
        if self._idle():
            return self.world.next_input_change(self.slot)
        n = self._quiet_span(HORIZON)
        return None if n >= HORIZON else self.slot + n

    def on_event(self, now: int) -> None:
        """As the shared engine's event source: run the slots up to `now`."""
        self.run_to(now)

    def motion_plan(self, index: int) -> AxisPlan | None:
        """The axis's motion from now as a `MotionPlan` (None: it stands still): the
        buffered slots as a step function, or its internal controller's profiles."""
        a = self.axes[index]
        if self.state not in GENERATING or not self.active(a) or self.syncs_outputs(a):
            return None
        if self.consumes_buffer() and self.buffered(a):
            rows = self.buffer.peek(self.buffer.count)
            return pulse_plan(self.slot, a.position, rows[:, index])
        return None if a.motion is None else segment_plan(a.motion)

    def syncs_outputs(self, a: Axis) -> bool:
        """Is this axis's buffer column output bits (synced fast outputs), not pulses?"""
        return a.index == self.sync_outputs_axis and self.buffered(a)

    def notify(self, event: str, axis: int = -1, slot: int | None = None) -> None:
        for listener in self.listeners:
            listener(self.slot if slot is None else slot, event, axis)

    def idle(self) -> bool:
        """Nothing will move until told: no buffer being consumed, no motion, homing or
        probing."""
        return self._idle()

    def _idle(self) -> bool:
        if self.state not in GENERATING:
            return True
        if self.state in (EngineState.PROBE, EngineState.HOMING):
            return False
        if self.consumes_buffer() and self.buffer.count:
            return False
        return not any(a.motion is not None or a.mpg_pending for a in self.axes)

    # ---- inputs at the start of a slot -------------------------------------------------
    def switch_bits(self) -> tuple[int, int, int]:
        """(limit+, limit-, home) activated bits at the present positions."""
        lim_p = lim_n = home = 0
        for a in self.axes:
            n, p, h = a.settings.tripped(self.world.switch_levels(a.index, a.stage))
            lim_n |= n << a.index
            lim_p |= p << a.index
            home |= h << a.index
        return lim_p, lim_n, home

    def _sample(self) -> None:
        lim_p, lim_n, home = self.switch_bits()
        self.estop_tripped = self.world.estop_level(self.slot) != bool(self.estop_polarity)
        if self.state not in GENERATING:
            return
        if self.estop_tripped:
            self.hard_stop(EngineState.STOP_EMERGENCY, (), all_error=True)
            self.notify("estop")
            return
        if (lim_n | lim_p) and self.limits_checked():
            tripped = [a.index for a in self.axes if self.active(a) and self._limit_stops(
                a, bool(lim_n >> a.index & 1), bool(lim_p >> a.index & 1))]
            if tripped:
                self.hard_stop(EngineState.STOP_LIMIT, tripped)
                for i in tripped:
                    self.notify("limit", i)
                return
        if self.state == EngineState.HOMING:
            self._homing_step(home)
        elif self.state == EngineState.PROBE:
            self._probing_step()
        elif self.state == EngineState.JOGGING:
            self._mpg_step()

    def _limit_stops(self, axis: Axis, lim_n: bool, lim_p: bool) -> bool:
        if self.limit_override >> axis.index & 1:
            return False
        sw = axis.settings.switches
        homing = self.state == EngineState.HOMING and axis.held_state in (
            AxisState.HOMING_START, AxisState.HOMING_SEARCH, AxisState.HOMING_BACK)
        if lim_n and sw & _LIMIT_N and not (homing and sw & _HOME_N):
            return True
        return bool(lim_p and sw & _LIMIT_P and not (homing and sw & _HOME_P))

    def hard_stop(self, state: EngineState, tripped: Iterable[int], all_error: bool = False
                  ) -> None:
        """Stop every pulse in this slot; drop motions and the buffered slots."""
        tripped = set(tripped)
        self.state = state
        for a in self.axes:
            a.motion = None
            a.mpg_pending = 0
            a.probe_limit = None
            if self.active(a):
                a.held_state = (AxisState.LIMIT if a.index in tripped
                                else AxisState.ERROR if all_error else AxisState.STOPPED)
        self.buffer.clear()
        self.notify("state")

    def _homing_step(self, home_bits: int) -> None:
        done = True
        for a in self.axes:
            held = a.held_state
            if held not in (AxisState.HOMING_START, AxisState.HOMING_SEARCH,
                            AxisState.HOMING_BACK):
                continue
            tripped = bool(home_bits >> a.index & 1)
            toward = 1 if a.settings.config & _INVERTED_HOME else -1
            search, back = self.homing_speeds(a)
            if held == AxisState.HOMING_START:
                held = AxisState.HOMING_SEARCH
                a.motion = constant_speed(a.position, self.slot, toward * search)
            if held == AxisState.HOMING_SEARCH and tripped:
                held = AxisState.HOMING_BACK
                a.motion = constant_speed(a.position, self.slot, -toward * back)
            elif held == AxisState.HOMING_BACK and not tripped:
                a.motion = None
                a.set_counter(a.home_offset)
                held = AxisState.HOME
                self.notify("home", a.index)
            a.held_state = held
            done = done and held == AxisState.HOME
        if done:
            self.state = EngineState.HOME
            self.notify("homed")

    def _probing_step(self) -> None:
        probing = [a for a in self.axes if a.held_state in (AxisState.PROBE_START,
                                                            AxisState.PROBE_SEARCH)]
        positions = [a.position for a in self.axes]
        level = self.world.probe_level(self.probe_input, self.slot, self.stages())
        if level == bool(self.probe_polarity):
            self.probe_positions = positions
            self.probe_status = 1
            for a in probing:
                a.motion, a.probe_limit, a.held_state = None, None, AxisState.PROBED
            self.state = EngineState.PROBE_COMPLETE
            self.notify("probed")
            return
        if any(a.position == a.probe_limit for a in probing):
            self.probe_status = 2
            for a in probing:
                a.motion, a.probe_limit, a.held_state = None, None, AxisState.ERROR
            self.state = EngineState.PROBE_ERROR
            self.notify("probe_error")
            return
        for a in probing:
            if a.held_state == AxisState.PROBE_START and a.probe_limit is not None:
                a.held_state = AxisState.PROBE_SEARCH
                toward = 1 if a.probe_limit > a.position else -1
                a.motion = constant_speed(a.position, self.slot, toward * self.probe_speed(a))

    def probe_speed(self, axis: Axis) -> float:
        return 0.0

    def _max_speed(self, axis: Axis) -> float:
        """The axis's maximum speed as the engine can run it, pulses/ms: at most the
        engine's own, and a host's NaN or negative setting is no speed at all (D), so
        homing, probing and MPG jogging never run the wrong way or beyond a slot."""
        setting = axis.settings.max_speed
        if not setting > 0.0:  # also NaN
            return 0.0
        return min(setting, self.spec.max_speed_per_ms)

    def _mpg_step(self) -> None:
        for a in self.axes:
            enc = a.settings.mpg_encoder
            if not enc or not self.active(a):
                continue
            count = self.world.mpg_count(enc, self.slot)
            if a.mpg_last is not None:
                a.mpg_pending += (count - a.mpg_last) * a.settings.mpg_multiplier
            a.mpg_last = count

    # ---- how many slots can go at once -----------------------------------------------
    def _quiet_span(self, limit: int) -> int:
        s = self.slot
        n = limit
        t = self.world.next_input_change(s)
        if t is not None:
            n = min(n, t - s)
        if n <= 1 or self.state == EngineState.PROBE:
            return 1
        if self.state not in GENERATING:
            return n
        if any(a.mpg_pending for a in self.axes):
            return 1
        consuming = self.consumes_buffer()
        fed: list[Axis] = []
        for a in self.axes:
            if not self.active(a):
                continue
            if consuming and self.syncs_outputs(a):
                continue  # output bits: no switch is ever reached
            if consuming and self.buffered(a):
                fed.append(a)
            elif a.motion is not None:
                end = a.motion.end_slot()
                if end is not None and end > s:
                    n = min(n, end - s)
                n = self._motion_span(a, a.motion, n)
                if n <= 1:
                    return 1
        if fed and self.buffer.count:
            n = self._buffered_span(fed, min(n, self.buffer.count))
            n = self._backlash_buffered_span(fed, n)
        return max(n, 1)

    def _backlash_buffered_span(self, fed: list[Axis], n: int) -> int:
        """With backlash compensation, the register moves only while the direction holds:
        a stretch ends before the first slot against the settled direction, and a slot
        whose register is still on its way runs alone (the stage moves by more than the
        counter then)."""
        compensated = [a for a in fed if a.backlash_width]
        if not compensated:
            return n
        rows = self.buffer.peek(n)
        for a in compensated:
            column = rows[:, a.index]
            moving = np.nonzero(column)[0]
            if not len(moving):
                continue
            first = int(moving[0])
            d = 1 if column[first] > 0 else -1
            if not a.backlash_settled(d):
                return max(first, 1)  # up to the first pulse, then slot by slot
            against = np.nonzero(column * d < 0)[0]
            if len(against):
                n = min(n, max(int(against[0]), 1))
        return n

    def _buffered_span(self, fed: list[Axis], n: int) -> int:
        """Slots of the buffer that run before a buffered axis crosses a switch edge at a
        slot boundary (that slot included) or would pass a soft limit (that slot not)."""
        reach = n * self.spec.max_pulses_per_slot  # no axis can travel farther in n slots
        up: list[int] = []
        down: list[int] = []
        near = False
        for a in fed:
            e_up, e_down = self._edges(a)
            up.append(HORIZON if e_up is None else e_up)
            down.append(HORIZON if e_down is None else e_down)
            st = a.settings
            near = near or up[-1] <= reach or down[-1] <= reach or (st.soft_limits and (
                st.soft_limit_max - a.position < reach or a.position - st.soft_limit_min < reach))
        if not near:
            return n
        rows = self.buffer.peek(n)
        if len(fed) < rows.shape[1]:
            rows = rows[:, [a.index for a in fed]]
        cum = np.cumsum(rows, axis=0)
        hits = ((cum >= np.array(up)) | (cum <= -np.array(down))).any(axis=1)
        if hits.any():
            n = min(n, int(np.argmax(hits)) + 1)  # the crossing slot itself still runs
        soft = [i for i, a in enumerate(fed) if a.settings.soft_limits]
        if soft:
            pos = cum[:n, soft] + np.array([fed[i].position for i in soft])
            lo = np.array([fed[i].settings.soft_limit_min for i in soft])
            hi = np.array([fed[i].settings.soft_limit_max for i in soft])
            out = ((pos > hi) | (pos < lo)).any(axis=1)
            if out.any():
                n = min(n, int(np.argmax(out)))  # the clipped slot runs alone
        return n

    def _switches_act(self, a: Axis) -> bool:
        """Can a switch edge change anything for this axis? Only an enabled limit, or the
        home input while homing (the status reads levels when asked, needing no event)."""
        return self.state == EngineState.HOMING or bool(a.settings.switches & _LIMITS)

    def _edges(self, a: Axis) -> tuple[int | None, int | None]:
        if not self._switches_act(a):
            return None, None
        return (self.world.next_switch_edge(a.index, a.stage, 1),
                self.world.next_switch_edge(a.index, a.stage, -1))

    def _motion_span(self, a: Axis, motion: SlotMotion, n: int) -> int:
        s, p0 = self.slot, a.position
        dirs = motion.directions(s, s + n)
        if len(dirs) > 1:  # a reversal ahead: the stretch up to it travels one way
            both = first_tick(lambda k: len(motion.directions(s, k)) > 1, s + 1, s + n)
            if both is None or both - 1 == s:
                return 1
            n = both - 1 - s
            dirs = motion.directions(s, both - 1)
        if not dirs:
            return n
        d = dirs.pop()
        if not a.backlash_settled(d):
            return 1  # the register is taking up the play: slot by slot
        edge = self.world.next_switch_edge(a.index, a.stage, d) if self._switches_act(a) \
            else None
        if edge is not None:
            k = first_tick(lambda k: (motion.position_at(k) - p0) * d >= edge, s + 1, s + n)
            if k is not None:
                n = min(n, k - s)
        if a.settings.soft_limits:
            bound = a.settings.soft_limit_max if d > 0 else a.settings.soft_limit_min
            k = first_tick(lambda k: (motion.position_at(k) - bound) * d > 0, s + 1, s + n)
            if k is not None:
                n = min(n, k - s - 1)
        return max(n, 1)

    # ---- emitting slots ---------------------------------------------------------------
    def _emit(self, n: int) -> None:
        s = self.slot
        generating = self.state in GENERATING
        consuming = generating and self.consumes_buffer()
        rows = self.buffer.pop(n) if consuming and self.buffer.count else None
        sums: list[int] = []
        last: list[int] = []
        if rows is not None:
            sums = rows.sum(axis=0).tolist()
            # The last nonzero pulse count of each column (0 if none) sets its direction pin.
            at = len(rows) - 1 - np.argmax(rows[::-1] != 0, axis=0)
            last = rows[at, np.arange(rows.shape[1])].tolist()
        m = self.spec.max_pulses_per_slot
        pulses = [0] * self.spec.axes
        for a in self.axes:
            if not generating or not self.active(a):
                continue
            p0 = a.position
            step = 0
            if consuming and self.syncs_outputs(a):
                if rows is not None and self.on_sync_outputs is not None:
                    self.on_sync_outputs(int(rows[-1, a.index]))  # the span's last slot
                continue
            if consuming and self.buffered(a):
                if rows is None:
                    continue
                new = p0 + sums[a.index]
                step = last[a.index]
            elif a.motion is not None:
                new = a.motion.position_at(s + n)
            elif a.mpg_pending:
                cap = min(m, max(1, int(self._max_speed(a))))
                new = p0 + max(-cap, min(cap, a.mpg_pending))
                a.mpg_pending -= new - p0
            else:
                continue
            if n == 1:
                new = self._clip_single(a, new)
            if new != p0 or step:
                self._direction(a, step or new - p0)
                a.position = new
                pulses[a.index] = new - p0
                moved = new - p0 or step
                a.take_up_backlash(1 if moved > 0 else -1, n)
        self.slot = s + n
        ended: list[tuple[int, int, int]] = []
        for a in self.axes:
            if a.motion is not None:
                end = a.motion.end_slot()
                if end is not None and end <= self.slot:
                    a.motion = None
                    # told in the order slot by slot would tell them: a motion that had
                    # already ended (a move to where the axis stood) after the first slot
                    ended.append((max(end, s + 1), a.index, end))
        for _told, index, end in sorted(ended):
            self.notify("move_done", index, end)
        if rows is not None and self.buffer.count == 0:
            self.notify("buffer_empty", -1, self.slot)
        if self.trace is not None:
            self.trace(SlotRecord(s, tuple(pulses), tuple(a.direction_out for a in self.axes),
                                  int(self.state), tuple(int(x) for x in self.axis_states())))

    def _clip_single(self, a: Axis, new: int) -> int:
        """Soft limits and the probing max position stop an axis exactly on the bound."""
        st = a.settings
        if st.soft_limits and not st.soft_limit_min <= new <= st.soft_limit_max:
            new = max(st.soft_limit_min, min(st.soft_limit_max, new))
            a.motion = None
            a.mpg_pending = 0
        if a.probe_limit is not None:
            lo, hi = sorted((a.position, a.probe_limit))
            new = max(lo, min(hi, new))
        return new

    def _direction(self, a: Axis, step: int) -> None:
        a.direction_out = (step < 0) != bool(a.settings.config & _INVERTED)

    # ---- status ------------------------------------------------------------------------
    def axis_states(self) -> list[AxisState]:
        return [self.axis_state(a) for a in self.axes]

    def axis_state(self, a: Axis) -> AxisState:
        if a.held_state is not None:
            return a.held_state
        if not self.active(a):
            return AxisState.STOPPED
        return self.mode_axis_state(a)

    def moving(self, a: Axis) -> bool:
        if a.motion is not None:
            end = a.motion.end_slot()
            return end is None or end > self.slot
        return False

    def positions(self) -> list[int]:
        return [a.position for a in self.axes]

    def stages(self) -> list[int]:
        """Physical positions (where the switches see the axes)."""
        return [a.stage for a in self.axes]



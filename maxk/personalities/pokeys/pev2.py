"""Pulse engine v2 (PoKeys57E, PoKeys57CNC): 8 axes, RUNNING with each axis either fed
from the slot buffer or driven by its own internal controller (separate buffers, so the
two mix freely), homing, probing, MPG jogging, soft limits (seed v2, reference 6-9)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .axis import Axis, AxisSettings
from .constants import PEV2, AxisState, EngineState
from .engine import PulseEngine
from .motion import plan_position, plan_speed
from .world import PulseEngineWorld

SETTABLE_STATES = frozenset({EngineState.STOPPED, EngineState.RUNNING, EngineState.JOGGING})


class PulseEngineV2(PulseEngine):
    def __init__(self, world: PulseEngineWorld | None = None) -> None:
        super().__init__(PEV2, world)
        self.enabled_axes = 0  # PulseEngineEnabled: axes 0..n-1 take part
        self.activated = 1
        self.charge_pump = 0
        self.generator_type = 0
        self.buffer_size_setting = 0
        self.axis_enabled_states_mask = 0
        self.axis_enable_mask = 0
        self.estop_pin = 0
        self.external_relays = 0
        self.external_oc = 0
        self.probe_fraction = 0.0

    # ---- engine answers -----------------------------------------------------------------
    def active(self, axis: Axis) -> bool:
        return axis.index < self.enabled_axes and bool(axis.settings.config & 1)

    def consumes_buffer(self) -> bool:
        return self.state == EngineState.RUNNING

    def buffered(self, axis: Axis) -> bool:
        return not axis.settings.internal

    def homing_speeds(self, axis: Axis) -> tuple[float, float]:
        search = self._max_speed(axis) * (axis.settings.homing_speed or 10) / 100.0
        return search, search * (axis.settings.homing_return_speed or 50) / 100.0

    def probe_speed(self, axis: Axis) -> float:
        return self._max_speed(axis) * self.probe_fraction

    def mode_axis_state(self, axis: Axis) -> AxisState:
        if self.state == EngineState.RUNNING:
            busy = self.moving(axis) if axis.settings.internal else self.buffer.count > 0
            return AxisState.RUNNING if busy else AxisState.READY
        if self.state == EngineState.JOGGING:
            return AxisState.RUNNING if axis.mpg_pending else AxisState.READY
        return AxisState.STOPPED

    # ---- commands -----------------------------------------------------------------------
    def setup(self, enabled_axes: int, charge_pump: int, generator_type: int, buffer_size: int,
              estop_polarity: int, enabled_states_mask: int) -> None:
        self.enabled_axes = min(enabled_axes, self.spec.axes)
        self.charge_pump = charge_pump
        self.generator_type = generator_type
        self.buffer_size_setting = buffer_size
        self.estop_polarity = estop_polarity
        self.axis_enabled_states_mask = enabled_states_mask

    def set_state(self, state: int, limit_override: int, axis_enable_mask: int) -> bool:
        """PulseEngineStateSet; False if the state cannot be set by the host."""
        if state not in SETTABLE_STATES:
            return False
        self.limit_override = limit_override
        self.axis_enable_mask = axis_enable_mask
        self._enter(EngineState(state))
        return True

    def _enter(self, state: EngineState) -> None:
        if state == self.state:
            return
        self.state = state
        for a in self.axes:
            a.motion, a.target, a.held_state, a.probe_limit = None, None, None, None
            a.mpg_last, a.mpg_pending = None, 0
        self.notify("state")

    def set_positions(self, mask: int, values: Sequence[int]) -> None:
        """PositionSet: a moving axis keeps moving; its counter is shifted."""
        for a in self.axes:
            if mask >> a.index & 1:
                delta = values[a.index] - a.position
                a.set_counter(values[a.index])
                if a.motion is not None:
                    for i, seg in enumerate(a.motion.segments):
                        a.motion.segments[i] = type(seg)(seg.start, seg.origin + delta, seg.motion)
                    if a.target is not None and a.settings.position_mode:
                        a.target += delta

    def configure_axis(self, index: int, settings: AxisSettings) -> None:
        a = self.axes[index]
        if a.settings.internal != settings.internal:
            a.motion, a.target = None, None
        a.settings = settings

    def move(self, values: Sequence[float], mask: int = 0xFF,
             fractions: Sequence[float] | None = None) -> None:
        """PulseEngineMove(PV): internal-controller axes go to a position or run at a
        speed (pulses/s); other axes and other engine states ignore it."""
        if self.state != EngineState.RUNNING:
            return
        for a in self.axes:
            if not (mask >> a.index & 1) or not self.active(a) or not a.settings.internal:
                continue
            st = a.settings
            fraction = 1.0 if fractions is None else fractions[a.index]
            if fraction <= 0:
                continue
            if st.position_mode:
                target = int(values[a.index])
                if st.soft_limits:
                    target = max(st.soft_limit_min, min(st.soft_limit_max, target))
                if target == a.target and (a.motion is not None or a.position == target):
                    continue
                a.motion = plan_position(a.motion, a.position, self.slot, target,
                                         self._max_speed(a), st.max_acceleration,
                                         st.max_deceleration, fraction)
            else:
                speed = float(values[a.index])
                if speed == a.target:
                    continue
                a.motion = plan_speed(a.motion, a.position, self.slot, speed,
                                      self._max_speed(a), st.max_acceleration,
                                      st.max_deceleration)
            a.target = values[a.index]

    def fill(self, entries: np.ndarray) -> int:
        """Buffer fill: rows of signed pulses for axes 0..AX-1 (the synced-outputs axis:
        its raw output bits); returns slots accepted."""
        return self.buffer.accept(entries, self.sync_outputs_axis)

    def clear_buffer(self) -> None:
        self.buffer.clear()

    def reboot(self) -> None:
        """The pulse engine restarts: stopped, empty buffer, counters at 0, settings kept."""
        self._enter(EngineState.STOPPED)
        self.buffer.clear()
        for a in self.axes:
            a.set_counter(0)

    def homing_start(self, mask: int, offsets: Sequence[int]) -> None:
        homing = [a for a in self.axes if mask >> a.index & 1 and self.active(a)]
        if not any(a.settings.homing_input_available() for a in homing):
            return
        self._enter(EngineState.HOMING)
        for a in homing:
            a.home_offset = offsets[a.index]
            a.held_state = (AxisState.HOMING_START if a.settings.homing_input_available()
                            else AxisState.ERROR)

    def homing_finish(self, state: int) -> bool:
        if state not in SETTABLE_STATES:
            return False
        self._enter(EngineState(state))
        return True

    def probing_start(self, mask: int, max_positions: Sequence[int], speed: float,
                      probe_input: int, polarity: int) -> None:
        probing = [a for a in self.axes if mask >> a.index & 1 and self.active(a)]
        if not probing:
            return
        before = self.state
        self._enter(EngineState.PROBE)
        self.state_before_probe = before
        self.probe_fraction = max(0.0, min(1.0, speed))
        self.probe_input, self.probe_polarity, self.probe_status = probe_input, polarity, 0
        for a in probing:
            a.held_state = AxisState.PROBE_START
            a.probe_limit = max_positions[a.index]

    def probing_finish(self) -> tuple[list[int], int]:
        """Probe positions and status (0 none, 1 probed, 2 max position reached); the
        engine returns to the state it had before probing."""
        result = (list(self.probe_positions), self.probe_status)
        if self.state in (EngineState.PROBE, EngineState.PROBE_COMPLETE,
                          EngineState.PROBE_ERROR):
            self._enter(self.state_before_probe)
        return result

    def soft_limit_bits(self) -> int:
        bits = 0
        for a in self.axes:
            st = a.settings
            if st.soft_limits and self.active(a) and not (
                    st.soft_limit_min < a.position < st.soft_limit_max):
                bits |= 1 << a.index
        return bits

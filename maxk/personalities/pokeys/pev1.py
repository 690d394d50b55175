"""Pulse engine v1 (PoKeys56E): 3 axes, at most 25 pulses per slot, one engine-wide
mode (stopped, internal controller, buffer, jogging, homing) (seed v1, reference 10).

The internal controller works through the slot buffer too, planning LOOKAHEAD slots
ahead: so after internal mode the buffer may still hold up to 10 ms of its motion, which
runs first in buffer mode unless the host waits 10 ms or clears the buffer (the seed's
rule). Jogging ignores the limit switches.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .axis import Axis
from .constants import PEV1, AxisConfigBits, AxisState, EngineState
from .engine import PulseEngine
from .motion import plan_position, plan_speed
from .world import PulseEngineWorld

LOOKAHEAD = 10
"""Slots the v1 internal controller writes ahead into the buffer (the seed's 10 ms)."""

SETTABLE_STATES = frozenset({EngineState.STOPPED, EngineState.INTERNAL, EngineState.BUFFER,
                             EngineState.JOGGING})
CONTROLLER_STATES = frozenset({EngineState.INTERNAL, EngineState.JOGGING})


class PulseEngineV1(PulseEngine):
    def __init__(self, world: PulseEngineWorld | None = None) -> None:
        super().__init__(PEV1, world)
        self.enabled = 1
        self.charge_pump = 0
        self.homing_speed = 10  # % of max speed (seed: 10 %)
        self.homing_return_speed = 1  # % of max speed (seed: 1 %)
        self.kb48cnc = 0
        self.mpg_config = bytearray(16)  # 0x03: [8] on, [9..20] multipliers, [21..23] encoders
        for a in self.axes:
            a.settings.config = int(AxisConfigBits.ENABLED)

    # ---- engine answers -----------------------------------------------------------------
    def active(self, axis: Axis) -> bool:
        return self.enabled != 0

    def consumes_buffer(self) -> bool:
        return self.state == EngineState.BUFFER

    def buffered(self, axis: Axis) -> bool:
        return True

    def limits_checked(self) -> bool:
        return super().limits_checked() and self.state != EngineState.JOGGING

    def homing_speeds(self, axis: Axis) -> tuple[float, float]:
        top = self._max_speed(axis)
        return top * self.homing_speed / 100.0, top * self.homing_return_speed / 100.0

    def mode_axis_state(self, axis: Axis) -> AxisState:
        if self.state in CONTROLLER_STATES:
            return AxisState.RUNNING if self.moving(axis) else AxisState.READY
        if self.state == EngineState.BUFFER:
            return AxisState.RUNNING if self.buffer.count else AxisState.READY
        return AxisState.STOPPED

    # ---- commands -----------------------------------------------------------------------
    def set_state(self, state: int) -> bool:
        if state not in SETTABLE_STATES:
            return False
        new = EngineState(state)
        if new == self.state:
            return True
        if self.state in CONTROLLER_STATES:
            self._flush_lookahead()
        if new in CONTROLLER_STATES:
            self.buffer.clear()  # the internal controller takes the buffer over
        self.state = new
        for a in self.axes:
            a.motion, a.target, a.held_state = None, None, None
        self.notify("state")
        return True

    def lookahead(self) -> int:
        """Slots of internal-controller motion already sitting in the buffer."""
        if self.state not in CONTROLLER_STATES:
            return 0
        ahead = 0
        for a in self.axes:
            if self.moving(a) and a.motion is not None:
                end = a.motion.end_slot()
                ahead = max(ahead, LOOKAHEAD if end is None else min(LOOKAHEAD, end - self.slot))
        return ahead

    def _flush_lookahead(self) -> None:
        ahead = self.lookahead()
        if not ahead:
            return
        rows = np.zeros((ahead, self.spec.axes), dtype=np.int32)
        for a in self.axes:
            if a.motion is not None:
                pos = [a.motion.position_at(self.slot + j) for j in range(ahead + 1)]
                rows[:, a.index] = np.diff(pos)
        self.buffer.accept(rows)

    def free_slots(self) -> int:
        return self.buffer.free - self.lookahead()

    def move(self, values: Sequence[int], speed_mask: int = 0) -> None:
        """Internal mode: positions (axes in speed_mask: speeds in pulses/s); jogging:
        speeds. Other states ignore it."""
        if self.state not in CONTROLLER_STATES or not self.enabled:
            return
        for a in self.axes:
            st = a.settings
            value = values[a.index]
            if self.state == EngineState.JOGGING or speed_mask >> a.index & 1:
                if float(value) == a.target and a.motion is not None:
                    continue
                a.motion = plan_speed(a.motion, a.position, self.slot, float(value),
                                      self._max_speed(a), st.max_acceleration,
                                      st.max_deceleration)
            else:
                if value == a.target and (a.motion is not None or a.position == value):
                    continue
                a.motion = plan_position(a.motion, a.position, self.slot, int(value),
                                         self._max_speed(a), st.max_acceleration,
                                         st.max_deceleration)
            a.target = value

    def fill(self, entries: np.ndarray) -> int:
        """Buffer fill; while the internal controller owns the buffer nothing is taken."""
        if self.state in CONTROLLER_STATES:
            return 0
        return self.buffer.accept(entries)

    def clear_buffer(self) -> None:
        self.buffer.clear()

    def set_positions(self, values: Sequence[int]) -> None:
        for a in self.axes:
            a.set_counter(values[a.index])
            a.motion, a.target = None, None

    def homing_start(self, flags: Sequence[int]) -> None:
        homing = [a for a in self.axes if flags[a.index]]
        if not homing or not self.enabled:
            return
        self.buffer.clear()  # homing is a hard change of mode: nothing queued survives
        self.state = EngineState.HOMING
        for a in self.axes:
            a.motion, a.target, a.held_state = None, None, None
        for a in homing:
            a.home_offset = 0
            a.held_state = (AxisState.HOMING_START if a.settings.homing_input_available()
                            else AxisState.ERROR)
        if all(a.held_state == AxisState.ERROR for a in homing):
            self.state = EngineState.STOPPED
        self.notify("state")

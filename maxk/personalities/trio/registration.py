"""Registration of the MC405 as the REGIST help page gives it: MARK/REG_POS/REGIST_SPEED
(channel A), MARKB/REG_POSB/REGIST_SPEEDB (channel B) and the time-based channels
R_MARK/R_REGPOS/R_REGISTSPEED(0..7), on the world's index marks and inputs.

A capture latches the count at the edge itself: a Z mark (the world's index marks of the
axis, every `index_period` counts from `index_offset`, `index_width` wide) is found on the
axis's own motion by the shared bisection (`tick_reaching`), on a linked axis (CONNECT,
CAMBOX, ADDAX ...) by a bisection of its demand up to the next motion event; REG_POS is
then the mark's exact count and MARK turns TRUE on the servo tick the axis reaches it. An
input edge (the R inputs, any digital input, the time-based channels) is captured on the
tick the world changes the input, at the position the axis has then (D: the world's
inputs change on servo ticks, so the time-based interpolation has nothing between).

- **Modes 1..17** (C: page): 1/2 Z rising/falling into REG_POS, 3/4 the first R input
  (RA) rising/falling; 6..9 RA rising/falling into REG_POS with Z rising/falling into
  REG_POSB, 10..13 RA and the second R input (RB) likewise; 14/15 Z and 16/17 RB into
  REG_POSB only. + 256 / + 768: only edges inside / outside OPEN_WIN..CLOSE_WIN. RA and RB
  are the inputs REG_INPUTS names (bits 0..3 and 4..7; MC405 power-up: axis n's inputs n
  and n + 4 modulo 8, C for axes 0..4, D beyond). Mode 5 (reserved) and 18, 19 are
  refused (D).
- **Mode 20**(channel, source, edge, window[, quantity, table start]): channel 0 A, 1 B;
  source 0 the first R input, 1 the Z mark, 2 the second R input, 4 digital input
  `channel` (into channel A); windows 1/2 OPEN_WIN..CLOSE_WIN inside/outside, 5/6
  OPEN_WINB..CLOSE_WINB (REGIST page, modes 20 and 21), 3/4 only while the gate input
  (channel bits 16 and up) is high/low; quantity captures go to TABLE(table start ...)
  and MARK reads minus the count so far (C: MARK page).
- **Mode 21**(channel 0..7, source, edge, window[, quantity, table start]): the
  time-based channel of the axis on input `channel` (source 256 + n: input n), read with
  R_MARK(channel) etc.
- Mode 0 cancels every channel of the axis; 23/24 (input pulse width) are accepted with
  no effect: the world's edges are clean (D); 22 (Flexaxis) and 32..71 (the older time
  modes) are refused (D).

A channel is armed until its capture (or its quantity) is done (C: REGIST again to
re-arm); arming one channel leaves the other armed (C for mode 20, D for the older
modes). REGIST_SPEED is the demand's change over the servo cycle before the capture, in
user units per ms, signed (D). An encoder axis (ATYPE 76 ...) whose input the world
mounts on another axis's motor captures on that encoder's counts (the stage's shaft: I,
a calibration stage homes this way, REGIST(20, 0, 1, 0, 0) on the encoder axis while
the stepper moves). Links that start on a registration event (CAMBOX,
MOVELINK options 1, 256 and 512) start from the captured position (`links.py`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from maxk.firmware_model.axis import first_tick
from maxk.firmware_model.outputs import next_periodic_marks


@dataclass
class Capture:
    """One armed registration channel of an axis."""

    source: str  # "Z" (index marks) or "R" (a digital input)
    rising: bool
    input: int = -1  # R: the digital input
    level: bool = False  # the R input's level when armed (its edges are changes)
    window: int = 0  # 0 none, 1 inside OPEN_WIN..CLOSE_WIN, 2 outside, 3/4 gate high/low,
    # 5/6 inside/outside OPEN_WINB..CLOSE_WINB (REGIST page, modes 20 and 21)
    gate: int = -1  # windows 3/4: the gate input
    quantity: int = 0  # captures into TABLE (0: one capture into the mark)
    table_start: int = 0
    count: int = 0


@dataclass
class Channel:
    """What a channel captured: MARK (0 FALSE, -1 TRUE, -n n captures to TABLE), the
    position (user units, DEFPOS applied) and the speed (user units per ms)."""

    mark: float = 0.0
    position: float = 0.0
    speed: float = 0.0


@dataclass
class AxisRegistration:
    armed: dict[str, Capture] = field(default_factory=dict)  # "A", "B", "R0".."R7"
    channels: dict[str, Channel] = field(default_factory=dict)

    def channel(self, key: str) -> Channel:
        return self.channels.setdefault(key, Channel())


WINDOW_SEARCH = 10000
"""Index marks looked at, each way, for the next one a window takes (D: a bound)."""

# (channel, source, rising, R input: 0 the first REG_INPUTS input, 1 the second)
MODES: dict[int, list[tuple[str, str, bool, int]]] = {
    1: [("A", "Z", True, 0)], 2: [("A", "Z", False, 0)],
    3: [("A", "R", True, 0)], 4: [("A", "R", False, 0)],
    **{6 + k: [("A", "R", k < 2, 0), ("B", "Z", k % 2 == 0, 0)] for k in range(4)},
    **{10 + k: [("A", "R", k < 2, 0), ("B", "R", k % 2 == 0, 1)] for k in range(4)},
    14: [("B", "Z", True, 0)], 15: [("B", "Z", False, 0)],
    16: [("B", "R", True, 1)], 17: [("B", "R", False, 1)],
}
EVENTS = {"A": "MARK", "B": "MARKB"}  # a channel's event for the links (R_MARKn else)
READS = {"MARK": ("A", "mark"), "MARKB": ("B", "mark"), "REG_POS": ("A", "position"),
         "REG_POSB": ("B", "position"), "REGIST_SPEED": ("A", "speed"),
         "REGIST_SPEEDB": ("B", "speed"), "R_MARK": ("R", "mark"),
         "R_REGPOS": ("R", "position"), "R_REGISTSPEED": ("R", "speed")}
TIME_CHANNELS = 8  # R_MARK(0..7) (C: page)
INPUTS = 1024  # input numbers a capture may watch (as IN)


def default_inputs(axis: int) -> int:
    """REG_INPUTS at power-up: the MC405's axis n takes inputs n and n + 4 (modulo 8)
    (C for axes 0..4: REG_INPUTS page; the virtual axes likewise, D)."""
    return (axis % 8) | ((axis + 4) % 8) << 4


class Registration:
    """The machine's registration channels: an event source for Z-mark captures."""

    def __init__(self, machine: Any) -> None:
        self.m = machine
        self._cache: tuple[int, int | None, list[tuple[int, str, float]]] = (-1, None, [])
        self.reset()

    def reset(self) -> None:
        self.axes = [AxisRegistration() for _ in range(self.m.axis_count)]
        for axis, a in enumerate(self.m.axes):
            a.params["REG_INPUTS"] = float(default_inputs(axis))

    # ---- the program's side ------------------------------------------------------------
    def regist(self, axis: int, args: list[float]) -> None:
        """REGIST(mode[, ...]) AXIS(n): every argument checked before anything is armed."""
        if not args or any(a != int(a) for a in args):
            raise ValueError("Parameter out of range")
        mode = int(args[0])
        reg = self.axes[axis]
        if mode in (20, 21):
            key, capture = self._newer(axis, mode, [int(a) for a in args[1:]])
            self._arm(axis, {key: capture})
            return
        if len(args) > 1:
            raise ValueError("Parameter out of range")
        if mode == 0:
            reg.armed.clear()
            self.m.changed()
            return
        if mode in (23, 24):
            return  # the minimum pulse width: the world's edges are clean (D)
        window = {256: 1, 768: 2}.get(mode & 768, 0) if mode > 255 else 0
        mode = mode & 255 if window else mode
        if mode not in MODES or (window == 0 and args[0] > 255):
            raise ValueError("Parameter out of range")
        captures = {}
        for channel, source, rising, which in MODES[mode]:
            number = self._reg_input(axis, which) if source == "R" else -1
            captures[channel] = Capture(source, rising, number, window=window)
        self._arm(axis, captures)

    def _newer(self, axis: int, mode: int, args: list[int]) -> tuple[str, Capture]:
        """REGIST(20|21, channel, source, edge[, window[, quantity, table start]])."""
        if not 3 <= len(args) <= 6 or len(args) == 5:
            raise ValueError("Parameter out of range")
        channel, source, edge = args[0], args[1], args[2]
        window = args[3] if len(args) > 3 else 0
        quantity, start = (args[4], args[5]) if len(args) == 6 else (0, 0)
        gate, channel = channel >> 16, channel & 0xFFFF
        if channel < 0 or edge not in (0, 1) or not 0 <= window <= 6 or quantity < 0 \
                or start < 0 or start + quantity > self.m.table.size \
                or not 0 <= gate < INPUTS:  # bits 16 up: an input, used by windows 3/4
            raise ValueError("Parameter out of range")
        if mode == 21:
            number = channel if source == 0 else source - 256 if 256 <= source < 256 + \
                INPUTS else -1
            if channel >= TIME_CHANNELS or number < 0:
                raise ValueError("Parameter out of range")
            key, kind = f"R{channel}", "R"
        elif source == 4:
            if channel >= INPUTS:
                raise ValueError("Parameter out of range")
            key, kind, number = "A", "R", channel
        else:
            if channel not in (0, 1) or source not in (0, 1, 2):
                raise ValueError("Parameter out of range")
            key = "AB"[channel]
            kind = "Z" if source == 1 else "R"
            number = self._reg_input(axis, source // 2) if kind == "R" else -1
        return key, Capture(kind, edge == 0, number, window=window,
                            gate=gate if window in (3, 4) else -1, quantity=quantity,
                            table_start=start)

    def _reg_input(self, axis: int, which: int) -> int:
        value = int(self.m.axes[axis].params["REG_INPUTS"])
        return (value >> (4 * which)) & 15

    def _arm(self, axis: int, captures: dict[str, Capture]) -> None:
        reg = self.axes[axis]
        for key, capture in captures.items():
            if capture.source == "R":
                capture.level = self._input(capture.input)
            reg.armed[key] = capture
            reg.channel(key).mark = 0.0  # MARK is reset by REGIST (C)
        self.m.changed()

    def read(self, name: str, axis: int, channel: int | None = None) -> float:
        """MARK, REG_POS, REGIST_SPEED (and B), R_MARK(channel) ..., REGIST_CONTROL."""
        reg = self.axes[axis]
        if name == "REGIST_CONTROL":
            return float(self.control(axis))
        key, field_name = READS[name]
        if key == "R":
            if channel is None or not 0 <= channel < TIME_CHANNELS:
                raise ValueError("Parameter out of range")
            key = f"R{channel}"
        state = reg.channels.get(key)
        return 0.0 if state is None else float(getattr(state, field_name))

    def control(self, axis: int) -> int:
        """REGIST_CONTROL: per channel (A bits 0..3, B 4..7) input (1) or Z (0), enable,
        falling (1) (C: page) of what is armed now."""
        value = 0
        for shift, key in ((0, "A"), (4, "B")):
            cap = self.axes[axis].armed.get(key)
            if cap is not None:
                value |= ((cap.source == "R") | 4 | (0 if cap.rising else 8)) << shift
        return value

    def write_control(self, axis: int, value: float) -> None:
        """REGIST_CONTROL = v: a channel whose enable bit is 0 is disarmed; one enabled
        as it already is stays as it is; otherwise it is armed as the bits say, on its
        REG_INPUTS input or the Z mark (D: the page gives the bits only)."""
        if value != int(value) or not 0 <= value < 256:
            raise ValueError("Parameter out of range")
        bits, reg = int(value), self.axes[axis]
        now = self.control(axis)
        arm = {}
        for shift, key in ((0, "A"), (4, "B")):
            own = (bits >> shift) & 15
            if not own & 4:
                reg.armed.pop(key, None)
            elif own & 13 != (now >> shift) & 13:
                source = "R" if own & 1 else "Z"
                number = self._reg_input(axis, shift // 4) if source == "R" else -1
                arm[key] = Capture(source, not own & 8, number)
        self._arm(axis, arm)

    def captured(self, axis: int, event: str) -> float | None:
        """The position (user units) of a capture already made on the axis for a link
        waiting on `event` (MARK, MARKB, R_MARKn); None when there is none."""
        key = {"MARK": "A", "MARKB": "B"}.get(event, "R" + event[6:])
        state = self.axes[axis].channels.get(key)
        return state.position if state is not None and state.mark != 0 else None

    # ---- the world's side --------------------------------------------------------------
    def _input(self, number: int) -> bool:
        world = self.m.world
        return world.digital_level(number, self.m) if number in world.digital else False

    def world_changed(self) -> None:
        """An input changed: an armed input capture whose edge this is latches now."""
        for axis, reg in enumerate(self.axes):
            for channel, cap in list(reg.armed.items()):
                if cap.source != "R":
                    continue
                level = self._input(cap.input)
                here = self._counts_at(axis, self.m.tick)
                if level != cap.level and level == cap.rising and self._in_window(
                        axis, cap, here):
                    self._capture(axis, channel, here)
                cap.level = level

    def _in_window(self, axis: int, cap: Capture, counts: float) -> bool:
        """Does an edge at `counts` pass the capture's window?"""
        if cap.window == 0:
            return True
        if cap.window in (3, 4):
            return self._gate_open(cap)
        m = self.m
        a = m.axes[axis]
        position = m.wrapped(axis, (counts + a.datum) / a.units)
        low, high = ("OPEN_WINB", "CLOSE_WINB") if cap.window > 4 else \
            ("OPEN_WIN", "CLOSE_WIN")
        inside = a.params[low] <= position <= a.params[high]  # 5/6: the second window (C)
        return inside if cap.window in (1, 5) else not inside

    def _gate_open(self, cap: Capture) -> bool:
        """Windows 3/4: is the gate input high (3) / low (4)? Other windows: open."""
        return cap.window not in (3, 4) or self._input(cap.gate) == (cap.window == 3)

    def _z_ticks(self) -> list[tuple[int, str, float]]:
        """(tick, channel, position in counts) of each armed Z capture's next edge."""
        m = self.m
        out = []
        horizon: int | None = -1  # (looked up once, for linked axes)
        for axis, reg in enumerate(self.axes):
            if not any(cap.source == "Z" for cap in reg.armed.values()):
                continue
            a = m.axes[axis]
            encoder = m.encoder_counts(axis) is not None  # reads a mounted encoder (I)
            own = a.motion is not None and a.link is None and axis not in m.links.addax \
                and not encoder
            if not own and horizon == -1:
                horizon = m.motion_horizon()
            if not own and (horizon is None or horizon <= m.tick):
                continue
            stage = m.world.axes[axis]
            if stage.index_period <= 0:
                continue
            here = a.steps_now(m) if own else math.floor(self._counts_at(axis, m.tick))
            for channel, cap in reg.armed.items():
                if cap.source != "Z" or not self._gate_open(cap):
                    continue
                if cap.rising:
                    up, down = next_periodic_marks(here, stage.index_offset,
                                                   stage.index_period, stage.index_width)
                else:  # the first count past the mark each way
                    up = next_periodic_marks(here, stage.index_offset + stage.index_width,
                                             stage.index_period, 1)[0]
                    down = next_periodic_marks(here, stage.index_offset - 1,
                                               stage.index_period, 1)[1]
                for position, direction in ((up, 1), (down, -1)):
                    for _ in range(WINDOW_SEARCH):  # the next mark the window takes
                        if self._in_window(axis, cap, position):
                            break
                        position += direction * stage.index_period
                    else:
                        continue
                    tick = a.tick_reaching(position, direction, m) if own else \
                        self._linked_tick(axis, position, direction, horizon)
                    if tick is not None:
                        out.append((tick, f"{axis}:{channel}", float(position)))
        return out

    def _linked_tick(self, axis: int, position: float, direction: int,
                     horizon: int | None) -> int | None:
        """The first tick a linked axis's demand reaches `position` travelling
        `direction`, up to the horizon (the next tick the motion changes by itself:
        until then its demand is one closed form, taken as monotonic, D)."""
        m = self.m
        if horizon is None:
            return None

        def reached(tick: int) -> bool:
            return direction * (self._counts_at(axis, tick) - position) >= 0

        return first_tick(reached, m.tick + 1, horizon)

    def _counts_at(self, axis: int, tick: int) -> float:
        """Where the axis's capture latches, in counts: the encoder the world mounts on
        an encoder axis's input (ATYPE 76 ...: the stage's shaft), else its demand."""
        m = self.m
        mount = m.world.encoders.get(axis)
        if mount is not None and m.encoder_counts(axis) is not None:
            motor = float(m.motor_steps_at(mount.motor, np.array([tick]))[0])
            return float(mount.counts(motor - m.world.axes[mount.motor].lost_steps))
        return float(m.demand_counts(axis, np.array([tick]))[0])

    def next_event(self) -> int | None:
        m = self.m
        if self._cache[0] != m.revision:
            found = self._z_ticks()
            best = min((t for t, _c, _p in found), default=None)
            self._cache = (m.revision, best, found)
        return self._cache[1]

    def on_event(self, now: int) -> None:
        m = self.m
        _rev, _best, found = self._cache
        hits: dict[str, tuple[int, float]] = {}
        for tick, key, position in found:
            if tick <= now and (key not in hits or tick < hits[key][0]):
                hits[key] = (tick, position)
        for key, (_tick, position) in hits.items():
            axis, channel = key.split(":")
            self._capture(int(axis), channel, position)
        self._cache = (-1, None, [])
        m.changed()

    def _capture(self, axis: int, channel: str, counts: float) -> None:
        m = self.m
        a = m.axes[axis]
        reg = self.axes[axis]
        cap = reg.armed[channel]
        position = (counts + a.datum) / a.units
        change = self._counts_at(axis, m.tick) - self._counts_at(axis, m.tick - 1)
        state = reg.channel(channel)
        state.position = position
        state.speed = change / a.units / (m.period * 1000)
        if cap.quantity:
            m.table.write(cap.table_start + cap.count, [position])
            cap.count += 1
            state.mark = -float(cap.count)
            if cap.count >= cap.quantity:
                reg.armed.pop(channel)
        else:
            state.mark = -1.0
            reg.armed.pop(channel)
        m.links.registered(axis, EVENTS.get(channel, "R_MARK" + channel[1:]), counts)
        m.changed()


__all__ = ["MODES", "READS", "Registration", "default_inputs"]

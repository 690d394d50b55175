"""A small in-memory TrioMachine for testing the language without the engine.

Deliberately simple motion: a move runs at its base axis's SPEED with no ramps, taking
whole servo cycles, and moves on one axis run one after another (MERGE is ignored).
CONNPATH adds the driving group's path distance to its axis each cycle; CAMBOX follows
its TABLE profile by linear interpolation over the link axis's travel. PWM, TABLE and VR
are the real personality objects, so PWM marks, the gating FIFO and PWM_ENCODER behave
as they will on the engine. Measured positions equal demand positions.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from ...personalities.trio.memory import TableMemory, VrMemory
from ...personalities.trio.pwm import PwmBank
from .keywords import KEYWORDS, Kind

MOVE_BUFFER = 16  # moves an axis holds (running + buffered) in the fake
SERVO_PERIODS = (250, 500, 1000, 2000)
_PWM_PARAMETERS = frozenset({"PWM_CYCLE", "PWM_MARK", "PWM_ENCODER"})


@dataclass
class _Move:
    axes: list[int]
    values: list[float]
    absolute: bool
    start: list[float] | None = None
    delta: list[float] | None = None
    ticks: int = 0
    elapsed: int = 0


@dataclass
class _Cam:
    start: int
    end: int
    multiplier: float
    distance: float
    link: int
    link_origin: float
    origin: float


class FakeTrioMachine:
    def __init__(self, axis_count: int = 16, servo_period_us: int = 1000) -> None:
        self._axis_count = axis_count
        self.tick = 0
        self._period = servo_period_us
        self.axis_params = [
            {k.name: k.default for k in KEYWORDS.values()
             if k.kind is Kind.AXIS_PARAMETER and k.name not in _PWM_PARAMETERS}
            for _ in range(axis_count)
        ]
        self.system = {k.name: k.default for k in KEYWORDS.values()
                       if k.kind is Kind.SYSTEM_PARAMETER}
        self.system["SERVO_PERIOD"] = servo_period_us
        self.pwm = PwmBank(axis_count)
        self.table = TableMemory()
        self.vr = VrMemory()
        self.dpos = [0.0] * axis_count
        self.vp_speed = [0.0] * axis_count
        self._counts = [0] * axis_count  # PWM encoder baseline, counts
        self.queues: list[deque[_Move]] = [deque() for _ in range(axis_count)]
        self.inputs: dict[int, bool] = {}  # IN(n) levels a test sets
        self.inverted: set[int] = set()  # INVERT_IN(n, ON)
        self.analog: dict[int, float] = {}  # AIN(n) volts a test sets
        self.outputs: dict[int, bool] = {}
        self.connpaths: dict[int, tuple[int, float]] = {}
        self.cams: dict[int, _Cam] = {}
        self.gate_events: list[tuple[int, int, bool]] = []  # (tick, axis, gate level)
        self._path_step: dict[int, float] = {}

    # ---- TrioMachine -----------------------------------------------------------------
    @property
    def axis_count(self) -> int:
        return self._axis_count

    def servo_tick(self) -> int:
        return self.tick

    def servo_period_us(self) -> int:
        return self._period

    def axis_parameter(self, name: str, axis: int) -> float:
        if name == "DPOS" or name == "MPOS":
            return self.dpos[axis]
        if name == "VP_SPEED":
            return self.vp_speed[axis]
        if name == "PWM_CYCLE":
            return self.pwm[axis].cycle
        if name == "PWM_MARK":
            return self.pwm[axis].mark
        if name == "PWM_ENCODER":
            return self.pwm[axis].encoder
        if name == "AXISSTATUS":
            return float(self._axis_status(axis))
        return self.axis_params[axis][name]

    def _axis_status(self, axis: int) -> int:
        """The limit bits (16, 32, 512, 1024): the inputs FWD_IN/REV_IN name and the
        software limits (the fake's limits do not stop its moves)."""
        params = self.axis_params[axis]
        bits = 0
        for name, bit in (("FWD_IN", 16), ("REV_IN", 32)):
            if 0 <= params[name] < 32 and self.input_function(int(params[name])):
                bits |= bit
        if self.dpos[axis] > params["FS_LIMIT"]:
            bits |= 512
        if self.dpos[axis] < params["RS_LIMIT"]:
            bits |= 1024
        return bits

    def datum(self, axis: int, mode: int) -> None:
        """DATUM(0): the fake has no motion errors to clear; no Z marks to search."""
        if mode != 0:
            raise ValueError("Parameter out of range")

    def set_axis_parameter(self, name: str, axis: int, value: float) -> None:
        if name == "PWM_CYCLE":
            self.pwm[axis].set_cycle(value)
        elif name == "PWM_MARK":
            self.pwm[axis].set_mark(value)
        else:
            self.axis_params[axis][name] = value

    def system_parameter(self, name: str) -> float:
        return self.system[name]

    def set_system_parameter(self, name: str, value: float) -> None:
        if name == "SERVO_PERIOD" and value not in SERVO_PERIODS:
            raise ValueError("Parameter out of range")
        self.system[name] = value  # SERVO_PERIOD: in effect from the next restart

    def can_load(self, axes: Sequence[int]) -> bool:
        return all(len(self.queues[a]) < MOVE_BUFFER for a in axes)

    def move(self, axes: Sequence[int], distances: Sequence[float]) -> None:
        self._load(_Move(list(axes), list(distances), absolute=False))

    def move_abs(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        self._load(_Move(list(axes), list(positions), absolute=True))

    def arc_sp(self, axes: Sequence[int], args: Sequence[float], helical: bool) -> None:
        (self.mhelical if helical else self.movecirc)(axes, args)

    def move_sp(self, axes: Sequence[int], values: Sequence[float], absolute: bool) -> None:
        (self.move_abs if absolute else self.move)(axes, values)  # (no FORCE_SPEED here)

    def _load(self, move: _Move) -> None:
        for a in move.axes:
            self.queues[a].append(move)

    def axis_idle(self, axis: int) -> bool:
        return not self.queues[axis] and axis not in self.connpaths and axis not in self.cams

    def defpos(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        for a, p in zip(axes, positions, strict=True):
            self.dpos[a] = p
            self._counts[a] = self._encoder_counts(a)  # PWM_ENCODER does not jump

    def set_acc(self, axis: int, rate: float) -> None:
        self.axis_params[axis]["ACCEL"] = self.axis_params[axis]["DECEL"] = rate

    def cancel(self, axis: int, fast: bool = False, mode: float = 0) -> None:
        if self.queues[axis]:
            move = self.queues[axis][0]
            for a in move.axes:
                self.queues[a].popleft()
                self.vp_speed[a] = 0.0
        self.connpaths.pop(axis, None)
        self.cams.pop(axis, None)

    def rapidstop(self, mode: float = 0) -> None:
        for queue in self.queues:
            queue.clear()
        self.connpaths.clear()
        self.cams.clear()
        self.vp_speed = [0.0] * self._axis_count

    def connpath(self, axis: int, args: Sequence[float]) -> None:
        base = args[0]
        if base != int(base) or not 0 <= base < self._axis_count:
            raise ValueError("Invalid axis number")
        self.connpaths[axis] = (int(base), args[1] if len(args) > 1 else 1.0)

    def cambox(self, axis: int, args: Sequence[float]) -> None:
        start, end, multiplier, distance, link = args[:5]
        if link != int(link) or not 0 <= link < self._axis_count or distance <= 0:
            raise ValueError("Parameter out of range")
        if start != int(start) or end != int(end) or end <= start:
            raise ValueError("Parameter out of range")
        self.table.read_run(int(start), int(end))  # refuses a run outside TABLE
        self.cams[axis] = _Cam(int(start), int(end), multiplier, distance, int(link),
                               self.dpos[int(link)], self.dpos[axis])

    def cambox_group(self, axes: Sequence[int], args: Sequence[float]) -> None:
        raise ValueError("Parameter out of range")  # (the fake has no multi-axis form)

    def flexlink(self, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Parameter out of range")  # (the fake has no FLEXLINK)

    def cam(self, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Parameter out of range")  # (the fake has no CAM)

    def movetest(self, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Parameter out of range")  # (the fake has no test cycles)

    def regist(self, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Parameter out of range")  # (the fake has no registration)

    def channel_parameter(self, name: str, axis: int, channel: float) -> float:
        return 0.0  # (the fake has no registration channels)

    def position_switch(self, name: str, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Parameter out of range")  # (the fake has no position switches)

    def pwm_control(self, axis: int, args: Sequence[float]) -> None:
        self.pwm[axis].control(args, self.table, self.axis_params[axis]["UNITS"],
                               self._axis_count)

    def table_read(self, index: int) -> float:
        return self.table.read(index)

    def table_write(self, start: int, values: Sequence[float]) -> None:
        self.table.write(start, values)

    def vr_read(self, index: int) -> float:
        return self.vr.read(index)

    def vr_write(self, index: int, value: float) -> None:
        self.vr.write(index, value)

    # ---- one servo cycle -----------------------------------------------------------------
    def cycle(self) -> None:
        """Advance one servo cycle: moves, linked axes, PWM encoder and marks."""
        self.tick += 1
        self._path_step = {}
        self.vp_speed = [0.0] * self._axis_count
        running: dict[int, _Move] = {}  # moves at the head of all their axes' queues
        for queue in self.queues:
            if queue and all(self.queues[a][0] is queue[0] for a in queue[0].axes):
                running[id(queue[0])] = queue[0]
        for move in running.values():
            self._advance(move)
        for axis, (base, ratio) in self.connpaths.items():
            self.dpos[axis] += ratio * self._path_step.get(base, 0.0)
        for axis, cam in list(self.cams.items()):
            self._follow(axis, cam)
        for axis, output in self.pwm.outputs.items():
            counts = self._encoder_counts(axis)
            for entry in output.move_encoder(counts - self._counts[axis]):
                self.gate_events.append((self.tick, axis, entry.level))
            self._counts[axis] = counts
        self.pwm.servo_cycle(lambda a: self.vp_speed[a], lambda a: self.dpos[a])

    def run(self, cycles: int) -> None:
        for _ in range(cycles):
            self.cycle()

    def _encoder_counts(self, axis: int) -> int:
        return round(self.dpos[axis] * self.axis_params[axis]["UNITS"])

    def _advance(self, move: _Move) -> None:
        if move.start is None:
            move.start = [self.dpos[a] for a in move.axes]
            move.delta = [v - s if move.absolute else v for v, s in zip(move.values, move.start,
                                                                        strict=True)]
            length = math.sqrt(sum(d * d for d in move.delta))
            speed = self.axis_params[move.axes[0]]["SPEED"]
            seconds = length / speed if speed > 0 else math.inf
            move.ticks = max(1, math.ceil(round(seconds * 1e6 / self._period, 9)))
        assert move.delta is not None
        move.elapsed += 1
        fraction = move.elapsed / move.ticks
        length = math.sqrt(sum(d * d for d in move.delta))
        self._path_step[move.axes[0]] = length / move.ticks
        for a, s, d in zip(move.axes, move.start, move.delta, strict=True):
            self.dpos[a] = s + d * fraction if move.elapsed < move.ticks else s + d
            self.vp_speed[a] = length / move.ticks * 1e6 / self._period
        if move.elapsed >= move.ticks:
            for a in move.axes:
                self.queues[a].popleft()

    def _follow(self, axis: int, cam: _Cam) -> None:
        travelled = self.dpos[cam.link] - cam.link_origin
        span = cam.end - cam.start
        position = min(max(travelled / cam.distance, 0.0), 1.0) * span
        index = min(int(position), span - 1)
        low = self.table.read(cam.start + index)
        high = self.table.read(cam.start + index + 1)
        value = low + (high - low) * (position - index)
        self.dpos[axis] = cam.origin + value * cam.multiplier / self.axis_params[axis]["UNITS"]
        if travelled >= cam.distance:
            del self.cams[axis]

    def debounced_input(self, number: int) -> bool:
        return self.digital_input(number)  # (the fake has no IN_DEBOUNCE)

    def digital_input(self, number: int) -> bool:
        """A level a test sets; else an input FWD_IN/REV_IN/DATUM_IN names reads 1 (its
        normally closed switch, never reached: the fake has no stage), any other 0;
        inverted by INVERT_IN."""
        if number in self.inputs:
            level = self.inputs[number]
        else:
            level = any(params[name] == number for params in self.axis_params
                        for name in ("FWD_IN", "REV_IN", "DATUM_IN"))
        return level != (number in self.inverted)

    def input_function(self, number: int) -> bool:
        return not self.digital_input(number)

    def frame_group(self, args: Sequence[float]) -> str:
        raise ValueError("Parameter out of range")  # (the fake has no robot frames)

    def axis_hardware(self, name: str, axis: int, args: Sequence[float]) -> None:
        pass  # (the fake has no step output: accepted)

    def encoder_ratio(self, axis: int, mpos_count: float, input_count: float) -> None:
        if input_count <= 0 or mpos_count == 0:
            raise ValueError("Parameter out of range")

    def invert_input(self, number: int, on: bool) -> None:
        if on:
            self.inverted.add(number)
        else:
            self.inverted.discard(number)

    def input_inverted(self, number: int) -> bool:
        return number in self.inverted

    def analog_input(self, channel: int) -> float:
        return self.analog.get(channel, 0.0)

    def output(self, number: int) -> bool:
        return self.outputs.get(number, False)

    def set_output(self, number: int, on: bool) -> None:
        self.outputs[number] = on

    def movecirc(self, axes: Sequence[float], args: Sequence[float]) -> None:
        """The fake goes straight to the arc's end (the MC405 machine draws the arc)."""
        self.move([int(a) for a in axes], list(args[:2]))

    def mhelical(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """The fake goes straight to the helix's end, as it does for MOVECIRC."""
        self.move([int(a) for a in axes[:3]], [*args[:2], args[5]])

    def geometric_move(self, name: str, axes: Sequence[int], args: Sequence[float]) -> None:
        """The fake goes straight to the move's end (the MC405 machine draws the arc; a
        full circle, MSPHERICAL modes 2 and 3, ends where it started); MOVETANG is an
        absolute move there."""
        if name == "MOVETANG":
            self.move_abs([axes[0]], [args[0]])
            return
        end = list(args[:3]) if len(args) < 7 or args[6] in (0, 1) else [0.0] * 3
        self.move([int(a) for a in axes], [*end, *args[8:]][:len(axes)])

    def sequence(self, name: str, axes: Sequence[int], args: Sequence[float]
                 ) -> list[tuple[str, list[float]]]:
        """The fake goes straight from point to point (no fillets)."""
        count = int(args[1]) if len(args) > 2 and args[1] in (2, 3) else 0
        if not count:
            raise ValueError("Parameter out of range")
        return [("MOVEABS" if name == "MOVEABSSEQ" else "MOVE",
                 [self.table.read(int(args[0]) + i * count + k) for k in range(count)])
                for i in range(int(args[2]))]

    def movemodify(self, axis: int, args: Sequence[float]) -> None:
        """The fake has no running move to modify: an absolute move (as on an idle axis)."""
        self.move_abs([axis], [args[0]])

    def can_link(self, axis: int) -> bool:
        return self.can_load([axis])

    def movelink(self, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Linked moves need the MC405 machine")  # (the fake has no links)

    def connect(self, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Linked moves need the MC405 machine")

    def sync(self, axes: Sequence[int], args: Sequence[float]) -> None:
        raise ValueError("Linked moves need the MC405 machine")

    def addax(self, axis: int, args: Sequence[float]) -> None:
        raise ValueError("Linked moves need the MC405 machine")

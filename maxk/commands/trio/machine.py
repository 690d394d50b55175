"""What TrioBASIC needs from the machine below it.

The language evaluates and checks every argument (ranges from the keyword table) before
it calls one of these methods, and calls each at most once per statement, so a refusal
leaves nothing half-applied. A method refuses by raising ``ValueError`` with the
controller's error text (``PwmError`` and ``MemoryRangeError`` of the personality are
ValueErrors); the language prints it as the statement's error.

Positions, distances and speeds are in user units (the axis's UNITS applied by the
machine), time is the integer servo-cycle count.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Protocol


class TrioMachine(Protocol):
    @property
    def axis_count(self) -> int:
        """Axes the controller has (MC405: 0..axis_count-1, virtual axes included)."""
        ...

    def servo_tick(self) -> int:
        """Servo cycles since power-up: the clock of WA and WAIT."""
        ...

    def servo_period_us(self) -> int:
        """Length of one servo cycle in microseconds (SERVO_PERIOD in effect)."""
        ...

    # ---- parameters -----------------------------------------------------------------
    def axis_parameter(self, name: str, axis: int) -> float:
        """ATYPE UNITS SPEED ACCEL DECEL MERGE FE_LIMIT DPOS MPOS VP_SPEED PWM_CYCLE
        PWM_MARK PWM_ENCODER of one axis."""
        ...

    def channel_parameter(self, name: str, axis: int, channel: float) -> float:
        """A parameter of one of the axis's channels: R_MARK(channel) and the like."""
        ...

    def set_axis_parameter(self, name: str, axis: int, value: float) -> None:
        ...

    def system_parameter(self, name: str) -> float:
        """WDOG SERVO_PERIOD VERSION SYSTEM_ERROR SYSTEM_LOAD_MAX TSIZE."""
        ...

    def set_system_parameter(self, name: str, value: float) -> None:
        ...

    # ---- motion ---------------------------------------------------------------------
    def can_load(self, axes: Sequence[int]) -> bool:
        """Room for one more move on every one of these axes (else the process waits)."""
        ...

    def move(self, axes: Sequence[int], distances: Sequence[float]) -> None:
        """MOVE: load a relative interpolated move; axes[0] is the path's base axis."""
        ...

    def move_sp(self, axes: Sequence[int], values: Sequence[float], absolute: bool) -> None:
        """MOVESP / MOVEABSSP: MOVE / MOVEABS at FORCE_SPEED."""
        ...

    def arc_sp(self, axes: Sequence[int], args: Sequence[float], helical: bool) -> None:
        """MOVECIRCSP / MHELICALSP: MOVECIRC / MHELICAL at FORCE_SPEED."""
        ...

    def move_abs(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        """MOVEABS: load an absolute interpolated move."""
        ...

    def movecirc(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """MOVECIRC(end1, end2, centre1, centre2, direction) on the first two axes."""
        ...

    def mhelical(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """MHELICAL(end1, end2, centre1, centre2, direction, distance3[, mode]): MOVECIRC's
        arc on the first two axes, the third moving distance3 along it."""
        ...

    def geometric_move(self, name: str, axes: Sequence[int], args: Sequence[float]) -> None:
        """MSPHERICAL / MSPHERICALSP (personality geometry.py) on the BASE group `axes`;
        MOVETANG (tangential.py) on the one axis `axes[0]`."""
        ...

    def sequence(self, name: str, axes: Sequence[int], args: Sequence[float]
                 ) -> list[tuple[str, list[float]]]:
        """MOVEABSSEQ / MOVESEQ: the MOVEABS, MOVECIRC and MSPHERICAL moves they load
        (personality sequences.py), nothing loaded yet."""
        ...

    def movemodify(self, axis: int, args: Sequence[float]) -> None:
        """MOVEMODIFY(position): the running move now ends at this absolute position."""
        ...

    def can_link(self, axis: int) -> bool:
        """Room for one more linked move (MOVELINK, CONNECT) on the axis."""
        ...

    def movelink(self, axis: int, args: Sequence[float]) -> None:
        """MOVELINK(distance, link dist, link acc, link dec, link axis[, options[, pos]])."""
        ...

    def flexlink(self, axis: int, args: Sequence[float]) -> None:
        """FLEXLINK(base, excite, link dist, base in, base out, acc, dec, link axis[,
        options[, start pos]])."""
        ...

    def connect(self, axis: int, args: Sequence[float]) -> None:
        """CONNECT(ratio, link axis): electronic gearing until CANCEL."""
        ...

    def sync(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """SYNC(control, time[, sync pos, sync axis, pos1[, pos2[, pos3]]]) on the BASE
        group `axes` (personality sync.py)."""
        ...

    def addax(self, axis: int, args: Sequence[float]) -> None:
        """ADDAX(n): superimpose axis n's demand; ADDAX(-1) ends it."""
        ...

    def axis_idle(self, axis: int) -> bool:
        """No move running or buffered on the axis (IDLE, WAIT IDLE)."""
        ...

    def defpos(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        """DEFPOS: redefine the present positions (PWM_ENCODER is not changed)."""
        ...

    def set_acc(self, axis: int, rate: float) -> None:
        """ACC(rate): ACCEL and DECEL together."""
        ...

    def datum(self, axis: int, mode: int) -> None:
        """DATUM(0) clears the motion errors, DATUM(7) the axis's; DATUM(1)/(2) start a
        Z-mark search forward / reverse at CREEP (the axis is busy until it ends)."""
        ...

    def cancel(self, axis: int, fast: bool = False, mode: float = 0) -> None:
        ...

    def disable_group(self, args: Sequence[float]) -> None:
        """DISABLE_GROUP(-1): no groups; DISABLE_GROUP(a, b, ...): a motion error on one
        of those axes stops only them (ValueError: an axis out of range)."""
        ...

    def initialise(self) -> None:
        """INITIALISE: every axis parameter to its power-up value."""
        ...

    def rapidstop(self, mode: float = 0) -> None:
        ...

    def connpath(self, axis: int, args: Sequence[float]) -> None:
        """CONNPATH AXIS(axis), args (base axis of the driving group[, ratio]): the
        interpreter turns the page's CONNPATH(ratio, driving_axis) into this order."""
        ...

    def cambox(self, axis: int, args: Sequence[float]) -> None:
        """CAMBOX(start, end, multiplier, link distance, link axis[, options[, pos[,
        offset]]])."""
        ...

    def cambox_group(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """CAMBOX(table start, axis count) on these axes (the multi-axis loading form)."""
        ...

    def cam(self, axis: int, args: Sequence[float]) -> None:
        """CAM(start, end, multiplier, distance): the TABLE profile in time."""
        ...

    def movetest(self, axis: int, args: Sequence[float]) -> None:
        """MOVETEST(start/stop, ...) AXIS(n): a forward and back test cycle."""
        ...

    def regist(self, axis: int, args: Sequence[float]) -> None:
        """REGIST(mode) AXIS(n): arm a registration capture."""
        ...

    def position_switch(self, name: str, axis: int, args: Sequence[float]) -> None:
        """PSWITCH(...) or HW_PSWITCH(...) AXIS(axis): a position switch."""
        ...

    # ---- PWM and memory ---------------------------------------------------------------

    def pwm_control(self, axis: int, args: Sequence[float]) -> None:
        """PWM_CONTROL(mode, ...) on one axis (personality PwmOutput.control)."""
        ...

    def table_read(self, index: int) -> float:
        ...

    def table_write(self, start: int, values: Sequence[float]) -> None:
        ...

    def vr_read(self, index: int) -> float:
        ...

    def vr_write(self, index: int, value: float) -> None:
        ...

    # ---- I/O ------------------------------------------------------------------------
    def digital_input(self, number: int) -> bool:
        """IN(n): the input's level (the world's input, or the limit/home switch of an
        axis whose FWD_IN/REV_IN/DATUM_IN names it, normally closed), inverted when
        INVERT_IN says so."""
        ...

    def debounced_input(self, number: int) -> bool:
        """A program's IN(n): digital_input as IN_DEBOUNCE lets it through."""
        ...

    def input_function(self, number: int) -> bool:
        """The function an input drives (a limit, the datum, feed hold) is on: those
        inputs are active low, on while IN(n) reads 0."""
        ...

    def frame_group(self, args: Sequence[float]) -> str:
        """FRAME_GROUP(group[, table_offset, axes...]): define or delete (offset -1) a
        robot frame group; with the group alone, the line it prints."""
        ...

    def axis_hardware(self, name: str, axis: int, args: Sequence[float]) -> None:
        """STEP_RATIO(...) or BACKLASH(...) AXIS(axis): the axis's step output."""
        ...

    def encoder_ratio(self, axis: int, mpos_count: float, input_count: float) -> None:
        """ENCODER_RATIO(mpos_count, input_count): MPOS counts per encoder count."""
        ...

    def invert_input(self, number: int, on: bool) -> None:
        """INVERT_IN(n, state)."""
        ...

    def input_inverted(self, number: int) -> bool:
        """INVERT_IN(n): is input n inverted?"""
        ...

    def analog_input(self, channel: int) -> float:
        """AIN(n) in volts, -10..10."""
        ...

    def output(self, number: int) -> bool:
        ...

    def set_output(self, number: int, on: bool) -> None:
        ...

"""The MC405 on the shared engine: axes, buffered moves, linked axes and PWM outputs.

`MC405Machine` is an `Engine` whose tick is one servo cycle (SERVO_PERIOD, 1000 us by
default) and implements what TrioBASIC needs of a controller (the language's
`TrioMachine` protocol, structurally). Moves are runs of the shared machine
(`runs.py`); the engine jumps from event to event (a run ends, a CAMBOX ends, a gate
position is passed), and everything between is closed form:

- PWM modes 2 and 8: the mark is a `ComputedOutput` of the link axis's VP_SPEED and the
  amplitude axis's DPOS, evaluated at whatever servo tick it is read, traced or plotted.
- The gating FIFO: the head entry is a `PositionTrigger` on its axis; `trigger_ticks`
  finds the exact tick the axis passes it (bisection), and the gate toggles there.
- PWM_ENCODER follows the axis's whole counts and ignores DEFPOS.

`revision` counts every change a waiting program could notice; the process scheduler
of the language uses it to wake WAIT IDLE and full-buffer waits.

Long module: the MC405's parameters, motion queues, links and I/O on one engine are one
state; splitting them would spread every change across files.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Callable, Mapping, Sequence
from functools import partial

import numpy as np

from maxk.firmware_model.engine import Engine
from maxk.firmware_model.path import PathPlan
from maxk.firmware_model.profiles import Motion
from maxk.firmware_model.sampling import PlanArrays
from maxk.firmware_model.world import World

from . import (
    axismode,
    axistypes,
    encoders,
    geometry,
    links_modify,
    move_pa,
    moves,
    profile_readings,
    sequences,
    stepratio,
    tangential,
)
from .backlash import Backlash
from .cams import (
    cam_motion,
    cam_pointer,
    cambox_from,
    multi_axis,
    next_pattern,
    recam,
    retable,
)
from .clutch import ClutchWatch
from .combine import Combinations
from .compensate import Compensation, compensation_from
from .corner_state import CornerState
from .debounce import Debounce
from .drive import AXIS_READS, SYSTEM_READS, Drive
from .feedhold import FEEDHOLD, FeedHold
from .flash import AUTO_BACKUP, FLASH_PARAMETERS
from .following import superimposed
from .frames import READS as FRAME_READS
from .frames import Frames, fold
from .initialise import initialise
from .jogs import Jogs
from .kinematics import Kinematics
from .link_kinds import Cambox, Connpath, Link
from .links import LinkedMoves
from .memory import TableMemory, VrMemory
from .move_pa import MovePa
from .movetest import MoveTests
from .posiseq import DelayLine
from .profiles_sp import (
    DIRECTIONS,
    VP_MODES,
    cornered,
    forced_rates,
    forced_values,
    interp_share,
    jerk_counts,
    lookahead,
    sp_adjusted,
    sp_speeds,
    sramp_seconds,
    stop_jerk,
    v_limited,
    vp_factors,
)
from .pswitch import PositionSwitches
from .pwm import PwmBank, PwmError
from .pwm_link import GateEdge, PwmLinks
from .registration import Registration
from .respeed import refactor, respeed
from .runs import CORNER_HELD, Run, TrioAxis, single_profile
from .trace import PwmTrace

HELD = 2 ** 62  # the end tick of a run held at speed 0 (it ends when it goes on)
MOVE_BUFFER = 16  # moves an axis holds, running and buffered (D)
MIN_RATE = 1e-6
_NOT_HELD = (moves.CAM, moves.FWD_JOG, moves.REV_JOG, moves.MOVEMODIFY)  # (SPEED 0: refused)
"""The least SPEED, ACCEL or DECEL a move runs with, in counts per second (squared) (D: a
denormal SPEED made a 5-unit move last longer than a float counts; the move is refused
with 'Parameter out of range' as a zero SPEED is)."""
MAX_COUNTS = 2.0 ** 53
"""Below it: how far a move may go, and end, in counts as DPOS reads them, and the farthest
DEFPOS may set (D: beyond it a double no longer holds every count, so DPOS could not read
back where the axis is)."""
MAX_PHYSICAL = 2.0 ** 62
"""The farthest the stage itself may be taken, in counts from where it powered up (D:
DEFPOS moves only the frame DPOS reads; a 64-bit counter's range)."""
SERVO_PERIODS = (250, 500, 1000, 2000)
MIN_LINK_COUNTS = 1e-6
"""The shortest CAMBOX link distance, in counts of the link axis (D: shorter, a repeating
cam's cycle count would overflow a double)."""
AXIS_COUNT = 16  # axes 0-4 on the board, 5-15 virtual (D)
_PWM_PARAMETERS = frozenset({"PWM_CYCLE", "PWM_MARK", "PWM_ENCODER"})
# Axis types that are an encoder input and nothing else (the ATYPE help page: 76
# incremental encoder with Z input, 79 pulse and direction feedback, 86/87/88/93 absolute
# encoder inputs, 104/105 high density): their MPOS (and DPOS, which follows it: I) is
# the encoder the world mounts on their input.
ENCODER_ATYPES = frozenset({76, 79, 86, 87, 88, 93, 104, 105})
_COMPUTED = frozenset({"DPOS", "MPOS", "VP_SPEED", "TANG_DIRECTION", "TABLE_POINTER",
                       "BACKLASH_DIST"})
DAC_ALIASES = {"S_REF": "DAC", "T_REF": "DAC", "S_REF_OUT": "DAC_OUT", "T_REF_OUT": "DAC_OUT"}
"""Other names of the servo output (TrioBASIC help S_REF, T_REF, S_REF_OUT, T_REF_OUT)."""
_JOG_PARAMETERS = frozenset({"FWD_JOG", "REV_JOG", "FAST_JOG", "FWD_START", "REV_START"})
_REGISTRATION_READS = frozenset({"MARK", "MARKB", "REG_POS", "REG_POSB", "REGIST_SPEED",
                                 "REGIST_SPEEDB", "REGIST_CONTROL"})


class MC405Machine(Kinematics, Engine):
    """The MC405's firmware on the shared engine (one tick = one servo cycle)."""

    _speed_name = "SPEED"  # the parameter a move loaded now runs at (MOVESP, jogs)

    def __init__(self, axis_defaults: Mapping[str, float], system_defaults: Mapping[str, float],
                 axis_count: int = AXIS_COUNT) -> None:
        self._axis_defaults = dict(axis_defaults)
        self._system_defaults = dict(system_defaults)
        self._axis_count = axis_count
        period = int(self._system_defaults.get("SERVO_PERIOD", 1000))
        super().__init__(1e6 / period)
        self.revision = 0
        self.tracer: PwmTrace | None = None
        self.axes: list[TrioAxis] = []
        self.world = World.default(axis_count)  # the machine around it: kept over EX
        self._power_up()
        self.outputs = PwmLinks(self)
        self.drive = Drive(self)  # limits, motion errors, drive enables, Z-mark searches
        self.drive.following.command = self.command_offset  # (in a servo loop's command)
        self.drive.following.superimposed = partial(superimposed, self)  # (ADDAX, too)
        self.add_source(self.drive.limits)  # (before the runs end: a limit acts first)
        self.add_source(_MotionEvents(self))
        self.add_source(self.outputs)
        self.add_source(self.links)  # MOVELINKs ending (links.py)
        self.add_source(self.registration)  # Z-mark captures (registration.py)
        self.add_source(self.switches)  # PSWITCH / HW_PSWITCH edges (pswitch.py)
        self.add_source(_FollowWatch(self))  # forward-only links take in each stretch
        self.clutch = ClutchWatch(self)
        self.add_source(self.clutch)  # CONNECT ratios ramping at CLUTCH_RATE
        self.add_source(self.links.syncs)  # SYNC(4) stopping, cycle by cycle (sync.py)
        self.add_source(self.jogs)  # jog inputs, looked at every event
        self.add_source(self.movetests)  # MOVETEST's cycles (movetest.py)
        self.add_source(self.feedhold)  # feed-hold inputs, looked at every event
        self.add_source(self.frames)  # joints passing AXIS_FS_LIMIT / AXIS_RS_LIMIT
        self.add_source(self.posiseq)  # POSI_SEQ delay lines: every cycle while on (last)

    def _power_up(self) -> None:
        """Parameters, motion, PWM, TABLE and VR as at power-up (time goes on)."""
        self.system = dict(self._system_defaults)
        self.axes = [TrioAxis(i, str(i), params=dict(self._axis_defaults))
                     for i in range(self._axis_count)]
        self.queues: list[deque[Run]] = [deque() for _ in range(self._axis_count)]
        self.distance_done = [0.0] * self._axis_count  # path distance per base, user units
        self.tangents: dict[int, float] = {}  # TANG_DIRECTION at rest (tangential.py)
        self.table = TableMemory()
        self.vr = VrMemory()
        self.digital_outputs: dict[int, bool] = {}  # OP(n, ON): off at power-up
        self.inverted_inputs: set[int] = set()  # INVERT_IN(n, ON): none at power-up (D)
        if hasattr(self, "backlash"):
            self.backlash.reset()
        else:
            self.backlash: Backlash = Backlash(self._axis_count)  # BACKLASH (backlash.py)
        if hasattr(self, "posiseq"):
            self.posiseq.reset()
        else:
            self.posiseq: DelayLine = DelayLine(
                self._axis_count, lambda: self.tick, lambda axis: self.axes[axis].params,
                self.demand_counts, lambda: self.revision)
        if hasattr(self, "links"):
            self.links.reset()
        else:
            self.links = LinkedMoves(self, MOVE_BUFFER)
        if hasattr(self, "jogs"):
            self.jogs.reset()
        else:
            self.jogs: Jogs = Jogs(self)
        if hasattr(self, "movetests"):
            self.movetests.reset()
        else:
            self.movetests: MoveTests = MoveTests(self)
        if hasattr(self, "combinations"):
            self.combinations.reset()
        else:
            self.combinations: Combinations = Combinations()  # (combine.py)
        if hasattr(self, "debounce"):
            self.debounce.reset()
        else:
            self.debounce: Debounce = Debounce(self)  # IN_DEBOUNCE (debounce.py)
        if hasattr(self, "feedhold"):
            self.feedhold.reset()
        else:
            self.feedhold: FeedHold = FeedHold(self)
        if hasattr(self, "frames"):
            self.frames.reset()
        else:
            self.frames: Frames = Frames(self)
        if hasattr(self, "registration"):
            self.registration.reset()
        else:
            self.registration: Registration = Registration(self)
        if hasattr(self, "switches"):
            self.switches.reset()
        else:
            self.switches: PositionSwitches = PositionSwitches(self)
        if hasattr(self, "outputs"):
            self.outputs.reset()
        if hasattr(self, "drive"):
            self.drive.reset()
        if hasattr(self, "corners"):
            self.corners.reset()
        else:
            self.corners: CornerState = CornerState(self)
        if hasattr(self, "move_pa"):
            self.move_pa.reset()
        else:
            self.move_pa: MovePa = MovePa(self)
        self.changed()

    def restart(self) -> None:
        """EX: the controller restarts; a new SERVO_PERIOD takes effect now, the VRs are
        kept (EX's and FLASHVR's pages)."""
        period = int(self.system.get("SERVO_PERIOD", 1000))
        for name in FLASH_PARAMETERS & self.system.keys():  # (flash.py: they are kept)
            self._system_defaults[name] = self.system[name]
        self._system_defaults["SERVO_PERIOD"] = period
        if abs(self.period - period / 1e6) > 1e-12:
            self.change_update_rate(1e6 / period)
        kept = self.vr  # (EX's page: the VRs remain in memory; flash.py)
        backup = self.table.read_run(0, AUTO_BACKUP - 1) \
            if self.system.get("FLASH_DATA", 0.0) == 1 else None  # (FLASH_DATA's page)
        self._power_up()
        self.vr = kept
        if backup is not None:
            self.table.write(0, backup)

    def changed(self) -> None:
        """Something a waiting program, a cache or an event search depends on changed."""
        self.revision += 1

    def world_changed(self) -> None:
        """The world moved a switch or an input: a limit it turns on acts now."""
        self.changed()
        self.registration.world_changed()
        self.debounce.world_changed()
        self.drive.look(self.tick)
        self.jogs.look()
        self.feedhold.look()

    @property
    def pwm(self) -> PwmBank:
        return self.outputs.bank

    @property
    def gate_edges(self) -> Sequence[GateEdge]:
        """The newest gate edges (at most `GATE_LOG`)."""
        return self.outputs.edges

    def mark(self, axis: int) -> int:
        return self.outputs.mark(axis)

    def marks_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        return self.outputs.marks_at(axis, ticks)

    def duty(self, axis: int) -> float:
        return self.outputs.duty(axis)

    # ---- the engine's hooks: traces see every servo cycle ---------------------------------
    def integrate(self, limit: int) -> bool:
        """The servo axes' loops run every tick (drive.py, following.py); a following
        error stops time at its tick."""
        stop = self.drive.following.integrate(limit)
        end = limit if stop is None else stop
        self.frames.stretch(end)  # (frame 10 counts its turns: frames.py)
        if self.tracer is not None and end > self.tick:
            self.tracer.stretch(self.tick + 1, end)
        if stop is None:
            return False
        self.tick = max(self.tick, stop)
        self.drive.following_error()
        axismode.stop_where_mpos_met(self)  # (a servo axis's MPOS met a software limit)
        return True

    def after_events(self, now: int) -> None:
        if self.tracer is not None:
            self.tracer.at_event(now)

    def trace(self, pwm_axes: tuple[int, ...] = (4,), xy: tuple[int, int] = (0, 1)) -> PwmTrace:
        """Record every servo cycle from now on (the XY path and the PWM outputs)."""
        self.tracer = PwmTrace(self, pwm_axes, xy)
        self.tracer.at_event(self.tick)
        return self.tracer

    # ---- the TrioMachine protocol -----------------------------------------------------------
    @property
    def axis_count(self) -> int:
        return self._axis_count

    def servo_tick(self) -> int:
        return self.tick

    def servo_period_us(self) -> int:
        return round(self.period * 1e6)

    def axis_parameter(self, name: str, axis: int) -> float:
        name = DAC_ALIASES.get(name, name)
        if name in FRAME_READS:
            return self.frames.read(name, axis, self.axis_parameter("DPOS", axis))
        if name in ("MPOS", "FE") and self.frames.framed(axis):  # the motor (frames.py)
            return self.frames.axis_dpos(axis) if name == "MPOS" else 0.0
        if name in ("MPOS", "DPOS", "FE") and (counts := self.encoder_counts(axis)) is not None:
            a = self.axes[axis]
            return 0.0 if name == "FE" else (counts + a.datum) / a.units
        if name in _PWM_PARAMETERS:
            output = self.pwm[axis]
            if name == "PWM_CYCLE":
                return output.cycle
            if name == "PWM_MARK":
                return self.mark(axis)
            self.outputs.sync_encoder(axis)
            return output.encoder
        if name == "DAC_OUT":
            return self.drive.following.dac_out(axis)
        if name in ("SYNC_CONTROL", "SYNC_TIMER"):
            return self.links.syncs.read(name, axis)
        if name == "ENCODER":
            return encoders.encoder(self, axis)
        if name in AXIS_READS:
            value = self.drive.axis_parameter(name, axis)
            if name == "AXISSTATUS" and axis in self.feedhold.held:
                value = float(int(value) | FEEDHOLD)  # bit 7 (h), feedhold.py
            if name == "AXISSTATUS":
                value = float(int(value) | self.frames.status_bits(axis))  # frames.py
            if name == "MPOS":  # BACKLASH's compensation, a POSI_SEQ delay (on a servo
                # axis in its loop's command: FE, the loop's error, takes them back out)
                value += (self.compensation(axis) + self.output_counts(axis)
                          - self.motor(axis)) / self.axes[axis].units
            return self.wrapped(axis, value) if name == "MPOS" else value
        if name == "BACKLASH_DIST":
            return self.compensation(axis) / self.axes[axis].units
        if name == "DPOS":  # (= MPOS while a servo's loop is open: help DPOS)
            open_error = self.drive.following.open_error(axis) / self.axes[axis].units
            a = self.axes[axis]
            dpos = ((self.output_counts(axis) + a.datum) / a.units if axis in self.posiseq.lines
                    else self.dpos(axis))  # (a POSI_SEQ delay: posiseq.py)
            return self.wrapped(axis, dpos - open_error)
        if name == "VP_SPEED":
            return self.vp_speed(axis)
        if name in profile_readings.READS:  # REMAIN_TIME, STOPPING_DISTANCE
            return profile_readings.read(self, name, axis)
        if name == "TANG_DIRECTION":
            return tangential.direction(self, axis)
        if name == "TABLE_POINTER":
            return self.table_pointer(axis)
        if name in moves.REPORTS:
            return moves.report(self, name, axis)
        if name == "FE_LATCH":
            return self.drive.following.fe_latch(axis)
        if name in _REGISTRATION_READS:
            value = self.registration.read(name, axis)
            return self.wrapped(axis, value) if name.startswith("REG_POS") else value
        return self.axes[axis].params[name]

    def channel_parameter(self, name: str, axis: int, channel: float) -> float:
        """R_MARK(channel), R_REGPOS(channel), R_REGISTSPEED(channel) (registration.py)."""
        if channel != int(channel):
            raise ValueError("Parameter out of range")
        value = self.registration.read(name, axis, int(channel))
        return self.wrapped(axis, value) if name == "R_REGPOS" else value

    def set_axis_parameter(self, name: str, axis: int, value: float) -> None:
        name = DAC_ALIASES.get(name, name)
        if name == "PWM_CYCLE":
            self.pwm[axis].set_cycle(value)
        elif name == "PWM_MARK":
            self.pwm[axis].set_mark(value)
        elif name == "SERVO" and value != 0:
            self.drive.following.latch.pop(axis, None)  # FE_LATCH resets (C: page)
            self.axes[axis].params[name] = value
        elif name == "REGIST_CONTROL":
            self.registration.write_control(axis, value)
        elif name == "FRAME":
            self.frames.set_frame(axis, value)
        elif name == "AXIS_UNITS" and not (value != 0 and math.isfinite(value)):
            raise ValueError("Parameter out of range")
        elif name == "CLUTCH_RATE" and value >= 0:
            self.clutch.new_rate(axis)  # the ramp so far at the old rate (clutch.py)
            self.axes[axis].params[name] = value
        elif name == "MOVELINK_MODIFY":
            links_modify.request(self, axis, value)  # (links_modify.py)
        elif name == "ENDMOVE":
            moves.set_endmove(self, axis, value, MIN_RATE)
        elif name == "PP_STEP":
            self._rescale_encoder(axis, lambda params: encoders.set_pp_step(params, value))
        elif name == "ATYPE":
            self.axes[axis].params[name] = float(axistypes.check(value))  # (axistypes.py)
        elif name == "CORNER_STATE":
            self.corners.write(axis, value)  # the corner handshake (corner_state.py)
        elif name in _COMPUTED or name not in self.axes[axis].params \
                or name == "SYNC_CONTROL":  # (read only: its page, D)
            raise ValueError("Parameter is read only")
        elif name == "VP_MODE" and value not in VP_MODES or \
                name == "CLUTCH_RATE" and not value >= 0:
            raise ValueError("Parameter out of range")  # (CLUTCH_RATE < 0: D)
        elif name == "REP_OPTION" and int(value) & 2:
            self.links.stop_repeating(axis)  # bit 1: the repeating links end their cycle
            self.axes[axis].params[name] = float(int(value) & ~2)  # and it clears (C)
        else:
            self.axes[axis].params[name] = value
        self.changed()
        self.drive.look(self.tick)  # (a limit, an enable or ERRORMASK may act now)
        if name in _JOG_PARAMETERS:
            self.jogs.look()
        if name in ("FHOLD_IN", "FHSPEED"):
            self.feedhold.look()
        if name == "LOOKAHEAD_FACTOR":
            refactor(self, axis)  # the SP moves buffered take it (respeed.py)
        if name in ("SPEED", "ACCEL", "DECEL", "SPEED_FACTOR", "ACCEL_FACTOR"):
            respeed(self, axis)  # the plain moves running take it at once (respeed.py)
            if self.feedhold.held:
                self.feedhold.look()  # (a feed hold's share of the new speed)

    def system_parameter(self, name: str) -> float:
        if name == "HW_TIMER_DONE":
            return self.switches.timer_done()
        if name in SYSTEM_READS:
            return self.drive.system_parameter(name)
        return self.system[name]

    def set_system_parameter(self, name: str, value: float) -> None:
        if name == "SERVO_PERIOD" and value not in SERVO_PERIODS:
            raise ValueError("Parameter out of range")
        self.system[name] = value  # SERVO_PERIOD: from the next restart (EX)
        if name == "IN_DEBOUNCE":
            self.debounce.note()  # the levels from here on (debounce.py)
        self.changed()
        self.drive.look(self.tick)

    def can_load(self, axes: Sequence[int]) -> bool:
        depth = int(self.system.get("LIMIT_BUFFERED", 1)) + 1
        return all(self._buffered(a) < depth and self.axes[a].link is None
                   and self.axes[a].pending_link is None for a in axes)

    def _buffered(self, axis: int) -> int:
        return sum(run.moves_left(self.tick, self.period) for run in self.queues[axis])

    def _counts(self, axis: int, value: float) -> float:
        """User units to counts, refused when beyond the position range (an overflow on
        the controller: every operand checked before anything is loaded)."""
        counts = value * self.axes[axis].units
        if not abs(counts) < MAX_COUNTS:  # also NaN and inf
            raise ValueError("Parameter out of range")
        return counts

    def move(self, axes: Sequence[int], distances: Sequence[float]) -> None:
        deltas = [round(self._counts(a, d)) for a, d in zip(axes, distances, strict=True)]
        self._load(tuple(axes), deltas, kind=moves.move_kind(tuple(axes), deltas, False))

    def wrapped(self, axis: int, position: float) -> float:
        """A position as a repeating axis reads it: REP_DIST > 0 folds it into -REP_DIST
        ..REP_DIST, or 0..REP_DIST with REP_OPTION bit 0 (I: REP_DIST page as recalled;
        the machine keeps the unfolded position, so motion is never disturbed, D)."""
        params = self.axes[axis].params
        if int(params.get("REP_OPTION", 0.0)) & 8:  # FRAME_REP_DIST instead (frames.py)
            return self.frames.folded(axis, position, params)
        rep = params.get("REP_DIST", 0.0)
        if not rep > 0:
            return position
        return fold(position, rep, bool(int(params.get("REP_OPTION", 0.0)) & 1))

    def unwrapped(self, axis: int, position: float, here: float) -> float:
        """A position in the fold the axis reads now (`here` unfolded) as an unfolded
        one: MOVEABS and absolute link positions act within the current fold (D)."""
        return position + here - self.wrapped(axis, here)

    def move_sp(self, axes: Sequence[int], values: Sequence[float], absolute: bool) -> None:
        """MOVESP / MOVEABSSP: MOVE / MOVEABS at the base axis's FORCE_SPEED instead of
        SPEED (C: the speed-profiled moves' pages)."""
        self._speed_name = "FORCE_SPEED"
        try:
            (self.move_abs if absolute else self.move)(axes, values)
        finally:
            self._speed_name = "SPEED"

    def arc_sp(self, axes: Sequence[int], args: Sequence[float], helical: bool) -> None:
        """MOVECIRCSP / MHELICALSP: MOVECIRC / MHELICAL at FORCE_SPEED (as MOVESP)."""
        self._speed_name = "FORCE_SPEED"
        try:
            (self.mhelical if helical else self.movecirc)(axes, args)
        finally:
            self._speed_name = "SPEED"

    def move_abs(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        deltas = []
        for a, p in zip(axes, positions, strict=True):
            axis = self.axes[a]
            end = (self._end_counts(a) + axis.datum + self.links.shift[a]) / axis.units
            p = self.unwrapped(a, p, end)
            target = moves.own_target(self, a, p)  # physical counts
            delta = target - self._end_counts(a)
            if not abs(delta) < MAX_COUNTS:
                raise ValueError("Parameter out of range")
            deltas.append(round(delta))
        self._load(tuple(axes), deltas, kind=moves.MOVEABS)

    # ---- I/O on the shared world --------------------------------------------------------
    def digital_input(self, number: int) -> bool:
        """IN(n): the input's level, inverted when INVERT_IN(n, ON) says so. The level is
        one the world sets for input n; else, for an input FWD_IN/REV_IN/DATUM_IN of an
        axis names, that axis's world switch wired normally closed: 1 away from it, 0
        on it (the help pages: the inputs of those functions are active low, and the
        DATUM_IN page homes on a normally closed sensor; D: the world's switches are
        wired as those pages expect); an input nothing drives reads 0."""
        return self.raw_input(number) != (number in self.inverted_inputs)

    def debounced_input(self, number: int) -> bool:
        """A program's IN(n): digital_input after IN_DEBOUNCE (debounce.py)."""
        return self.debounce.read(number)

    def raw_input(self, number: int) -> bool:
        """The input's level before INVERT_IN (see `digital_input`)."""
        if number in self.world.digital:
            return self.world.digital_level(number, self)  # type: ignore[arg-type]
        wired = False
        for i, axis in enumerate(self.axes):
            params = axis.params
            for name, switch in (("FWD_IN", "plus_limit"), ("REV_IN", "minus_limit"),
                                 ("DATUM_IN", "home")):
                if params.get(name, -1) == number:
                    wired = True
                    stage = self.world.axes[i]
                    if getattr(stage, switch).active(self.motor_steps(i) - stage.lost_steps):
                        return False  # the normally closed switch has opened
        return wired

    def input_function(self, number: int) -> bool:
        """Is the function an input drives (FWD_IN, REV_IN, DATUM_IN, FHOLD_IN ...) on?
        Those inputs are active low (help pages): on while IN(n) reads 0."""
        return not self.digital_input(number)

    def encoder_counts(self, axis: int) -> float | None:
        """What an encoder input's MPOS counts: its encoder's counts times ENCODER_RATIO
        (`encoders.py`); None when the axis is no encoder input with an encoder."""
        raw = self.raw_encoder(axis)
        return None if raw is None else raw * encoders.ratio(self.axes[axis].params)

    def frame_group(self, args: Sequence[float]) -> str:
        """FRAME_GROUP (frames.py): the group alone prints its line."""
        if not args or any(a != int(a) for a in args):
            raise ValueError("Parameter out of range")
        group = int(args[0])
        if len(args) == 1:
            return self.frames.describe(group)
        self.frames.frame_group(group, args[1], [int(a) for a in args[2:]])
        return ""

    def encoder_ratio(self, axis: int, mpos_count: float, input_count: float) -> None:
        """ENCODER_RATIO(mpos_count, input_count): an encoder input's MPOS keeps its
        value at the change (its DEFPOS offset takes up the difference, D)."""
        self._rescale_encoder(axis, lambda params: encoders.set_ratio(params, mpos_count,
                                                                      input_count))

    def _rescale_encoder(self, axis: int, change: Callable[[dict[str, float]], None]) -> None:
        """ENCODER_RATIO or PP_STEP changed: MPOS keeps its value (DEFPOS takes it up, D).
        On a servo axis the loop runs in MPOS counts (encoders.servo_rescale)."""
        a = self.axes[axis]
        if a.servo is not None:
            encoders.servo_rescale(a, change)
            self.changed()
            return
        before = self.encoder_counts(axis)
        change(a.params)
        after = self.encoder_counts(axis)
        if before is not None and after is not None:
            a.datum += before - after
        self.changed()

    def raw_encoder(self, axis: int) -> float | None:
        """The counts of the encoder the world mounts on this axis's encoder input, when
        the axis is an encoder input (ENCODER_ATYPES); None otherwise."""
        mount = self.world.encoders.get(axis)
        if mount is None or int(self.axes[axis].params["ATYPE"]) not in ENCODER_ATYPES:
            return None
        if not 0 <= mount.motor < self.axis_count:
            return None
        return mount.counts(self.motor_steps(mount.motor)
                            - self.world.axes[mount.motor].lost_steps)

    def motor_steps_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """Where the axis's world motor is at `ticks` (its steps before the stage's lost
        steps): the demand, with BACKLASH's compensation, through STEP_RATIO."""
        counts = self.output_counts_at(axis, ticks)
        comp = self.backlash.counts(axis, ticks, self.period)
        if comp is not None:
            counts = counts + comp
        return stepratio.motor(self.axes[axis].params, counts)

    def output_counts_at(self, axis: int, ticks: np.ndarray) -> np.ndarray:
        """The demand the axis puts out: its motor demand (a FRAME's inverse transform)
        through its POSI_SEQ delay line (posiseq.py)."""
        return self.posiseq.delayed(axis, ticks, self.motor_counts(axis, ticks))

    def output_counts(self, axis: int) -> float:
        return float(self.output_counts_at(axis, self._now())[0])

    def motor_steps(self, axis: int) -> float:
        return float(self.motor_steps_at(axis, self._now())[0])

    def command_offset(self, axis: int) -> Callable[[int], float] | None:
        """What a servo loop adds to its command at a tick: BACKLASH's compensation and
        the POSI_SEQ delay line's shift of the demand (None: neither, the loop runs
        compiled and in closed form)."""
        comp = self.backlash.offset(axis, self.period)
        if axis not in self.posiseq.lines:
            return comp

        def offset(tick: int) -> float:
            ticks = np.array([tick])
            demand = self.demand_counts(axis, ticks)
            shift = float(self.posiseq.delayed(axis, ticks, demand)[0] - demand[0])
            return shift + (0.0 if comp is None else comp(tick))

        return offset

    def compensation(self, axis: int) -> float:
        """BACKLASH's compensation on the axis now, counts."""
        comp = self.backlash.counts(axis, self._now(), self.period)
        return 0.0 if comp is None else float(comp[0])

    def axis_hardware(self, name: str, axis: int, args: Sequence[float]) -> None:
        """STEP_RATIO(output_count, dpos_count), BACKLASH(enable, ...) or COMPENSATE_XY(...)
        on an axis."""
        a = self.axes[axis]
        if name == "STEP_RATIO":
            stepratio.set_ratio(a.params, args, self.demand(axis) + self.compensation(axis))
        elif name == "BACKLASH":
            self.backlash.command(axis, args, a.units, self.tick * self.period)
        elif name == "ADD_DAC":  # (add_dac.py)
            self.drive.following.add_dac(axis, list(args))
        elif name == "COMBINE_CONTROL":  # kept, a running COMBINE_AXES takes it (combine.py)
            self.combinations.control(axis, args)
        elif name == "COMBINE_AXES":  # a linked move in the axis's buffer (combine.py)
            self._link(axis, self.combinations.combination(
                axis, args, lambda v: self._compensated_by(axis, v), a.units, a.datum))
            return
        elif name == "COMPENSATE_XY":  # a linked move in the axis's buffer (compensate.py)
            link = compensation_from(args, lambda v: self._compensated_by(axis, v),
                                     self.table.read_run, self.table.size, a.units)
            self._link(axis, link)
            return
        else:
            raise ValueError("Syntax error")
        self.changed()

    def _compensated_by(self, axis: int, value: float) -> int:
        """COMPENSATE_XY's X or Y axis: another axis, not following this one (D)."""
        leader = self.links.check_axis(value, axis)
        if self.links.depends(leader, axis):
            raise ValueError("Parameter out of range")
        return leader

    def input_inverted(self, number: int) -> bool:
        return number in self.inverted_inputs

    def invert_input(self, number: int, on: bool) -> None:
        """INVERT_IN(n, state)."""
        if on:
            self.inverted_inputs.add(number)
        else:
            self.inverted_inputs.discard(number)
        self.changed()
        self.drive.look(self.tick)

    def analog_input(self, channel: int) -> float:
        return self.world.analog_volts(channel, self)  # type: ignore[arg-type]

    def output(self, number: int) -> bool:
        """OP's setting OR every position switch driving the output, or the hardware
        timer's level while it runs (pswitch.py)."""
        return self.switches.level(number, self.digital_outputs.get(number, False))

    def set_output(self, number: int, on: bool) -> None:
        self.digital_outputs[number] = on
        self.changed()

    def set_corner_state(self, axis: int, value: float) -> None:
        self.axes[axis].params["CORNER_STATE"] = value
        self.changed()

    def params_of(self, axis: int) -> dict[str, float]:
        return self.axes[axis].params

    def axis_idle(self, axis: int) -> bool:
        a = self.axes[axis]
        return (not self.queues[axis] and a.link is None and a.pending_link is None
                and not self.links.chains[axis])

    def defpos(self, axes: Sequence[int], positions: Sequence[float]) -> None:
        if not all(abs(p * self.axes[a].units) < MAX_COUNTS
                   for a, p in zip(axes, positions, strict=True)):
            raise ValueError("Parameter out of range")  # every axis checked, none changed
        for a, p in zip(axes, positions, strict=True):
            axis = self.axes[a]
            counts = self.encoder_counts(a)  # an encoder input: its encoder reads p from now
            axis.datum = p * axis.units - (self.demand(a) if counts is None else counts)
        self.changed()
        self.drive.look(self.tick)

    def set_acc(self, axis: int, rate: float) -> None:
        params = self.axes[axis].params
        params["ACCEL"] = params["DECEL"] = rate
        self.changed()

    def datum(self, axis: int, mode: int) -> None:
        self.drive.datum(axis, mode)

    def disable_group(self, args: Sequence[float]) -> None:
        self.drive.errors.disable_group(args)  # (errors.py)
        self.changed()

    def initialise(self) -> None:
        initialise(self)  # (initialise.py)

    def cancel(self, axis: int, fast: bool = False, mode: float = 0) -> None:
        """Stop the axis's move or link; `fast` (the CANCEL command): at FASTDEC where it
        applies (`fast_decel`), else at DECEL (a jog released, a datum search). CANCEL
        page's modes: 1 drops the moves and linked moves buffered on the axis, the running
        one ends as planned; 2 drops them and cancels the running one (C). 3 to 6 (at
        speed into the next move, the last buffered move, MOVEADD) cancel the running
        move as 0 does (D: not modelled); others: 'Parameter out of range'."""
        if mode != int(mode) or not 0 <= mode <= 6:
            raise ValueError("Parameter out of range")
        self.movetests.cancel(axis)  # (movetest.py)
        if mode in (1, 2):
            self.links.chains[axis].clear()
            self._drop_buffered(self.queues[axis])
            if mode == 1:
                self.changed()
                return
        a = self.axes[axis]
        if a.link is not None or a.pending_link is not None:
            self._unlink(axis)
            self.links.cancelled(axis)  # the next linked move buffered starts
        elif self.queues[axis] and self.queues[axis][0].started:
            run = self.queues[axis][0]
            self._stop(run, self.fast_decel(run) if fast else None)
        self.changed()

    def fast_decel(self, run: Run) -> float | None:
        """The rate a CANCEL, RAPIDSTOP or a limit stops the run at: its base's FASTDEC
        (counts/s^2) when set and greater than DECEL, else None: its DECEL (C: CANCEL,
        RAPIDSTOP and FASTDEC pages, 'FASTDEC must be greater than DECEL, otherwise DECEL
        will be used')."""
        fast = self.axes[run.base].params["FASTDEC"] * run.units
        return fast if fast > run.decel else None

    def rapidstop(self, mode: float = 0) -> None:
        """RAPIDSTOP(mode) on every axis (its page): 0 cancels the running moves and links,
        those buffered then load ('motion will not stop'); 1 drops every buffered move
        and linked move, the running ones end as planned; 2 both (C). Running moves ramp
        down at FASTDEC where it applies. Other modes: 'Parameter out of range'."""
        if mode not in (0, 1, 2):
            raise ValueError("Parameter out of range")
        self.movetests.cancel()  # (movetest.py)
        if mode:
            self.links.clear()
            for queue in self.queues:
                self._drop_buffered(queue)
        if mode == 1:
            self.changed()
            return
        for axis in range(self._axis_count):
            if self.axes[axis].link is not None or self.axes[axis].pending_link is not None:
                self._unlink(axis)
                self.links.cancelled(axis)  # (mode 0: the next linked move buffered starts)
        for queue in self.queues:
            if queue and queue[0].started and not queue[0].stopping:
                self._stop(queue[0], self.fast_decel(queue[0]))
        self.changed()

    def _drop_buffered(self, queue: deque[Run]) -> None:
        """The runs waiting in an axis's buffer go, from every axis of their group."""
        for run in [r for r in queue if not r.started]:
            for a in run.axes:
                kept = [r for r in self.queues[a] if r is not run]
                self.queues[a].clear()
                self.queues[a].extend(kept)

    def connpath(self, axis: int, args: Sequence[float]) -> None:
        base = args[0]
        if base != int(base) or not 0 <= base < self._axis_count or int(base) == axis:
            raise ValueError("Invalid axis number")
        ratio = args[1] if len(args) > 1 else 1.0
        link = Connpath(int(base), ratio, 0.0, 0.0)
        self._link(axis, link)

    def cambox(self, axis: int, args: Sequence[float]) -> None:
        """CAMBOX on the axis, or its multi-axis loading form CAMBOX(table start, axis
        count) (`cambox_group`): every option of the help page but bits 5 and 14."""
        if len(args) < 5:
            raise ValueError("Syntax error")
        self._load_camboxes([(axis, self._cambox(axis, args))])

    def cambox_group(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """CAMBOX(table start, axis count): the axes' CAMBOXes from consecutive TABLE
        values, 8 per axis; all checked before any is loaded (C: CAMBOX page)."""
        start = args[0]
        if start != int(start) or start < 0:
            raise ValueError("Parameter out of range")
        rows = multi_axis(int(start), len(axes), self.table.read)
        self._load_camboxes([(a, self._cambox(a, row)) for a, row in zip(axes, rows,
                                                                          strict=True)])

    def _cambox(self, axis: int, args: Sequence[float]) -> Cambox:
        link_axis = args[4]
        if link_axis != int(link_axis) or not 0 <= link_axis < self._axis_count \
                or int(link_axis) == axis:
            raise ValueError("Invalid axis number")
        if self.links.depends(int(link_axis), axis):
            raise ValueError("Parameter out of range")  # a loop of CAMBOX links (D)
        if not args[3] * self.axes[int(link_axis)].units >= MIN_LINK_COUNTS:
            raise ValueError("Parameter out of range")  # (D: cycles no double counts)
        return cambox_from(args, self.table.read, self.table.read_run)

    def _load_camboxes(self, cams: list[tuple[int, Cambox]]) -> None:
        if not all(self.can_load([a]) for a, _cam in cams):
            raise ValueError("Parameter out of range")  # (a group waits for none: D)
        for axis, cam in cams:
            self._link(axis, cam)

    def movetest(self, axis: int, args: Sequence[float]) -> None:
        """MOVETEST(...) AXIS(n): a forward and back test cycle (movetest.py)."""
        self.movetests.movetest(axis, list(args))
        self.changed()

    def regist(self, axis: int, args: Sequence[float]) -> None:
        """REGIST(mode) AXIS(n): arm a registration capture (registration.py)."""
        self.registration.regist(axis, list(args))

    def position_switch(self, name: str, axis: int, args: Sequence[float]) -> None:
        """PSWITCH(...) / HW_PSWITCH(...) AXIS(n) (pswitch.py)."""
        if name == "PSWITCH":
            self.switches.pswitch(args)
        elif name == "HW_TIMER":
            self.switches.hw_timer(args)
        else:
            self.switches.hw_pswitch(axis, args)

    def pwm_control(self, axis: int, args: Sequence[float]) -> None:
        self.outputs.control(axis, args)
        self.changed()

    def table_read(self, index: int) -> float:
        return self.table.read(index)

    def table_write(self, start: int, values: Sequence[float]) -> None:
        held: list[tuple[Cambox, float | None]] = []
        for a in self.axes:  # the CAMBOXes read their TABLE live (cams.py)
            for cam in (a.link, a.pending_link):
                if isinstance(cam, Cambox):
                    running = cam is a.link and cam.link_origin is not None
                    held.append((cam, self.dpos(cam.link) if running else None))
        cams = [run for queue in self.queues for run in queue if run.cam is not None]
        if held or cams:
            self.outputs.sync_all()  # the encoders see the motion before a cam changes
        self.table.write(start, values)
        retable(held, start, len(values), self.table.read_run)
        for run in cams:  # a CAM too (cams.recam): over the same time
            profile = recam(run, start, len(values), self.table.read_run)
            if profile is not None and run.started:
                axis = self.axes[run.base]
                run.profile = axis.motion = profile
                axis.direction = profile.direction
        self.changed()

    def vr_read(self, index: int) -> float:
        return self.vr.read(index)

    def vr_write(self, index: int, value: float) -> None:
        self.vr.write(index, value)
        self.changed()

    # ---- loading moves -------------------------------------------------------------------------
    def _end_counts(self, axis: int) -> float:
        """Where the axis stands once its buffered moves are done (physical counts, its
        own demand: ADDAX's part not included)."""
        position = self.own_demand(axis)
        for run in self.queues[axis]:
            k = run.axes.index(axis)
            if run.started and run.profile is None and run.plan is not None:
                position = float(round(run.plan.point(run.plan.s_end, k)))
            elif run.started and run.profile is not None:
                position = float(self.axes[axis].steps + run.profile.final_offset) \
                    if self.axes[axis].motion is not None else position
            else:
                position += sum(delta[k] for delta in run.deltas)
        return position

    def movecirc(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """MOVECIRC(end1, end2, centre1, centre2, direction): an arc on the shared path
        planner from here to the end, about the centre (both relative): moves.arc_of."""
        if len(args) < 5 or any(a != 0 for a in args[5:]):
            raise ValueError("Parameter out of range")
        ex, ey, arc = moves.arc_of(self, tuple(axes), list(args))
        self._load(tuple(axes), [ex, ey], arc=arc, kind=moves.MOVECIRC)

    # ---- linked moves and the moves of links.py / moves.py --------------------------------
    def mhelical(self, axes: Sequence[int], args: Sequence[float]) -> None:
        moves.mhelical(self, tuple(axes), list(args))

    def geometric_move(self, name: str, axes: Sequence[int], args: Sequence[float]) -> None:
        """MSPHERICAL / MSPHERICALSP (geometry.py), the SP form at FORCE_SPEED; MOVETANG
        (tangential.py) on its one axis."""
        if name == "MOVETANG":
            tangential.movetang(self, axes[0], args, MIN_RATE)
            return
        sp = name.endswith("SP")
        self._speed_name = "FORCE_SPEED" if sp else "SPEED"
        try:
            geometry.mspherical(self, tuple(axes), list(args),
                                geometry.MSPHERICALSP if sp else geometry.MSPHERICAL)
        finally:
            self._speed_name = "SPEED"

    def sequence(self, name: str, axes: Sequence[int], args: Sequence[float]
                 ) -> list[tuple[str, list[float]]]:
        """MOVEABSSEQ / MOVESEQ: the moves they load, from where the group's buffered
        moves end (sequences.py)."""
        start = [(self._end_counts(a) + self.axes[a].datum + self.links.shift[a])
                 / self.axes[a].units for a in axes]
        return sequences.plan(name, args, start, self.table.read)

    def movemodify(self, axis: int, args: Sequence[float]) -> None:
        moves.movemodify(self, axis, args[0], MIN_RATE)

    def motion_horizon(self) -> int | None:
        """The next tick the motion changes by itself (a run or a CAMBOX ends)."""
        for source in self._sources:
            if isinstance(source, _MotionEvents):
                return source.next_event()
        return None

    def can_link(self, axis: int) -> bool:
        return self.links.can_load(axis)

    def connect(self, axis: int, args: Sequence[float]) -> None:
        self.links.connect(axis, list(args))

    def sync(self, axes: Sequence[int], args: Sequence[float]) -> None:
        """SYNC(control, time[, sync pos, sync axis, pos1[, pos2[, pos3]]]) (sync.py)."""
        self.links.syncs.command(list(axes), list(args), self.links.depends)

    def movelink(self, axis: int, args: Sequence[float]) -> None:
        self.links.movelink(axis, list(args))

    def flexlink(self, axis: int, args: Sequence[float]) -> None:
        self.links.flexlink(axis, list(args))

    def addax(self, axis: int, args: Sequence[float]) -> None:
        self.links.set_addax(axis, args[0])

    def cam(self, axis: int, args: Sequence[float]) -> None:
        """CAM(start, end, multiplier, distance): the TABLE profile in time (cams.py)."""
        a = self.axes[axis]
        motion = cam_motion(args, self.table.read_run, a.params["SPEED"] * a.units,
                            a.units)
        self._load((axis,), [motion.final_offset], kind=moves.CAM, preset=motion)
        for run in self.queues[axis]:
            if run.preset is motion:
                run.table, run.cam = int(args[0]), (int(args[1]), float(args[2]))

    def table_pointer(self, axis: int) -> float:
        """TABLE_POINTER: where in its TABLE the axis's CAMBOX or running CAM is; 0 with
        neither (D)."""
        link = self.axes[axis].link
        if isinstance(link, Cambox):
            return link.pointer(float(self.dpos_at(link.link, self._now())[0]))
        run = self.queues[axis][0] if self.queues[axis] else None
        if run is None or run.table is None or not run.started or run.profile is None:
            return 0.0
        return cam_pointer(run, (self.tick - self.axes[axis].motion_start) * self.period)

    def _load(self, axes: tuple[int, ...], deltas: list[int],
              arc: tuple[float, ...] | None = None, kind: int = moves.MOVE,
              preset: Motion | None = None, helix: float = 1.0) -> None:
        """Queue one move; `helix` (MHELICAL mode 0, moves.py) is the path's length over
        the planned arc's: the rates along the arc are that much lower."""
        self.drive.check_move(axes)
        base = self.axes[axes[0]]
        speed = base.params[self._speed_name] * base.units
        accel = base.params["ACCEL"] * base.units
        decel = base.params["DECEL"] * base.units
        jerk = jerk_counts(base.params, base.units)
        if self._speed_name == "SPEED":  # SPEED_FACTOR, ACCEL_FACTOR (VP_MODE 5, 6)
            speed_factor, accel_factor = vp_factors(base.params)
            speed, accel, decel = (speed * speed_factor, accel * accel_factor,
                                   decel * accel_factor)
        if self._speed_name == "FORCE_SPEED":  # an SP move's own rates (profiles_sp.py)
            accel, decel, jerk = forced_rates(base.params, base.units, accel, decel, jerk)
        waits = (speed == 0 and self._speed_name == "SPEED" and preset is None
                 and kind not in _NOT_HELD)  # loaded at SPEED 0: held (CONNPATH page)
        if not min(max(speed, MIN_RATE) if waits else speed, accel, decel) >= MIN_RATE:
            raise ValueError("Parameter out of range")
        speed, accel, decel = speed / helix, accel / helix, decel / helix
        for a, delta in zip(axes, deltas, strict=True):
            end = self._end_counts(a) + delta  # physical counts
            if not (abs(delta) < MAX_COUNTS and abs(end + self.axes[a].datum) < MAX_COUNTS
                    and abs(end) <= MAX_PHYSICAL):
                raise ValueError("Parameter out of range")
        share = 1.0
        if arc is None and kind in (moves.MOVE, moves.MOVEABS):  # INTERP_FACTOR (C)
            share = interp_share([self.axes[a].params.get("INTERP_FACTOR", 1.0)
                                  for a in axes], [float(d) for d in deltas])
            if share == 0:
                return  # no interpolated axis moves: done at once, nothing moves (C)
            speed, accel = speed / share, accel / share
        merge = base.params["MERGE"] != 0 and preset is None  # (a CAM never merges: D)
        corner = self.corners.holds(axes, deltas, arc)  # held behind a corner (C)
        merge = merge and not corner
        if waits:  # (a move held at 0 merges only behind moves held at 0, D)
            queue = self.queues[axes[0]]
            merge = merge and bool(queue) and not any(queue[-1].speeds)
        carried = {a: move_pa.copies(self.axes[a].params) for a in axes}  # (move_pa.py)
        sp = (sp_speeds(base.params, base.units) if self._speed_name == "FORCE_SPEED"
              else None)
        last = self.queues[axes[0]][-1] if self.queues[axes[0]] else None
        dwell = max(0.0, base.params.get("FORCE_DWELL", 0.0)) / 1000.0 if sp is not None \
            else 0.0  # (an SP move's dwell at its end, FORCE_DWELL page: C)
        if sp is not None:  # INTERP_FACTOR, LOOKAHEAD_FACTOR, FORCE_RAMP (profiles_sp.py)
            speed, accel, sp = sp_adjusted(base.params, base.units, speed, accel, sp, share)
        if sp is not None:  # CORNER_MODE and the directions (profiles_sp.py)
            speed, sp, headings = cornered(base.params, base.units, speed, accel, sp,
                                           tuple(float(d) for d in deltas), arc)
            for name, value in zip(DIRECTIONS, headings, strict=True):
                base.params[name] = value
        speed = v_limited(speed, [self.axes[a].params.get("V_LIMIT", 0.0) * self.axes[a].units
                                  for a in axes], [float(d) for d in deltas],
                          arc is not None, base.params.get("VP_MODE", 0.0))  # V_LIMIT (C)
        if (merge and last is not None and last.axes == axes and last.mergeable
                and all(self.queues[a] and self.queues[a][-1] is last for a in axes)):
            if arc is not None:
                last.arcs[len(last.deltas)] = arc
            last.kinds[len(last.deltas)] = kind
            if sp is not None:
                last.forced[len(last.deltas)] = forced_values(base.params)
                last.sp[len(last.deltas)] = sp
                last.factored[len(last.deltas)] = lookahead(base.params)
            last.carried[len(last.deltas)] = carried
            if share != 1.0:
                last.interp[len(last.deltas)] = share
            last.deltas.append(tuple(deltas))
            last.speeds.append(speed)
            last.accels.append(accel)
            last.dwell = dwell
            if last.started:
                last.resolve(())
                self._apply_plan(last, last.plan_new(self.tick, period=self.period))
            self.changed()
            return
        run = Run(axes, [tuple(deltas)], [speed], [accel], decel, base.units,
                  single=len(axes) == 1 and not merge and not waits,
                  sramp=sramp_seconds(base.params),
                  jerk=jerk / helix, preset=preset)
        if sp is not None:
            run.forced[0] = forced_values(base.params)
            run.sp[0] = sp
            run.factored[0] = lookahead(base.params)
        if arc is not None:
            run.arcs[0] = arc
        run.kinds[0] = kind
        run.carried[0] = carried
        run.corner = CORNER_HELD if corner else 0
        run.dwell = dwell
        if share != 1.0:
            run.interp[0] = share
        for a in axes:
            self.queues[a].append(run)
        self._start_ready()
        if self.feedhold.held:
            self.feedhold.look()  # (a move starting under a feed hold)
        self.changed()

    def _start_ready(self) -> None:
        """Start every run at the head of all its axes' queues whose axes are free."""
        for queue in self.queues:
            run = queue[0] if queue else None
            if run is None or run.started or run.corner == CORNER_HELD:
                continue
            if all(self.queues[a][0] is run and self.axes[a].link is None
                   and self.axes[a].pending_link is None for a in run.axes):
                self._start(run)
                self.drive.started(run)
        moves.count_moves(self)  # MOVE_COUNT: the runs that started
        self.move_pa.update()  # MOVE_PA/MOVE_PB of the moves that became active
        self.corners.update()  # CORNER_STATE: a held corner move next, or loaded

    def _start(self, run: Run) -> None:
        now = self.tick
        run.started = True
        run.start_tick = now
        for a in run.axes:  # a linked axis that stopped between counts starts from a count
            axis = self.axes[a]
            axis.steps, axis.fraction = round(axis.steps + axis.fraction), 0.0
        if run.single:
            axis = self.axes[run.base]
            run.profile = run.preset if run.preset is not None else single_profile(
                run.deltas[0][0], run.speeds[0], run.accels[0], run.decel, run.sramp,
                run.jerk)
            axis.begin(run.profile, self)
            self.backlash.began(run.base, run.profile, now * self.period)
            run.end_tick = (axis.motion_end if axis.motion_end is not None else now) \
                + self._dwell_ticks(run)
            return
        run.resolve(tuple(float(self.axes[a].steps) for a in run.axes))
        self._apply_plan(run, run.plan_new(now, period=self.period))

    def _apply_plan(self, run: Run, plan: PathPlan) -> None:
        now = self.tick
        run.plan = plan
        run.arrays = PlanArrays(plan, run.arrays)  # (its segment rows grow)
        run.plan_tick = now
        end = plan.end_time
        run.end_tick = (now + math.ceil(end / self.period - 1e-9) + self._dwell_ticks(run)
                        if end is not None else HELD)  # (held at speed 0: feed hold)
        for k, a in enumerate(run.axes):
            axis = self.axes[a]
            axis.steps = axis.steps_at_tick(now, self.period)
            axis.begin(run.motion_for(plan, k, axis.steps), self)
            if axis.motion is not None:
                self.backlash.began(a, axis.motion, now * self.period)

    def _dwell_ticks(self, run: Run) -> int:
        """FORCE_DWELL's wait after the run's last move, whole servo ticks (D: rounded
        up to the servo cycle)."""
        return math.ceil(run.dwell / self.period - 1e-9) if run.dwell > 0 else 0

    def _stop(self, run: Run, decel: float | None = None) -> None:
        """CANCEL: ramp down now (at `decel` counts/s^2, FASTDEC; else a linear path
        along itself at its ACCEL, a single axis or an S-curve path at DECEL); the moves
        buffered behind it then run (a FORCE_DWELL waiting is dropped, D)."""
        run.stopping = True
        run.dwell = 0.0
        run.jerk = stop_jerk(self.axes[run.base].params, run.units, run.jerk)  # FASTJERK
        if run.profile is not None:
            axis = self.axes[run.base]
            residual, velocity = axis.freeze(self)
            run.profile = run.stop_profile(residual, velocity,
                                           run.decel if decel is None else decel)
            run.start_tick = self.tick
            axis.begin(run.profile, self)
            self.backlash.began(run.base, run.profile, self.tick * self.period)
            run.end_tick = axis.motion_end if axis.motion_end is not None else self.tick
            run.deltas = run.deltas[:1]
            return
        self._apply_plan(run, run.plan_new(self.tick, stop=True, period=self.period,
                                           decel=decel))
        run.deltas = run.deltas[:len(run.segments)]

    def _finish_runs(self, now: int) -> None:
        for queue in self.queues:
            run = queue[0] if queue else None
            if run is None or not run.started or run.end_tick > now:
                continue
            tangential.finished(self, run)
            for a in run.axes:
                axis = self.axes[a]
                if axis.motion is not None:
                    axis.finish_motion()
                self.queues[a].popleft()
            self.distance_done[run.base] += run.length() / run.units
        for a, axis in enumerate(self.axes):
            if axis.pending_link is not None and not self.queues[a]:
                link, axis.pending_link = axis.pending_link, None
                self._attach(a, link)
        self._start_ready()

    # ---- linked axes --------------------------------------------------------------------------
    def _link(self, axis: int, link: Link) -> None:
        a = self.axes[axis]
        if self.queues[axis]:
            a.pending_link = link  # it starts when the buffered moves are done
        else:
            self._attach(axis, link)
        self.changed()

    def _attach(self, axis: int, link: Link, handover: Link | None = None) -> None:
        if self.links.attach(axis, link, handover):  # CONNECT, MOVELINK
            return
        link.origin = self.own_demand(axis)
        if isinstance(link, Connpath):
            link.distance0 = float(self.path_distance(link.base, self._now())[0])
        elif isinstance(link, Compensation):  # the correction here is its offset
            link.begin(self.dpos(link.link), self.dpos(link.link_y))
        else:
            assert isinstance(link, Cambox)
            self._start_cambox(link)
        self.axes[axis].link = link

    def _start_cambox(self, cam: Cambox) -> None:
        """A CAMBOX takes effect: from here, from its absolute link position (already
        past it: from where the link is, D), or on its registration event (one already
        captured on the link axis counts, D)."""
        here = cam.origin
        link_now = self.dpos(cam.link)
        if cam.follow is not None:
            cam.follow.rebase(link_now)
        if cam.wait is not None:  # MARK, MARKB, R_MARKn: one already captured counts (D)
            position = self.registration.captured(cam.link, cam.wait)
            if position is not None:
                cam.start_at(position, here)
                cam.held, cam.wait = True, None
            return
        if cam.start_pos is not None:
            start = self.unwrapped(cam.link, cam.start_pos, link_now)
            cam.start_at(max(start, link_now), here)
            cam.held = True
            return
        cam.start_at(link_now, here)

    def _cambox_done(self, axis: int) -> None:
        """A CAMBOX reached its end: a pattern-mode one takes its next shape, else it
        ends and what is buffered behind it starts."""
        link = self.axes[axis].link
        if isinstance(link, Cambox) and link.pattern is not None:
            try:
                going_on = next_pattern(link, self.table.read,
                                        lambda i, v: self.table.write(i, [v]))
            except (ValueError, IndexError):  # a control block pointing outside TABLE
                going_on = False  # the CAMBOX ends there (D: the program is not stopped)
            if going_on:
                self.changed()
                return
        self._unlink(axis)
        self.links.cancelled(axis)
        self.changed()

    def _unlink(self, axis: int) -> None:
        a = self.axes[axis]
        if a.link is not None:
            position = self.own_demand(axis)
            a.link = None
            a.steps = math.floor(position)
            a.fraction = position - a.steps
        a.pending_link = None
        a.link_end = None

    def _finish_camboxes(self, now: int) -> None:
        for a, axis in enumerate(self.axes):
            if isinstance(axis.link, Cambox) and axis.link_end is not None \
                    and axis.link_end <= now:
                self._cambox_done(a)  # a linked move buffered behind it starts


class _FollowWatch:
    """At every event tick, the forward-only links (link option bits 5 and 14) take in
    their link's travel so far: between events each link's motion is one closed form,
    monotonic (D), so the effective travel stays exact."""

    every_event = True

    def __init__(self, machine: MC405Machine) -> None:
        self.machine = machine

    def next_event(self) -> int | None:
        return None

    def on_event(self, now: int) -> None:
        self.machine.links.rebase()


class _MotionEvents:
    """Runs, their moves and CAMBOXes ending: the ticks the motion changes by itself."""

    def __init__(self, machine: MC405Machine) -> None:
        self.machine = machine
        self._cache: tuple[int, int | None] = (-1, None)  # (revision, next event)

    def next_event(self) -> int | None:
        m = self.machine
        if self._cache[0] == m.revision:  # (an event due now stays due until it acts)
            return self._cache[1]
        best: int | None = None
        for queue in m.queues:
            run = queue[0] if queue else None
            if run is None or not run.started:
                continue
            boundary = run.next_boundary(m.tick, m.period)  # a buffered move finished
            for tick in (run.end_tick, boundary):
                if tick is not None and (best is None or tick < best):
                    best = tick
        for a, axis in enumerate(m.axes):
            if isinstance(axis.link, Cambox):
                axis.link_end = m.cambox_end_tick(a)
                if axis.link_end is not None and (best is None or axis.link_end < best):
                    best = axis.link_end
        if best is not None:
            best = max(best, m.tick)
        self._cache = (m.revision, best)
        return best

    def on_event(self, now: int) -> None:
        m = self.machine
        m.outputs.sync_all()  # the encoders see the motion before it changes
        m._finish_camboxes(now)
        m._finish_runs(now)
        m.changed()


__all__ = ["MOVE_BUFFER", "SERVO_PERIODS", "GateEdge", "MC405Machine", "PwmError", "TrioAxis"]

"""One MM4005 axis on the shared machine: its settings in user units and its motion.

Positions are whole encoder counts (the shared `MotionAxis` steps, physical: what the
world's switches see); the host reads ``(steps + counter_offset) x TU`` in its units, so
``counts = units / TU``. VA and AC are user units per second (squared) and become counts
per second for the closed-form profiles (`profiles.plan_move`, linear ramps: the manual's
trapezoidal profile, MM4006 4.4.1).

What the axis is doing beyond its motion (a home search's stage, a destination waiting
for a stop to end, a trajectory driving it) is held here; the machine acts on it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import TYPE_CHECKING, Protocol

from maxk.firmware_model.axis import MotionAxis
from maxk.firmware_model.servo import Gains


@dataclass(frozen=True, slots=True)
class ServoConfig:
    """What the shared servo loop reads of an MM4005 axis: the PID gains in force."""

    gains: Gains = Gains()
    servo_polarity: int = 1

if TYPE_CHECKING:
    from maxk.firmware_model.engine import Engine


class AxisHost(Protocol):
    """What an axis asks of its machine when one of its events is due."""

    def axis_event(self, axis: MM4005Axis, now: int) -> None: ...


class HomeStage(Enum):
    """Where an OR home search is (our decision, docs/mm4005.md)."""

    SEEK = "seek"  # travelling at VA toward the home switch's edge
    BRAKE = "brake"  # edge latched, decelerating at AC
    RETURN = "return"  # moving back onto the latched edge


@dataclass
class HomeSearch:
    stage: HomeStage
    direction: int  # the way the search travels while seeking
    edge: int | None  # physical count that becomes the home preset (None: no usable switch)


@dataclass(eq=False)
class MM4005Axis(MotionAxis):
    """An MM4005 axis: settings as the host sets them, the motion the engine runs."""

    host: AxisHost | None = None
    resolution: float = 0.001  # TU, user units per encoder count
    speed: float = 1.0  # VA, units/s
    acceleration: float = 4.0  # AC, units/s^2
    loop_type: int = 0  # TC (0 open loop, as the EPICS test device answered)
    limits: tuple[float, float] = (-100.0, 100.0)  # TL/TR, changed by SL/SR and DH
    home_preset: float = 0.0  # XH (SH sets it)
    powered: bool = True  # MO / MF
    target_counts: int = 0  # DP, in counts
    homing: HomeSearch | None = None
    pending_target: int | None = None  # a PA/PR given while moving: after the stop
    in_trajectory: bool = False
    # the loop's settings as the shared servo reads them (gains in force since UF)
    config: ServoConfig = field(default_factory=lambda: ServoConfig())

    # ---- the engine's event-source interface ---------------------------------------------
    def next_event(self) -> int | None:
        """A home search's edge; the motion's end and the limits are the machine's shared
        `MotionEnds`'."""
        return self.switch_tick

    def on_event(self, now: int) -> None:
        assert self.host is not None
        self.host.axis_event(self, now)

    # ---- units -------------------------------------------------------------------------
    def to_counts(self, units: float) -> int:
        """A position in user units as whole counts (TU steps)."""
        return round(units / self.resolution)

    def counts_at(self, tick: int, period: float) -> int:
        """The profile's whole counts at a tick (the commanded position)."""
        return self.steps_at_tick(tick, period) + self.counter_offset

    def encoder(self, engine: Engine) -> int:
        """The encoder counter (TP): the servo's plant when the loop runs (KP set and
        applied by UF), else the profile's whole counts (the exact, profile-only axis)."""
        servo = self.servo
        if servo is not None:
            return servo.encoder_counts() + self.counter_offset
        return self.counts(engine)

    def counts(self, engine: Engine) -> int:
        return self.counts_at(engine.tick, engine.period)

    def exact_counts(self, engine: Engine) -> float:
        """Where the profile generator has the axis now, fractions of a count included
        (TH, the theoretical position)."""
        m = self.motion
        if m is None or (self.motion_end is not None and engine.tick >= self.motion_end):
            return float(self.counts(engine))
        t = (engine.tick - self.motion_start) * engine.period
        return self.steps + self.counter_offset + m.offset(t)

    def exact_counts_at(self, engine: Engine, tick: int) -> float:
        """The profile's exact counts at any tick of the running motion."""
        m = self.motion
        if m is None or (self.motion_end is not None and tick >= self.motion_end):
            return float(self.counts_at(tick, engine.period))
        return self.steps + self.counter_offset + m.offset((tick - self.motion_start)
                                                           * engine.period)

    def th_tp_counts(self, engine: Engine) -> tuple[float, int]:
        """(TH, TP) in counts now, the profile evaluated once (a pulse's trace point)."""
        m = self.motion
        if m is None or (self.motion_end is not None and engine.tick >= self.motion_end):
            counts = self.counts(engine)
            return float(counts), self.encoder(engine) if self.servo is not None else counts
        offset = m.offset((engine.tick - self.motion_start) * engine.period)
        base = self.steps + self.counter_offset
        servo = self.servo
        if servo is not None:
            return base + offset, servo.encoder_counts() + self.counter_offset
        return base + offset, base + int(offset)

    def servo_counts(self) -> int:
        """The encoder counter of a servo axis."""
        assert self.servo is not None
        return self.servo.encoder_counts() + self.counter_offset

    def counts_per_second(self, units: float) -> float:
        return units / self.resolution

    def load_position(self, counts: int, engine: Engine) -> None:
        """The counter reads `counts` here (DH, the end of a home search); the stage stays."""
        self.counter_offset = counts - self.steps_now(engine)
        self.target_counts = counts

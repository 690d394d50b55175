"""A MAXk axis's parameters (what commands set and the archive keeps) and its counters'
width. Kept below every other module of the personality: the archive, the capture ring,
homing and the axis all read it."""

from __future__ import annotations

from dataclasses import dataclass, field

from maxk.firmware_model.profiles import Motion, RampShape, plan_move
from maxk.firmware_model.servo import Gains


def wrap32(value: int) -> int:
    """Position counters are signed 32-bit registers: they wrap, as the hardware's do."""
    return ((value + 0x8000_0000) & 0xFFFF_FFFF) - 0x8000_0000


class _PlanParameters:
    """The parameters an axis's memoised plans were made with (AxisConfig.plan_move)."""

    __slots__ = ("velocity", "acceleration", "deceleration", "base_velocity", "ramp",
                 "ramp_factor", "scurve_factor", "ramp_parameter")

    def __init__(self, c: AxisConfig | None = None) -> None:
        """The parameters of `c`; none (matching no configuration) without one."""
        self.ramp: RampShape | None = None
        self.velocity = self.acceleration = self.deceleration = self.base_velocity = 0
        self.ramp_factor = self.scurve_factor = self.ramp_parameter = 0
        if c is not None:
            self.velocity = c.velocity
            self.acceleration = c.acceleration
            self.deceleration = c.deceleration
            self.base_velocity = c.base_velocity
            self.ramp = c.ramp
            self.ramp_factor = c.ramp_factor
            self.scurve_factor = c.scurve_factor
            self.ramp_parameter = c.ramp_parameter

    def same(self, c: AxisConfig) -> bool:
        return (self.velocity == c.velocity and self.acceleration == c.acceleration
                and self.deceleration == c.deceleration
                and self.base_velocity == c.base_velocity and self.ramp is c.ramp
                and self.ramp_factor == c.ramp_factor
                and self.scurve_factor == c.scurve_factor
                and self.ramp_parameter == c.ramp_parameter)


@dataclass
class AxisConfig:
    """The axis parameters that commands set; factory defaults from manual 2.14."""

    velocity: int = 200_000  # VL, steps/s
    base_velocity: int = 0  # VB
    acceleration: int = 2_000_000  # AC (also sets the deceleration)
    deceleration: int = 2_000_000  # DC
    ramp: RampShape = RampShape.LINEAR
    ramp_factor: int = 0  # PN#: the parabolic curve's degree (0: factory, the square)
    scurve_factor: int = 0  # SS#: S-curve jerk share of acceleration ramps, % (0: 100)
    ramp_parameter: int = 0  # PR#: S-curve jerk share of deceleration ramps, % (0: as SS)
    axis_type: str = "O"  # PSO open-loop stepper, PSE stepper with encoder, PSM servo
    limit_active_high: bool = False  # LTL factory: active low
    limits_enabled: bool = True  # LN/LF, LMN/LMF
    limit_hard_stop: bool = True  # LMH stop at once (factory "hard"), LMS decelerate
    home_active_high: bool = False  # manual 2.14: "Home Active 'Low'" (HT/HH/HL)
    home_encoder: bool = False  # HE: encoder home logic; HS (factory): home switch alone
    home_pattern: str = "1111"  # EH: +A, -B, Index, Home switch (1 true, 0 false, X ignore)
    move_direction: int = 1  # MP / MM
    aux_auto: bool = False  # PA1: aux output on while moving
    settle_ms: int = 0  # SE: aux stays on this long after the axis comes to rest
    gains: Gains = field(default_factory=Gains)  # KP KI KD KU KV KA KF KO (servo)
    servo_bipolar: bool = True  # SVB1 +/-10 V (factory), SVB0 unipolar 0..10 V + sign
    servo_polarity: int = 1  # SVN normal (factory); SVI inverts the DAC output
    encoder_ratio: tuple[int, int] = (1, 1)  # ER: encoder counts, motor steps
    slip_tolerance: int = 0  # ES: encoder counts of disagreement before a slip
    slip_detect: bool = False  # TN/TF: stall (slip) detection on/off
    hold_velocity: int = 0  # HV: position maintenance correction velocity
    hold_deadband: int = 0  # HD: position maintenance deadband, encoder counts
    hold_gain: int = 0  # HG: position maintenance gain (stored)
    user_units: float | None = None  # UU: counts per user unit; None after UF (factory)
    encoder_interface: str = "incremental"  # ECI (factory) | "SSI" (ECA) | "BiSS" (ECB)
    absolute_encoder: tuple[int, int] | None = None  # ECA/ECB: data bits, clock Hz
    encoder_inverted: bool = False  # EDI / EDN (stored: the count is not inverted)
    kod: float = 0.0  # KOD: a second offset term, stored only (meaning unknown)
    backlash: int = 0  # BC: backlash compensation, steps
    # the moves planned with these parameters, by distance, and the parameters they were
    # planned with (VB, VL, AC, DC, the ramp and its three factors): a scan repeats its
    # moves, and a plan is never modified once made. The parameters are compared at every
    # move, not the memo dropped in a __setattr__: compiled (maxk/compiled.py), the class's
    # attributes are set without calling one.
    _moves: dict[int, Motion] = field(default_factory=dict, init=False, repr=False,
                                      compare=False)
    _planned_for: _PlanParameters = field(default_factory=_PlanParameters, init=False,
                                          repr=False, compare=False)

    def plan_move(self, distance: int) -> Motion:
        """A point-to-point move from rest over `distance` steps at VB, VL, AC, DC and the
        selected ramp (memoised per parameter set: one dictionary lookup a move)."""
        key = self._planned_for
        if not key.same(self):
            self._planned_for = _PlanParameters(self)
            self._moves = {}
        moves = self._moves
        motion = moves.get(distance)
        if motion is None:
            if len(moves) >= 256:
                moves.clear()
            motion = moves[distance] = plan_move(
                distance, self.base_velocity, self.velocity, self.acceleration,
                self.deceleration, self.ramp, *self.ramp_params)
        return motion

    @property
    def ramp_params(self) -> tuple[float | None, float | None]:
        """The shape parameters (acceleration, deceleration ramps) of the selected ramp
        for `profiles.plan_move` (None: the factory curve). Decisions (D), recorded in
        the command table: PN# is the parabolic curve's degree; SS# the percentage of an
        S-curve acceleration ramp spent changing the acceleration (the two corners
        share it), PR# the same for deceleration ramps; 0 keeps the factory curve (a full
        S-curve; PR0 follows SS)."""
        if self.ramp is RampShape.PARABOLIC:
            degree = float(self.ramp_factor) if self.ramp_factor else None
            return degree, degree
        if self.ramp is RampShape.SCURVE:
            up = self.scurve_factor / 100.0 if self.scurve_factor else None
            down = self.ramp_parameter / 100.0 if self.ramp_parameter else up
            return up, down
        return None, None

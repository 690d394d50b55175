"""The motor a servo axis drives: part of the world around a controller, not of its
firmware. python-control builds its transfer function (DAC counts in, encoder counts
out) and discretizes it at the update period, once per parameter set; `control` is
imported only when a servo first needs it."""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

VOLTS_PER_COUNT = 10.0 / 32767.0  # a 16-bit DAC: +/-32767 counts = +/-10 V
PlantMatrices = tuple[float, float, float, float, float, float]  # a11 a12 a21 a22 b1 b2
PARAMETER_SMALLEST, PARAMETER_LARGEST = 1e-12, 1e12  # a motor parameter's range (D)
ENCODER_LINES_LIMIT = 10_000_000


@dataclass(frozen=True)
class MotorPlant:
    """A DC motor, its amplifier and its encoder: the physical axis a servo drives.

    Defaults: a small servo motor with a 2000-line encoder (8000 counts per turn, as in
    the manual's tuning check) on a voltage-mode amplifier of gain 3: 1 V (KO3277) turns
    it at about a tenth of its top speed, as the manual's set-up step 4 asks. The factory
    gains (KP 10, KD 160, KI 1) hold it stably; the manual's tuning procedure behaves as
    it describes (docs/servo.md).
    """

    inertia: float = 5e-6  # kg m^2, motor and load
    viscous_friction: float = 2e-5  # N m s/rad
    coulomb_friction: float = 0.005  # N m (static friction taken equal)
    torque_constant: float = 0.1  # N m/A (= back-EMF constant, V s/rad)
    amplifier: str = "voltage"  # "voltage" (velocity-like) or "current" (torque mode)
    amplifier_gain: float = 3.0  # V/V in voltage mode, A/V in current mode
    resistance: float = 2.0  # ohm: the winding, used in voltage mode
    encoder_lines: int = 2000  # x4 quadrature

    def __post_init__(self) -> None:
        """Every parameter a finite number in a range (D, issue 34: NaN or infinity made
        the servo's arithmetic NaN): positive ones from 1e-12 to 1e12, frictions from 0
        to 1e12, the encoder's lines a whole number from 1 to 10,000,000."""
        if self.amplifier not in ("current", "voltage"):
            raise ValueError("amplifier is 'current' or 'voltage'")
        for name in ("inertia", "torque_constant", "amplifier_gain", "resistance",
                     "viscous_friction", "coulomb_friction"):
            value = getattr(self, name)
            positive = not name.endswith("friction")
            low = PARAMETER_SMALLEST if positive else 0.0
            if (isinstance(value, bool) or not isinstance(value, int | float)
                    or not low <= value <= PARAMETER_LARGEST):  # NaN fails both
                raise ValueError(f"{name} must be a number from {low:g} to "
                                 f"{PARAMETER_LARGEST:g}, not {value!r}")
        lines = self.encoder_lines
        if (isinstance(lines, bool) or not isinstance(lines, int | float)
                or not 1 <= lines <= ENCODER_LINES_LIMIT or lines != int(lines)):
            raise ValueError(f"encoder_lines must be a whole number from 1 to "
                             f"{ENCODER_LINES_LIMIT:,}, not {lines!r}")

    @property
    def counts_per_rev(self) -> int:
        return 4 * self.encoder_lines

    @property
    def counts_per_radian(self) -> float:
        return self.counts_per_rev / (2.0 * math.pi)

    def _torque_per_count(self) -> float:
        """Stall torque per DAC count (N m)."""
        torque_per_volt = self.torque_constant * self.amplifier_gain
        if self.amplifier == "voltage":
            torque_per_volt /= self.resistance
        return torque_per_volt * VOLTS_PER_COUNT

    def coefficients(self) -> tuple[float, float, float]:
        """(g, a, friction): acceleration in counts/s^2 per DAC count, damping 1/s, and
        the Coulomb friction as DAC counts. The motor obeys ``y'' = g*u - a*y'``."""
        return _coefficients(self)

    def _compute_coefficients(self) -> tuple[float, float, float]:
        damping = self.viscous_friction
        if self.amplifier == "voltage":  # back-EMF through the winding damps the motor
            damping += self.torque_constant ** 2 / self.resistance
        torque = self._torque_per_count()
        g = torque / self.inertia * self.counts_per_radian
        return g, damping / self.inertia, self.coulomb_friction / torque

    def transfer_function(self) -> Any:  # a control.TransferFunction
        """Encoder counts per DAC count: ``g / (s (s + a))``."""
        import control

        g, a, _ = self.coefficients()
        return control.tf([g], [1.0, a, 0.0])

    def discrete(self, period: float) -> PlantMatrices:
        return _discretize(self, period)


@lru_cache(maxsize=256)
def _coefficients(plant: MotorPlant) -> tuple[float, float, float]:
    return plant._compute_coefficients()  # every servo axis asks on every advance: cached


@lru_cache(maxsize=256)
def _discretize(plant: MotorPlant, period: float) -> PlantMatrices:
    """c2d (zero-order hold) of the plant in the physical states (position, velocity):
    returns a11, a12, a21, a22, b1, b2 of ``x' = A x + B u``."""
    import control

    g, a, _ = plant.coefficients()
    continuous = control.ss([[0.0, 1.0], [0.0, -a]], [[0.0], [g]], [[1.0, 0.0]], [[0.0]])
    sampled = control.c2d(continuous, period, method="zoh")
    A, B = np.asarray(sampled.A), np.asarray(sampled.B)
    return (float(A[0, 0]), float(A[0, 1]), float(A[1, 0]), float(A[1, 1]),
            float(B[0, 0]), float(B[1, 0]))  # (a11, a12, a21, a22, b1, b2)



"""ADD_DAC: a second axis's servo output added to a servo axis's DAC (TrioBASIC help
ADD_DAC; the Omron TJ1/TJ2 manuals restate it).

The page's use is dual feedback on one motor: the base axis drives the motor and reads
the motor's encoder; the added axis (a servo ATYPE too, so that its filter runs) reads a
second encoder of the same machine (a measuring wheel on the material) and has the same
demand (ADDAX); its loop output is added to the base axis's, and the sum goes out on the
base axis's DAC (DAC_OUT is the sum). Here:

- The base axis's loop is the shared servo loop on its world motor (`following.py`), with
  its own gains (P_GAIN 0, as the page's example sets it, leaves only the added output;
  the base axis keeps its loop while ADD_DAC is on, D).
- The added axis's encoder is the one the world mounts on its input (`World.encoders`,
  `@world N shaft-encoder M RATIO`), normally on the base axis's motor; with none mounted
  it reads the base axis's motor count for count (D: the page's example measures the
  same motor's travel). Its MPOS is that encoder's count times its ENCODER_RATIO.
- The added axis's filter is the shared filter's arithmetic with the added axis's gains
  (`following.gains_of`: P_GAIN, I_GAIN, D_GAIN, VFF_GAIN, OV_GAIN, AFF_GAIN, DAC_SCALE),
  on the error of its demand (DPOS with ADDAX's part) less its MPOS, every servo cycle
  on the same encoder sample as the base loop's, while its own drive is enabled (WDOG,
  SERVO and AXIS_ENABLE ON); with SERVO OFF its open-loop DAC is added instead, as the
  TJ2 manual's figure switches each axis's output (I). The sum goes out whether the
  base's own part is its loop's (SERVO ON) or its DAC (SERVO OFF: the TJ1 manual's
  second example, the motor under the added axis's loop alone, C).
  The base loop is then stepped in Python (`ServoLoop.added`), the MAXk's loops and every
  other MC405 loop stay compiled and in closed form.
- The added axis drives no motor of its own (its output goes to the base axis's DAC, D);
  its DAC_OUT reads its own filter's last output. Its FE (DPOS - MPOS) is compared with
  FE_LIMIT on every cycle, as a servo axis's (FE_LIMIT_MODE too): the motion error is
  raised on the cycle it is passed, however time is sliced; the integral is limited as
  the shared loop's (4 x KU); the 32768-count trip of the shared loop is not applied to
  it (D).
- ADD_DAC(-1) ends it; the axis must be another axis of the controller, else 'Parameter
  out of range' (D), nothing changed. An axis is added to one base at a time; a base
  takes one added axis (a second ADD_DAC replaces the first, D).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Protocol

from maxk.firmware_model.servo import DAC_LIMIT, Gains, ServoLoop
from maxk.firmware_model.world import World

from . import encoders
from .runs import TrioAxis


class AddHost(Protocol):
    axes: list[TrioAxis]
    world: World

    def motor(self, axis: int, tick: int | None = None) -> float: ...


class AddedFilter:
    """The added axis's filter, stepped by the base loop on every cycle (`__call__`)."""

    def __init__(self, machine: AddHost, base: int, added: int, gains: Gains,
                 polarity: int, base_polarity: int, enabled: Callable[[], bool],
                 open_output: Callable[[], float]) -> None:
        self.m = machine
        self.base = base
        self.added = added
        self.gains = gains
        self.polarity = polarity
        self.base_polarity = base_polarity  # (the base loop applies it: taken off here)
        self.sign = float(polarity * base_polarity)
        self.enabled = enabled  # the added axis's drive (its loop closed)?
        self.open_output = open_output  # its open-loop DAC (shared counts) while not
        self.s = 0.0  # error sum
        self.q = 0.0  # previous error
        self.r_prev: float | None = None  # demand of the last two cycles
        self.r_prev2: float | None = None
        self.u = 0.0  # last output (the added axis's DAC counts, shared 16-bit)
        self.fresh = True  # the next cycle starts the filter (no derivative kick)
        # FE_LIMIT watched on every cycle of a stretch (`watch`): the bound (counts;
        # None: not watched), two cycles in a row (FE_LIMIT_MODE 1), the last cycle's
        # error beyond it, and the first cycle (and its error) that passed it
        self.bound: float | None = None
        self.twice = False
        self.previous = False
        self.over: tuple[int, float] | None = None

    def measured(self, p: float) -> float:
        """The added axis's MPOS counts (DEFPOS not applied) for the base loop's plant
        position `p` (MPOS counts of the base axis)."""
        base = self.m.axes[self.base]
        motor = p / base.servo.feedback_scale if base.servo is not None else p
        mount = self.m.world.encoders.get(self.added)
        counts = motor if mount is None else mount.counts(motor)
        return encoders.ratio(self.m.axes[self.added].params) * counts

    def __call__(self, tick: int, p: float) -> float:
        r = self.m.motor(self.added, tick)
        e = r - self.measured(p)
        if not self.enabled():  # (SERVO OFF: its DAC, as its own output would be)
            self.u, self.fresh, self.r_prev, self.r_prev2 = 0.0, True, None, None
            return self.base_polarity * self.open_output()
        g = self.gains
        if self.fresh:  # (closing: no accumulated sum, no derivative kick)
            self.s, self.q, self.fresh = 0.0, e, False
        v = 0.0 if self.r_prev is None else r - self.r_prev
        v_prev = 0.0 if self.r_prev is None or self.r_prev2 is None \
            else self.r_prev - self.r_prev2
        ki = g.ki_per_tick
        if ki > 0:
            cap = g.integral_sum_limit
            self.s = max(-cap, min(cap, self.s + e))
        if self.bound is not None and self.over is None:
            beyond = abs(e) > self.bound
            if beyond and (self.previous or not self.twice):
                self.over = (tick, e)
            self.previous = beyond
        u = g.kp * e + g.kd * (e - self.q) + ki * self.s + g.kv * v + g.ka * (v - v_prev)
        u = max(-DAC_LIMIT, min(DAC_LIMIT, u))  # (its own output's range)
        self.q = e
        self.r_prev2, self.r_prev = self.r_prev, r
        self.u = u
        return self.sign * u

    def watch(self, bound: float | None, twice: bool, previous: bool) -> None:
        """Compare the error with FE_LIMIT (`bound` counts) on every cycle from now."""
        self.bound, self.twice, self.previous, self.over = bound, twice, previous, None

    def snapshot(self) -> tuple[float, float, float | None, float | None, float, bool,
                                bool]:
        return self.s, self.q, self.r_prev, self.r_prev2, self.u, self.fresh, \
            self.previous

    def restore(self, state: tuple[float, float, float | None, float | None, float,
                                   bool, bool]) -> None:
        self.s, self.q, self.r_prev, self.r_prev2, self.u, self.fresh, \
            self.previous = state

    def follow(self, loop: ServoLoop, base: ServoLoop) -> None:
        """Put the added axis's own loop (its readings: MPOS, FE, DAC_OUT) where the
        base loop's motor has brought its encoder; it drives no motor itself."""
        loop.p = self.measured(base.p)
        loop.w = 0.0
        loop.tick = base.tick
        loop.dac = self.u
        loop.q = self.m.motor(self.added, base.tick) - loop.p


def target(value: float, axis: int, axis_count: int) -> int | None:
    """ADD_DAC's argument: another axis, or -1 (None: end the link); else 'Parameter
    out of range'."""
    if not math.isfinite(value) or value != int(value):
        raise ValueError("Parameter out of range")
    added = int(value)
    if added == -1:
        return None
    if not 0 <= added < axis_count or added == axis:
        raise ValueError("Parameter out of range")
    return added


__all__ = ["AddedFilter", "target"]

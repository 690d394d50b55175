"""Servo axes: the MAXk's PID filter driving a DC motor plant, evaluated every update tick.

The plant is a DC motor with its amplifier and a quadrature encoder. python-control builds
its transfer function (DAC counts in, encoder counts out) and discretizes it with ``c2d``
(zero-order hold) at the update period, once per parameter set. The loop then runs in
plain floats, never calling python-control or numpy per tick.

The filter, evaluated once per tick on the position error ``e = commanded - encoder``
(counts; the encoder is read with sub-count resolution, see docs/servo.md)::

    DAC = KP*e + KD*(e - e_prev) + KI/1024 * sum(e) + KV*v + KA*a + KF*sign(v) + KO

``v`` and ``a`` are the commanded velocity and acceleration in counts per tick (and per
tick squared), the sum is clamped so that the integral term never exceeds ``4*KU`` DAC
counts, and the DAC saturates at +/-32767 (+/-10 V). These scalings are our decisions
(the manual gives ranges, not formulas); they are recorded in the command table.

Speed: between events an axis's commanded position is a polynomial in the tick (each
ramp or slew phase), so while the loop is linear (no DAC saturation, integral inside
KU, friction not changing sign) the closed loop has a closed-form solution: modal
decomposition plus a polynomial particular solution. The engine jumps over such
stretches in O(1), checks per tick only where a bound says a limit might be reached,
and steps tick by tick only where the loop is really nonlinear (saturation, stiction).
Where the compiled kernel is built (`servo_kernel.py`), stepping costs tens of
nanoseconds a tick against a closed-form jump's few hundred microseconds, so it steps
every piece shorter than `KERNEL_SPAN`, every non-polynomial piece (arcs, cosine ramps)
and the first `SETTLE_SPAN` ticks at rest, and jumps only over long linear stretches.
Which ticks the kernel steps depends on the piece and the tick, not on how a host
slices time. The kernel also jumps by itself, in C, over a profile's slews and linear
ramps (the closed loop's modes from `_kernel_modes` in its parameters: about a
microsecond a jump), so a closed-loop profile move of any length is one stretch for it.

Long module: one algorithm (the loop, its closed-form solution, the checks that decide
where it holds and the scalar steps where it does not) whose parts share the solution's
state; split, each part would only make sense beside the others.
"""

from __future__ import annotations

import math
from array import array
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Protocol

import numpy as np

from maxk.firmware_model import servo_kernel as K
from maxk.firmware_model.profiles import Motion, Phase, RampShape

if TYPE_CHECKING:
    from maxk.firmware_model.motion import MotionPlan
    from maxk.firmware_model.world import World


class ServoSettings(Protocol):
    """What the loop reads of an axis's parameters."""

    @property
    def gains(self) -> Gains: ...
    @property
    def servo_polarity(self) -> int: ...


class ServoAxis(Protocol):
    """A servo axis as the loop sees it: the shared kinematics (`MotionAxis`) and its
    settings."""

    index: int
    servo: ServoLoop | None
    steps: int
    counter_offset: int
    encoder_offset: int
    motion: MotionPlan | None
    motion_start: int
    motion_end: int | None
    rest_since: int

    @property
    def config(self) -> ServoSettings: ...


class ServoHost(Protocol):
    """The machine the loop runs in: its time and the world (the motor plant)."""

    @property
    def tick(self) -> int: ...
    @property
    def period(self) -> float: ...
    @property
    def world(self) -> World: ...

DAC_LIMIT = 32767.0  # 16-bit DAC: +/-32767 counts = +/-10 V
FOLLOWING_ERROR_LIMIT = 32768.0  # manual 2.13: above this the PID is disabled
INTEGRAL_DIVISOR = 1024.0  # KI acts on sum(e) / 1024
INTEGRAL_LIMIT_PER_KU = 4.0  # KU limits the integral term to 4*KU DAC counts
HORIZON = 1 << 22  # ticks a closed-form solution is checked ahead when nothing ends
SETTLED_ERROR = 1e-3  # counts: stick-slip below this is not simulated (see _breakaway)
KERNEL_SPAN = 32768  # ticks: a polynomial piece no longer than this is stepped, compiled
SETTLE_SPAN = 8192  # ticks at rest after a piece starts that are stepped, compiled


@dataclass(frozen=True)
class SwitchedTerms:
    """Terms that switch inside the filter (an MC405's D_ZONE_MIN/MAX dead band, in
    counts of error, and its POS_OFFSET/NEG_OFFSET, in output counts). A loop without
    them (every MAXk) is linear and runs compiled and in closed form; a loop with them
    (`ServoLoop.switched`) is stepped in Python, the only place they act, and never
    jumps. Kept out of the kernel so that its arithmetic stays the linear filter's, and
    out of `Gains` so that a MAXk's archived gains stay KP..KO."""

    dead_band: float = 0.0  # |error| below which an idle axis's output clamps to 0
    live_band: float = 0.0  # |error| above which the clamped output is released
    pos_offset: float = 0.0  # added to a positive output (after the polarity)
    neg_offset: float = 0.0  # added to a negative output (after the polarity)

    @property
    def active(self) -> bool:
        return bool(self.dead_band or self.pos_offset or self.neg_offset)


@dataclass(frozen=True)
class Gains:
    """The filter coefficients of one axis, as the KP..KO commands set them."""

    kp: float = 10.0
    ki: float = 1.0
    kd: float = 160.0
    ku: float = 1000.0
    kv: float = 0.0
    ka: float = 0.0
    kf: float = 0.0
    ko: float = 0.0

    @property
    def ki_per_tick(self) -> float:
        return self.ki / INTEGRAL_DIVISOR

    @property
    def integral_sum_limit(self) -> float:
        """Largest |sum(e)| the integrator keeps: |KI*sum/1024| <= 4*KU."""
        if self.ki <= 0:
            return 0.0
        return INTEGRAL_LIMIT_PER_KU * self.ku / self.ki_per_tick


# ---- the closed form -----------------------------------------------------------------
class _Modal:
    """A discrete linear system ``X' = A X + B w`` in modal coordinates, with the rows of
    the outputs the engine checks, for O(1) evaluation at any tick."""

    def __init__(self, A: np.ndarray, B: np.ndarray, outputs: dict[str, tuple]) -> None:
        lam, V = np.linalg.eig(A)
        self.ok = bool(np.isfinite(lam).all()) and np.linalg.cond(V) < 1e8
        if not self.ok:
            return
        self.n = len(lam)
        self.lam = lam.astype(complex)
        self.abs_lam = np.abs(self.lam)
        self.unit = np.abs(self.lam - 1.0) < 1e-13
        self.stable = bool(np.all(self.abs_lam <= 1.0 + 1e-12))
        self.V = V.astype(complex)
        self.Vinv = np.linalg.inv(self.V)
        self.VB = self.Vinv @ B
        # output = cX . X + dW . w  ->  per-mode weights G = cX V
        self.names = list(outputs)
        self.index = {name: k for k, name in enumerate(self.names)}
        self.G = np.array([np.asarray(outputs[k][0], dtype=float) @ self.V
                           for k in self.names])
        self.abs_G = np.abs(self.G)
        self.DW = np.array([outputs[k][1] for k in self.names], dtype=float)


_NODES = (0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0)
_NODES_INV = [[float(x) for x in row] for row in np.linalg.inv(
    np.array([[x ** m for m in range(4)] for x in _NODES]))]


def _poly_eval(c: list, j: float):
    out = 0.0
    for coefficient in reversed(c):
        out = out * j + coefficient
    return out


def _poly_range(c: list[float], a: float, n: float) -> tuple[float, float] | None:
    """(min, max) of a real polynomial (degree <= 3) over [a, n]; None if degree > 3."""
    while len(c) > 1 and abs(c[-1]) < 1e-300:
        c = c[:-1]
    if len(c) > 4:
        return None
    points = [a, n]
    if len(c) == 3:  # derivative linear
        if c[2] != 0.0:
            points.append(-c[1] / (2.0 * c[2]))
    elif len(c) == 4:  # derivative quadratic: 3 c3 j^2 + 2 c2 j + c1
        qa, qb, qc = 3.0 * c[3], 2.0 * c[2], c[1]
        disc = qb * qb - 4.0 * qa * qc
        if disc >= 0.0:
            root = math.sqrt(disc)
            points += [(-qb - root) / (2.0 * qa), (-qb + root) / (2.0 * qa)]
    values = [_poly_eval(c, j) for j in points if a <= j <= n]
    return min(values), max(values)


_FAULHABER = np.array([[0.0, 1.0, 0.0, 0.0, 0.0],
                       [0.0, -0.5, 0.5, 0.0, 0.0],
                       [0.0, 1 / 6, -0.5, 1 / 3, 0.0],
                       [0.0, 0.0, 0.25, -0.5, 0.25]])
"""Row m: the coefficients (in j) of sum_{i<j} i^m, for modes at exactly 1."""


class _Solution:
    """The closed-form trajectory of a _Modal system from a start state under polynomial
    inputs: each mode is a polynomial particular part plus a decaying lambda^j part."""

    __slots__ = ("modal", "P", "delta", "W", "tick0", "poly_out")

    tick0: int  # the tick the solution starts at (set by its user)

    def __init__(self, modal: _Modal, X0: list[float], W: list[list[float]]) -> None:
        self.modal = modal
        Wa = np.zeros((len(W), 5))
        Wa[:, :4] = W
        self.W = Wa  # per input: polynomial coefficients in j
        z0 = modal.Vinv @ np.asarray(X0, dtype=float)
        D = modal.VB @ Wa  # per mode: the input's polynomial
        k = 1.0 - modal.lam
        safe = np.where(modal.unit, 1.0, k)
        P = np.zeros((modal.n, 5), dtype=complex)
        P[:, 3] = D[:, 3] / safe
        P[:, 2] = (D[:, 2] - 3.0 * P[:, 3]) / safe
        P[:, 1] = (D[:, 1] - 2.0 * P[:, 2] - 3.0 * P[:, 3]) / safe
        P[:, 0] = (D[:, 0] - P[:, 1] - P[:, 2] - P[:, 3]) / safe
        delta = z0 - P[:, 0]
        if modal.unit.any():  # a pure accumulator: sum the input (Faulhaber)
            unit = modal.unit
            P[unit] = D[unit, :4] @ _FAULHABER
            P[unit, 0] += z0[unit]
            delta[unit] = 0.0
        self.P = P
        self.delta = delta
        self.poly_out = (modal.G @ P).real + modal.DW @ Wa  # outputs' polynomial parts

    def state(self, j: int) -> list[float]:
        modal = self.modal
        powers = np.array([1.0, j, j * j, j ** 3, j ** 4], dtype=float)
        z = self.P @ powers + self.delta * modal.lam ** j
        return (modal.V @ z).real.tolist()

    def first_violation(self, checks: list[tuple[str, float, float]], n: int) -> int:
        """The first tick (0..n) at which a checked output leaves its bounds, as far as
        the linear solution is concerned; n if none. Bounds first, exact values only on
        stretches where a bound is not enough (short ones first: transients decay)."""
        start, chunk = 0, 64
        modal = self.modal
        rows = [modal.index[c[0]] for c in checks]
        while start < n:
            failing = []
            if modal.stable:
                decay = np.abs(self.delta) * (modal.abs_lam ** start if start else 1.0)
                transients = (modal.abs_G[rows] @ decay).tolist()
                polys = self.poly_out[rows].tolist()
            for i, check in enumerate(checks):
                span = _poly_range(polys[i], float(start), float(n)) if modal.stable \
                    else None
                if (span is None or span[0] - transients[i] <= check[1]
                        or span[1] + transients[i] >= check[2]):
                    failing.append(check)
            if not failing:
                return n
            stop = min(n, start + chunk)
            values = self.outputs_per_tick([c[0] for c in failing], start, stop + 1)
            first = n
            for name, low, high in failing:
                bad = np.flatnonzero((values[name] <= low) | (values[name] >= high))
                if len(bad):
                    at = start + int(bad[0])
                    if name == "w":  # the velocity changed sign during the tick before
                        at -= 1
                    elif at >= stop:
                        continue
                    first = min(first, at)
            if first < n:
                return max(0, first)
            start, chunk = stop, chunk * 4
        return n

    def outputs_per_tick(self, names: list[str], start: int, stop: int) -> dict[str, np.ndarray]:
        """Exact outputs at ticks start..stop-1 (vectorized), where a bound was not
        enough."""
        modal = self.modal
        j = np.arange(start, stop, dtype=float)
        powers = np.vander(j, 5, increasing=True).T  # 5 x len
        growth = np.empty((modal.n, len(j)), dtype=complex)  # lambda^(j - start)
        growth[:, 0] = self.delta * modal.lam ** start
        growth[:, 1:] = modal.lam[:, None]
        Z = self.P @ powers + np.cumprod(growth, axis=1)
        rows = [modal.index[name] for name in names]
        values = (modal.G[rows] @ Z).real + modal.DW[rows] @ (self.W @ powers)
        return {name: values[i] for i, name in enumerate(names)}


@lru_cache(maxsize=512)
def _closed_loop(gains: Gains, plant_matrices: tuple[float, ...]) -> _Modal:
    """The PID and plant as one linear system. States: position, velocity, error sum,
    previous error. Inputs: commanded position (loop frame) and the feed-forward sum."""
    a11, a12, a21, a22, b1, b2 = plant_matrices
    kp, kd, ki = gains.kp, gains.kd, gains.ki_per_tick
    K = kp + kd + ki
    A = np.array([
        [a11 - b1 * K, a12, b1 * ki, -b1 * kd],
        [a21 - b2 * K, a22, b2 * ki, -b2 * kd],
        [-1.0, 0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.0, 0.0],
    ])
    B = np.array([[b1 * K, b1], [b2 * K, b2], [1.0, 0.0], [1.0, 0.0]])
    outputs = {
        "u": ([-K, 0.0, ki, -kd], [K, 1.0]),  # DAC before saturation
        "e": ([-1.0, 0.0, 0.0, 0.0], [1.0, 0.0]),
        "w": ([0.0, 1.0, 0.0, 0.0], [0.0, 0.0]),
        "s": ([-1.0, 0.0, 1.0, 0.0], [1.0, 0.0]),  # the sum after this tick's error
    }
    if ki == 0.0:  # no integrator: drop its state (it would be a mode at exactly 1)
        A = A[np.ix_([0, 1, 3], [0, 1, 3])]
        B = B[[0, 1, 3]]
        outputs = {k: ([v[0][0], v[0][1], v[0][3]], v[1]) for k, v in outputs.items()
                   if k != "s"}
    return _Modal(A, B, outputs)


def _kernel_modes(gains: Gains, plant_matrices: tuple[float, ...]) -> tuple[float, ...]:
    """The closed loop's modes as the compiled kernel's closed-form jump over a slew
    reads them (`_servo_kernel.c`, "the closed-form jump"): the number of modes, then
    lambda, V, V^-1, V^-1 B, the output rows u, e, w, s (complex, as re, im pairs) and
    their direct terms. Empty where the kernel should not jump (switched off, an
    ill-conditioned or undecaying loop)."""
    return _modes(gains, plant_matrices) if K.JUMPS else ()


@lru_cache(maxsize=512)
def _modes(gains: Gains, plant_matrices: tuple[float, ...]) -> tuple[float, ...]:
    modal = _closed_loop(gains, plant_matrices)
    if not modal.ok or not modal.stable or modal.unit.any():
        return ()
    n = modal.n
    names = ["u", "e", "w", "s"]
    G = np.zeros((4, n), dtype=complex)
    DW = np.zeros((4, 2))
    for row, name in enumerate(names):
        if name in modal.index:
            G[row] = modal.G[modal.index[name]]
            DW[row] = modal.DW[modal.index[name]]
    parts = [modal.lam, modal.V.ravel(), modal.Vinv.ravel(),
             np.asarray(modal.VB, dtype=complex).ravel(), G.ravel()]
    values = np.concatenate([part.astype(complex).view(float) for part in parts])
    return (float(n), *values.tolist(), *DW.ravel().tolist())


@lru_cache(maxsize=256)
def _open_loop(plant_matrices: tuple[float, ...]) -> _Modal:
    a11, a12, a21, a22, b1, b2 = plant_matrices
    A = np.array([[a11, a12], [a21, a22]])
    B = np.array([[b1], [b2]])
    return _Modal(A, B, {"w": ([0.0, 1.0], [0.0])})


# ---- the loop of one axis -------------------------------------------------------------
def _slot(index: int, doc: str) -> property:
    def get(loop: ServoLoop) -> float:
        return loop.x[index]

    def put(loop: ServoLoop, value: float) -> None:
        loop.x[index] = value

    return property(get, put, doc=doc)


def _optional(index: int, present: int, doc: str) -> property:
    def get(loop: ServoLoop) -> float | None:
        return loop.x[index] if loop.x[present] else None

    def put(loop: ServoLoop, value: float | None) -> None:
        loop.x[present] = value is not None
        loop.x[index] = 0.0 if value is None else value

    return property(get, put, doc=doc)


def _flag(index: int, doc: str) -> property:
    def get(loop: ServoLoop) -> bool:
        return bool(loop.x[index])

    def put(loop: ServoLoop, value: bool) -> None:
        loop.x[index] = bool(value)

    return property(get, put, doc=doc)


class ServoLoop:
    """The servo state of one PSM axis: plant position/velocity, the filter's memory and
    whether the loop is closed. ``tick`` is how far the loop has been simulated."""

    def __init__(self, position: float, tick: int) -> None:
        # the state the compiled kernel steps, in one array (slots: servo_kernel.P..STUCK):
        # plant position (counts since power-up, physical) and velocity (counts/s), the
        # error sum, the previous error, the last DAC output (after saturation), the
        # commanded position of the last two ticks; closed (PSM powers up open loop: the
        # DAC puts out KO, manual 2.9), tripped (following error exceeded: PID disabled
        # until CL1/HN) and stuck (held by static friction)
        self.x = array("d", (float(position),) + (0.0,) * (K.STATE_SIZE - 1))
        self.tick = tick
        self.trip_tick: int | None = None
        self.recorder: list | None = None  # per-tick samples for the tuning plot
        self._cache: tuple | None = None  # a closed-form solution still valid ahead
        self._params: tuple[tuple, array | None] = ((), None)  # the kernel's, by key
        self._program: tuple[tuple, array | None] = ((), None)
        # a stretch the kernel steps: (until, what it depends on, plant, friction, gains,
        # the kernel's inputs, the same dependencies as checks for the compiled pass)
        self._fast: tuple | None = None
        # the plant's matrices and friction, by (plant, period, polarity) (a frozen plant)
        self._plant: tuple = (None, 0.0, 1, (), 0.0)
        self.switched: SwitchedTerms | None = None  # a dead band, offsets (None: linear)
        # counts added to the commanded position at a tick (an MC405's BACKLASH
        # compensation, superimposed on its motion): a loop with one is stepped in Python,
        # which alone reads it; None for every MAXk
        self.command_offset: Callable[[int], float] | None = None
        # the loop's counts per motor encoder count (an MC405's ENCODER_RATIO on a servo
        # axis: its MPOS counts): p and w are in those counts; 1 for every MAXk
        self.feedback_scale = 1.0
        self.clamped = False  # in the dead band: the output held at 0
        # an output added to the loop's at a tick (closed or open), given the position the
        # loop reads (an MC405's ADD_DAC: a second axis's filter on another encoder of
        # this motor): a loop with one is stepped in Python, which alone reads it; None
        # for every MAXk (`set_added`)
        self.added: Callable[[int, float], float] | None = None

    p = _slot(K.P, "plant position, counts since power-up (physical)")
    w = _slot(K.W, "plant velocity, counts/s")
    s = _slot(K.S, "error sum")
    q = _slot(K.Q, "previous error")
    dac = _slot(K.DAC, "last output, DAC counts (after saturation)")
    r_prev = _optional(K.RPREV, K.HAS_PREV, "commanded position of the last tick")
    r_prev2 = _optional(K.RPREV2, K.HAS_PREV2, "commanded position the tick before")
    closed = _flag(K.CLOSED, "the loop is closed (CL1)")
    tripped = _flag(K.TRIPPED, "following error exceeded: PID disabled until CL1/HN")
    stuck = _flag(K.STUCK, "held by static friction")

    # ---- what the host reads ---------------------------------------------------------
    def encoder_counts(self) -> int:
        """The encoder counter: the count whose cell holds the position."""
        return math.floor(self.p + 0.5)

    def set_feedback_scale(self, scale: float) -> None:
        """Take a new feedback scale (see `feedback_scale`): the motor does not move, so
        its position and speed in the loop's counts scale with it; what was solved or
        kept for the old one is dropped."""
        if scale == self.feedback_scale:
            return
        k = scale / self.feedback_scale
        self.p *= k
        self.w *= k
        self.feedback_scale = scale
        self._plant = (None, 0.0, 1, (), 0.0)
        self._cache = None
        self._fast = None

    def set_added(self, added: Callable[[int, float], float] | None) -> None:
        """Take (or drop) an output added to the loop's (see `added`): what the
        kernel or a closed form was to step is dropped, the loop is stepped in Python."""
        if added is self.added:
            return
        self.added = added
        self._cache = None
        self._fast = None

    def reset_filter(self, error: float) -> None:
        """CL1 closing an open loop: start the filter afresh (no accumulated sum, no
        derivative kick); the commanded-velocity history carries on."""
        self.s = 0.0
        self.q = error
        self._cache = None

    def snapshot(self) -> tuple[array, int, int | None, bool]:
        """The loop's state now: run it ahead, then `restore` it to go again only as far
        as something found on the way (an MC405 FE_LIMIT passed on some tick)."""
        return array("d", self.x), self.tick, self.trip_tick, self.clamped

    def restore(self, state: tuple[array, int, int | None, bool]) -> None:
        x, self.tick, self.trip_tick, self.clamped = state
        self.x[:] = x
        self._cache = None  # (solutions and stretches found from the later state)
        self._fast = None

    def counters_moved(self, motor: float, encoder: float) -> None:
        """LP/LO/LPE, homing or #UR moved the counters by these amounts: the filter's
        memory moves with them, so nothing jumps (no derivative or feed-forward kick)."""
        if self.r_prev is not None:
            self.r_prev += motor
        if self.r_prev2 is not None:
            self.r_prev2 += motor
        self.q += motor - encoder
        self._cache = None

    # ---- simulation ------------------------------------------------------------------
    def advance(self, axis: ServoAxis, board: ServoHost, to_tick: int) -> None:
        """Simulate up to `to_tick` (exclusive of its inputs). Stops early at a
        following-error trip, leaving ``trip_tick`` for the board to act on."""
        if self.trip_tick is not None:
            return
        fast = self._fast
        if fast is not None:
            # inside a stretch the kernel steps, with nothing it reads changed: no
            # decisions to remake (a pacing pass costs one comparison per axis)
            config = axis.config
            plant = board.world.axes[axis.index].motor
            if (to_tick <= fast[0] and self.recorder is None
                    and fast[1] == (axis.motion, axis.motion_start, axis.motion_end,
                                    axis.rest_since, axis.steps, axis.counter_offset,
                                    axis.encoder_offset, config.gains,
                                    config.servo_polarity, plant, board.period)):
                self._scalar(axis, board, fast[2], fast[3], fast[4], to_tick - self.tick,
                             fast[5])
                return
            self._fast = None
        plant = board.world.axes[axis.index].motor
        period = board.period
        polarity = axis.config.servo_polarity
        scale = self.feedback_scale
        sign = polarity if scale > 0 else -polarity  # friction's sign in drive terms
        held = self._plant
        if held[0] is plant and held[1] == period and held[2] == sign:
            matrices, friction = held[3], held[4]
        else:  # (a frozen plant: the same object, the same matrices)
            matrices = plant.discrete(period)
            if polarity < 0 or scale != 1.0:  # SVP-: the DAC output inverted; a feedback
                a11, a12, a21, a22, b1, b2 = matrices  # scale: the plant in its counts
                f = polarity * scale
                matrices = (a11, a12, a21, a22, f * b1, f * b2)
            friction = plant.coefficients()[2]
            self._plant = (plant, period, sign, matrices, friction)
        gains = axis.config.gains
        if (self.switched is not None or self.command_offset is not None
                or self.added is not None):
            # (a dead band or output offsets: SwitchedTerms; an offset on the command;
            # an added output)
            self._cache = None
            self._scalar_python(axis, board, matrices, friction, gains, to_tick - self.tick)
            return
        while self.tick < to_tick:
            if self.recorder is not None:
                self._scalar(axis, board, matrices, friction, gains, to_tick - self.tick)
            else:
                self._segment(axis, board, matrices, friction, gains, to_tick)
            if self.trip_tick is not None:
                return

    def _commanded(self, axis: ServoAxis, board: ServoHost, tick: float) -> float:
        """Commanded position (counter frame, exact float) at a tick."""
        m = axis.motion
        base: float = axis.steps + axis.counter_offset
        if self.command_offset is not None:  # (only ever stepped in Python: see advance)
            base += self.command_offset(int(tick))
        if m is None:
            return float(base)
        if axis.motion_end is not None and tick >= axis.motion_end:
            return float(base + m.final_offset)
        return base + m.offset((tick - axis.motion_start) * board.period)

    def _piece(self, axis: ServoAxis, board: ServoHost, tick: int) -> tuple[int, int | None, bool]:
        """The ticks where the commanded position's present polynomial piece started and
        ends (None: never), and whether it is a polynomial (cosine ramps are not)."""
        m = axis.motion
        if m is None:
            return axis.rest_since, None, True
        if axis.motion_end is not None and tick >= axis.motion_end:
            return axis.motion_end, None, True
        period = board.period
        t = (tick - axis.motion_start) * period
        phase = m.phase_at(t)
        if phase is None:
            return axis.motion_start, axis.motion_end, True
        start_t, end_t = phase.t0, phase.t0 + phase.duration
        ramp = phase.v1 != phase.v2
        if ramp and phase.shape is RampShape.SCURVE:
            # an S-curve is polynomial between its knots (its middle, with SS/PR, too)
            knots = phase.knots if isinstance(phase, Phase) else (phase.duration / 2,)
            for knot in knots:
                if t < phase.t0 + knot:
                    end_t = phase.t0 + knot
                    break
                start_t = phase.t0 + knot
        polynomial = phase.polynomial  # cosine ramps and contour arcs are not
        start = axis.motion_start + math.ceil(start_t / period - 1e-9)
        if math.isinf(end_t):
            end = axis.motion_end
        else:
            end = axis.motion_start + math.ceil(end_t / period - 1e-9)
            if axis.motion_end is not None:
                end = min(end, axis.motion_end)
            end = max(end, tick + 1)
        return start, end, polynomial

    def _segment(self, axis: ServoAxis, board: ServoHost, matrices: tuple, friction: float,
                 gains: Gains, to_tick: int) -> None:
        """Advance as far as one closed-form jump allows; scalar steps where it can't."""
        cache = self._cache
        if cache is not None:
            key, tick0, sol, valid_until, r = cache
            if tick0 <= self.tick < valid_until and key == self._key(axis, matrices, friction,
                                                                     gains):
                self._commit(axis, sol, r, min(valid_until, to_tick) - tick0)
                return
            self._cache = None
        tick = self.tick
        motion_end = axis.motion_end
        if (K.STEP is not None and self.recorder is None and axis.motion is not None
                and motion_end is not None and tick < motion_end
                and (motion_end <= tick + KERNEL_SPAN
                     or self._kernel_jumps(axis, board, matrices, friction, gains))):
            # the rest of a short move: each of its pieces would be stepped compiled, one
            # after the other (the kernel's ticks do not depend on where a call ends), so
            # step them in one stretch, with one decision instead of one per piece; a
            # move of any length where the kernel jumps its linear ramps and slews itself
            kernel = self._kernel_inputs(axis, board, matrices, friction, gains)
            self._scalar(axis, board, matrices, friction, gains, min(motion_end, to_tick) - tick,
                         kernel)
            if kernel is not None:
                self._remember(axis, board, motion_end, matrices, friction, gains, kernel)
            return
        start, end, polynomial = self._piece(axis, board, tick)
        limit = to_tick if end is None else min(end, to_tick)
        n = limit - self.tick
        if K.STEP is not None and self.recorder is None:
            # compiled ticks are cheaper than a closed-form jump over short pieces,
            # non-polynomial ones (arcs, cosine ramps) and the settling after a move
            until = None
            if not polynomial or (end is not None and end - self.tick <= KERNEL_SPAN):
                until = end
                count = n
            elif end is None and self.tick - start < SETTLE_SPAN:
                until = start + SETTLE_SPAN
                count = min(n, until - self.tick)
            else:
                count = 0
            if count:
                kernel = self._kernel_inputs(axis, board, matrices, friction, gains)
                self._scalar(axis, board, matrices, friction, gains, count, kernel)
                if until is not None and kernel is not None:
                    self._remember(axis, board, until, matrices, friction, gains, kernel)
                return
        fresh = start + 2 - self.tick  # ticks until the history is on this piece
        if fresh > 0 and polynomial and not (self.stuck and end is None):
            self._scalar(axis, board, matrices, friction, gains, min(n, fresh))
            return
        # The first two ticks of a piece take their velocity and acceleration from the
        # piece before: step them one by one, as any tick where the loop is nonlinear.
        if (not polynomial or n < 8 or self.r_prev2 is None or self.stuck
                or (friction and self.w == 0.0)):
            open_loop = not self.closed or self.tripped
            if self.stuck and end is None:
                if open_loop:
                    self._stuck_open(friction, gains, limit)
                    return
                if self._stuck_closed(axis, board, friction, gains, limit):
                    return
            if (self.stuck and polynomial and not open_loop and n >= 8
                    and self._stuck_moving(axis, board, gains, friction, n)):
                return
            # two ticks bring the velocity/acceleration history onto this piece
            self._scalar(axis, board, matrices, friction, gains, min(n, 2) if polynomial
                         else n)
            return
        horizon = (end if end is not None else self.tick + HORIZON) - self.tick
        taken = self._jump(axis, board, matrices, friction, gains, horizon, n)
        if taken is not True:
            # off the polynomial (a new piece): two ticks; nonlinear: a few more
            self._scalar(axis, board, matrices, friction, gains,
                         min(n, 2 if taken is None else 16))

    def _kernel_jumps(self, axis: ServoAxis, board: ServoHost, matrices: tuple,
                      friction: float, gains: Gains) -> bool:
        """Whether the kernel takes this motion's linear ramps and slews in closed form
        itself (a profile, the loop closed, the closed loop's modes in its parameters)."""
        if (not K.JUMPS or type(axis.motion) is not Motion or not self.closed
                or self.tripped):
            return False
        kernel = self._kernel_inputs(axis, board, matrices, friction, gains)
        return kernel is not None and len(kernel[0]) > K.PARAM_SIZE

    def _inputs(self, axis: ServoAxis, board: ServoHost, n: int, gains: Gains,
                friction_drive: float) -> tuple[list[float], list[float]] | None:
        """Polynomial coefficients (in j = tick - self.tick) of the commanded position
        (loop frame) and of the feed-forward sum over the next n ticks."""
        t0 = self.tick
        span = float(n - 1)
        # the exact cubic through 4 samples spread over the piece (normalised abscissa)
        ys = [self._commanded(axis, board, t0 + x * span) for x in _NODES]
        cx = [sum(_NODES_INV[row][k] * ys[k] for k in range(4)) for row in range(4)]
        r = [cx[m] / span ** m for m in range(4)]
        eo = axis.encoder_offset
        r[0] -= eo  # loop frame: e = r' - p
        # v(j) = r(j) - r(j-1), a(j) = v(j) - v(j-1)
        c1, c2, c3 = r[1], r[2], r[3]
        v = [c1 - c2 + c3, 2 * c2 - 3 * c3, 3 * c3, 0.0]
        a = [v[1] - v[2], 2 * v[2], 0.0, 0.0]
        for back, seen in ((-1.0, self.r_prev), (-2.0, self.r_prev2)):
            if seen is None:
                return None
            if abs(_poly_eval(r, back) - (seen - eo)) > 1e-9 * max(1.0, abs(seen)) + 1e-6:
                return None  # the last two ticks were not on this polynomial
        m = axis.motion
        sign_v = 0.0
        if m is not None and (axis.motion_end is None or self.tick < axis.motion_end):
            phase = m.phase_at((self.tick - axis.motion_start) * board.period)
            if phase is not None and (phase.v1 or phase.v2):
                sign_v = float(phase.direction)
        if not self.closed or self.tripped:
            u = 0.0 if self.tripped else gains.ko
            return r, [u - friction_drive, 0.0, 0.0, 0.0]
        ff = [gains.kv * v[m_] + gains.ka * a[m_] for m_ in range(4)]
        ff[0] += gains.kf * sign_v + gains.ko - friction_drive
        return r, ff

    def _key(self, axis: ServoAxis, matrices: tuple, friction: float, gains: Gains) -> tuple:
        """What a cached closed-form solution depends on besides the state it started
        from (the state is ours: any step outside the solution drops the cache)."""
        return (id(axis.motion), axis.motion_start, axis.steps, axis.counter_offset,
                axis.encoder_offset, gains, self.closed, self.tripped, matrices, friction)

    def _commit(self, axis: ServoAxis, sol: _Solution, r: list[float], j: int) -> None:
        """Take the state `j` ticks into a solution (which started at its tick0)."""
        X = sol.state(j)
        if len(X) == 4:
            self.p, self.w, self.s, self.q = X
        elif len(X) == 3:
            self.p, self.w, self.q = X
        else:
            self.p, self.w = X
        self.r_prev = _poly_eval(r, j - 1) + axis.encoder_offset
        self.r_prev2 = _poly_eval(r, j - 2) + axis.encoder_offset
        self.tick = sol.tick0 + j
        if j > 0 and "u" in sol.modal.index:  # the output of the last tick jumped over,
            # so what reads it (an MC405's DAC_OUT) is never a tick's before the jump: the
            # solution's u is the drive (friction taken off along the motor's way, which a
            # jump's checks keep); no saturation (its checks keep u inside +/-DAC_LIMIT)
            u = float(sol.outputs_per_tick(["u"], j - 1, j)["u"][0])
            friction = self._plant[4]
            if friction:
                u += friction * (1.0 if self.w > 0 else -1.0) * (-1.0 if self._plant[2] < 0
                                                                   else 1.0)
            self.dac = u

    def _jump(self, axis: ServoAxis, board: ServoHost, matrices: tuple, friction: float,
              gains: Gains, n: int, wanted: int) -> bool | None:
        """Solve the next n ticks (the rest of the piece) in closed form, check the loop
        stays linear over them, and take up to `wanted` of them; the rest is cached for
        the next call (other axes' events split a jump, they do not redo it). False when
        not even one tick could be taken this way, None when the last ticks were not on
        the present polynomial piece."""
        closed = self.closed and not self.tripped
        modal = _closed_loop(gains, matrices) if closed else _open_loop(matrices)
        if not modal.ok:
            return False
        sign = (1.0 if self.w > 0 else -1.0) if friction else 0.0
        # friction opposes the motor: in drive terms along polarity * sign(w)
        inputs = self._inputs(axis, board, n, gains,
                              friction * sign * (-1.0 if self._plant[2] < 0 else 1.0))
        if inputs is None:
            return None
        r, ff = inputs
        integrating = closed and gains.ki > 0
        if closed:
            X0 = [self.p, self.w, self.s, self.q] if integrating else [self.p, self.w, self.q]
            W = [r, ff]
        else:
            X0 = [self.p, self.w]
            W = [ff]
        sol = _Solution(modal, X0, W)
        checks: list[tuple[str, float, float]] = []
        if closed:
            checks.append(("u", -DAC_LIMIT, DAC_LIMIT))
            checks.append(("e", -FOLLOWING_ERROR_LIMIT, FOLLOWING_ERROR_LIMIT))
            if integrating:
                limit = gains.integral_sum_limit
                checks.append(("s", -limit, limit))
        if friction:
            checks.append(("w", 0.0, math.inf) if sign > 0 else ("w", -math.inf, 0.0))
        take = sol.first_violation(checks, n)
        if take <= 0:
            return False
        sol.tick0 = self.tick
        if take > wanted:
            self._cache = (self._key(axis, matrices, friction, gains), self.tick, sol,
                           self.tick + take, r)
        self._commit(axis, sol, r, min(take, wanted))
        return True

    def _stuck_open(self, friction: float, gains: Gains, limit: int) -> None:
        """Open loop and held by friction: the DAC output is constant, nothing moves."""
        self._cache = None
        u = gains.ko if not self.tripped else 0.0
        if abs(u) <= friction:
            self.dac = u
            self.tick = limit
        else:
            self.stuck = False

    def _stuck_moving(self, axis: ServoAxis, board: ServoHost, gains: Gains, friction: float,
                      n: int) -> bool:
        """Closed loop, held by static friction while the commanded position moves (the
        start of a move): the motor stays put until the output exceeds the friction.
        Everything but the plant is a polynomial in the tick: find the breakaway tick."""
        self._cache = None
        inputs = self._inputs(axis, board, n, gains, 0.0)
        if inputs is None:
            return False
        r, ff = inputs
        take = min(n, 4096)
        j = np.arange(take + 1, dtype=float)
        e = np.polyval(r[::-1], j) - self.p
        e_prev = np.empty_like(e)
        e_prev[0] = self.q
        e_prev[1:] = e[:-1]
        ki = gains.ki_per_tick
        if ki > 0:
            summed = np.where(np.abs(e) < SETTLED_ERROR, 0.0, e)  # as _scalar: held
            s = self.s + np.cumsum(summed)
            cap = gains.integral_sum_limit
        else:
            s = np.zeros_like(e)
            cap = math.inf
        u = (gains.kp * e + gains.kd * (e - e_prev) + ki * s + np.polyval(ff[::-1], j))
        bad = np.flatnonzero((np.abs(u) > friction) | (np.abs(e) > FOLLOWING_ERROR_LIMIT)
                             | (np.abs(s) > cap))
        k = int(bad[0]) if len(bad) else take
        if k <= 0:
            return False
        # state after k stuck ticks: the sum holds k errors, q the last one
        self.s = float(s[k - 1]) if ki > 0 else 0.0
        self.q = float(e[k - 1])
        self.dac = float(max(-DAC_LIMIT, min(DAC_LIMIT, u[k - 1])))
        self.r_prev = _poly_eval(r, k - 1) + axis.encoder_offset
        self.r_prev2 = _poly_eval(r, k - 2) + axis.encoder_offset
        self.tick += k
        return True

    def _stuck_closed(self, axis: ServoAxis, board: ServoHost, friction: float, gains: Gains,
                      limit: int) -> bool:
        """Closed loop, at rest, held by static friction: the error is constant, so only
        the integrator moves. Jump to the tick the output breaks away (or to `limit`)."""
        self._cache = None
        r = self._commanded(axis, board, self.tick) - axis.encoder_offset
        e = r - self.p
        if abs(e) > FOLLOWING_ERROR_LIMIT or self.q != e:
            return False
        if abs(e) < SETTLED_ERROR:
            e = 0.0  # below what the encoder can see: the integrator holds
        ki = gains.ki_per_tick
        base = gains.kp * e + gains.ko  # derivative term is 0: e == q
        breaks = _breakaway(base, ki, self.s, e, gains.integral_sum_limit, friction)
        # jump to just before the tick whose output breaks away; that tick is stepped
        k = limit - self.tick if breaks is None else min(limit - self.tick, breaks - 1)
        if k <= 0:
            return False
        if ki > 0:
            cap = gains.integral_sum_limit
            self.s = max(-cap, min(cap, self.s + k * e))
            self.dac = max(-DAC_LIMIT, min(DAC_LIMIT, base + ki * self.s))
        else:
            self.dac = max(-DAC_LIMIT, min(DAC_LIMIT, base))
        self.r_prev = self.r_prev2 = r + axis.encoder_offset
        self.tick += k
        return True

    def _scalar(self, axis: ServoAxis, board: ServoHost, matrices: tuple, friction: float,
                gains: Gains, count: int, kernel: tuple[array, array] | None = None) -> None:
        """Step tick by tick, where the loop is nonlinear or a stretch is too short for a
        closed-form jump: compiled where the kernel is built, else in Python. `kernel`:
        its inputs, if the caller knows them still valid."""
        self._cache = None
        step = K.STEP
        if step is not None and self.recorder is None and count > 0:
            if kernel is None:
                kernel = self._kernel_inputs(axis, board, matrices, friction, gains)
            if kernel is not None:
                self._step(kernel[0], kernel[1], count)
                return
        self._scalar_python(axis, board, matrices, friction, gains, count)

    def _remember(self, axis: ServoAxis, board: ServoHost, until: int, matrices: tuple,
                  friction: float, gains: Gains, kernel: tuple[array, array]) -> None:
        """Keep the kernel stepping this axis until `until` while nothing it reads
        changes: what that is, as a tuple for `advance` and as (object, attribute, value)
        checks for the compiled pass over a board (`advance_servo_axes`)."""
        config = axis.config
        world = board.world
        world_axis = world.axes[axis.index]
        plant = world_axis.motor
        motion, start, end, rest = axis.motion, axis.motion_start, axis.motion_end, \
            axis.rest_since
        steps, counter, encoder = axis.steps, axis.counter_offset, axis.encoder_offset
        set_gains, polarity, period = config.gains, config.servo_polarity, board.period
        key = (motion, start, end, rest, steps, counter, encoder, set_gains, polarity, plant,
               period)
        checks = ((axis, "motion", motion), (axis, "motion_start", start),
                  (axis, "motion_end", end), (axis, "rest_since", rest),
                  (axis, "steps", steps), (axis, "counter_offset", counter),
                  (axis, "encoder_offset", encoder), (axis, "config", config),
                  (config, "gains", set_gains), (config, "servo_polarity", polarity),
                  (board, "world", world), (world, "axes", world.axes),
                  (world_axis, "motor", plant), (board, "period", period))
        self._fast = (until, key, matrices, friction, gains, kernel, checks)

    def _step(self, params: array, program: array, count: int) -> None:
        """`count` ticks through the compiled kernel."""
        step = K.STEP
        assert step is not None
        done = step(self.x, params, program, self.tick, count)
        if done < 0:  # the following error tripped on the tick after these
            self.tick += -done - 1
            self.trip_tick = self.tick
        else:
            self.tick += done

    def _kernel_inputs(self, axis: ServoAxis, board: ServoHost, matrices: tuple,
                       friction: float, gains: Gains) -> tuple[array, array] | None:
        """The kernel's parameters and program for this axis, remade only when what they
        describe changed (None: the kernel cannot describe this motion)."""
        key = (matrices, friction, gains, axis.encoder_offset)
        held_key = self._params[0]
        if not (held_key and held_key[0] is matrices and held_key[1] == friction
                and held_key[2] is gains and held_key[3] == key[3]) and held_key != key:
            self._params = (key, K.params(matrices, friction, gains.kp, gains.kd,
                                          gains.ki_per_tick, gains.kv, gains.ka, gains.kf,
                                          gains.ko, gains.integral_sum_limit,
                                          axis.encoder_offset, self._plant[2],
                                          _kernel_modes(gains, matrices)))
        motion = axis.motion
        base = axis.steps + axis.counter_offset
        where = (motion, axis.motion_start, axis.motion_end, base, board.period)
        held = self._program[0]
        if (not held or held[0] is not motion or held[1] != where[1] or held[2] != where[2]
                or held[3] != base or held[4] != where[4]):
            self._program = (where, K.program(motion, base, axis.motion_start,
                                               axis.motion_end, board.period))
        params, program = self._params[1], self._program[1]
        if params is None or program is None:
            return None
        return params, program

    def _scalar_python(self, axis: ServoAxis, board: ServoHost, matrices: tuple,
                       friction: float, gains: Gains, count: int) -> None:
        """Step tick by tick in Python: the reference semantics (the compiled kernel does
        exactly this arithmetic), and the loop where no kernel was built."""
        a11, a12, a21, a22, b1, b2 = matrices
        fdir = -1.0 if self._plant[2] < 0 else 1.0  # SVP-: friction's sign in drive terms
        eo = axis.encoder_offset
        kp, kd, ki, kv, ka, kf, ko = (gains.kp, gains.kd, gains.ki_per_tick, gains.kv,
                                      gains.ka, gains.kf, gains.ko)
        cap = gains.integral_sum_limit
        recorder = self.recorder
        added = self.added
        x = self.x
        p, w, s, q, dac = x[K.P], x[K.W], x[K.S], x[K.Q], x[K.DAC]
        r_prev, r_prev2 = self.r_prev, self.r_prev2
        closed, tripped, stuck = self.closed, self.tripped, self.stuck
        tick = self.tick
        for _ in range(count):
            r_abs = self._commanded(axis, board, tick)
            r = r_abs - eo
            v = 0.0 if r_prev is None else r_abs - r_prev
            v_prev = 0.0 if r_prev is None or r_prev2 is None else r_prev - r_prev2
            a = v - v_prev
            e = r - p
            if tripped:
                u = 0.0
            elif not closed:
                u = ko
            else:
                if abs(e) > FOLLOWING_ERROR_LIMIT:
                    self.trip_tick = tick
                    break
                held = stuck and abs(e) < SETTLED_ERROR  # invisible to the encoder
                s_new = s + e if ki > 0 and not held else s if ki > 0 else 0.0
                s_new = max(-cap, min(cap, s_new))
                sign_v = 1.0 if v > 1e-12 else -1.0 if v < -1e-12 else 0.0
                u = (kp * e + kd * (e - q) + ki * s_new + kv * v + ka * a + kf * sign_v
                     + ko)
                s, q = s_new, e
                if self.switched is not None:
                    u = self._switched(axis, self.switched, tick, e, u)
            if added is not None and not tripped:
                u += added(tick, p)
            u = max(-DAC_LIMIT, min(DAC_LIMIT, u))
            dac = u
            r_prev2, r_prev = r_prev, r_abs
            if recorder is not None:
                recorder.append((tick, r_abs, p + eo, v, w, e, u))
            tick += 1
            if stuck:
                if abs(u) <= friction:
                    continue
                stuck = False
            w0 = w
            if friction:
                direction = (fdir if w0 > 0 else -fdir) if w0 else (1.0 if u > 0 else -1.0)
                drive = u - friction * direction
                if w0 == 0.0 and abs(u) <= friction:
                    stuck = True
                    continue
            else:
                drive = u
            p_new = a11 * p + a12 * w0 + b1 * drive
            w_new = a21 * p + a22 * w0 + b2 * drive
            if friction and w0 != 0.0 and (w_new > 0) != (w0 > 0) and abs(u) <= friction:
                w_new = 0.0  # friction stopped the motor within this tick
                stuck = True
            p, w = p_new, w_new
        x[K.P], x[K.W], x[K.S], x[K.Q], x[K.DAC] = p, w, s, q, dac
        self.r_prev, self.r_prev2, self.stuck = r_prev, r_prev2, stuck
        self.tick = tick


    def _switched(self, axis: ServoAxis, terms: SwitchedTerms, tick: int, e: float,
                  u: float) -> float:
        """The closed loop's output through the dead band and the output offsets (see
        SwitchedTerms): clamped to 0 once the axis's motion is over and |e| fell below the dead
        band, until |e| passes the live band or a motion runs; an offset added by the
        sign of the output as put out (after the polarity)."""
        running = axis.motion is not None and (axis.motion_end is None
                                               or tick < axis.motion_end)
        if terms.dead_band:
            clamped = self.clamped
            if running or (clamped and abs(e) > terms.live_band):
                clamped = False
            elif not clamped and abs(e) < terms.dead_band:
                clamped = True
            self.clamped = clamped
            if clamped:
                return 0.0
        polarity = -1.0 if axis.config.servo_polarity < 0 else 1.0
        out = u * polarity
        if out > 0:
            out += terms.pos_offset
        elif out < 0:
            out += terms.neg_offset
        return out * polarity


def advance_servo_axes(axes: Sequence[ServoAxis], board: ServoHost, limit: int) -> None:
    """Run every servo loop of a board up to `limit`: one compiled call steps the axes
    inside a stretch the kernel steps (no Python per axis), `ServoLoop.advance` the
    others."""
    step_axes = K.STEP_AXES
    rest = axes if step_axes is None else step_axes(axes, limit)
    for axis in rest:
        loop = axis.servo
        if loop is not None:
            loop.advance(axis, board, limit)


def _breakaway(base: float, ki: float, s: float, e: float, cap: float,
               friction: float) -> int | None:
    """How many more errors summed make ``|base + ki*sum|`` exceed the static friction
    (the sum grows by e each tick, clamped at +/-cap); None if never: the axis stays."""
    if abs(e) < SETTLED_ERROR or ki <= 0.0:
        return None if abs(base + ki * s) <= friction else 1
    step = e
    final = max(-cap, min(cap, s + step * 1e18))
    if abs(base + ki * final) <= friction:
        return None
    # the output crosses +friction or -friction, whichever it heads for
    target = friction if step > 0 else -friction
    needed = ((target - base) / ki - s) / step
    return max(1, math.floor(needed) + 1)

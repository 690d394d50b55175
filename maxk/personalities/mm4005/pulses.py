"""Pulses synchronized to a trajectory (manual 6.1.2: NB, NE, NI, NN, NS).

Equally spaced pulses are generated along the path from the start of element NB to the
end of element NE: NN pulses, NN - 1 equal curvilinear steps, "in a symmetric geometric
fashion". ET checks NB < NE <= element count and 2 < NN <= MPN, where

    MPN = CPTL / max(2 * max(encoder resolution of X and Y), trajectory velocity * Tbase)

and CPTL is the sum of the lengths of elements NB..NE. A pulse number outside that range
is replaced by the MPN and ET reports an error; NI? then reads the MPN.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import overload

from .errors import PULSE_ELEMENTS, PULSE_NUMBER, ErrorCode, MM4005Error
from .geometry import Geometry, Point

# MPN is a count of whole pulses; the quotient is floored after this relative slack so
# that 25.70796.../0.002 rounding to 12853.999999 still counts 12854 when exact.
_FLOOR_SLACK = 1e-9


@dataclass(slots=True)
class PulseSettings:
    """NB, NE, NI, NN as last set, NS's arm, and the MPN reported after a substitution."""

    start_element: int = 0  # NB
    end_element: int = 0  # NE
    step: float = 0.0  # NI, as specified
    count: int = 0  # NN
    armed: bool = False  # NS, cleared when ET takes it
    substituted_mpn: int | None = None  # set when ET replaced NN; NI? reads it then

    def set_step(self, step: float) -> None:
        self.step = step
        self.substituted_mpn = None

    def set_count(self, count: int) -> None:
        self.count = count
        self.substituted_mpn = None

    def apply_substitution(self, mpn: int) -> None:
        """ET replaced NN by the MPN: NN? and NI? read it from now on."""
        self.count = mpn
        self.substituted_mpn = mpn

    def reported_step(self) -> float | int:
        """NI?: the MPN after ET substituted it, else the value NI specified."""
        return self.substituted_mpn if self.substituted_mpn is not None else self.step


@dataclass(frozen=True, slots=True)
class PulsePoint:
    """One pulse: its index (0 first), path distance from the trajectory start, distance
    from the start of element NB, the element it falls in, and where X/Y are then
    (trajectory coordinates, relative to the start point)."""

    index: int
    path_distance: float
    pulsed_distance: float
    element: int
    point: Point


@dataclass(frozen=True, slots=True)
class PulsePlan:
    start_element: int
    end_element: int
    count: int
    step: float
    cptl: float
    mpn: int
    points: PulsePoints


def maximum_pulse_number(cptl: float, resolution: float, velocity: float,
                         base_period: float) -> int:
    """MPN: how many spacings of max(2 x resolution, velocity x Tbase) fit in CPTL."""
    spacing = max(2.0 * resolution, velocity * base_period)
    if spacing <= 0.0:
        raise ValueError("pulse spacing must be positive")
    return int(math.floor(cptl / spacing * (1.0 + _FLOOR_SLACK)))


class PulsePoints(Sequence[PulsePoint]):
    """``count`` pulses at equal curvilinear distances, the first at the start of element
    ``start_element`` and the last at the end of ``end_element`` (1-based, inclusive),
    each computed when asked: ET must not build a million pulses (NN up to the MPN) before
    it has checked the travel, and the run fires them a batch at a time."""

    def __init__(self, elements: Sequence[Geometry], start_element: int, end_element: int,
                 count: int) -> None:
        self._elements = elements
        self._start = start_element
        self._count = count
        lengths = [g.length for g in elements]
        self._before = sum(lengths[: start_element - 1])
        self._cptl = sum(lengths[start_element - 1 : end_element])
        ends: list[float] = []  # where each element from NB to NE ends on the path
        end = self._before
        for length in lengths[start_element - 1 : end_element]:
            end += length
            ends.append(end)
        self._ends = ends

    def __len__(self) -> int:
        return self._count

    @overload
    def __getitem__(self, index: int) -> PulsePoint: ...

    @overload
    def __getitem__(self, index: slice) -> Sequence[PulsePoint]: ...

    def __getitem__(self, index: int | slice) -> PulsePoint | Sequence[PulsePoint]:
        if isinstance(index, slice):
            return [self[k] for k in range(*index.indices(self._count))]
        k, s, path, j = self._locate(index)
        ends = self._ends
        element_start = self._before if j == 0 else ends[j - 1]
        geometry = self._elements[self._start - 1 + j]
        at = (geometry.end if k == self._count - 1
              else geometry.point_at(path - element_start))
        return PulsePoint(k, path, s, self._start + j, at)

    def element(self, index: int) -> int:
        """The element pulse `index` falls in (what the run logs; no point computed)."""
        return self._start + self._locate(index)[3]

    def _locate(self, index: int) -> tuple[int, float, float, int]:
        """(index, distance from NB's start, path distance, element offset from NB)."""
        k = index + self._count if index < 0 else index
        if not 0 <= k < self._count:
            raise IndexError(index)
        s = self._cptl * k / (self._count - 1)
        path = self._before + s
        # the first element that ends at or after the pulse
        j = min(bisect.bisect_left(self._ends, path), len(self._ends) - 1)
        return k, s, path, j


def pulse_points(elements: Sequence[Geometry], start_element: int, end_element: int,
                 count: int) -> PulsePoints:
    """The pulses of NB..NE, computed when asked (see `PulsePoints`)."""
    return PulsePoints(elements, start_element, end_element, count)


def plan_pulses(settings: PulseSettings, elements: Sequence[Geometry], resolution: float,
                velocity: float, base_period: float) -> tuple[PulsePlan, ErrorCode | None]:
    """ET's pulse checks, without changing ``settings`` (ET applies a substitution only
    once every check has passed). Element numbers out of order refuse ET; a pulse number
    outside (2, MPN] is replaced by the MPN and reported. When NN was never set but NI
    was, NN is derived from NI (our decision: floor(CPTL / NI) + 1)."""
    nb, ne, total = settings.start_element, settings.end_element, len(elements)
    if nb < 1 or ne > total or nb >= ne:
        raise MM4005Error(PULSE_ELEMENTS, f"NB{nb} NE{ne} with {total} elements")
    cptl = sum(g.length for g in elements[nb - 1 : ne])
    mpn = maximum_pulse_number(cptl, resolution, velocity, base_period)
    count = settings.count
    if count == 0 and settings.step > 0.0:
        count = int(math.floor(cptl / settings.step * (1.0 + _FLOOR_SLACK))) + 1
    warning: ErrorCode | None = None
    if not 2 < count <= mpn:
        if mpn <= 2:
            raise MM4005Error(PULSE_NUMBER, f"MPN {mpn} leaves no room for pulses")
        count = mpn
        warning = PULSE_NUMBER
    points = pulse_points(elements, nb, ne, count)
    return PulsePlan(nb, ne, count, cptl / (count - 1), cptl, mpn, points), warning

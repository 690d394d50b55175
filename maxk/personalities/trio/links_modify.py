"""MOVELINK_MODIFY: move the end of the running MOVELINK by an offset.

The MOVELINK_MODIFY page of the TrioBASIC help: the MOVELINK running on the axis is to
complete at its end plus the offset (ENDMOVE moves by it: C, the page's example 1); it
is applied only if the MOVELINK has not started decelerating and there is room to make
the change without a deceleration faster than the one specified; otherwise the
parameter keeps the offset (C). Applied, it reads 0 (C: the example waits for it). A
MOVELINK of no distance (a delay by a distance) has its link distance changed instead
(C: example 2).

What the page leaves open, decided here (D):
- how the rest is reshaped: the offset is added over the link travel from where the link
  is now to where the deceleration starts, as a symmetric S (the share 2z^2 of it over
  the first half of that stretch, 1 - 2(1 - z)^2 over the second), so the position and
  the ratio stay continuous, the deceleration ramp is the MOVELINK's own, and the axis
  moves exactly the offset more;
- "room": the S's change of ratio per count of link travel, 4 |offset| / stretch^2, at
  most the specified deceleration's (the peak ratio over the decel distance); with no
  decel distance any stretch is room;
- an offset that cannot be applied stays, and is tried again when the next MOVELINK on
  the axis starts (the page's examples clear it to 0 before a MOVELINK for that reason);
- a repeating MOVELINK, one waiting for its start, and FLEXLINK are not modified (it
  stays).
"""

from __future__ import annotations

from typing import Protocol

import numpy as np

from .link_kinds import Movelink
from .runs import TrioAxis


class Host(Protocol):
    axes: list[TrioAxis]

    def changed(self) -> None: ...
    def demand(self, axis: int) -> float: ...


def peak_ratio(link: Movelink) -> float:
    """The MOVELINK's ratio between its ramps (counts per count of link travel)."""
    distance = link.distance if link.shaped is None else link.shaped
    return distance / (link.span - (link.accel + link.decel) / 2.0)


def apply(m: Host, axis: int, link: Movelink, offset: float) -> bool:
    """Apply the offset to the MOVELINK running on the axis now; False: not possible."""
    if type(link) is not Movelink or link.repeat or link.wait is not None:
        return False
    position = np.array([m.demand(link.link)])
    if link.follow is not None:
        position = link.follow.effective(position)
    travelled = max(float(position[0]) - link.link_origin, 0.0)
    if link.distance == 0 and link.shaped is None:  # a delay: its link distance moves
        if not link.span + offset > travelled:
            return False
        link.span += offset
        return True
    decelerating = link.span - link.decel
    stretch = decelerating - travelled
    if not stretch > 0:
        return False
    if link.decel > 0 and 4.0 * abs(offset) / (stretch * stretch) \
            > abs(peak_ratio(link)) / link.decel:
        return False  # (no room: D)
    if link.shaped is None:
        link.shaped = link.distance
    link.adjust.append((offset, travelled, decelerating))
    link.distance += offset
    return True


def request(m: Host, axis: int, offset: float) -> None:
    """MOVELINK_MODIFY = offset: applied now if it can be (the parameter then reads 0),
    else kept."""
    a = m.axes[axis]
    a.params["MOVELINK_MODIFY"] = offset
    attempt(m, axis)


def attempt(m: Host, axis: int) -> None:
    """Apply a kept offset to the axis's running MOVELINK (a write, a MOVELINK start)."""
    a = m.axes[axis]
    offset = a.params.get("MOVELINK_MODIFY", 0.0)  # user units (D)
    if offset != 0 and isinstance(a.link, Movelink) \
            and apply(m, axis, a.link, offset * a.units):
        a.params["MOVELINK_MODIFY"] = 0.0
        m.changed()


__all__ = ["apply", "attempt", "request"]

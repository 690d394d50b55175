"""DLINK: the SLM digital drive interface, as an MC405 answers it (TrioBASIC help DLINK).

DLINK's functions talk to an SLM module on a Motion Coordinator's rear slot and to the
servo drive behind it. The MC405 has no SLM slot and the world has no SLM module or
drive, so each function answers as the page says it does when nothing answers: the
presence checks (2, 3) return 0, assigning an axis (4) fails (FALSE, the axis's ATYPE is
not set to 11), the reads (5, 8, 10) and the channel query (9) return -1, the writes (6, 7)
return FALSE. Arguments are checked first, so a wrong call is refused the way the
controller refuses a bad argument, and nothing is half done (there is nothing to do).
"""

from __future__ import annotations

from collections.abc import Sequence

FALSE = 0.0
FAILED = -1.0  # what the reads return when the command fails (help DLINK 5, 8, 9, 10)

ARGUMENTS = {2: 3, 3: 3, 4: 4, 5: 3, 6: 4, 7: 3, 8: 3, 9: 2, 10: 3}
"""Each function's argument count, the function number included (help DLINK)."""
_AXIS_FIRST = frozenset({5, 6, 7, 8, 9, 10})  # the second argument is an axis


def _whole(value: float, low: float, high: float) -> int:
    if value != int(value) or not low <= value <= high:
        raise ValueError("Parameter out of range")
    return int(value)


def dlink(args: Sequence[float], axis_count: int) -> float:
    """DLINK(function, ...): the value the function returns on an MC405 (see the module
    docstring). Functions 0 and 1 are reserved and refused (D)."""
    if not args:
        raise ValueError("Syntax error")
    function = _whole(args[0], 2, 10)
    if len(args) != ARGUMENTS[function]:
        raise ValueError("Syntax error")
    if function in _AXIS_FIRST:
        _whole(args[1], 0, axis_count - 1)
    else:  # slot, communication channel (and the axis to assign, function 4)
        _whole(args[1], 0, 1e6)
        _whole(args[2], 0, 1e6)
        if function == 4:
            _whole(args[3], 0, axis_count - 1)
    if function in (2, 3):
        return 0.0  # no SLM module, no SLM drive answers
    if function in (4, 6, 7):
        return FALSE
    return FAILED


__all__ = ["ARGUMENTS", "dlink"]

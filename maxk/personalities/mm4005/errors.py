"""The MM4005 error register: one ASCII character read by TE, code and text by TB.

The controller keeps only the last error (a newer one overwrites it) and reading it with
TE or TB clears it (manual 3.126, TB). Codes A, B, D and S and the texts of @ and B are
the manual's; C's meaning comes from a sibling controller and the French firmware text;
the trajectory letters are our choice because the manual's error appendix was not
available (recorded per entry, see docs/mm4005.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Final


@dataclass(frozen=True, slots=True)
class ErrorCode:
    """One error character with the text TB reports, and where it comes from."""

    char: str
    text: str
    confidence: str  # C certain / I inferred / D our decision
    source: str


def _code(char: str, text: str, confidence: str, source: str) -> ErrorCode:
    return ErrorCode(char, text, confidence, source)


NO_ERROR: Final = _code("@", "No error", "C", "manual 3.126 TB example: 'TB@ No error'")
UNKNOWN_MESSAGE: Final = _code(
    "A", "Unknown message code", "C",
    "manual 3.75 MS / 3.41 DP / 3.132 TH: 'A - Unknown message code', also a floating-point axis")
AXIS_NUMBER: Final = _code(
    "B", "Axis Number not Correct", "C",
    "manual 3.126 TB example 'TBB Axis Number not Correct'; 3.75 MS 'B - Incorrect axis number'")
PARAMETER: Final = _code(
    "C", "Parameter out of limits", "I",
    "LDS1000 (same TE scheme) 'C: Parameters out of limits'; French MM4005 firmware text "
    "'C Parametre manque, hors limites ou incorrect' (missing, out of range or wrong)")
IO_CHANNEL: Final = _code(
    "E", "Incorrect I/O channel number", "C", "manual 3.103 RB: 'E - Incorrect I/O channel number'")
UNAUTHORIZED: Final = _code(
    "D", "Unauthorized execution", "C", "manual 3.41 DP: 'D - Unauthorized execution'")
NOT_AUTHORIZED_FUNCTION: Final = _code(
    "Q", "Function not authorized", "I",
    "French MM4005 firmware text 'Q Fonction non autorise'; raised (D) by a command the "
    "table knows but the emulator cannot carry out (RQ, the program commands)")
TIME_OUT: Final = _code(
    "S", "Communication time-out", "C",
    "manual 3.75 MS 'S - Communication time-out'; never raised (no link time-out modelled)")
TRAJECTORY_EMPTY: Final = _code(
    "K", "Trajectory not defined", "D", "letter ours: ET, LT, XE or EL with no element")
TRAJECTORY_ELEMENT: Final = _code(
    "L", "Trajectory element incorrect", "D",
    "letter ours: an element that cannot be built (LX along a vertical tangent, a line or "
    "arc running backwards or of zero length, CA without CR, CY without CX, MY without MX)")
ANGLE_DISCONTINUITY: Final = _code(
    "M", "Angle discontinuity too large", "D",
    "letter ours: ET finds an element whose entry angle differs from the previous exit "
    "angle by more than AD (MM4006 manual 5.4 'maximum angle discontinuity')")
PULSE_ELEMENTS: Final = _code(
    "N", "Pulse start or end element incorrect", "D",
    "letter ours: ET with NS armed and NB < 1, NB >= NE or NE > element count (seed 6.1.2)")
PULSE_NUMBER: Final = _code(
    "P", "Pulse number replaced by the maximum pulse number", "D",
    "letter ours: ET with NS armed and NN <= 2 or NN > MPN (seed 6.1.2: 'ET will replace the "
    "desired number of pulses with the Maximum Pulse Number and return the appropriate "
    "error code')")
TRAVEL_LIMITS: Final = _code(
    "R", "Trajectory outside travel limits", "D",
    "letter ours: ET when the path (from where X and Y stand) leaves an axis's SL/SR limits")

TRAJECTORY_SPEED_CHANGE: Final = _code(
    "G", "Trajectory speed change too large", "D",
    "letter ours: VC finds a speed change between two elements of the time-based "
    "trajectory above the axis's GC ('maximum allowable speed error between blocks', "
    "MM4005_trajectoryScan.st)")
TRAJECTORY_VELOCITY: Final = _code(
    "H", "Trajectory velocity too large", "D",
    "letter ours: VC finds an element of the time-based trajectory faster than the "
    "axis's maximum speed VU")
TRAJECTORY_NOT_VERIFIED: Final = _code(
    "J", "Trajectory not verified", "D",
    "letter ours: EC before a VC that passed on the present definition")

FOLLOWING_ERROR: Final = _code(
    "T", "Following error", "D",
    "letter ours: a servo axis (gains applied by UF) lagged its profile by more than FE "
    "(or its loop tripped): its motor was turned off (it was F until the manual's XM page, "
    "3.175, showed F is the program-number error)")
PROGRAM_NUMBER: Final = _code(
    "F", "Program number out of range", "C",
    "manual 3.175 XM: program number 0 to 127, 'Out of range: Error F'; the text is ours "
    "after TY's 'O - Variable number out of range' (I)")
VARIABLE_NUMBER: Final = _code(
    "O", "Variable number out of range", "C",
    "manual 3.145 TY: 'O - Variable number out of range' (missing or out of range)")

ERROR_CODES: Final[dict[str, ErrorCode]] = {
    code.char: code
    for code in (NO_ERROR, UNKNOWN_MESSAGE, AXIS_NUMBER, PARAMETER, UNAUTHORIZED, IO_CHANNEL,
                 TRAJECTORY_EMPTY, TRAJECTORY_ELEMENT, ANGLE_DISCONTINUITY, PULSE_ELEMENTS,
                 PULSE_NUMBER, NOT_AUTHORIZED_FUNCTION, TRAVEL_LIMITS, TIME_OUT,
                 TRAJECTORY_SPEED_CHANGE, TRAJECTORY_VELOCITY, TRAJECTORY_NOT_VERIFIED,
                 FOLLOWING_ERROR, PROGRAM_NUMBER, VARIABLE_NUMBER)
}

UNKNOWN_ERROR_TEXT: Final = "Unknown error code"  # manual 3.126: TB with an out-of-range code


class MM4005Error(Exception):
    """A command refused by the controller; the language stores ``code`` in the register."""

    def __init__(self, code: ErrorCode, detail: str = "") -> None:
        super().__init__(f"{code.char} {code.text}" + (f": {detail}" if detail else ""))
        self.code = code
        self.detail = detail


class ErrorRegister:
    """The single last-error character: a new error overwrites, a read clears."""

    def __init__(self) -> None:
        self._code: ErrorCode = NO_ERROR

    def record(self, code: ErrorCode) -> None:
        """Keep only the newest error (manual 3.126: earlier ones are lost)."""
        self._code = code

    def peek(self) -> ErrorCode:
        return self._code

    def take(self) -> ErrorCode:
        """TE / TB without a code: report the error and clear the buffer."""
        code, self._code = self._code, NO_ERROR
        return code

    @staticmethod
    def describe(char: str) -> str:
        """TB with a code: translate it without touching the register."""
        code = ERROR_CODES.get(char)
        return code.text if code is not None else UNKNOWN_ERROR_TEXT

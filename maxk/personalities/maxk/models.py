"""Board models MAXk-1000 .. MAXk-A000 and the factory constants of the manual."""

from __future__ import annotations

from dataclasses import dataclass

AXIS_LETTERS = "XYZTUVRSWK"
"""Axis order everywhere on the board (manual, Appendix C)."""

QUEUE_CAPACITY = 2559
"""Units in each axis command queue (manual 6.2 and Appendix C)."""

MAX_VELOCITY = 4_176_000
"""Steps/s (Appendix C; the introduction says 4,000,000: we accept the larger)."""

MAX_ACCELERATION = 8_000_000
"""Steps/s^2 (Appendix C)."""

POSITION_MIN = -2_147_483_647
POSITION_MAX = 2_147_483_647
"""Signed 32-bit position counters (manual 3.x: +/- 2,147,483,647)."""

UPDATE_RATES_HZ = (1024, 2048, 4096, 8192)
"""#UR operands: update rate in Hz, i.e. 976.6, 488.3, 244.1 and 122.1 us periods."""

DEFAULT_UPDATE_RATE_HZ = 8192
"""Factory update rate: 122.07 us per tick."""

FIRMWARE_VERSION = "1.33"
SERIAL_NUMBER = "000001"
FPGA_VERSION = "20"


@dataclass(frozen=True)
class BoardModel:
    """One orderable MAXk model: the name's first digit is the axis count (A = 10)."""

    name: str
    axes: int

    @property
    def axis_letters(self) -> str:
        return AXIS_LETTERS[: self.axes]

    @property
    def io_lines(self) -> int:
        """General purpose digital I/O lines (Table 6-2): 16 from six axes up; boards with
        five or fewer axes have connector J1 only, "half of the possible I/Os": 8, and
        the MAXk-2000 6, as the table prints it."""
        if self.axes >= 6:
            return 16
        return 6 if self.axes == 2 else 8

    @property
    def analog_inputs(self) -> int:
        """General purpose analog inputs (Table 6-2): 4 from six axes up, else 2."""
        return 4 if self.axes >= 6 else 2


def _model_name(axes: int) -> str:
    return f"MAXk-{'A' if axes == 10 else axes}000"


MODELS: dict[str, BoardModel] = {
    _model_name(n): BoardModel(_model_name(n), n) for n in range(1, 11)
}
DEFAULT_MODEL = "MAXk-8000"


def model_by_name(name: str) -> BoardModel:
    """Look up a model by name, case-insensitively; also accept a bare axis count."""
    text = name.strip()
    if text.isdigit() and 1 <= int(text) <= 10:
        return MODELS[_model_name(int(text))]
    for key, model in MODELS.items():
        if key.lower() == text.lower():
            return model
    known = ", ".join(MODELS)
    raise ValueError(f"unknown board model {name!r}; known models: {known}")

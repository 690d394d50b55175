"""The compiled servo kernel (_servo_kernel.c); see servo_kernel.py."""

from array import array
from collections.abc import Sequence
from typing import Any

STATE_SIZE: int
PARAM_SIZE: int
HEADER: int

def step(state: array, params: array, program: array, tick: int, count: int, /) -> int: ...
def step_axes(axes: Sequence[Any], limit: int, /) -> list[Any]: ...

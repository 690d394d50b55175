"""The OMS MAXk personality: queues, LS/LE loops, command mode, flags and doorbell, MAXnet
words, status strings, capture ring, models, parameter archive and power-up, vector tasks."""

from maxk.personalities.maxk.board import Board, CommandErrorRecord
from maxk.personalities.maxk.models import (
    AXIS_LETTERS,
    DEFAULT_MODEL,
    MODELS,
    BoardModel,
    model_by_name,
)

__all__ = ["AXIS_LETTERS", "DEFAULT_MODEL", "MODELS", "Board", "BoardModel",
           "CommandErrorRecord", "model_by_name"]

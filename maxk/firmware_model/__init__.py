"""The machine: a deterministic MAXk board model that owns virtual time."""

from .board import Board, CommandErrorRecord
from .models import AXIS_LETTERS, DEFAULT_MODEL, MODELS, BoardModel, model_by_name

__all__ = ["AXIS_LETTERS", "DEFAULT_MODEL", "MODELS", "Board", "BoardModel",
           "CommandErrorRecord", "model_by_name"]

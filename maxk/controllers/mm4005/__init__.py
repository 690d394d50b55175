"""The Newport MM4005 behind the doors: its controller and console (`controller.py`) and
the recording of a run for traces and plots (`trace.py`).
`from maxk.controllers.mm4005 import MM4005Controller` is the public path."""

from maxk.controllers.mm4005.controller import MODELS, MM4005Controller, axis_count_of

__all__ = ["MODELS", "MM4005Controller", "axis_count_of"]

"""The Trio MC405 behind the doors: its controller, console and world view
(`controller.py`). `from maxk.controllers.trio import MC405` is the public path."""

from maxk.controllers.trio.controller import MC405, program_directory

__all__ = ["MC405", "program_directory"]

"""The OMS MAXk behind the doors: its controller (`controller.py`) and its console
(`console.py`). `from maxk.controllers.maxk import MAXk` is the public path."""

from maxk.controllers.maxk.controller import MAXk, MaxWorldView

__all__ = ["MAXk", "MaxWorldView"]

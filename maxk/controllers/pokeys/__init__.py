"""The PoKeys behind the doors: its controller and Python API (`controller.py`,
`io_api.py`), its console (`console.py`, `console_io.py`, `status.py`), its world view
(`world_view.py`) and its slot recorder (`trace.py`).
`from maxk.controllers.pokeys import PoKeys` is the public path."""

from maxk.controllers.pokeys.controller import PoKeys, build
from maxk.controllers.pokeys.status import PoKeysError

__all__ = ["PoKeys", "PoKeysError", "build"]

"""maxk: an emulator of the OMS MAXk motion controller."""

__version__ = "0.1.0"

from .controller import MAXk  # noqa: E402

__all__ = ["MAXk", "__version__"]

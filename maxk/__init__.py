"""maxk: an emulator of the OMS MAXk motion controller."""

__version__ = "0.1.0"

from maxk import compiled as _compiled  # noqa: E402

if _compiled.pure_python_requested():  # MAXK_PURE_PYTHON=1: the sources, not mypyc's build
    _compiled.use_pure_python()

from maxk.controllers.maxk.controller import MAXk  # noqa: E402


def _register_pyserial_handler() -> None:
    """pyserial's documented hook for URL handlers: `maxk://` finds maxk.host.protocol_maxk."""
    try:
        import serial
    except ImportError:  # pragma: no cover - pyserial is a dependency
        return
    packages = getattr(serial, "protocol_handler_packages", None)
    if packages is not None and "maxk.host" not in packages:
        packages.append("maxk.host")


_register_pyserial_handler()

__all__ = ["MAXk", "__version__"]

"""Which modules the install compiles with mypyc, and the switch that turns them off.

setup.py compiles these typed hot modules (the shared engine, profiles, axis and paths,
the MAXk board, axes, queues and vector tasks, the MAX lexer, interpreter and actions)
where mypyc and a C compiler exist, and installs pure Python where they do not: the
replies are the same either way (README, "Speed"). ``MAXK_PURE_PYTHON=1`` in the
environment makes an installed build import the Python sources instead of the compiled
modules, so that one install can run the suite both ways. setup.py reads this file
without importing maxk: keep it free of imports from the package.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType

COMPILED_MODULES = (
    "maxk.firmware_model.engine",
    "maxk.firmware_model.axis",
    "maxk.firmware_model.profiles",
    "maxk.firmware_model.motion",
    "maxk.firmware_model.path",
    "maxk.firmware_model.world",
    "maxk.personalities.maxk.axis",
    "maxk.personalities.maxk.board",
    "maxk.personalities.maxk.queue",
    "maxk.personalities.maxk.waits",
    "maxk.personalities.maxk.config",
    "maxk.personalities.maxk.contouring",
    "maxk.personalities.maxk.capture",
    "maxk.commands.max.queued_motion",
    "maxk.commands.max.context",
    "maxk.commands.max.queued",
    "maxk.commands.max.lexer",
    "maxk.commands.max.interpreter",
    "maxk.commands.max.vector",
)
"""Compiled when a compiled build's rules (docs/architecture.md) are kept in them: the
shared machine's modules (the world too: every controller's switches and inputs) and
the MAXk's, never a module only another controller's team edits. A compiled class
calls no custom `__setattr__` on attribute assignments from compiled code: AxisConfig
checks its plans' parameters at each move instead of dropping them in one."""

GROUP = "maxk._compiled"
"""mypyc's shared library for them (`maxk/_compiled__mypyc*.so`), inside the package so
an editable install finds it."""

PURE_PYTHON_VARIABLE = "MAXK_PURE_PYTHON"


def pure_python_requested() -> bool:
    return os.environ.get(PURE_PYTHON_VARIABLE, "") not in ("", "0")


class _SourceFirst:
    """A meta-path finder that loads the compiled modules from their .py files."""

    @staticmethod
    def find_spec(name: str, path: Sequence[str] | None = None,
                  target: ModuleType | None = None) -> importlib.machinery.ModuleSpec | None:
        if name not in COMPILED_MODULES:
            return None
        package = Path(__file__).resolve().parent
        source = package.joinpath(*name.split(".")[1:]).with_suffix(".py")
        if not source.is_file():
            return None
        return importlib.util.spec_from_file_location(name, source)


def use_pure_python() -> None:
    """Import the compiled modules from source from now on (before any is imported)."""
    if not any(isinstance(f, _SourceFirst) for f in sys.meta_path):
        sys.meta_path.insert(0, _SourceFirst())


def built() -> list[str]:
    """The listed modules whose shared library was built beside their source."""
    package = Path(__file__).resolve().parent
    found = []
    for name in COMPILED_MODULES:
        stem = package.joinpath(*name.split(".")[1:])
        if any(stem.with_name(stem.name + suffix).is_file()
               for suffix in importlib.machinery.EXTENSION_SUFFIXES):
            found.append(name)
    return found


def active() -> list[str]:
    """The compiled modules this process runs compiled (imported from a shared library)."""
    compiled = []
    for name in COMPILED_MODULES:
        module = sys.modules.get(name)
        if module is not None and not str(getattr(module, "__file__", "")).endswith(".py"):
            compiled.append(name)
    return compiled

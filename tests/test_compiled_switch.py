"""The mypyc-compiled modules (maxk/compiled.py, setup.py) and MAXK_PURE_PYTHON: a module
runs compiled exactly when its shared library was built beside it, and the switch turns
every one back into its Python source. (That the replies are the same either way is the
whole suite's job: CI runs it both ways, .ci/run.)"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import maxk
from maxk import compiled

PACKAGE = Path(maxk.__file__).resolve().parent
REPORT = ("import json, importlib, maxk.compiled as c\n"
          "for name in c.COMPILED_MODULES: importlib.import_module(name)\n"
          "print(json.dumps([c.active(), [importlib.import_module(n).__file__ "
          "for n in c.COMPILED_MODULES]]))")


def _run(pure: bool) -> tuple[list[str], list[str]]:
    env = dict(os.environ)
    env.pop(compiled.PURE_PYTHON_VARIABLE, None)
    if pure:
        env[compiled.PURE_PYTHON_VARIABLE] = "1"
    env["PYTHONPATH"] = str(PACKAGE.parent) + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run([sys.executable, "-c", REPORT], env=env, capture_output=True,
                         text=True, timeout=120, check=True).stdout
    active, files = json.loads(out)
    return active, files


def test_a_module_runs_compiled_exactly_when_it_was_built() -> None:
    active, files = _run(pure=False)
    assert active == compiled.built()
    for name, file in zip(compiled.COMPILED_MODULES, files, strict=True):
        assert file.endswith(".py") == (name not in active)


def test_the_switch_imports_every_listed_module_from_its_source() -> None:
    active, files = _run(pure=True)
    assert active == []
    expected = [str(PACKAGE.joinpath(*n.split(".")[1:]).with_suffix(".py"))
                for n in compiled.COMPILED_MODULES]
    assert files == expected


def test_setup_compiles_the_listed_modules_and_nothing_another_team_edits() -> None:
    # never a module of another controller's language, personality or the doors
    for name in compiled.COMPILED_MODULES:
        parts = name.split(".")
        assert not {"trio", "mm4005", "pokeys", "host"} & set(parts), name
        assert PACKAGE.joinpath(*parts[1:]).with_suffix(".py").is_file(), name

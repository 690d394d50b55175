"""pytest plugin: command scripts (`*.maxk`) of any controller collected and run as tests.

Registered through the `pytest11` entry point, so installing maxk is enough: pytest
collects every `*.maxk` file under its test paths (pytest's pattern for non-Python test
files). Each script runs on a fresh controller in virtual time, at its own rate unless the
script's `@rate` says otherwise; a script naming several
models (`@board MAXk-4000 MAXk-A000`) or rates (`@rate 1024 8192`) becomes one test per
combination, and `--maxk-model` / `--maxk-rate` override what the scripts say.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from maxk.controllers.registry import KINDS, canonical_model, kind_of
from maxk.script import Script, ScriptError, Transcript, load_script, run_script


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("maxk", "maxk command scripts (any controller)")
    group.addoption("--maxk-model", action="append", default=None, metavar="MODEL",
                    help="run every .maxk script on this controller model (repeatable)")
    group.addoption("--maxk-rate", action="append", default=None, type=int, metavar="HZ",
                    help="run every .maxk script whose controller runs at this update "
                    "rate at it (repeatable; the others at their own)")
    parser.addini("maxk_suffix", "file suffix of maxk command scripts", default=".maxk")


def pytest_collect_file(parent: pytest.Collector, file_path: Path) -> pytest.Collector | None:
    if file_path.suffix == parent.config.getini("maxk_suffix"):
        return MaxkScriptFile.from_parent(parent, path=file_path)
    return None


class MaxkScriptFile(pytest.File):
    """One script file: one test per (model, update rate) it asks for."""

    def collect(self) -> Any:
        try:
            script = load_script(self.path)
        except ScriptError as error:
            # A malformed script is a collection error naming the line, not a traceback.
            raise self.CollectError(str(error)) from None
        config = self.config
        models = config.getoption("maxk_model") or script.models
        asked: list[int] = config.getoption("maxk_rate") or []
        try:
            models = [canonical_model(m) for m in models]
        except ValueError as error:
            raise self.CollectError(f"--maxk-model: {error}") from None
        unknown = [r for r in asked if not any(r in k.update_rates_hz for k in KINDS)]
        if unknown:
            raise self.CollectError(f"--maxk-rate {unknown[0]}: no controller runs at it")
        combos: list[tuple[str, int | None]] = []
        for model in models:
            kind = kind_of(model)
            rates: list[int | None]
            if asked:  # --maxk-rate: the rates this controller runs at, else its own
                rates = [r for r in asked if r in kind.update_rates_hz] or [None]
            else:
                rates = list(script.update_rates_hz)
                for rate in rates:
                    try:
                        kind.check_rate(rate)
                    except ValueError as error:
                        raise self.CollectError(f"{self.path.name}: {error}") from None
            combos += [(model, rate) for rate in rates]
        for model, rate in combos:
            shown = rate or kind_of(model).default_rate_hz
            name = "script" if len(combos) == 1 else f"{model}-{shown}Hz"
            yield MaxkScriptItem.from_parent(self, name=name, script=script, model=model,
                                             rate=rate)


class ScriptFailed(Exception):
    def __init__(self, transcript: Transcript) -> None:
        super().__init__(f"{len(transcript.failures)} failure(s)")
        self.transcript = transcript


class MaxkScriptItem(pytest.Item):
    def __init__(self, *, script: Script, model: str, rate: int | None,
                 **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.script = script
        self.model = model
        self.rate = rate

    def runtest(self) -> None:
        transcript = run_script(self.script, model=self.model, update_rate_hz=self.rate)
        if transcript.failures:
            raise ScriptFailed(transcript)

    def repr_failure(self, excinfo: pytest.ExceptionInfo[BaseException],
                     style: Any = None) -> str:
        if isinstance(excinfo.value, ScriptFailed):
            failures = excinfo.value.transcript.failures
            head = (f"{self.path.name} on {self.model} at {self._hz} Hz: "
                    f"{len(failures)} failure(s)")
            return "\n".join([head, *(f.report() for f in failures)])
        return str(super().repr_failure(excinfo))

    def reportinfo(self) -> tuple[Path, int | None, str]:
        return self.path, 0, f"maxk script {self.path.name} [{self.model} {self._hz} Hz]"

    @property
    def _hz(self) -> int | None:
        return self.rate or kind_of(self.model).default_rate_hz

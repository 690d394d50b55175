"""tools/fault_check.py's faults still name code that exists: each anchor is in its file
exactly once, and each fault's test files exist (the slow part, breaking the tree and
running the tests, is the tool's, run by hand: docs/contributing.md)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).parent.parent
_spec = importlib.util.spec_from_file_location("fault_check", ROOT / "tools" / "fault_check.py")
assert _spec is not None and _spec.loader is not None
fault_check = importlib.util.module_from_spec(_spec)
sys.modules.setdefault("fault_check", fault_check)  # its dataclasses look it up
_spec.loader.exec_module(fault_check)


@pytest.mark.parametrize("fault", fault_check.FAULTS, ids=[f.name for f in fault_check.FAULTS])
def test_each_fault_anchor_is_in_the_tree_once(fault) -> None:
    assert fault_check.anchor_problem(fault) is None
    assert fault.anchor != fault.replacement
    for test in fault.tests:
        assert (ROOT / test).exists(), test


def test_the_issue_41_faults_are_all_listed() -> None:
    names = {f.name for f in fault_check.FAULTS}
    assert {"trigger-late", "json-level-false", "stuck-inactive", "pokeys-byte-3",
            "pokeys-byte-5", "pokeys-byte-11", "pokeys-byte-14", "pokeys-byte-60",
            "cmd-buffer-free", "s-curve-text", "absolute-encoder",
            "clear-controller-flags"} <= names
    assert len(names) == len(fault_check.FAULTS)


def test_a_moved_anchor_is_reported(tmp_path: Path) -> None:
    fault = fault_check.FAULTS[0]
    (tmp_path / fault.path).parent.mkdir(parents=True)
    (tmp_path / fault.path).write_text("nothing of it here\n")
    assert "anchor not found" in fault_check.anchor_problem(fault, tmp_path)
    (tmp_path / fault.path).write_text(fault.anchor + "\n" + fault.anchor)
    assert "2 times" in fault_check.anchor_problem(fault, tmp_path)

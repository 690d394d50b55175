"""The benchmarks' yardstick is the shared naive loop, statement for statement.

Every speed figure is a multiple of `benchmarks/naive_servo.py`'s rate; a copy that drifted
from the shared loop (a cheaper clamp, fewer axes, another plant) would change every
ratio quoted. The two `run` functions are compared as syntax trees, so comments and
spacing may differ but no operation, constant or order may.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from benchmarks import naive_servo

SHARED = naive_servo.SHARED_LOOP


def _tree(path: Path) -> tuple[str, list[str]]:
    """The `run` function's body and the module constants it reads, as AST dumps."""
    module = ast.parse(path.read_text())
    run = next(node for node in module.body
               if isinstance(node, ast.FunctionDef) and node.name == "run")
    body = [stmt for stmt in run.body
            if not (isinstance(stmt, ast.Expr) and isinstance(stmt.value, ast.Constant))]
    constants = sorted(ast.dump(node) for node in module.body
                       if isinstance(node, ast.Assign) and len(node.targets) == 1
                       and isinstance(node.targets[0], ast.Name)
                       and node.targets[0].id in ("RATE", "AXES"))
    return ast.dump(ast.Module(body=body, type_ignores=[])) + ast.dump(run.args), constants


@pytest.mark.skipif(not SHARED.is_file(), reason="the shared bench is not beside this "
                    "checkout (../shared/bench/naive_servo.py)")
def test_the_copy_is_the_shared_loop_statement_for_statement() -> None:
    assert _tree(Path(naive_servo.__file__)) == _tree(SHARED)


def test_a_changed_loop_is_told_apart(tmp_path: Path) -> None:
    """The comparison sees a one-constant change (a yardstick test that cannot fail
    would hold nothing)."""
    changed = tmp_path / "naive_servo.py"
    changed.write_text(Path(naive_servo.__file__).read_text().replace("32767.0", "32000.0"))
    assert _tree(changed) != _tree(Path(naive_servo.__file__))


def test_the_benchmarks_divide_by_it() -> None:
    """`python -m benchmarks naive` measures the shared loop where it is, this copy
    elsewhere: no other loop."""
    run, which = naive_servo.loop()
    if SHARED.is_file():
        assert which == "the shared naive_servo.py"
        assert run is not naive_servo.run
    else:
        assert run is naive_servo.run

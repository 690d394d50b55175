"""Every script in examples/ is a regression: it must run and match its expected replies."""

from pathlib import Path

import pytest

from maxk.script import load_script, run_script

EXAMPLES = sorted((Path(__file__).parent.parent / "examples").glob("*.maxk"))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.name for p in EXAMPLES])
def test_example_script(path):
    transcript = run_script(load_script(path))
    assert not transcript.failures, "\n".join(map(str, transcript.failures))


def test_there_are_examples():
    assert len(EXAMPLES) >= 4


def test_same_script_same_bytes():
    path = EXAMPLES[0]
    first = run_script(load_script(path))
    second = run_script(load_script(path))
    assert first.entries == second.entries

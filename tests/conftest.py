import os
import tempfile

import pytest
from hypothesis import settings

from maxk import MAXk

# The property tests run the same examples on every run, as every other test does (a run
# that passes passes again); MAXK_HYPOTHESIS=explore draws new examples each run to hunt
# for what the fixed ones miss (a failure found that way is pinned with @example).
# No deadline: a test never depends on the machine's speed (a loaded CI machine or a
# busy neighbour once failed a property on time alone).
settings.register_profile("fixed", derandomize=True, deadline=None)
settings.register_profile("explore", derandomize=False, deadline=None)
settings.load_profile(os.environ.get("MAXK_HYPOTHESIS", "fixed"))

pytest_plugins = ["pytester"]

# The doors' per-user parameter archives (~/.local/share/maxk) must never leak into, or
# out of, a test run: point them at a directory of the run's own.
os.environ["XDG_DATA_HOME"] = tempfile.mkdtemp(prefix="maxk-test-data-")


@pytest.fixture
def board() -> MAXk:
    """A factory-fresh MAXk-8000 at 8192 Hz."""
    return MAXk()


@pytest.fixture
def board4() -> MAXk:
    return MAXk("MAXk-4000")


# The differential suite (test_differential_maxk.py: this tree against an older one on the
# same command streams) is retired from the default run (issue 41): it was written for the
# engine refactor against c4c36cf, and no old commit can be identical to today's MAXk
# (issue 17 and later changed what a MAXk user sees, on purpose: against 2e72938 the
# first random stream already differs), so in CI it could only skip. As a refactoring
# tool: MAXK_BEFORE=<a directory holding the old tree> or MAXK_BEFORE=<a git revision of
# this clone> (extracted here with `git archive`), e.g. `MAXK_BEFORE=main python3 -m
# pytest tests/test_differential_maxk.py`. Measured against HEAD itself: its 30
# in-process comparisons pass; its 7 door-stream comparisons and the pre-refactor
# message check fail against any recent tree (their harness predates today's doors).
collect_ignore: list[str] = []


def _differential_reference() -> None:
    import subprocess
    from pathlib import Path

    before = os.environ.get("MAXK_BEFORE")
    if not before:
        collect_ignore.append("test_differential_maxk.py")
        return
    if Path(before).is_dir():
        return
    root = Path(__file__).resolve().parent.parent
    rev = subprocess.run(["git", "rev-parse", "--verify", "--quiet", f"{before}^{{commit}}"],
                         cwd=root, capture_output=True, text=True)
    if rev.returncode != 0:
        raise pytest.UsageError(
            f"MAXK_BEFORE={before}: neither a directory nor a commit in this clone's "
            "history (a shallow clone? `git fetch --unshallow`)")
    target = Path(tempfile.mkdtemp(prefix="maxk-before-"))
    archive = subprocess.run(["git", "archive", rev.stdout.strip()], cwd=root,
                             capture_output=True, check=True)
    subprocess.run(["tar", "-x", "-C", str(target)], input=archive.stdout, check=True)
    os.environ["MAXK_BEFORE"] = str(target)


_differential_reference()

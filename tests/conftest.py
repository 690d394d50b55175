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

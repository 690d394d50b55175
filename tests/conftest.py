import os
import tempfile

import pytest

from maxk import MAXk

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

import pytest

from maxk import MAXk

pytest_plugins = ["pytester"]


@pytest.fixture
def board() -> MAXk:
    """A factory-fresh MAXk-8000 at 8192 Hz."""
    return MAXk()


@pytest.fixture
def board4() -> MAXk:
    return MAXk("MAXk-4000")

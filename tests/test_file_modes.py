"""Issue 34: every file the server writes for its user has one mode, 0600, whatever the
umask: the MAXk's parameter archive, the PoKeys configuration archive (it was 0644), the
MC405's program store and the PCI map."""

from __future__ import annotations

import os
import stat
from collections.abc import Iterator
from pathlib import Path

import pytest

from maxk.controllers.contract import BuildOptions
from maxk.controllers.registry import build
from maxk.host.shared_memory import SharedMemoryDoor
from tests.hosting import HostedBoards


@pytest.fixture
def open_umask() -> Iterator[None]:
    """The most permissive umask: a mode the code does not choose would show."""
    old = os.umask(0)
    try:
        yield
    finally:
        os.umask(old)


def _modes(directory: Path) -> dict[str, int]:
    return {str(p.relative_to(directory)): stat.S_IMODE(p.stat().st_mode)
            for p in directory.rglob("*") if p.is_file()}


def test_every_file_a_controller_saves_is_0600(tmp_path: Path, open_umask: None) -> None:
    maxk = build("MAXk-4000", BuildOptions(1, str(tmp_path / "maxk.params.json")))
    maxk.send("VL12345;APP;")  # the working parameters become the power-up set
    maxk.engine.advance(8192)
    pokeys = build("PoKeys57CNC", BuildOptions(1, str(tmp_path / "pokeys.json")))
    pokeys.device.io.save()  # PK_SaveConfiguration
    pokeys.device.io.save()  # again: the file is replaced, its mode stays
    trio = build("MC405", BuildOptions(1, str(tmp_path / "mc405.json")))
    session = trio.open_session()
    session.feed(b'SELECT "PROG",0\r\n!PROG,0RPRINT 1\r\n!PROG,1RPRINT 2\r\nRUN "PROG"\r\n')
    modes = _modes(tmp_path)
    assert {"maxk.params.json", "pokeys.json", "mc405.programs/PROG.BAS",
            "mc405.programs/directory.json"} <= set(modes), modes
    assert set(modes.values()) == {0o600}, {k: oct(v) for k, v in modes.items()}


def test_the_map_is_0600(tmp_path: Path, open_umask: None) -> None:
    boards = HostedBoards(models=("MAXk-4000",))
    try:
        door = SharedMemoryDoor(boards.services[0], str(tmp_path / "maxk"))
        try:
            assert _modes(tmp_path) == {"maxk": 0o600}
        finally:
            door.close()
    finally:
        boards.close()

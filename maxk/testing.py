"""A pytest fixture for system tests of host code against served controllers: it starts
`maxk serve --control` with the models asked for, and gives each controller's doors and
the control door's client (`maxk.control.Client`).

    def test_ioc_sees_the_limit(maxk_served):
        served = maxk_served("MAXk-8000", "PoKeys57CNC")
        host, port = served.doors[0].tcp
        ...
        served.client.world(1, "X fault plus active")

Registered as a pytest plugin (entry point `maxk-testing`; or `-p maxk.testing`).
"""

from __future__ import annotations

import os
import re
import selectors
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import pytest

from maxk.control import Client

START_SECONDS = 30.0  # how long a server may take to print its doors (a slow CI machine)
_BOARD = re.compile(r"^board (\d+): (\S+) ?(.*)$")


def _address(text: str) -> tuple[str, int]:
    host, _, port = text.rpartition(":")
    return host, int(port)


@dataclass
class Door:
    """One served controller: where its hosts connect."""

    number: int
    model: str
    tcp: tuple[str, int] | None = None
    udp: tuple[str, int] | None = None
    serial: str | None = None


@dataclass
class Served:
    """A running `maxk serve`: its doors (board 1 first), its control door's client."""

    process: subprocess.Popen[str]
    doors: list[Door] = field(default_factory=list)
    url: str = ""
    token: str | None = None
    client: Client = field(init=False)

    def __post_init__(self) -> None:
        self.client = Client(self.url or "http://127.0.0.1:0", self.token)

    def stop(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self.process.stdout is not None:
            self.process.stdout.close()


def serve(*models: str, options: tuple[str, ...] = ()) -> Served:
    """Start `maxk serve --control` with one controller per model; return once it has
    printed every door (RuntimeError with what it said if it does not)."""
    command = [sys.executable, "-m", "maxk", "serve", "--model", ",".join(models),
               "--port", "0", "--no-archive", "--control", *options]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               stdin=subprocess.DEVNULL, text=True, env=os.environ.copy())
    assert process.stdout is not None
    doors: list[Door] = []
    url, token = "", None
    said: list[str] = []
    deadline = time.monotonic() + START_SECONDS
    with selectors.DefaultSelector() as selector:
        selector.register(process.stdout, selectors.EVENT_READ)
        while not url:
            if time.monotonic() > deadline or process.poll() is not None:
                process.kill()
                process.wait()
                process.stdout.close()
                raise RuntimeError("maxk serve did not start: " + " | ".join(said))
            if not selector.select(0.5):
                continue
            line = process.stdout.readline().strip()
            said.append(line)
            match = _BOARD.match(line)
            if match:
                door = Door(int(match.group(1)), match.group(2))
                for part in match.group(3).split(", "):
                    kind, _, where = part.partition(" ")
                    if kind == "tcp":
                        door.tcp = _address(where)
                    elif kind == "udp":
                        door.udp = _address(where)
                    elif kind == "serial":
                        door.serial = where.split(" ")[0]
                doors.append(door)
            elif line.startswith("control "):
                words = line.split()
                url = words[1]
                token = words[3] if len(words) > 3 and words[2] == "token" else None
    return Served(process, doors, url, token)


@pytest.fixture
def maxk_served() -> Iterator[Callable[..., Served]]:
    """Start served controllers: `maxk_served("MAXk-8000", "MM4005")`; every server
    started is stopped after the test."""
    started: list[Served] = []

    def start(*models: str, options: tuple[str, ...] = ()) -> Served:
        served = serve(*models, options=options)
        started.append(served)
        return served

    yield start
    for served in started:
        served.stop()

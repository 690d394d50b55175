"""The one contract between controllers and doors.

A controller owns an engine (virtual time), opens sessions, resets, and tells its
sessions when it has something to say unasked. Every door (TCP, UDP, pty, the pyserial
URL, the REPL, command scripts, the pytest plugin) and the pacer are written once against
these protocols, so a new controller gets every door by declaring its session:

- a *line* session (MAXk, Trio, MM4005): bytes of command text in, reply bytes out,
  framed as that controller frames them (the MAXnet LF CR, the Trio's echo and prompt,
  the MM4005's CR);
- a *packet* session (PoKeys): fixed-size requests in, one fixed-size reply each.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal, Protocol

if TYPE_CHECKING:
    from maxk.controllers.world_view import WorldView
    from maxk.firmware_model.engine import Engine

Transport = Literal["tcp", "udp", "pty"]
Notify = Callable[[], None]
"""Called by a session when it has output nobody asked for (a flag notification, a
program's PRINT): the door then reads the session and sends what it has."""


class Session(Protocol):
    """One host's conversation with a controller. Its own parser state: half a command
    from one host never mixes with another's."""

    def feed(self, data: bytes) -> None:
        """Bytes from the host, split anywhere; runs what is complete."""
        ...

    def read(self) -> bytes:
        """Everything the controller has to send to this host now (and forget it)."""
        ...

    def close(self) -> None:
        """The host went away: stop telling this session anything."""
        ...


class HoldsInput(Protocol):
    """A session that can hold input it cannot run yet (a Trio statement that waits): a
    door feeds it nothing while `holding` and keeps the rest itself, where its
    back-pressure applies; the session notifies when it takes input again."""

    @property
    def holding(self) -> bool: ...


class Console(Protocol):
    """A person's view of a controller, for the REPL and command scripts: lines typed in,
    lines of output back (no wire framing, no echo), help and completion from the
    language's table, a status line. A packet controller's console is a small command
    language of its own, since its wire protocol is binary."""

    def execute(self, line: str) -> list[str]:
        """Run one typed line; its output lines."""
        ...

    def new_errors(self) -> list[str]:
        """A `! ...` line for each error since the last look (bad commands, power-up)."""
        ...

    def refused(self, replies: list[str], noted: list[str]) -> list[str]:
        """Which of a line's replies and newly noted errors are commands the controller
        refused: what fails a regression script unless it says it expects them."""
        ...

    def prompt(self) -> str: ...
    def status_line(self, width: int = 80) -> str: ...  # one line, fits `width` columns
    def status_lines(self) -> list[str]: ...  # the full picture (`:status`)
    def help(self, topic: str) -> list[str] | None: ...  # None: no such command
    def words(self) -> list[str]: ...  # what Tab completes
    def summary(self, word: str) -> str: ...  # one line about a word, beside a completion
    def is_idle(self) -> bool: ...  # nothing moving, nothing waiting (`:run`, `@wait idle`)
    def repl_help(self) -> list[str]: ...  # its own REPL words, for `help`
    def after_reset(self) -> list[str]: ...  # what `:reset` reports
    def repl_word(self, word: str, rest: str) -> list[str] | None:
        """A controller's own `:word` of the REPL (None: not one of its words)."""
        ...


class ConsoleBase:
    """The `Console` defaults a controller's console inherits, so that it writes only
    what it has: `execute` (and usually `status_line`, `help`, `words`). A console of a
    controller (`self.controller`) gets the prompt, idleness and the full status from
    the contracts."""

    def __init__(self, controller: Controller) -> None:
        self.controller = controller

    def execute(self, line: str) -> list[str]:  # pragma: no cover - each has its own
        raise NotImplementedError

    def new_errors(self) -> list[str]:
        return []

    def refused(self, replies: list[str], noted: list[str]) -> list[str]:
        """By default every error noted (its replies are the controller's own text)."""
        return noted

    def prompt(self) -> str:
        return f"{self.controller.model}> "

    def status_line(self, width: int = 80) -> str:
        """Time and each axis's position (D done, ~ moving), cut to `width`."""
        engine = self.controller.engine
        view = self.controller.world_view()
        parts = []
        for name in view.axis_names:
            r = view.reading(name)
            parts.append(f"{name}{r.position}{'~' if r.moving else 'D' if r.done else ''}")
        return f" t={engine.time:.3f}s  {' '.join(parts)}"[:width]

    def status_lines(self) -> list[str]:
        view = self.controller.world_view()
        lines = ["axis  position   encoder  velocity  state"]
        for name in view.axis_names:
            r = view.reading(name)
            state = "moving" if r.moving else "done" if r.done else "stopped"
            encoder = "-" if r.encoder is None else str(r.encoder)
            lines.append(f"{name:>4} {r.position:>9} {encoder:>9} {round(r.velocity):>9}  "
                         f"{' '.join([state, *r.flags])}")
        return lines

    def help(self, topic: str) -> list[str] | None:
        return None

    def words(self) -> list[str]:
        return []

    def summary(self, word: str) -> str:
        return ""

    def is_idle(self) -> bool:
        view = self.controller.world_view()
        return not any(view.reading(name).moving for name in view.axis_names)

    def repl_help(self) -> list[str]:
        return []

    def after_reset(self) -> list[str]:
        return [f"reset: {self.controller.model} powered up again"]

    def repl_word(self, word: str, rest: str) -> list[str] | None:
        return None


class Controller(Protocol):
    """A controller as the doors see it."""

    @property
    def kind(self) -> str: ...  # "MAXk", "PoKeys", "MC405", "MM4005"
    @property
    def model(self) -> str: ...  # the model name, as `--model` takes it
    @property
    def engine(self) -> Engine: ...  # virtual time; a door advances it to "now"
    @property
    def transports(self) -> Sequence[Transport]: ...  # the doors it has
    @property
    def packet_size(self) -> int | None: ...  # None: a stream of lines

    def open_session(self, notify: Notify | None = None) -> Session: ...
    # A packet controller may also offer `open_datagram_session() -> Session`, whose
    # every feed is one whole datagram (the UDP door uses it when it is there).
    def console(self) -> Console: ...
    def reset(self) -> None: ...
    def world_view(self) -> WorldView: ...  # the machine around it (controllers/world_view.py)


class Recording(Protocol):
    """What `maxk run --trace CSV --plot PNG` keeps of a run (a controller that can say
    so has `record(every_ticks) -> Recording`): its samples as CSV, its XY path as a
    picture. `draw` is the door's path drawing (`maxk.pathplot.draw_path`), handed in so
    that a controller need not import a door."""

    def write_csv(self, path: str) -> None: ...
    def plot(self, path: str, title: str, draw: Callable[..., object]) -> None: ...


class VirtualTime:
    """The Python API's clock words, the same on every controller: virtual time moves
    only when asked (`advance`), in the controller's own ticks."""

    @property
    def engine(self) -> Engine:  # pragma: no cover - every controller has one
        raise NotImplementedError

    @property
    def tick(self) -> int:
        return self.engine.tick

    @property
    def time(self) -> float:
        return self.engine.time

    def ticks(self, seconds: float) -> int:
        """Seconds as whole ticks, rounded up (a wait is never short)."""
        return math.ceil(seconds / self.engine.period - 1e-9)

    def advance(self, seconds: float = 0.0, *, ticks: int = 0) -> None:
        """Advance virtual time by seconds and/or ticks."""
        self.engine.advance(self.ticks(seconds) + ticks)


@dataclass(frozen=True)
class BuildOptions:
    """What `maxk serve`, the REPL and scripts may say about a controller they start."""

    number: int = 1  # board number (J5 jumper for a MAXk; the order given otherwise)
    archive: str | None = None  # the flash file (MAXk parameters, Trio programs); None: memory
    update_rate_hz: int | None = None  # None: the controller's default
    line_options: dict[str, str] = field(default_factory=dict)  # e.g. {"eol": "lf", "ack": ""}


@dataclass(frozen=True)
class ControllerKind:
    """A family of controllers: its models and how to build one."""

    name: str
    models: Sequence[str]
    build: Callable[[str, BuildOptions], Controller]
    summary: str = ""
    default_archive: Callable[[str, int], object] | None = None  # (model, number) -> path
    update_rates_hz: Sequence[int] = ()  # the rates it can run at, its default first
    line_options: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # option ->
    # its values (`serve --eol lf`); () for a flag (`--ack`)
    shared_memory: bool = False  # has a PCI map a host can open (`serve --shm`)
    default_port: int | None = None  # the port its host software has built in
    reference: Callable[[], str] | None = None  # its command table as Markdown

    @property
    def default_rate_hz(self) -> int | None:
        return self.update_rates_hz[0] if self.update_rates_hz else None

    def check_rate(self, rate_hz: int | None) -> None:
        """ValueError naming the rates this kind runs at, for one it cannot run."""
        if rate_hz is not None and rate_hz not in self.update_rates_hz:
            rates = ", ".join(str(r) for r in sorted(self.update_rates_hz))
            raise ValueError(f"the {self.name} runs at {rates} Hz, not {rate_hz}")

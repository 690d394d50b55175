"""A person's session at a console, kept so that it can become a regression script.

The REPL (`:record FILE`) and the front panel's console ("save as script") both keep one:
every command line typed with the tick it ran at and the replies it gave, the world
changes made (`:world` words, switches clicked), and the virtual time between them. Its
text is a command script (docs/scripts.md) that `maxk run` and the pytest plugin pass at
once on a fresh controller: waits in exact ticks, replies as `<` lines, the controller's
refusals as `@expect error MESSAGE`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from maxk.controllers.contract import Controller
from maxk.controllers.registry import kind_of

MAX_ENTRIES = 20_000
"""What one session keeps at most: past it the oldest half is let go and the script says
its start is missing (a session left recording for days stays bounded)."""


@dataclass
class Entry:
    tick: int  # when it ran
    kind: str  # "command" or "world"
    text: str
    replies: list[str] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)  # refusals not among the replies
    end_tick: int = 0  # when it was done (a statement that waits runs time itself)


class SessionRecord:
    """The session on one controller since it started (or since its last reset)."""

    def __init__(self, controller: Controller, origin: str = "the maxk REPL") -> None:
        self.controller = controller
        self.origin = origin
        self.entries: list[Entry] = []
        self.start_tick = controller.engine.tick
        self.dropped = 0  # entries let go to keep the budget
        self.revision = 0  # counts the changes: a writer saves only a record that changed

    def command(self, line: str, tick: int, replies: list[str], refused: list[str]) -> None:
        """A command line sent at `tick`, with its replies and the refusals it raised."""
        errors = [e.removeprefix("! ") for e in refused
                  if e not in replies and e.removeprefix("! ") not in replies]
        self._add(Entry(tick, "command", line.rstrip("\r\n"), list(replies), errors,
                        self.controller.engine.tick))

    def world(self, words: str, tick: int) -> None:
        """A world change (the words `@world` and `:world` take) made at `tick`."""
        self._add(Entry(tick, "world", words.strip(), end_tick=self.controller.engine.tick))

    def reset(self) -> None:
        """The controller powered up again: the script starts over from here."""
        self.entries.clear()
        self.dropped = 0
        self.revision += 1
        self.start_tick = self.controller.engine.tick

    def _add(self, entry: Entry) -> None:
        self.entries.append(entry)
        self.revision += 1
        if len(self.entries) > MAX_ENTRIES:
            half = MAX_ENTRIES // 2
            self.dropped += half
            self.start_tick = self.entries[half - 1].end_tick
            del self.entries[:half]

    def script(self) -> str:
        """The session as a command script: `@board`, `@rate` where not the default,
        then each line at its tick."""
        controller = self.controller
        engine = controller.engine
        out = [f"// Recorded in {self.origin} on the {controller.model}."]
        if self.dropped:
            out.append(f"// Its first {self.dropped} lines were let go (the record keeps "
                       f"{MAX_ENTRIES}): replayed from power-up, the rest may differ.")
        out.append(f"@board {controller.model}")
        if engine.update_rate_hz != kind_of(controller.model).default_rate_hz:
            out.append(f"@rate {round(engine.update_rate_hz)}")
        now = self.start_tick
        for entry in self.entries:
            if entry.tick > now:
                out.append(f"@wait {entry.tick - now} ticks")
            if entry.kind == "world":
                out.append(f"@world {entry.text}")
            else:
                out.append(entry.text)
                out.extend(f"< {reply}" for reply in entry.replies)
                out.extend(f"@expect error {error}" for error in entry.errors)
            now = max(entry.tick, entry.end_tick)
        return "\n".join(out) + "\n"

"""A person's conversation with one controller's console, line by line: the REPL and the
front panel's console both run their lines through it, so that they answer alike.

Controller commands go to the controller's console (`Console.execute`), its errors come
back as `! ...` lines, `help` and `help WORD` come from its table, and a few words of
our own (`:status`, `:time`, `:world ...`) read or change the machine around it. Every
line typed and every world change is kept in a `SessionRecord`, from which the session
becomes a regression script. Time is not this module's: the REPL moves the clock with its
own words, the control door with its pacer.
"""

from __future__ import annotations

from maxk.controllers.contract import Console, Controller
from maxk.controllers.world_settings import parse_world
from maxk.session_record import SessionRecord


class ConsoleSession:
    """One person's lines on one controller (the REPL's, or one panel console's)."""

    SHARED_WORDS = ("help", "status", "time", "world")
    """The words of our own that every console door has (`help`, `:status`, ...)."""

    def __init__(self, controller: Controller, origin: str) -> None:
        self.controller = controller
        self.console: Console = controller.console()
        self.record = SessionRecord(controller, origin)

    def run_line(self, line: str) -> tuple[list[str], list[str]]:
        """A controller command line: its output lines and the errors it raised (the
        `! ...` lines the REPL shows after them). Kept in the record."""
        tick = self.controller.engine.tick
        out = self.console.execute(line)
        noted = self.console.new_errors()
        self.record.command(line, tick, out, self.console.refused(out, noted))
        return out, noted

    def is_meta(self, text: str) -> bool:
        """A line for us, not for the controller: `help ...` or a `:` word. No
        controller's command starts with `:`, and `help` is no command of theirs."""
        word = text.strip().lower()
        return word == "help" or word.startswith("help ") or word.startswith(":")

    def shared_word(self, word: str, rest: str) -> list[str] | None:
        """`help [WORD]`, `:status`, `:time`, `:world [words]`; None: not one of them."""
        engine = self.controller.engine
        if word == "help":
            if not rest:
                return None  # each door has its own list of words
            lines = self.console.help(rest)
            return [f"no command {rest!r}; try :commands"] if lines is None else lines
        if word == "status":
            return self.console.status_lines()
        if word == "time":
            return [f"tick {engine.tick}, {engine.time:.6f} s virtual "
                    f"({engine.period * 1e6:.2f} us per tick)"]
        if word == "world":
            view = self.controller.world_view()
            if not rest:
                return view.describe()
            try:
                said = parse_world(rest)(view)
            except (KeyError, ValueError, OverflowError) as error:
                return [f"world: {error.args[0] if error.args else error}"]
            self.record.world(rest, engine.tick)
            return [said]
        return None

    def completions(self, prefix: str) -> list[tuple[str, str]]:
        """The controller's words that start with `prefix` (any case), each with its
        one-line summary: what Tab offers."""
        key = prefix.upper()
        return [(word, self.console.summary(word)) for word in self.console.words()
                if word.upper().startswith(key)]

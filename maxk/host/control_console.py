"""The front panel's console: the controller's own language typed in the page.

A person who opens the panel to try an emulated controller types `AX; MR1000; GO;` (or
`MOVE(1000)`, `1PA5`, a PoKeys console word) in the board's console, as in the vendor's
terminal. Each line runs through the same `ConsoleSession` as the REPL's, so the replies,
the `! ...` errors, `help WORD` and completion are the REPL's own; nothing of a language
is written again in JavaScript. A line is an action: it comes as a JSON POST through the
control door's guard (Host, Origin, token, content type). It shows in the board's traffic
as the host `console`, and the session (lines, replies, world clicks, the virtual time
between them) is kept so that "save as script" hands it over as a regression script.

Time stays the pacer's: a line runs at the board's now. A statement that waits (an MC405
`WA(500)`, an MM4005 `1WS`) runs the board's virtual time to its end at once, as the
REPL does in manual time, within the console's own bound (D: a page cannot hold a
request open for the length of a wait; the board then stands until real time catches up,
which the hosts see as a board whose clock paused).
"""

from __future__ import annotations

from typing import Any

from maxk.console_session import ConsoleSession
from maxk.host.client import Service
from maxk.host.control_board import BadRequest

MAX_LINE = 1024
"""Characters of one console line (a longer one is refused whole: no controller's
command line is longer; the MAXk's own buffer is smaller)."""

MAX_COMPLETIONS = 64
"""Words a completion answer lists at most (a bare prefix of one letter may match many)."""

HELP = ["The console sends each line to the controller, as its terminal would.",
        "  help WORD    the command's entry (source and confidence)",
        "  :status      every axis     :time   virtual time",
        "  :world       the machine around it   :world X limits 5000 -5000",
        "Tab completes the controller's words; Up/Down walk the history;",
        "'save as script' downloads the session as a regression script (maxk run)."]


class PanelConsole(ConsoleSession):
    """One board's console in the front panel (one per board: every page open on the
    door types into the same terminal, as people at one machine would)."""

    def __init__(self, service: Service) -> None:
        super().__init__(service.controller, "the front panel's console")
        self.service = service
        self.traffic = service.open_traffic("console", "front panel")

    def handle(self, line: Any) -> dict[str, Any]:
        """Run one typed line; what the page shows of it."""
        if not isinstance(line, str):
            raise BadRequest("line: the text typed, as a JSON string")
        if len(line) > MAX_LINE or "\r" in line or "\n" in line or "\x00" in line:
            raise BadRequest(f"line: one line of at most {MAX_LINE} characters, without "
                             "CR, LF or NUL")
        text = line.strip()
        errors: list[str] = []
        if not text:
            out: list[str] = []
        elif self.is_meta(text):
            body = text[1:] if text.startswith(":") else text
            word, _, rest = body.strip().partition(" ")
            word, rest = word.lower(), rest.strip()
            if word == "help" and not rest:
                out = list(HELP)
            else:
                shared = self.shared_word(word, rest)
                out = shared if shared is not None else [
                    f"the console has help, :status, :time and :world; :{word} is a word "
                    "of the terminal (maxk repl)"]
            errors = self.console.new_errors()
        else:
            self.traffic.incoming(line.encode("latin-1", "replace") + b"\r")
            out, errors = self.run_line(line)
            shown = out + errors
            if shown:
                self.traffic.outgoing(("\n".join(shown) + "\n").encode("latin-1", "replace"))
        engine = self.controller.engine
        return {"lines": out, "errors": errors, "prompt": self.console.prompt(),
                "status": self.console.status_line(100), "tick": engine.tick,
                "time": engine.time, "recorded": len(self.record.entries)}

    def words(self, prefix: Any) -> dict[str, Any]:
        """What Tab offers for `prefix`: the controller's words and their summaries."""
        if not isinstance(prefix, str) or len(prefix) > 32:
            raise BadRequest("prefix: up to 32 characters")
        found = self.completions(prefix)
        return {"words": [{"word": w, "summary": s} for w, s in found[:MAX_COMPLETIONS]],
                "more": max(0, len(found) - MAX_COMPLETIONS)}

"""A Python client of the control door (`maxk serve --control`, docs/control.md): what a
system test needs to act on the served machines while its host code runs.

    client = Client("http://127.0.0.1:8765")
    client.world(1, "X limits 12000 -5000")
    client.arm(1, "X fault plus active", axis="X", passes=12000)
    client.reading(1, "X")["flags"]

Standard library only (urllib): a test of an IOC or of PoKeysLib needs nothing more.
"""

from __future__ import annotations

import json
import urllib.error
import urllib.parse
import urllib.request
from typing import Any


class ControlError(Exception):
    """The door refused a request: its status and its reason."""

    def __init__(self, status: int, reason: str) -> None:
        super().__init__(f"{status}: {reason}")
        self.status = status
        self.reason = reason


class Client:
    """The control door at `url`; `token` when it listens beyond loopback."""

    def __init__(self, url: str, token: str | None = None, timeout: float = 10.0) -> None:
        self.url = url.rstrip("/")
        self.token = token
        self.timeout = timeout

    # ---- the wire ------------------------------------------------------------------
    def request(self, method: str, path: str, body: Any = None) -> Any:
        """One request; the JSON answer (text for CSV), or ControlError."""
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(self.url + path, data=data, method=method)
        if data is not None:
            request.add_header("Content-Type", "application/json")
        if self.token:
            request.add_header("Authorization", f"Bearer {self.token}")
        try:
            with urllib.request.urlopen(request, timeout=self.timeout) as answer:
                text = answer.read().decode()
                kind = answer.headers.get("Content-Type", "")
        except urllib.error.HTTPError as error:
            with error:
                raw = error.read().decode(errors="replace")
            try:
                reason = json.loads(raw).get("error", raw)
            except (ValueError, AttributeError):
                reason = raw
            raise ControlError(error.code, reason) from None
        return json.loads(text) if "json" in kind else text

    def _board(self, board: int) -> str:
        return f"/api/boards/{int(board)}"

    # ---- read ----------------------------------------------------------------------
    def boards(self) -> list[dict[str, Any]]:
        return self.request("GET", "/api")["boards"]  # type: ignore[no-any-return]

    def board(self, board: int) -> dict[str, Any]:
        """Everything about one controller: axes (readings and switches), inputs,
        outputs, analog, its world in words."""
        return self.request("GET", self._board(board))  # type: ignore[no-any-return]

    def reading(self, board: int, axis: str) -> dict[str, Any]:
        quoted = urllib.parse.quote(str(axis), safe="")
        return self.request("GET", f"{self._board(board)}/axes/{quoted}")  # type: ignore

    def traffic(self, board: int) -> list[dict[str, Any]]:
        """Each host's recent bytes in and replies out, with virtual time stamps."""
        return self.request("GET", f"{self._board(board)}/traffic")["hosts"]  # type: ignore

    def errors(self) -> list[dict[str, Any]]:
        return self.request("GET", "/api/errors")["errors"]  # type: ignore[no-any-return]

    def panel(self) -> dict[str, Any]:
        """What the front panel shows, at once (the page gets it pushed)."""
        return self.request("GET", "/api/panel")  # type: ignore[no-any-return]

    # ---- act -----------------------------------------------------------------------
    def world(self, board: int, words: str | None = None, **form: Any) -> str:
        """A world setting in the `@world` words, or its JSON form (`axis=, set=,
        values=`; `input=, level=`; `analog=, volts=`); what it did."""
        body = {"words": words} if words is not None else form
        return self.request("POST", f"{self._board(board)}/world", body)["did"]  # type: ignore

    def arm(self, board: int, words: str, *, time: float | None = None,
            tick: int | None = None, after: float | None = None, axis: str | None = None,
            passes: float | None = None) -> dict[str, Any]:
        """A world setting applied later: at a virtual time or tick, after some virtual
        seconds, or when an axis passes a position."""
        when: dict[str, Any] = {}
        if axis is not None:
            when = {"axis": axis, "passes": passes}
        elif tick is not None:
            when = {"tick": tick}
        elif time is not None:
            when = {"time": time}
        elif after is not None:
            when = {"after": after}
        return self.request("POST", f"{self._board(board)}/triggers",  # type: ignore
                            {"words": words, "when": when})

    def triggers(self, board: int) -> list[dict[str, Any]]:
        return self.request("GET", f"{self._board(board)}/triggers")["triggers"]  # type: ignore

    def disarm(self, board: int, ident: int) -> dict[str, Any]:
        return self.request("DELETE", f"{self._board(board)}/triggers/{int(ident)}")  # type: ignore

    def reset(self, board: int) -> dict[str, Any]:
        """Reset (power-cycle) one controller."""
        return self.request("POST", f"{self._board(board)}/reset", {})  # type: ignore

    # ---- the clock -----------------------------------------------------------------
    def clock(self) -> list[dict[str, Any]]:
        return self.request("GET", "/api/clock")["boards"]  # type: ignore[no-any-return]

    def _clock(self, body: dict[str, Any], board: int | None) -> list[dict[str, Any]]:
        if board is not None:
            body["board"] = board
        return self.request("POST", "/api/clock", body)["boards"]  # type: ignore

    def pause(self, board: int | None = None) -> list[dict[str, Any]]:
        return self._clock({"pause": True}, board)

    def run(self, board: int | None = None) -> list[dict[str, Any]]:
        return self._clock({"run": True}, board)

    def speed(self, speed: float, board: int | None = None) -> list[dict[str, Any]]:
        return self._clock({"speed": speed}, board)

    def step(self, seconds: float = 0.0, *, ticks: int | None = None,
             board: int | None = None) -> list[dict[str, Any]]:
        """Advance virtual time while paused (stepping pauses first)."""
        body = {"ticks": ticks} if ticks is not None else {"step": seconds}
        return self._clock(body, board)

    # ---- traces --------------------------------------------------------------------
    def start_trace(self, board: int, every_ticks: int | None = None) -> dict[str, Any]:
        body = {} if every_ticks is None else {"every_ticks": every_ticks}
        return self.request("POST", f"{self._board(board)}/trace", body)  # type: ignore

    def stop_trace(self, board: int) -> dict[str, Any]:
        return self.request("DELETE", f"{self._board(board)}/trace")  # type: ignore

    def trace_csv(self, board: int) -> str:
        return self.request("GET", f"{self._board(board)}/trace.csv")  # type: ignore

    # ---- the console ---------------------------------------------------------------
    def console(self, board: int, line: str) -> dict[str, Any]:
        """Type a line in the board's console: `{lines, errors, prompt, status, tick}`."""
        return self.request("POST", f"{self._board(board)}/console",  # type: ignore
                            {"line": line})

    def console_words(self, board: int, prefix: str) -> list[dict[str, str]]:
        """What Tab completes for `prefix`: `[{word, summary}]`."""
        answer = self.request("GET", f"{self._board(board)}/console/words?prefix="
                              + urllib.parse.quote(prefix))
        return answer["words"]  # type: ignore[no-any-return]

    def console_script(self, board: int) -> str:
        """The console's session as a regression script."""
        return self.request("GET", f"{self._board(board)}/console/script")  # type: ignore

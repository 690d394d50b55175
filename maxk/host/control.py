"""The control door: `maxk serve --control` puts an HTTP door beside the hosts' doors, for
programs (a system test tripping a limit in the middle of an IOC's move) and for people
(the front panel at `/`, pushed by server-sent events).

Everything it reads and does goes through the one world contract (controllers/
world_view.py, world_settings.py): a world setting here is the same words as `@world`
and `:world`. The virtual clock is the pacer's (pause, step, speed). Built on aiohttp on
the doors' own event loop: a request runs between two pacing passes, so it sees and
changes a controller at one tick, as a host's command does. Every limit is here:
request size, traces, triggers, streams; a bad request gets a 4xx with a reason, and a
fault in a handler is a 500 for that request only, never the server's end. Who may ask
and how many may connect is control_guard.py's; what a board keeps, control_board.py's.

Long module: every route of the door, the clock's words and the panel's picture in one
place, so that what the door answers can be read in one file.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import secrets
from collections import Counter
from collections.abc import Awaitable, Callable
from importlib import resources
from typing import Any

from aiohttp import web

from maxk.controllers.panel import panel_extras
from maxk.controllers.world_settings import parse_world
from maxk.host.client import Service
from maxk.host.control_board import (
    BadRequest,
    Board,
    ErrorLog,
    is_loopback,
    number_of,
    reason_of,
    step_to,
    world_words,
)
from maxk.host.control_console import PanelConsole
from maxk.host.control_guard import (
    BODY_SECONDS,
    CONNECTIONS,
    HEADER_SECONDS,
    KEEPALIVE_SECONDS,
    LOOPBACK_NAMES,
    WRITE_SECONDS,
    GuardedHandler,
    Refused,
    abort,
    door_names,
    error_response,
    small_send_buffer,
)
from maxk.host.control_guard import refusal as guard_refusal

log = logging.getLogger("maxk.door.control")

MAX_BODY = 64 * 1024  # bytes of one request
STREAM_HZ = 15.0  # panel updates a second (server-sent events)
STREAMS = 16  # panels open at once
CSV_CHUNK = 64 * 1024  # characters of trace CSV written at a time
TRAFFIC_SHOWN = 8  # entries per host in a panel update
MAX_STEP_SECONDS = 3600.0  # one clock step at most
MAX_SPEED = 1000.0
MIN_SPEED = 1e-3  # slower is no clock a person or a test would wait for (D)
OUTPUTS = 32  # digital outputs looked at for the panel (those a controller has)


class ControlDoor:
    """The HTTP door for every served controller."""

    def __init__(self, services: list[Service], token: str | None = None,
                 stream_hz: float = STREAM_HZ, *, connections: int = CONNECTIONS,
                 header_seconds: float = HEADER_SECONDS,
                 write_seconds: float = WRITE_SECONDS) -> None:
        self.services = services
        self.boards = {s.number: Board(s) for s in services}
        self.token = token
        self.stream_hz = stream_hz
        self.connections = connections
        self.header_seconds = header_seconds
        self.write_seconds = write_seconds
        self.errors = ErrorLog()
        self.hosts: frozenset[str] = LOOPBACK_NAMES
        self.any_address = False  # listening on every address: any IP literal names it
        self.open_connections = 0
        self.refused = 0  # connections refused over the cap (for tests and the log)
        self.refusals: Counter[int] = Counter()  # requests refused by `_guard`, by status
        self._server: asyncio.Server | None = None
        self._streams = 0
        self._panel_cache: tuple[float, bytes] | None = None
        self._panel_building: asyncio.Task[bytes] | None = None
        self._closing = asyncio.Event()
        self._runner: web.AppRunner | None = None
        self.consoles: dict[int, PanelConsole] = {}  # a board's, from its first line
        self.app = self._make_app()

    # ---- life ----------------------------------------------------------------------
    async def start(self, host: str, port: int) -> tuple[str, int]:
        """Listen; a token is made when the address is not loopback (unless given). The
        listener is aiohttp's own request handler behind a factory that caps the
        connections (one over the cap gets a 503 and is closed: never an EMFILE) and
        times the headers (`GuardedHandler`)."""
        if self.token is None and not is_loopback(host):
            self.token = secrets.token_urlsafe(16)
        self.hosts = door_names(host)
        self.any_address = host in ("", "0.0.0.0", "::")
        logging.getLogger("maxk").addHandler(self.errors)
        self._runner = web.AppRunner(self.app, access_log=None, handle_signals=False,
                                    shutdown_timeout=0.2)
        await self._runner.setup()
        loop = asyncio.get_running_loop()
        self._server = await loop.create_server(self._connection, host or None, port,
                                                backlog=16, reuse_address=True)
        sockets = list(self._server.sockets)
        address = sockets[0].getsockname()[:2] if sockets else (host, port)
        return str(address[0]), int(address[1])

    def _connection(self) -> asyncio.Protocol:
        """A connection accepted: served, or refused over the cap."""
        if self.open_connections >= self.connections:
            self.refused += 1
            if self.refused in (1, 10, 100) or self.refused % 1000 == 0:
                log.warning("control door: more than %d connections at once; %d refused",
                            self.connections, self.refused)
            return Refused()
        assert self._runner is not None and self._runner.server is not None
        self.open_connections += 1
        return GuardedHandler(self, self._runner.server, loop=asyncio.get_running_loop(),
                              keepalive_timeout=KEEPALIVE_SECONDS, access_log=None,
                              max_line_size=8190, max_field_size=8190, max_headers=64)

    async def close(self) -> None:
        self._closing.set()
        logging.getLogger("maxk").removeHandler(self.errors)
        for board in self.boards.values():
            board.stop_trace()
            board.clock_word += 1  # a step under way ends at its next slice
        if self._server is not None:
            self._server.close()
            self._server = None
        if self._runner is not None:
            server = self._runner.server
            if server is not None:  # every connection (streams too) ends now
                for handler in list(server.connections):
                    abort(handler)
            await self._runner.cleanup()
            self._runner = None

    # ---- the app -------------------------------------------------------------------
    def _make_app(self) -> web.Application:
        app = web.Application(client_max_size=MAX_BODY, middlewares=[self._guard])
        get, post, delete = web.get, web.post, web.delete
        app.add_routes([
            get("/", self.page), get("/static/{name}", self.static),
            get("/api", self.index), get("/api/errors", self.error_log),
            get("/api/panel", self.panel), get("/api/stream", self.stream),
            get("/api/clock", self.clock), post("/api/clock", self.set_clock),
            get("/api/boards/{n}", self.board), get("/api/boards/{n}/world", self.world),
            post("/api/boards/{n}/world", self.set_world),
            get("/api/boards/{n}/axes/{axis}", self.axis),
            get("/api/boards/{n}/traffic", self.traffic),
            get("/api/boards/{n}/triggers", self.triggers),
            post("/api/boards/{n}/triggers", self.arm),
            delete("/api/boards/{n}/triggers/{id}", self.disarm),
            post("/api/boards/{n}/reset", self.reset),
            get("/api/boards/{n}/trace", self.trace_state),
            post("/api/boards/{n}/trace", self.start_trace),
            delete("/api/boards/{n}/trace", self.stop_trace),
            get("/api/boards/{n}/trace.csv", self.trace_csv),
            post("/api/boards/{n}/console", self.console_line),
            get("/api/boards/{n}/console/words", self.console_words),
            get("/api/boards/{n}/console/script", self.console_script),
        ])
        return app

    @web.middleware
    async def _guard(self, request: web.Request,
                     handler: Callable[[web.Request], Awaitable[web.StreamResponse]]
                     ) -> web.StreamResponse:
        """Who may ask, then every fault as a reasoned 4xx/500 JSON body. In order: the
        Host must name this door (a DNS-rebinding page names its own), the token when one
        is set (every route), a browser's request from another origin is refused (its
        Origin, or Sec-Fetch-Site), and a request that acts must say its body is JSON (a
        form or text/plain POST is what a page may send anywhere without asking)."""
        protocol = request.protocol
        if isinstance(protocol, GuardedHandler):
            protocol.request_started()
        refusal = guard_refusal(request, self.token, self.hosts, self.any_address)
        if refusal is not None:
            self.refusals[refusal.status] += 1
            return refusal
        try:
            return await handler(request)
        except web.HTTPException as error:
            if error.status < 400:
                raise
            return _error(error.status, error.reason or "bad request")
        except BadRequest as error:
            return _error(error.status, str(error))
        except RecursionError:
            return _error(400, "the body is nested too deeply")
        except OverflowError as error:
            return _error(400, f"a number out of range: {error}")
        except KeyError as error:
            return _error(404, reason_of(error))
        except (ValueError, TypeError) as error:
            return _error(400, reason_of(error))
        except asyncio.CancelledError:
            raise
        except Exception as error:  # a fault in one request is that request's
            log.error("control door: %s %s: %s: %s", request.method, request.path,
                      type(error).__name__, error)
            return _error(500, f"{type(error).__name__}: {error}")

    # ---- helpers -------------------------------------------------------------------
    def _board(self, request: web.Request) -> Board:
        text = request.match_info["n"]
        try:
            board = self.boards.get(int(text))
        except ValueError:
            board = None
        if board is None:
            raise BadRequest(f"no board {text} (boards {sorted(self.boards)})", 404)
        board.service.sync()
        return board

    @staticmethod
    async def _body(request: web.Request) -> dict[str, Any]:
        if not request.can_read_body:
            return {}
        try:
            raw = await asyncio.wait_for(request.read(), BODY_SECONDS)
        except TimeoutError:
            raise BadRequest(f"the body did not arrive within {BODY_SECONDS:g} s", 408) from None
        try:
            body = json.loads(raw.decode("utf-8"), parse_constant=_no_constant)
        except (json.JSONDecodeError, UnicodeDecodeError):
            raise BadRequest("the body must be JSON (an object)") from None
        except RecursionError:
            raise BadRequest("the body is nested too deeply") from None
        if not isinstance(body, dict):
            raise BadRequest("the body must be a JSON object")
        return body

    def _describe(self, board: Board) -> dict[str, Any]:
        service = board.service
        controller = board.controller
        view = controller.world_view()
        return {
            "number": service.number, "model": controller.model, "kind": controller.kind,
            "doors": {"tcp": [f"{h}:{p}" for h, p in service.ports],
                      "udp": [f"{h}:{p}" for h, p in service.udp_ports],
                      "pty": list(service.ptys)},
            "hosts": len(service.clients),
            "axes": list(view.axis_names), "inputs": list(view.inputs),
            "analog": list(view.analog),
            "tick": controller.engine.tick, "time": controller.engine.time,
            "speed": service.pacer.speed, "paused": service.pacer.speed == 0,
        }

    # ---- read ----------------------------------------------------------------------
    async def index(self, request: web.Request) -> web.Response:
        for service in self.services:
            service.sync()
        return web.json_response({"boards": [self._describe(b) for b in self.boards.values()],
                                  "token_required": self.token is not None})

    async def board(self, request: web.Request) -> web.Response:
        board = self._board(request)
        view = board.controller.world_view()
        return web.json_response({**self._describe(board), **view.snapshot(),
                                  "outputs": _outputs(view), "world": view.describe()})

    async def world(self, request: web.Request) -> web.Response:
        board = self._board(request)
        view = board.controller.world_view()
        return web.json_response({"world": view.describe(), **view.snapshot()})

    async def axis(self, request: web.Request) -> web.Response:
        board = self._board(request)
        view = board.controller.world_view()
        return web.json_response(view.reading(request.match_info["axis"]).as_dict())

    async def traffic(self, request: web.Request) -> web.Response:
        board = self._board(request)
        book = board.service.traffic
        return web.json_response({"hosts": [] if book is None else book.as_list()})

    async def error_log(self, request: web.Request) -> web.Response:
        return web.json_response({"errors": list(self.errors.records)})

    async def panel(self, request: web.Request) -> web.Response:
        return web.Response(body=await self.panel_json(), content_type="application/json")

    async def panel_json(self) -> bytes:
        """The panel's state as JSON, built at most once per stream period however many
        panels and pollers ask, and built a board at a time with the hosts' doors served
        in between (a host's query waits for one board's picture, never sixteen)."""
        loop = asyncio.get_running_loop()
        cached = self._panel_cache
        if cached is not None and loop.time() - cached[0] < 1.0 / self.stream_hz:
            return cached[1]
        if self._panel_building is None:
            self._panel_building = loop.create_task(self._build_panel())
        building = self._panel_building
        return await asyncio.shield(building)

    async def _build_panel(self) -> bytes:
        try:
            boards = []
            for board in self.boards.values():
                board.service.sync()
                boards.append(json.dumps(self._panel_board(board), separators=(",", ":")))
                await asyncio.sleep(0)
            errors = json.dumps(list(self.errors.records)[-5:], separators=(",", ":"))
            data = f'{{"boards":[{",".join(boards)}],"errors":{errors}}}'.encode()
            self._panel_cache = (asyncio.get_running_loop().time(), data)
            return data
        finally:
            self._panel_building = None

    def panel_state(self) -> dict[str, Any]:
        """What the front panel shows, for every board at once."""
        boards = []
        for board in self.boards.values():
            board.service.sync()
            boards.append(self._panel_board(board))
        return {"boards": boards, "errors": list(self.errors.records)[-5:]}

    def _panel_board(self, board: Board) -> dict[str, Any]:
        controller = board.controller
        view = controller.world_view()
        axes = []
        for name, stage in zip(view.axis_names, view.world.axes, strict=False):
            reading = view.reading(name)
            at = reading.position
            axes.append({**reading.as_dict(), "lamps": {
                side: {"on": bool(getattr(stage, attr).active(at)),
                       "fault": getattr(stage, attr).fault}
                for side, attr in (("plus", "plus_limit"), ("minus", "minus_limit"),
                                   ("home", "home"))}})
        hosts = []
        book = board.service.traffic
        if book is not None:
            for host in book.hosts:
                if host.open:
                    entries = list(host.entries)[-TRAFFIC_SHOWN:]
                    hosts.append({"peer": host.peer, "transport": host.transport,
                                  "entries": [{"time": e.time, "direction": e.direction,
                                               "text": e.data[:80].decode("latin-1")}
                                              for e in entries]})
        try:
            extras = panel_extras(controller)
        except Exception as error:  # a picture that fails is not a panel that fails
            extras = {"error": str(error)}
        return {"number": board.service.number, "model": controller.model,
                "kind": controller.kind, "tick": controller.engine.tick,
                "time": controller.engine.time, "speed": board.service.pacer.speed,
                "axes": axes,
                "inputs": {str(n): bool(view.input_level(n)) for n in view.inputs},
                "outputs": _outputs(view),
                "analog": {str(c): _volts(view, c) for c in view.analog},
                "hosts": hosts, "extras": extras, "trace": board.trace is not None}

    async def stream(self, request: web.Request) -> web.StreamResponse:
        """The panel's updates as server-sent events, `stream_hz` a second."""
        if self._streams >= STREAMS:
            raise BadRequest(f"at most {STREAMS} panels at once", 429)
        self._streams += 1
        try:
            response = web.StreamResponse(headers={"Content-Type": "text/event-stream",
                                                   "Cache-Control": "no-cache"})
            small_send_buffer(request)
            await response.prepare(request)
            period = 1.0 / self.stream_hz
            while not self._closing.is_set():
                data = await self.panel_json()
                if not await self._write(request, response, b"data: " + data + b"\n\n"):
                    break
                with contextlib.suppress(asyncio.TimeoutError):
                    await asyncio.wait_for(self._closing.wait(), period)
            return response
        finally:
            self._streams -= 1

    async def _write(self, request: web.Request, response: web.StreamResponse,
                     data: bytes) -> bool:
        """Write to a stream; a reader that took none of it for `write_seconds` (or went
        away) is let go: its connection is closed and False said."""
        try:
            await asyncio.wait_for(response.write(data), self.write_seconds)
            return True
        except (ConnectionError, RuntimeError):
            return False
        except TimeoutError:
            abort(request.protocol)
            return False

    # ---- act -----------------------------------------------------------------------
    async def set_world(self, request: web.Request) -> web.Response:
        board = self._board(request)
        words = world_words(await self._body(request))
        setting = parse_world(words)
        did = setting(board.controller)
        console = self.consoles.get(board.service.number)
        if console is not None:  # a click is part of the session a person records
            console.record.world(words, board.controller.engine.tick)
        return web.json_response({"did": did, "world": board.controller.world_view().describe()})

    async def triggers(self, request: web.Request) -> web.Response:
        board = self._board(request)
        return web.json_response({"triggers": [t.as_dict() for t in board.triggers.values()],
                                  "tick": board.controller.engine.tick})

    async def arm(self, request: web.Request) -> web.Response:
        board = self._board(request)
        body = await self._body(request)
        when = body.get("when")
        if not isinstance(when, dict):
            raise BadRequest("when: {\"time\": s} | {\"tick\": n} | {\"after\": s} | "
                             "{\"axis\": NAME, \"passes\": position}")
        trigger = board.arm(world_words(body), when)
        return web.json_response(trigger.as_dict(), status=201)

    async def disarm(self, request: web.Request) -> web.Response:
        board = self._board(request)
        try:
            ident = int(request.match_info["id"])
        except ValueError:
            raise BadRequest(f"no trigger {request.match_info['id']}", 404) from None
        return web.json_response(board.disarm(ident).as_dict())

    async def reset(self, request: web.Request) -> web.Response:
        """Reset (power-cycle) one controller: its own reset runs the power-up sequence;
        the world around it and virtual time stay."""
        board = self._board(request)
        board.controller.reset()
        console = self.consoles.get(board.service.number)
        if console is not None:  # a script starts from power-up: so does its record
            console.record.reset()
        log.info("board %d reset through the control door", board.service.number)
        return web.json_response(self._describe(board))

    async def clock(self, request: web.Request) -> web.Response:
        return web.json_response(self._clock_state())

    def _clock_state(self) -> dict[str, Any]:
        return {"boards": [{"number": s.number, "tick": s.controller.engine.tick,
                            "time": s.controller.engine.time, "speed": s.pacer.speed,
                            "paused": s.pacer.speed == 0, "lag": s.pacer.lag()}
                           for s in self.services]}

    async def set_clock(self, request: web.Request) -> web.Response:
        """`{"pause": true}`, `{"run": true}`, `{"speed": K}`, `{"step": seconds}` or
        `{"ticks": n}` (stepping pauses first), on every board or `"board": N`."""
        body = await self._body(request)
        if "board" in body:
            number = body["board"]
            board = (self.boards.get(number) if isinstance(number, int)
                     and not isinstance(number, bool) else None)
            if board is None:
                raise BadRequest(f"no board {number!r} (boards {sorted(self.boards)})", 404)
            boards = [board]
        else:
            boards = list(self.boards.values())
        actions = [k for k in ("pause", "run", "speed", "step", "ticks") if k in body]
        if len(actions) != 1:
            raise BadRequest("say one of pause, run, speed, step (seconds) or ticks")
        action = actions[0]
        if action in ("pause", "run") and body[action] is not True:
            raise BadRequest(f"{action}: true")
        if action == "speed":
            speed = number_of(body["speed"], "speed")
            if not MIN_SPEED <= speed <= MAX_SPEED:
                raise BadRequest(f"speed: from {MIN_SPEED:g} to {MAX_SPEED:g} times real time")
        if action in ("step", "ticks"):
            amount = number_of(body[action], action)
            limit = MAX_STEP_SECONDS
            if amount < 0:
                raise BadRequest(f"{action}: >= 0")
            if action == "ticks" and amount != int(amount):
                raise BadRequest("ticks: a whole number")
            for board in boards:
                engine = board.controller.engine
                seconds = amount if action == "step" else amount * engine.period
                if seconds > limit:
                    raise BadRequest(f"one step is at most {limit:g} virtual seconds")
        steps = []
        for board in boards:
            pacer = board.service.pacer
            board.service.sync()
            board.clock_word += 1  # the latest word on a board's clock wins over a step
            if action == "pause" and pacer.speed != 0:
                board.paused_speed = pacer.speed
                pacer.set_speed(0.0)
            elif action == "run" and pacer.speed == 0:
                pacer.set_speed(board.paused_speed or 1.0)
            elif action == "speed":
                if pacer.speed == 0:
                    board.paused_speed = speed
                else:
                    pacer.set_speed(speed)
            elif action in ("step", "ticks"):
                if pacer.speed != 0:
                    board.paused_speed = pacer.speed
                    pacer.set_speed(0.0)
                engine = board.controller.engine
                ticks = (board.controller_ticks(amount) if action == "step" and amount
                         else int(amount) if action == "ticks" else 0)
                steps.append((board, board.clock_word, engine.tick + ticks))
        for board, word, target in steps:
            await step_to(board, target)
            if board.clock_word == word:
                board.service.pacer.set_speed(0.0)  # the paused clock stands where it ended
        return web.json_response(self._clock_state())

    async def trace_state(self, request: web.Request) -> web.Response:
        return web.json_response(self._board(request).trace_state())

    async def start_trace(self, request: web.Request) -> web.Response:
        board = self._board(request)
        body = await self._body(request)
        every = body.get("every_ticks")
        if every is not None:
            every = int(number_of(every, "every_ticks"))
            if every < 1:
                raise BadRequest("every_ticks: at least 1 (or leave it out: every event)")
        board.start_trace(every)
        return web.json_response(board.trace_state(), status=201)

    async def stop_trace(self, request: web.Request) -> web.Response:
        board = self._board(request)
        board.stop_trace()
        return web.json_response(board.trace_state())

    async def trace_csv(self, request: web.Request) -> web.StreamResponse:
        """The trace's CSV as it stands now, written CSV_CHUNK characters at a time: a
        reader holds one chunk of the server's memory (never a copy of the trace), and
        one that takes none for `write_seconds` is let go."""
        board = self._board(request)
        text = board.trace_text
        if text is None:
            raise BadRequest("no trace: start one with POST .../trace", 404)
        end = text.tell()
        response = web.StreamResponse(headers={"Content-Type": "text/csv; charset=utf-8"})
        small_send_buffer(request)
        await response.prepare(request)
        offset = 0
        while offset < end and not self._closing.is_set():
            chunk = text.read_at(offset, min(CSV_CHUNK, end - offset))
            if not chunk:
                break
            offset += len(chunk)
            if not await self._write(request, response, chunk.encode("utf-8")):
                return response
        await response.write_eof()
        return response

    # ---- the console ---------------------------------------------------------------
    def _console(self, board: Board) -> PanelConsole:
        number = board.service.number
        console = self.consoles.get(number)
        if console is None or console.controller is not board.controller:
            console = self.consoles[number] = PanelConsole(board.service)
        return console

    async def console_line(self, request: web.Request) -> web.Response:
        """`{"line": "AX; MR1000; GO;"}`: the line run on the board's console."""
        board = self._board(request)
        line = (await self._body(request)).get("line")
        return web.json_response(self._console(board).handle(line))

    async def console_words(self, request: web.Request) -> web.Response:
        """`?prefix=V`: the controller's words starting so, with their summaries."""
        board = self._board(request)
        return web.json_response(self._console(board).words(request.query.get("prefix", "")))

    async def console_script(self, request: web.Request) -> web.Response:
        """The console's session as a regression script, to save (`maxk run` passes it)."""
        board = self._board(request)
        number = board.service.number
        return web.Response(
            text=self._console(board).record.script(), content_type="text/plain",
            headers={"Content-Disposition": f'attachment; filename="board{number}.maxk"',
                     "Cache-Control": "no-store"})

    # ---- the page ------------------------------------------------------------------
    async def page(self, request: web.Request) -> web.Response:
        """The panel's page; off loopback its script and style are linked with the token
        it was opened with (the script carries it on its own requests and stream)."""
        if self.token is None:
            return _asset("index.html")
        text = _asset_text("index.html")
        mark = "?token=" + self.token  # token_urlsafe: nothing to quote in it
        text = text.replace('"static/panel.css"', f'"static/panel.css{mark}"').replace(
            '"static/panel.js"', f'"static/panel.js{mark}"')
        return web.Response(text=text, content_type="text/html",
                            headers={"Cache-Control": "no-store",
                                     "Referrer-Policy": "no-referrer"})

    async def static(self, request: web.Request) -> web.Response:
        return _asset(request.match_info["name"])


ASSETS = {"index.html": "text/html", "panel.js": "text/javascript", "panel.css": "text/css"}


def _asset_text(name: str) -> str:
    if name not in ASSETS:
        raise BadRequest(f"no file {name!r}", 404)
    return resources.files("maxk.host").joinpath("panel", name).read_text(encoding="utf-8")


def _asset(name: str) -> web.Response:
    """The panel's files, shipped in the package (no build step, nothing from the net)."""
    return web.Response(text=_asset_text(name), content_type=ASSETS[name],
                        headers={"Cache-Control": "no-cache", "Referrer-Policy": "no-referrer"})


def _no_constant(name: str) -> Any:
    raise BadRequest(f"{name}: JSON has no such number; a finite number only")


def _outputs(view: Any) -> dict[str, bool]:
    levels = {}
    for n in range(OUTPUTS):
        level = view.output_level(n)
        if level is not None:
            levels[str(n)] = bool(level)
    return levels


def _volts(view: Any, channel: int) -> float:
    try:
        return float(view.world.analog_volts(channel, view.source_owner))
    except Exception:  # a source that fails reads as an open input
        return 0.0


_error = error_response

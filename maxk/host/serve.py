"""The `maxk serve` command: start controllers of any kinds and their doors, print where
they are (one line a controller, `board N: MODEL tcp HOST:PORT, ...`, for scripts)."""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import gc
import logging
import math
import signal
import sys
from pathlib import Path
from typing import Any

from maxk.controllers.contract import BuildOptions
from maxk.controllers.registry import (
    DEFAULT_MODEL,
    build,
    canonical_model,
    default_archive,
    kind_of,
    line_option_choices,
)
from maxk.host.pacing import Pacer
from maxk.host.server import HOSTS_PER_DOOR, Server, Service


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--boards", type=int, default=None, help="how many controllers "
                        "(1-16; J5 jumper numbers 1..N); default: one per model given")
    parser.add_argument("--model", default=DEFAULT_MODEL,
                        help="controller model, or a comma list with one model per "
                        "controller (kinds may be mixed)")
    store = parser.add_mutually_exclusive_group()
    store.add_argument("--archive-dir", default=None,
                       help="directory of the boards' parameter archives (APP/power-up; "
                       "default ~/.local/share/maxk)")
    store.add_argument("--no-archive", action="store_true",
                       help="keep saved parameters in memory only")
    parser.add_argument("--host", default="127.0.0.1",
                        help="address to listen on (default 127.0.0.1; 0.0.0.0 for all)")
    parser.add_argument("--port", type=int, default=None, help="port of board 1 (board N "
                        "takes port + N - 1); 0 picks free ports; default: free ports, but "
                        "a controller whose host software has its port built in is tried "
                        "on it first (PoKeys 20055, MC405 23)")
    parser.add_argument("--no-tcp", action="store_true", help="no TCP ports")
    parser.add_argument("--pty", action="store_true", help="a serial pseudo-terminal per "
                        "board")
    parser.add_argument("--pty-link", default=None, help="a stable symlink to board 1's "
                        "pty (board N gets the same path with N appended)")
    parser.add_argument("--shm", default=None, metavar="PATH", help="shared-memory map file "
                        "of board 1 (board N: PATH with N appended), e.g. /dev/shm/maxk")
    parser.add_argument("--speed", type=_speed, default=1.0, help="K times faster than real "
                        "time (default 1)")
    parser.add_argument("--eol", choices=line_option_choices("eol"), default=None,
                        help="a MAXk's reply line ending (default lfcr: LF CR as the EPICS "
                        "MAXnet driver expects; lf for firmware >= 1.33 style)")
    parser.add_argument("--ack", action="store_true", help="a MAXk leads every reply with "
                        "ACK 0x06")
    parser.add_argument("--framing", choices=line_option_choices("framing"), default=None,
                        help="a MAXk's stream framing (default maxnet; pc68: the older "
                        "boards' CR/LF-framed replies with in-band status bytes, "
                        "docs/doors.md)")
    parser.add_argument("-v", "--verbose", action="count", default=0,
                        help="-v: hosts connecting and leaving; -vv: every host's bytes in "
                        "and replies out, with virtual time stamps (logger maxk.door.*)")
    parser.add_argument("--log-level", choices=LEVELS, default=None, type=str.lower,
                        help="the maxk loggers' level (default warning: faults only)")
    parser.add_argument("--seconds", type=_seconds, default=None,
                        help="stop after this many seconds (default: run until interrupted)")
    parser.add_argument("--control", action="store_true", help="the control door and front "
                        "panel on HTTP (docs/control.md); on --host, with a token when that "
                        "is not loopback")
    parser.add_argument("--control-port", type=_port, default=0, help="the control door's "
                        "port (default: a free one; implies --control)")


LEVELS = ("debug", "info", "warning", "error")


def configure_logging(args: argparse.Namespace) -> None:
    """Faults go to stderr as before (one line each); `-v`/`--log-level` show more, each
    line naming its logger (`maxk.door.tcp: 127.0.0.1:41234 t=0.500000 <- b'WY'`)."""
    verbose = getattr(args, "verbose", 0)
    level = (args.log_level or ("debug" if verbose >= 2 else "info" if verbose else
                                "warning")).upper()
    logger = logging.getLogger("maxk")
    logger.setLevel(level)
    if not any(getattr(h, "maxk_serve", False) for h in logger.handlers):
        handler = logging.StreamHandler(sys.stderr)
        handler.maxk_serve = True  # type: ignore[attr-defined]
        logger.addHandler(handler)
        logger.propagate = False
    for each in logger.handlers:
        each.setFormatter(logging.Formatter(
            "%(message)s" if level == "WARNING" else "%(name)s: %(message)s"))


def _port(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a port: {text!r}") from None
    if not 0 <= value <= 65535:
        raise argparse.ArgumentTypeError("a port is 0..65535")
    return value


MAX_SPEED = 1e6
"""The fastest --speed: a million times real time keeps every tick count of a day's run
far inside exact integers and floats (beyond, a wall second is years of ticks) (D)."""


def _speed(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value) or not 1 / MAX_SPEED <= value <= MAX_SPEED:
        raise argparse.ArgumentTypeError("--speed must be a positive number from "
                                         f"{1 / MAX_SPEED:g} to {MAX_SPEED:g}")
    return value


def _seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value) or value < 0:
        raise argparse.ArgumentTypeError("--seconds must be a number of seconds, 0 or more")
    return value




async def _open(opener: Any, service: Service, args: argparse.Namespace,
                number: int) -> tuple[str, int]:
    """A door on `--port` + N - 1; without --port, a free port, or first the one the
    controller's host software has built in (free ports if that one cannot be had: in
    use, or 23 without the right to bind it)."""
    if args.port is not None:
        return await opener(service, args.host, 0 if args.port == 0 else args.port + number - 1)
    built_in = kind_of(service.controller.model).default_port
    if built_in is not None:
        try:
            return await opener(service, args.host, built_in)
        except OSError as error:
            print(f"maxk serve: board {number}: port {built_in} ({error.strerror}); a free "
                  "port instead", file=sys.stderr, flush=True)
    return await opener(service, args.host, 0)


RESERVED_FILES = 128 + 100 + 32
"""Descriptors kept out of the doors' connection caps (D): the listeners, ptys, the map
and logs (128); a burst of connections accepted at once, before they are refused and
closed some turns of the loop later (100: asyncio accepts up to the listen backlog in
one go, and a TCP door's backlog is held within its cap, server.py); the control door's
refusals left to read their 503 (32). A flood under `ulimit -n 256` met EMFILE in the
accept burst when only 128 were kept."""


def connection_caps(doors: int, door_cap: int) -> int:
    """Each door's cap on connections so that all of them together stay inside the
    process's descriptors (raised to the hard limit first): a flood on one door then
    meets that door's cap, never EMFILE, and the other doors' hosts still connect."""
    try:
        import resource

        soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
        if hard == resource.RLIM_INFINITY or hard > soft:
            wanted = 65536 if hard == resource.RLIM_INFINITY else hard
            with contextlib.suppress(ValueError, OSError):
                resource.setrlimit(resource.RLIMIT_NOFILE, (min(wanted, 65536), hard))
        soft = resource.getrlimit(resource.RLIMIT_NOFILE)[0]
    except ImportError:  # (no resource module: not Unix)
        return door_cap
    if soft == resource.RLIM_INFINITY:
        return door_cap
    return max(4, min(door_cap, (soft - RESERVED_FILES) // max(1, doors)))


def _numbered(path: str, number: int, count: int) -> str:
    return path if count == 1 or number == 1 else f"{path}{number}"


async def serve(args: argparse.Namespace) -> int:
    names = [m.strip() for m in args.model.split(",")]
    boards = args.boards if args.boards is not None else len(names)
    if not 1 <= boards <= 16:
        print("maxk serve: --boards is 1..16 (the J5 jumper)", file=sys.stderr)
        return 2
    if args.port and not 0 < args.port <= 65536 - boards:
        print(f"maxk serve: --port {args.port} leaves no room for {boards} board(s)",
              file=sys.stderr)
        return 2
    if len(names) not in (1, boards):
        print("maxk serve: give one model, or one per board", file=sys.stderr)
        return 2
    try:
        models = [canonical_model(n) for n in names] * (boards if len(names) == 1 else 1)
    except ValueError as error:
        print(f"maxk serve: {error}", file=sys.stderr)
        return 2
    asked = {**({"eol": args.eol} if args.eol else {}), **({"ack": ""} if args.ack else {}),
             **({"framing": args.framing} if args.framing else {})}
    for option in asked:
        if not any(option in kind_of(m).line_options for m in models):
            print(f"maxk serve: --{option} means nothing to the "
                  f"{', '.join(sorted({kind_of(m).name for m in models}))}", file=sys.stderr)
            return 2
    services = []
    for number, model in enumerate(models, start=1):
        kind = kind_of(model)
        archive = default_archive(model, number)
        if args.no_archive or archive is None:
            archive = None
        elif args.archive_dir:
            archive = str(Path(args.archive_dir) / Path(archive).name)
        line_options = {k: v for k, v in asked.items() if k in kind.line_options}
        try:
            controller = build(model, BuildOptions(number, archive, None, line_options))
        except ValueError as error:  # line options that do not go together
            print(f"maxk serve: {error}", file=sys.stderr)
            return 2
        services.append(Service(number, controller, Pacer(controller, args.speed)))
    control_wanted = bool(args.control or args.control_port)
    doors = sum(1 for s in services if "tcp" in s.controller.transports) * (not args.no_tcp)
    cap = connection_caps(doors + control_wanted, HOSTS_PER_DOOR)
    server = Server(services, hosts_per_door=cap)
    memories = []
    try:
        for service in services:
            n = service.number
            controller = service.controller
            transports = controller.transports
            where = []
            tcp_port = None
            if not args.no_tcp and "tcp" in transports:
                host, tcp_port = await _open(server.open_tcp, service, args, n)
                where.append(f"tcp {host}:{tcp_port}")
            if not args.no_tcp and "udp" in transports:
                try:  # one port number for both, as a host (PoKeysLib) dials one number
                    if tcp_port is None:
                        raise OSError
                    host, bound = await server.open_udp(service, args.host, tcp_port)
                except OSError:
                    host, bound = await _open(server.open_udp, service, args, n)
                where.append(f"udp {host}:{bound}")
            if (args.pty or args.pty_link) and "pty" in transports:
                link = _numbered(args.pty_link, n, boards) if args.pty_link else None
                path = server.open_pty(service, link)
                where.append(f"serial {path}" + (f" (link {link})" if link else ""))
            if args.shm and kind_of(controller.model).shared_memory:
                from maxk.host.shared_memory import SharedMemoryDoor

                door = SharedMemoryDoor(service, _numbered(args.shm, n, boards))
                door.watch(asyncio.get_running_loop())  # a host's command wakes it
                memories.append(door)
                server.after_pacing(door.update)
                where.append(f"shared memory {door.path}")
            print(f"board {n}: {controller.model} " + ", ".join(where), flush=True)
    except OSError as error:
        print(f"maxk serve: {error}", file=sys.stderr)
        server.stop()
        await server.run()
        for door in memories:
            door.close()
        return 1
    control = None
    if args.control or args.control_port:
        from maxk.host.control import CONNECTIONS as CONTROL_CONNECTIONS
        from maxk.host.control import ControlDoor

        control = ControlDoor(services, connections=min(cap, CONTROL_CONNECTIONS))
        try:
            host, bound = await control.start(args.host, args.control_port)
        except OSError as error:
            print(f"maxk serve: control door: {error}", file=sys.stderr)
            await control.close()
            server.stop()
            await server.run()
            for door in memories:
                door.close()
            return 1
        token = f" token {control.token}" if control.token else ""
        print(f"control http://{host}:{bound}{token}", flush=True)
    loop = asyncio.get_running_loop()

    def on_signal() -> None:
        args.stopped_by_signal = True
        server.stop()

    for sig in (signal.SIGINT, signal.SIGTERM):
        with contextlib.suppress(NotImplementedError, RuntimeError):
            loop.add_signal_handler(sig, on_signal)
    if args.seconds is not None:
        loop.call_later(args.seconds, server.stop)
    savers = [save for s in services  # what a controller keeps across runs (its flash)
              if (save := getattr(s.controller, "save_archive", None)) is not None]
    for save in savers:
        server.after_pacing(save)  # (it decides itself how often it writes)
    try:
        await server.run()
    finally:
        for save in savers:  # the last word at shutdown: a power cycle keeps it
            try:
                save(True)
            except Exception as error:  # one board's failure must not stop the others'
                logging.getLogger("maxk.serve").error("maxk serve: %r (saving the archive)",
                                                      error)
        if control is not None:
            await control.close()
        for door in memories:
            door.close()
    return 0


def main(args: argparse.Namespace) -> int:
    configure_logging(args)
    code = asyncio.run(serve(args))
    if getattr(args, "stopped_by_signal", False):
        # The process ends now, every door closed: the interpreter's last collection of
        # the controllers' object graphs took 0.35 s of SIGTERM's budget of 1 s; frozen,
        # they are left to the process's end (measured: 0.05 s).
        gc.freeze()
    return code

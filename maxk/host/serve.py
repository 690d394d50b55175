"""The `maxk serve` command: start controllers of any kinds and their doors, print where
they are (one line a controller, `board N: MODEL tcp HOST:PORT, ...`, for scripts)."""

from __future__ import annotations

import argparse
import asyncio
import contextlib
import math
import signal
import sys
from pathlib import Path
from typing import Any

from maxk.commands.max.session import EOLS
from maxk.controllers.contract import BuildOptions
from maxk.controllers.registry import build, canonical_model, kind_of
from maxk.host.pacing import Pacer
from maxk.host.server import Server, Service
from maxk.personalities.maxk.parameters import default_archive_path


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--boards", type=int, default=None, help="how many controllers "
                        "(1-16; J5 jumper numbers 1..N); default: one per model given")
    parser.add_argument("--model", default="MAXk-8000",
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
    parser.add_argument("--eol", choices=sorted(EOLS), default="lfcr",
                        help="reply line ending (default lfcr: LF CR as the EPICS MAXnet "
                        "driver expects; lf for firmware >= 1.33 style)")
    parser.add_argument("--ack", action="store_true", help="lead every reply with ACK 0x06")
    parser.add_argument("--seconds", type=_seconds, default=None,
                        help="stop after this many seconds (default: run until interrupted)")


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


DEFAULT_PORTS = {"PoKeys": 20055, "MC405": 23}
"""Ports the hosts' software has built in: PoKeysLib's 20055, atrio's telnet 23."""


async def _open(opener: Any, service: Service, args: argparse.Namespace,
                number: int) -> tuple[str, int]:
    """A door on `--port` + N - 1; without --port, a free port, or first the one the
    controller's host software has built in (free ports if that one cannot be had: in
    use, or 23 without the right to bind it)."""
    if args.port is not None:
        return await opener(service, args.host, 0 if args.port == 0 else args.port + number - 1)
    built_in = DEFAULT_PORTS.get(service.controller.kind)
    if built_in is not None:
        try:
            return await opener(service, args.host, built_in)
        except OSError as error:
            print(f"maxk serve: board {number}: port {built_in} ({error.strerror}); a free "
                  "port instead", file=sys.stderr, flush=True)
    return await opener(service, args.host, 0)


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
    line_options = {"eol": args.eol, **({"ack": ""} if args.ack else {})}
    services = []
    for number, model in enumerate(models, start=1):
        archive = None if args.no_archive else str(
            Path(args.archive_dir) / f"{model}-board{number}.params.json"
            if args.archive_dir else default_archive_path(model, number))
        controller = build(model, BuildOptions(number, archive, None, line_options))
        services.append(Service(number, controller, Pacer(controller, args.speed)))
    server = Server(services)
    memories = []
    try:
        for service in services:
            n = service.number
            controller = service.controller
            transports = controller.transports
            where = []
            if not args.no_tcp and "tcp" in transports:
                host, bound = await _open(server.open_tcp, service, args, n)
                where.append(f"tcp {host}:{bound}")
            if not args.no_tcp and "udp" in transports:
                host, bound = await _open(server.open_udp, service, args, n)
                where.append(f"udp {host}:{bound}")
            if (args.pty or args.pty_link) and "pty" in transports:
                link = _numbered(args.pty_link, n, boards) if args.pty_link else None
                path = server.open_pty(service, link)
                where.append(f"serial {path}" + (f" (link {link})" if link else ""))
            if args.shm and kind_of(controller.model).name == "MAXk":
                from maxk.host.shared_memory import SharedMemoryDoor

                door = SharedMemoryDoor(service, _numbered(args.shm, n, boards))
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
    loop = asyncio.get_running_loop()
    for sig in (signal.SIGINT, signal.SIGTERM):
        with contextlib.suppress(NotImplementedError, RuntimeError):
            loop.add_signal_handler(sig, server.stop)
    if args.seconds is not None:
        loop.call_later(args.seconds, server.stop)
    try:
        await server.run()
    finally:
        for door in memories:
            door.close()
    return 0


def main(args: argparse.Namespace) -> int:
    return asyncio.run(serve(args))

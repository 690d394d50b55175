"""A `maxk serve` in-process for door tests: real sockets, a clock the test moves."""

from __future__ import annotations

import asyncio
import socket
import threading

from maxk import MAXk
from maxk.commands.max.session import EOLS, Framing
from maxk.controllers.registry import build
from maxk.host.pacing import Pacer
from maxk.host.server import Server, Service


class ManualClock:
    """Wall time that only moves when the test says so (no sleeps in tests)."""

    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


class HostedBoards:
    def __init__(self, models=("MAXk-8000",), eol="lfcr", ack=False, pty=False,
                 shm_paths=None, real_time_speed=None, host="127.0.0.1"):
        """real_time_speed: run on the wall clock, that many times faster (for tests of
        separate host processes, which cannot be told when virtual time moves)."""
        import time

        self.clock = ManualClock() if real_time_speed is None else time.monotonic
        speed = 1.0 if real_time_speed is None else real_time_speed
        framing = Framing(EOLS[eol], ack)
        self.services = []
        for n, model in enumerate(models, start=1):
            controller = build(model)
            if isinstance(controller, MAXk):
                controller.framing = framing
            self.services.append(Service(n, controller, Pacer(controller, speed, self.clock)))
        self.server = Server(self.services)
        self._closers: list = []
        self.loop = asyncio.new_event_loop()
        self.ports = []
        self.udp_ports = []
        self.ptys = []
        self.memories = []
        ready = threading.Event()

        def run():
            asyncio.set_event_loop(self.loop)

            async def main():
                for service in self.services:
                    if "tcp" in service.controller.transports:
                        self.ports.append(
                            (await self.server.open_tcp(service, host, 0))[1])
                    if "udp" in service.controller.transports:
                        self.udp_ports.append(
                            (await self.server.open_udp(service, host, 0))[1])
                    if pty:
                        self.ptys.append(self.server.open_pty(service))
                    if shm_paths:
                        from maxk.host.shared_memory import SharedMemoryDoor

                        door = SharedMemoryDoor(service, shm_paths[service.number - 1])
                        self.memories.append(door)
                        self.server.after_pacing(door.update)
                ready.set()
                await self.server.run()
                for door in self.memories:
                    door.close()

            self.loop.run_until_complete(main())

        self.thread = threading.Thread(target=run, daemon=True)
        self.thread.start()
        assert ready.wait(10)

    def call(self, fn):
        """Run fn on the server's loop (the board is not thread-safe) and return its value."""
        async def wrapper():
            return fn()

        return asyncio.run_coroutine_threadsafe(wrapper(), self.loop).result(10)

    def advance(self, seconds: float) -> None:
        """Move the wall clock; the boards catch up at once (as the pacer would)."""
        self.clock.now += seconds
        self.call(lambda: [s.pacer.sync() for s in self.services])

    def until_run(self, host: Client, board: int = 1, timeout: float = 10.0) -> None:
        """Wait (a liveness bound, not a clock) until every byte `host` sent has reached
        the door and run: known through the door's contract (the host's traffic record
        and its client's `input_run`), for any controller, with no probe command."""
        import time

        service = self.services[board - 1]
        name = f"127.0.0.1:{host.sock.getsockname()[1]}"

        def run() -> bool:
            for client in service.clients:
                traffic = client.traffic
                if traffic is not None and traffic.peer == name:
                    return traffic.bytes_in == host.sent and client.input_run
            return False

        deadline = time.monotonic() + timeout
        while not self.call(run):
            assert time.monotonic() < deadline, "the door never ran what the host sent"
            time.sleep(0.001)

    def connect(self, board: int = 1) -> Client:
        client = Client(self.ports[board - 1])
        self._closers.append(client.close)
        return client

    def on_close(self, close) -> None:
        """Something of the test's to close with the boards (a serial port, a socket)."""
        self._closers.append(close)

    def close(self) -> None:
        for close in self._closers:  # the hosts' side (a test may have closed it already)
            close()
        self.loop.call_soon_threadsafe(self.server.stop)
        self.thread.join(10)
        if not self.thread.is_alive():
            self.loop.close()


class Client:
    """A host's socket, reading framed lines the way the EPICS MAXnet driver does."""

    def __init__(self, port: int, eol: bytes = b"\n\r") -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5)
        self.sent = 0  # bytes sent, for HostedBoards.until_run
        self.eol = eol
        self.buffer = b""
        self.held: list[str] = []  # lines read early by command(), handed out by line()

    def send(self, text: str | bytes) -> None:
        data = text.encode() if isinstance(text, str) else text
        self.sock.sendall(data)
        self.sent += len(data)

    def command(self, text: str) -> None:
        """Send MAX commands and know the server has run them: a #WS probe follows, and its
        =0 comes back only after everything before it was processed (a MAXk's way; any
        controller's: `HostedBoards.until_run`)."""
        self.send(text + "\n#WS\n")
        while True:
            line = self._read_line()
            if line == "=0":
                return
            self.held.append(line)

    def line(self) -> str:
        if self.held:
            return self.held.pop(0)
        return self._read_line()

    def _read_line(self) -> str:
        while self.eol not in self.buffer:
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("closed")
            self.buffer += chunk
        line, self.buffer = self.buffer.split(self.eol, 1)
        return line.decode("latin-1")

    def query(self, text: str) -> str:
        """Send a command line and return its reply, skipping notifications as EPICS does."""
        self.send(text + "\n")
        while True:
            line = self.line()
            if "000 0" not in line:
                return line

    def nothing_pending(self, board: HostedBoards) -> bool:
        self.command("")  # everything sent so far has been processed
        if self.held:
            return False
        self.sock.setblocking(False)
        try:
            data = self.sock.recv(65536)
        except BlockingIOError:
            data = b""
        finally:
            self.sock.setblocking(True)
            self.sock.settimeout(5)
        self.buffer += data
        return not self.buffer

    def close(self) -> None:
        self.sock.close()

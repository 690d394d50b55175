"""The control door under a live panel: 16 boards of mixed kinds served in their own
process (4 each of MAXk-8000 running endless back-to-back moves, MM4005, MC405,
PoKeys57CNC), the front panel open in headless Chromium (server-sent events at 20 Hz)
and a program polling `/api/panel` at 20 Hz, while a host polls its MAXk boards' `RP`
over TCP as EPICS does. Measured: the host's round trip (p50, p99) and how well the
server keeps real time (the worst pacer lag and the worst gap between pacing passes).
The same run prints the naive loop's figure, the yardstick of every benchmark here.

    python3 -m benchmarks.control_panel [--seconds 20] [--no-browser] [--json]
"""

from __future__ import annotations

import argparse
import asyncio
import os
import shutil
import socket
import tempfile
import threading
import time
import urllib.request

from benchmarks.doors import BUSY, PacingWatch
from benchmarks.figure import Figure
from benchmarks.live_server import percentile, print_figures
from benchmarks.servo_figures import naive_reference

MODELS = ["MAXk-8000", "MM4005", "MC405", "PoKeys57CNC"] * 4
PANEL_HZ = 20.0


def _serve(seconds: float, ports_out, stats_out, done) -> None:  # type: ignore[no-untyped-def]
    """The server with its control door, in its own process as `maxk serve` runs."""
    from maxk.controllers.registry import build
    from maxk.host.control import ControlDoor
    from maxk.host.pacing import Pacer
    from maxk.host.server import Server, Service

    services = []
    for n, model in enumerate(MODELS, start=1):
        controller = build(model)
        if controller.kind == "MAXk":
            controller.send(BUSY)  # type: ignore[attr-defined]
        services.append(Service(n, controller, Pacer(controller)))
    server = Server(services)
    door = ControlDoor(services, stream_hz=PANEL_HZ)
    watch = PacingWatch(services)
    worst = watch.worst

    async def main() -> None:
        ports = []
        for service in services:
            if service.controller.kind == "MAXk":
                ports.append((await server.open_tcp(service, "127.0.0.1", 0))[1])
        control = (await door.start("127.0.0.1", 0))[1]
        server.after_pacing(watch)
        ports_out.send((ports, control))
        watch.restart()
        loop = asyncio.get_running_loop()
        loop.call_later(seconds + 300.0, server.stop)  # a bound, should the benchmark die

        def look() -> None:  # the benchmark says when it is done
            if done.is_set():
                server.stop()
            else:
                loop.call_later(0.2, look)

        look()
        await server.run()
        await door.close()

    asyncio.run(main())
    stats_out.send(worst)


def _browser(url: str):  # type: ignore[no-untyped-def]
    """The panel in headless Chromium (None when the browser is not installed)."""
    chromium, driver = shutil.which("chromium"), shutil.which("chromedriver")
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service as DriverService
    except ImportError:
        return None, None
    if not chromium or not driver:
        return None, None
    profile = tempfile.mkdtemp(prefix="maxk-bench-")
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for flag in ("--headless", "--no-sandbox", "--disable-gpu",
                 "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", "--no-first-run", "--disable-dev-shm-usage",
                 f"--user-data-dir={profile}", "--window-size=1400,1000"):
        options.add_argument(flag)
    browser = webdriver.Chrome(service=DriverService(executable_path=driver), options=options)
    browser.get(url + "/")
    return browser, profile


def run(seconds: float = 20.0, host_rate: float = 200.0, with_browser: bool = True,
        with_panel: bool = True) -> dict[str, float]:
    """One run; without the panel (no poller, no browser) it is the baseline."""
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")
    ports_rx, ports_tx = ctx.Pipe(duplex=False)
    stats_rx, stats_tx = ctx.Pipe(duplex=False)
    done = ctx.Event()
    proc = ctx.Process(target=_serve, args=(seconds, ports_tx, stats_tx, done))
    proc.start()
    ports, control = ports_rx.recv()
    url = f"http://127.0.0.1:{control}"
    browser, profile = _browser(url) if with_browser and with_panel else (None, None)
    stop = threading.Event()
    polls: list[float] = []

    def poll_panel() -> None:  # the panel's program twin: /api/panel at 20 Hz
        next_at = time.monotonic()
        while not stop.is_set():
            start = time.perf_counter()
            try:
                with urllib.request.urlopen(url + "/api/panel", timeout=10) as answer:
                    answer.read()
            except OSError:
                return  # the server has stopped
            polls.append(time.perf_counter() - start)
            next_at += 1.0 / PANEL_HZ
            stop.wait(max(0.0, next_at - time.monotonic()))

    poller = threading.Thread(target=poll_panel, daemon=True)
    if with_panel:
        poller.start()
    socks = [socket.create_connection(("127.0.0.1", p)) for p in ports]
    for sock in socks:
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    times: list[float] = []
    buffers = [b""] * len(socks)
    end = time.monotonic() + seconds
    next_at = time.monotonic()
    i = 0
    while time.monotonic() < end:
        next_at += 1.0 / host_rate
        delay = next_at - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        k = i % len(socks)
        sock = socks[k]
        start = time.perf_counter()
        sock.sendall(b"AA RP;\n")
        data = buffers[k]
        while True:  # notifications (%...) set aside, as EPICS does
            while b"\n\r" not in data:
                chunk = sock.recv(4096)
                if not chunk:
                    raise RuntimeError("the server hung up on the host")
                data += chunk
            line, data = data.split(b"\n\r", 1)
            if not line.startswith(b"%"):
                break
        buffers[k] = data
        times.append(time.perf_counter() - start)
        i += 1
    updates = 0
    if browser is not None:
        updates = int(browser.find_element("tag name", "body").get_attribute("data-updates")
                      or 0)
        browser.quit()
        shutil.rmtree(profile, ignore_errors=True)
    stop.set()
    if with_panel:
        poller.join(10)
    for sock in socks:
        sock.close()
    done.set()
    worst = stats_rx.recv()
    proc.join(15)
    times.sort()
    polls.sort()
    return {"p50_ms": percentile(times, 0.5) * 1e3, "p99_ms": percentile(times, 0.99) * 1e3,
            "queries": float(len(times)), "panel_polls": float(len(polls)),
            "panel_poll_p99_ms": percentile(polls, 0.99) * 1e3,
            "browser_updates_per_s": updates / seconds,
            "worst_lag_ms": worst["lag"] * 1e3, "worst_gap_ms": worst["gap"] * 1e3}


def figures(seconds: float, with_browser: bool) -> list[Figure]:
    base = run(seconds, with_panel=False)
    r = run(seconds, with_browser=with_browser)
    note = (f"16 boards (4 kinds), panel at {PANEL_HZ:g} Hz"
            + (f", browser {r['browser_updates_per_s']:.1f} updates/s" if with_browser
               else ", no browser") + f", {int(r['queries'])} host queries")
    return [
        Figure("control_host_rtt_p99_no_panel", base["p99_ms"], "ms", None,
               f"the same boards and host, no panel ({int(base['queries'])} queries); "
               f"worst gap {base['worst_gap_ms']:.1f} ms"),
        Figure("control_host_rtt_p50", r["p50_ms"], "ms", None, note),
        Figure("control_host_rtt_p99", r["p99_ms"], "ms", 5.0, note),
        Figure("control_panel_poll_p99", r["panel_poll_p99_ms"], "ms", None,
               f"{int(r['panel_polls'])} GET /api/panel"),
        Figure("control_worst_pacer_lag", r["worst_lag_ms"], "ms", None,
               "virtual time behind the wall clock, worst of any board"),
        Figure("control_worst_pacing_gap", r["worst_gap_ms"], "ms", None,
               "longest wall time between two pacing passes"),
        naive_reference(),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--no-browser", action="store_true")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    os.environ.setdefault("PYTHONHASHSEED", "0")
    print_figures(figures(args.seconds, not args.no_browser), args.json)


if __name__ == "__main__":
    main()

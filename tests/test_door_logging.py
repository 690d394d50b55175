"""Logging and the per-host traffic record: what a person debugging a host turns on."""

import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

from maxk.controllers.registry import build
from maxk.host.traffic import ENTRIES, TrafficBook, peer_name

ROOT = Path(__file__).parent.parent


def test_a_hosts_bytes_are_kept_with_virtual_time_and_bounded():
    controller = build("MAXk-1000")
    book = TrafficBook(controller.engine, hosts=2)
    first = book.open("tcp", peer_name(("127.0.0.1", 5000)))
    controller.engine.advance(8192)  # one second of virtual time
    first.incoming(b"WY\r")
    first.outgoing(b"MAXk-1000, ver:1.33\n\r")
    assert [(e.tick, e.direction, e.data) for e in first.entries] == [
        (8192, "in", b"WY\r"), (8192, "out", b"MAXk-1000, ver:1.33\n\r")]
    assert first.as_dict()["entries"][0]["time"] == 1.0
    for n in range(ENTRIES + 5):
        first.incoming(b"%d" % n)
    assert len(first.entries) == ENTRIES and first.dropped == 7
    assert first.entries[-1].data == b"%d" % (ENTRIES + 4)
    book.open("udp", peer_name(("::1", 20055)))
    book.open("tcp", "/dev/pts/9")
    assert [h.peer for h in book.hosts] == ["[::1]:20055", "/dev/pts/9"]  # 2 hosts kept


def test_serve_vv_logs_each_hosts_bytes_with_its_address_and_virtual_time():
    proc = subprocess.Popen(
        [sys.executable, "-m", "maxk", "serve", "--model", "MAXk-1000,MM4005", "--port", "0",
         "--no-archive", "-vv"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        ports = [int(re.search(r"tcp 127\.0\.0\.1:(\d+)", proc.stdout.readline())[1])
                 for _ in range(2)]
        for port, line, reply in ((ports[0], b"WY\r", b"\n\r"), (ports[1], b"VE\r", b"\r")):
            with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
                sock.sendall(line)
                data = b""
                while not data.endswith(reply):
                    data += sock.recv(200)
                local = sock.getsockname()[1]
    finally:
        proc.send_signal(signal.SIGTERM)
        _out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err
    assert re.search(r"maxk\.door\.tcp: 127\.0\.0\.1:\d+ connected", err)
    assert re.search(r"maxk\.door\.tcp: 127\.0\.0\.1:\d+ t=\d+\.\d{6} <- b'WY\\r'", err)
    assert re.search(r"maxk\.door\.tcp: 127\.0\.0\.1:\d+ t=\d+\.\d{6} -> b'MAXk-1000, ver:",
                     err)
    assert f"127.0.0.1:{local} t=" in err and f"127.0.0.1:{local} hung up" in err  # MM4005's


def test_serve_is_quiet_by_default_and_refuses_line_options_that_mean_nothing():
    result = subprocess.run(
        [sys.executable, "-m", "maxk", "serve", "--model", "MM4005", "--eol", "lf",
         "--seconds", "0.1", "--no-archive"], capture_output=True, text=True, timeout=30,
        cwd=ROOT)
    assert result.returncode == 2
    assert result.stderr.strip() == "maxk serve: --eol means nothing to the MM4005"
    result = subprocess.run(
        [sys.executable, "-m", "maxk", "serve", "--model", "MAXk-1000,MM4005", "--eol", "lf",
         "--port", "0", "--seconds", "0.2", "--no-archive"], capture_output=True, text=True,
        timeout=30, cwd=ROOT)
    assert result.returncode == 0 and result.stderr == ""  # the MAXk takes it


def test_a_test_knows_a_command_has_run_on_any_controller_without_a_probe():
    """HostedBoards.until_run: through the door's contract (the host's traffic record and
    its client's input_run), an MM4005 move that answers nothing is known to have run."""
    from hosting import Client, HostedBoards

    boards = HostedBoards(models=("MM4005", "MC405"))
    try:
        host = Client(boards.ports[0], eol=b"\r")
        boards.on_close(host.close)
        host.send("1PA0.5\r")  # no reply: nothing to wait for but the door itself
        boards.until_run(host)
        view = boards.services[0].controller.world_view()
        assert boards.call(lambda: view.reading("1").moving)
        boards.advance(2.0)
        assert boards.call(lambda: view.reading("1").position) == 500
        trio = Client(boards.ports[1], eol=b"\r\n")
        boards.on_close(trio.close)
        trio.send("BASE(0): MOVE(25)\r\n")
        boards.until_run(trio, board=2)
        boards.advance(1.0)
        assert boards.call(lambda: boards.services[1].controller.world_view()
                           .reading("0").position) == 25
    finally:
        boards.close()


def test_a_rate_the_controller_does_not_run_at_is_refused_by_every_door(tmp_path):
    result = subprocess.run([sys.executable, "-m", "maxk", "--model", "MM4005", "--rate",
                             "8192", "--manual-time", "--no-archive"], input="quit\n",
                            capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert result.returncode == 2
    assert result.stderr.strip() == "maxk: the MM4005 runs at 2000 Hz, not 8192"
    script = tmp_path / "s.maxk"
    script.write_text("@board MC405\n?1+1\n")
    result = subprocess.run([sys.executable, "-m", "maxk", "run", "--rate", "8192",
                             str(script)], capture_output=True, text=True, timeout=60,
                            cwd=ROOT)
    assert result.returncode == 2
    assert result.stderr.strip() == "maxk run: the MC405 runs at 500, 1000, 2000, 4000 Hz, " \
        "not 8192"
    result = subprocess.run([sys.executable, "-m", "maxk", "run", "--rate", "4000",
                             str(script)], capture_output=True, text=True, timeout=60,
                            cwd=ROOT)
    assert result.returncode == 0 and result.stdout == "2\n", result.stderr

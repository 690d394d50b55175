"""`maxk serve` as a user starts it: a real process, its printed doors, a clean exit."""

import os
import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).parent.parent


def test_serve_prints_its_doors_answers_and_cleans_up(tmp_path):
    shm = tmp_path / "maxk"
    link = tmp_path / "ttyMAXk"
    proc = subprocess.Popen(
        [sys.executable, "-m", "maxk", "serve", "--boards", "2", "--model",
         "MAXk-4000,MAXk-A000", "--pty-link", str(link), "--shm", str(shm), "--speed", "10"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        lines = [proc.stdout.readline() for _ in range(2)]
        m1 = re.match(r"board 1: MAXk-4000 tcp 127\.0\.0\.1:(\d+), serial (/dev/\S+) "
                      r"\(link (\S+)\), shared memory (\S+)", lines[0])
        m2 = re.match(r"board 2: MAXk-A000 tcp 127\.0\.0\.1:(\d+), serial (\S+) \(link (\S+)\)",
                      lines[1])
        assert m1 and m2, lines
        assert m1[3] == str(link) and os.path.realpath(link) == m1[2]
        assert m1[4] == str(shm) and shm.stat().st_size == 0xE010
        for match, answer in ((m1, "0,0,0,0"), (m2, "0,0,0,0,0,0,0,0,0,0")):
            with socket.create_connection(("127.0.0.1", int(match[1])), timeout=10) as sock:
                sock.sendall(b"AA RP;\n")
                data = b""
                while not data.endswith(b"\n\r"):
                    data += sock.recv(100)
                assert data == answer.encode() + b"\n\r"
    finally:
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err
    assert not shm.exists() and not link.exists()  # cleaned up


def test_serve_refuses_bad_arguments():
    for args, message in ((["--boards", "17"], "1..16"),
                          (["--model", "MAXk-9999"], "unknown controller model"),
                          (["--boards", "2", "--model", "MAXk-1000,MAXk-2000,MAXk-3000"],
                           "one per board")):
        result = subprocess.run([sys.executable, "-m", "maxk", "serve", "--seconds", "0.1",
                                 *args], capture_output=True, text=True, timeout=30, cwd=ROOT)
        assert result.returncode == 2 and message in result.stderr, (args, result.stderr)


def test_serve_refuses_a_map_path_that_is_not_its_own_and_keeps_the_file(tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    link = tmp_path / "link"
    link.symlink_to(notes)
    for path, message in ((notes, "not a maxk map"), (link, "symbolic link")):
        result = subprocess.run([sys.executable, "-m", "maxk", "serve", "--no-tcp", "--shm",
                                 str(path), "--seconds", "5"],
                                capture_output=True, text=True, timeout=60, cwd=ROOT)
        assert result.returncode == 1 and message in result.stderr, result.stderr
        assert "Traceback" not in result.stderr
    assert notes.read_text() == "my notes\n" and link.is_symlink()


def test_a_second_server_on_one_map_refuses_and_the_first_keeps_serving(tmp_path):
    shm = tmp_path / "maxk"
    first = subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--shm", str(shm),
                              "--seconds", "60"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        line = first.stdout.readline()
        port = int(re.match(r"board 1: \S+ tcp 127\.0\.0\.1:(\d+)", line)[1])
        second = subprocess.run([sys.executable, "-m", "maxk", "serve", "--shm", str(shm),
                                 "--seconds", "5"],
                                capture_output=True, text=True, timeout=60, cwd=ROOT)
        assert second.returncode == 1 and "in use" in second.stderr, second.stderr
        assert shm.exists()
        from maxk.host.shm_client import SharedMemoryHost

        host = SharedMemoryHost(str(shm))
        assert host.query("WY").startswith("MAXk-8000")
        host.close()
        with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
            sock.sendall(b"AX RP;\n")
            data = b""
            while not data.endswith(b"\n\r"):
                data += sock.recv(100)
            assert data == b"0\n\r"
    finally:
        first.send_signal(signal.SIGTERM)
        _, err = first.communicate(timeout=20)
    assert first.returncode == 0, err
    assert not shm.exists()


def _lines(stream):
    """A queue of the stream's lines, read by a thread (so waits can be bounded)."""
    import queue
    import threading

    lines: queue.Queue = queue.Queue()

    def pump():
        for line in stream:
            lines.put(line)
        lines.put("")  # end of stream

    threading.Thread(target=pump, daemon=True).start()
    return lines


def _tcp_query(port, text):
    with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
        sock.sendall(text.encode() + b"\n")
        data = b""
        while not data.endswith(b"\n\r"):
            chunk = sock.recv(100)
            assert chunk, "connection closed"
            data += chunk
        return data[:-2].decode()


def test_a_truncated_map_closes_that_door_alone_and_the_server_goes_on(tmp_path):
    from maxk.host.shm_client import SharedMemoryHost

    shm = tmp_path / "maxk"
    proc = subprocess.Popen(
        [sys.executable, "-m", "maxk", "serve", "--boards", "2", "--shm", str(shm),
         "--seconds", "120"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    errors = _lines(proc.stderr)
    try:
        ports = [int(re.match(r"board \d: \S+ tcp 127\.0\.0\.1:(\d+)", proc.stdout.readline())[1])
                 for _ in range(2)]
        shm2 = Path(f"{shm}2")
        os.truncate(shm, 0)  # another process breaks board 1's map
        report = errors.get(timeout=30)
        assert "truncated" in report and str(shm) in report, report
        assert proc.poll() is None  # still serving
        host = SharedMemoryHost(str(shm2))
        assert host.query("AX RP") == "0"  # board 2's map works on
        host.close()
        assert _tcp_query(ports[0], "WY").startswith("MAXk-8000")  # board 1 too, by TCP
        assert _tcp_query(ports[1], "AY RP") == "0"
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=20)
        _close_pipes(proc)
    assert proc.returncode == 0
    assert not shm.exists() and not shm2.exists()  # cleaned up


def test_serve_starts_on_a_deeply_nested_archive_and_rdp_is_a_command_error(tmp_path):
    (tmp_path / "MAXk-8000-board1.params.json").write_bytes(b"[" * 100_000 + b"]" * 100_000)
    proc = subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--archive-dir",
                             str(tmp_path), "--seconds", "60"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        line = proc.stdout.readline()
        match = re.match(r"board 1: MAXk-8000 tcp 127\.0\.0\.1:(\d+)", line)
        assert match, (line, proc.stderr.read() if proc.poll() is not None else "")
        with socket.create_connection(("127.0.0.1", int(match[1])), timeout=10) as sock:
            sock.sendall(b"RDP\nWY\n")
            data = b""
            while b"MAXk-8000, ver" not in data:
                chunk = sock.recv(1000)
                assert chunk, data  # the connection lives on
                data += chunk
        assert b"%000 01000000" in data  # the command error, notified
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=20)
        _close_pipes(proc)
    assert proc.returncode == 0


def test_serve_takes_one_controller_per_model_listed():
    """`--model A,B` alone starts two controllers (`--boards` follows from the list),
    each answering on its own port as its own model."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "maxk", "serve", "--model", "MAXk-8000,MAXk-2000",
         "--no-archive"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        lines = [proc.stdout.readline() for _ in range(2)]
        ports = []
        for n, model in ((1, "MAXk-8000"), (2, "MAXk-2000")):
            m = re.match(rf"board {n}: {model} tcp 127\.0\.0\.1:(\d+)$", lines[n - 1].strip())
            assert m, lines
            ports.append(int(m[1]))
        for port, model in zip(ports, ("MAXk-8000", "MAXk-2000"), strict=True):
            with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
                sock.sendall(b"WY\r")
                data = b""
                while not data.endswith(b"\n\r"):
                    data += sock.recv(100)
                assert data.startswith(model.encode() + b", ver:"), data
    finally:
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err


def test_a_pokeys_listens_on_its_library_port_by_default():
    """PoKeysLib has 20055 built in: without --port a PoKeys is served there (or, when
    20055 cannot be had, on a free port with a note saying so)."""
    proc = subprocess.Popen(
        [sys.executable, "-m", "maxk", "serve", "--model", "PoKeys57CNC", "--no-archive",
         "--seconds", "5"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        cwd=ROOT)
    try:
        line = proc.stdout.readline()
        m = re.match(r"board 1: PoKeys57CNC tcp 127\.0\.0\.1:(\d+), udp 127\.0\.0\.1:(\d+)",
                     line)
        assert m, line
    finally:
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=20)
    assert (m[1], m[2]) == ("20055", "20055") or "port 20055" in err, (line, err)


def _close_pipes(proc: subprocess.Popen) -> None:
    for pipe in (proc.stdout, proc.stderr):
        if pipe is not None:
            pipe.close()

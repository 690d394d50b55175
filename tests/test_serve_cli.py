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

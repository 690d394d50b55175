"""The command line's program editing: SELECT (quoted or not, creating a missing
program) and every ``!`` line-editor form, as atrio and a vendor-style uploader send
them; the uploader also over the real TCP door of ``maxk serve --model MC405``."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
import time
from pathlib import Path

from tests.trio_helpers import Rig

ROOT = Path(__file__).resolve().parents[1]


def lines_of(rig: Rig, name: str) -> list[str]:
    return rig.session.programs.lines[name]


def test_select_unquoted_selects_an_existing_program() -> None:
    rig = Rig()
    rig.load("CYCLE", "VR(1)=1")
    rig.command('SELECT "OTHER",0')
    rig.command("SELECT CYCLE")
    assert rig.session.system.selected == "CYCLE"
    assert rig.command("LIST") == b"VR(1)=1"


def test_select_creates_a_missing_program_quoted_or_not() -> None:
    rig = Rig()
    rig.command('SELECT "FRESH"')
    rig.command("SELECT spare")
    assert rig.command('?PROG_TYPE "FRESH"') == b"0"
    assert rig.command('?PROG_TYPE "SPARE"') == b"0"
    rig.command("SELECT MC_CONFIG")  # no type given: a BASIC program (help page)
    assert rig.command('?PROG_TYPE "MC_CONFIG"') == b"0"
    assert rig.session.system.selected == "MC_CONFIG"
    rig.command('SELECT "LIB",12')
    rig.command("SELECT FRESH")  # an existing program keeps its type
    rig.command("SELECT LIB")
    assert rig.command('?PROG_TYPE "LIB"') == b"12"


def test_select_of_a_keyword_is_still_a_syntax_error() -> None:
    assert b"%[COMMAND LINE] - Syntax error" in Rig().send("SELECT SPEED")


def test_insert_drops_the_separating_comma() -> None:
    rig = Rig()
    rig.command("SELECT MC_CONFIG")
    rig.command("!MC_CONFIG,0I,ATYPE AXIS(0) = 76")
    rig.command("!MC_CONFIG,0 I,UNITS AXIS(0) = -200")  # a space before the letter too
    rig.command("!MC_CONFIG,2I,VR(9) = 1")
    assert lines_of(rig, "MC_CONFIG") == ["UNITS AXIS(0) = -200", "ATYPE AXIS(0) = 76",
                                          "VR(9) = 1"]


def test_replace_and_delete_in_both_spellings() -> None:
    rig = Rig()
    rig.load("P", "A=1\nB=2\nC=3")
    rig.command("!P,1RB=20")  # atrio: no separator
    rig.command("!P,2R,C=30")  # a vendor tool: one comma after the letter
    assert lines_of(rig, "P") == ["A=1", "B=20", "C=30"]
    rig.command("!P,0D")
    rig.command("!P,0 D")
    assert lines_of(rig, "P") == ["C=30"]
    assert b"Invalid line number" in rig.send("!P,5D")
    assert lines_of(rig, "P") == ["C=30"]


def test_line_count_and_listing() -> None:
    rig = Rig()
    rig.command("SELECT EMPTY")
    assert rig.command("!EMPTY,N") == b"0"
    rig.load("SHOW", "\n".join(f"VR({n})={n * 3}" for n in range(12)))
    assert rig.command("!SHOW,N") == b"12"
    assert rig.command("!SHOW,3,5L") == b"VR(3)=9\r\nVR(4)=12\r\nVR(5)=15"
    assert rig.command("!SHOW,10,40L") == b"VR(10)=30\r\nVR(11)=33"  # to the last line
    assert rig.command("!SHOW,20,30L") == b""
    assert b"Program not found" in rig.send("!NOPE,N")
    assert b"Syntax error" in rig.send("!SHOW,Q")


# ---- a raw-telnet uploader over the real door ---------------------------------------------
class Uploader:
    """A vendor-style uploader written for this test: each command is sent with CR alone
    and the reply is read until the prompt ``>>`` comes back (bounded by a timeout)."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5)

    def send(self, command: str) -> str:
        self.sock.sendall(command.encode() + b"\r")
        data = b""
        deadline = time.monotonic() + 5
        while not data.endswith(b">>"):
            assert time.monotonic() < deadline, data
            chunk = self.sock.recv(4096)
            assert chunk, "connection closed"
            data += chunk
        text = data.decode("latin-1")
        assert text.startswith(command + "\r\n"), text  # the echo, then the reply
        return text[len(command) + 2:-2]


def test_an_uploader_stores_mc_config_over_tcp(tmp_path) -> None:
    proc = subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--model", "MC405",
                             "--port", "0", "--archive-dir", str(tmp_path)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        assert proc.stdout is not None
        match = re.match(r"board 1: MC405 tcp 127\.0\.0\.1:(\d+)$", proc.stdout.readline().strip())
        assert match
        up = Uploader(int(match[1]))
        assert up.send('SELECT "MC_CONFIG",9') == ""  # as Motion Perfect made it
        assert up.send("SELECT MC_CONFIG") == ""  # the uploader's own start
        assert up.send("!MC_CONFIG,N") == "0\r\n"
        wanted = ["ATYPE AXIS(0) = 76", "UNITS AXIS(0) = -400", "VR(20) = 5"]
        up.send("!MC_CONFIG,0I,old line")
        assert up.send("!MC_CONFIG,N") == "1\r\n"
        assert up.send("!MC_CONFIG,0D") == ""
        for n, line in enumerate(wanted):
            assert up.send(f"!MC_CONFIG,{n}I,{line}") == ""
        assert up.send("!MC_CONFIG,N") == "3\r\n"
        assert up.send("!MC_CONFIG,0,10L") == "".join(w + "\r\n" for w in wanted)
        assert up.send("!MC_CONFIG,M") == ""
        directory = up.send("DIR")
        assert re.search(r"^MC_CONFIG\s+(\d+)\s+\d+\s+Power Up\s+MC_CONFIG", directory,
                         re.MULTILINE), directory
        assert int(re.search(r"^MC_CONFIG\s+(\d+)", directory, re.MULTILINE)[1]) == \
            sum(len(w) + 1 for w in wanted)
        up.sock.close()
    finally:
        proc.terminate()
        proc.communicate(timeout=20)
    stored = tmp_path / "MC405-board1.programs" / "MC_CONFIG.MCC"
    assert stored.read_text() == "".join(w + "\n" for w in wanted)


def test_a_basic_program_named_mc_config_runs_at_power_up(tmp_path: Path) -> None:
    """The uploader's way: SELECT MC_CONFIG (a BASIC program), its lines inserted, then a
    power cycle applies it (help "MC_CONFIG Program": run at power-up if present)."""
    rig = Rig(tmp_path)
    rig.command("SELECT MC_CONFIG")
    rig.command("!MC_CONFIG,0I,ATYPE AXIS(0) = 76")
    rig.command("!MC_CONFIG,1I,VR(9) = 3")
    rig.load("OTHER", "VR(9) = 7")  # a BASIC program of another name, not autorun
    assert rig.command("?ATYPE AXIS(0)") != b"76"
    again = Rig(tmp_path)  # a restart on the same program directory
    again.session.power_up()
    again.cycles(2)
    assert again.command("?ATYPE AXIS(0)") == b"76"
    assert again.command("?VR(9)") == b"3.0000"
    assert again.command("AUTORUN") == b""  # AUTORUN starts only the autorun programs

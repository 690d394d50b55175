"""The REPL's behaviour without a terminal: lines in, lines out, clock injected."""

import re
import subprocess
import sys
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.controllers.maxk.controller import AxisStatus
from maxk.personalities.maxk import flags as F
from maxk.repl import MnemonicCompleter, ReplSession

ROOT = Path(__file__).parent.parent


class FakeClock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


def test_commands_and_replies():
    s = ReplSession(manual_time=True)
    assert s.handle("WY") == ["MAXk-8000, ver:1.33, S/N: 000001, FPGA:20"]
    assert s.handle("AX RP RE") == ["0", "0"]
    assert s.prompt() == "MAXk-8000 AX> "
    s.handle("AM")
    assert s.prompt() == "MAXk-8000 AM> "


def test_errors_are_shown_with_their_cause():
    s = ReplSession(manual_time=True)
    out = s.handle("AX; MR; RP")
    assert out == ["0", "! command error: 'MR': MR needs an operand"]
    assert s.handle("RP") == ["0"]  # shown once
    assert s.handle(":errors") == ["tick 0: 'MR': MR needs an operand"]


def test_virtual_time_follows_the_wall_clock_by_default():
    clock = FakeClock()
    s = ReplSession(clock=clock)
    s.handle("AX; VL5000; AC50000; MA10000; GO; ID;")
    clock.now += 1.0
    assert s.handle("RP") == [str(250 + 4500)]
    clock.now += 1.2
    assert s.handle("QA") == ["PDNN"]


def test_speed_scales_the_clock():
    clock = FakeClock()
    s = ReplSession(clock=clock, speed=10.0)
    clock.now += 0.1
    s.handle("RP")
    assert s.controller.tick == 8192


def test_manual_time_and_meta_commands():
    clock = FakeClock()
    s = ReplSession(clock=clock, manual_time=True)
    s.handle("AX; VL5000; AC50000; MA10000; GO; ID;")
    clock.now += 10
    assert s.handle("RP") == ["0"]
    assert s.handle(":advance 1 s") == ["tick 8192"]
    assert s.handle("RP") == [str(250 + 4500)]
    assert s.handle(":run") == ["idle at tick 17204"]
    assert s.handle(":doorbell") == ["0x00000001: done X"]
    assert s.handle(":clear") == ["doorbell cleared"]
    assert s.handle(":time")[0].startswith("tick 17204, 2.100098 s virtual (manual")
    assert s.handle(":clock realtime") == ["clock: realtime"]
    clock.now += 1
    assert s.handle(":time")[0].startswith("tick 25396")


def test_help_reads_the_command_table():
    s = ReplSession(manual_time=True)
    out = s.handle("help VL")
    assert out[0].startswith("VL#  —  Peak (slew) velocity")
    assert any("source:" in line for line in out)
    assert s.handle("help")[0].startswith("REPL words")
    assert s.handle("help QQ") == ["no command 'QQ'; try :commands"]


def test_status_line_and_quit():
    s = ReplSession(manual_time=True)
    s.handle("AY; MR5; GO; ID;")
    s.handle(":run")
    lines = s.handle(":status")
    assert lines[2].split() == ["Y", "5", "5", "0", "PDNN", "0"]
    assert "done Y" in s.toolbar()
    s.handle("quit")
    assert s.finished


def test_completion_from_the_command_table():
    from prompt_toolkit.document import Document

    completions = list(MnemonicCompleter().get_completions(Document("AX; L"), None))
    names = {c.text for c in completions}
    assert {"LP", "LPE", "LO", "LS", "LE", "LT", "LM"} <= names
    assert all(c.start_position == -1 for c in completions)
    assert [c.text for c in MnemonicCompleter().get_completions(Document("rq"), None)] == ["RQC"]


def test_piped_repl_as_a_process():
    result = subprocess.run(
        [sys.executable, "-m", "maxk", "repl", "--manual-time"],
        input="WY\nAX; MR10; GO; ID;\n:run\nAX RP\nquit\n",
        capture_output=True, text=True, timeout=60,
    )
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [
        "MAXk-8000, ver:1.33, S/N: 000001, FPGA:20", "idle at tick 37", "10"]


def test_a_deeply_nested_archive_is_a_damaged_one_in_the_repl(tmp_path):
    archive = tmp_path / "flash.json"
    archive.write_bytes(b"[" * 100_000 + b"]" * 100_000)
    s = ReplSession(manual_time=True, archive=archive)
    assert s.handle(":advance 1 ticks") == [
        "tick 1", "! command error: power-up: unreadable archive (RecursionError)"]
    assert s.controller.board.firmware_flags == (F.FIRMWARE_RUNNING | F.ARCHIVE_CHECKSUM_ERROR
                                           | F.FACTORY_DEFAULTS_LOADED)
    out = s.handle("RDP")
    assert len(out) == 1 and out[0].startswith("! command error")
    assert s.handle("WY") == ["MAXk-8000, ver:1.33, S/N: 000001, FPGA:20"]


# ---- the status line on 80 columns -----------------------------------------------------
A000_TOKENS = re.compile(r"^ ?t=\S+ +X\S* +Y\S* +Z\S* +T\S* +U\S* +V\S* +R\S* +S\S* +W\S* +K\S*")


def test_the_status_line_of_a_maxk_a000_fits_80_columns():
    s = ReplSession(model="MAXk-A000", manual_time=True)
    s.handle("AA; VL2000000,2000000,2000000,2000000,2000000,2000000,2000000,2000000,"
             "2000000,2000000; AC8000000,8000000,8000000,8000000,8000000,8000000,8000000,"
             "8000000,8000000,8000000;")
    s.handle("AA; MR-100000,200000,-300000,400000,-500000,600000,-700000,800000,-900000,"
             "1000000; GO; ID;")
    s.handle(":run")
    s.handle("MR")  # a command error as well
    line = s.toolbar()
    assert len(line) <= 80 and A000_TOKENS.match(line), line
    assert line.endswith("  err")
    s.handle(":clear")
    assert s.toolbar(200) == (  # wide enough: in full, as before
        " t=0.750s  X-100000  Y200000  Z-300000  T400000  U-500000  V600000  R-700000  "
        "S800000  W-900000  K1000000   flags: none")


def test_the_status_line_abbreviates_positions_only_when_it_must():
    from maxk.controllers.maxk.console import status_line

    statuses = [AxisStatus(letter, position, 0, 0, done, moving, 0, "")
                for letter, position, done, moving in zip(
                    "XYZTUVRSWK",
                    [123456, -123456, 999999, -2**31, 2**31 - 1, 0, -999, 9999, 12345, -1500],
                    [True] * 5 + [False] * 5, [False] * 5 + [True, True, False, False, False],
                    strict=True)]
    line = status_line(12.5, statuses, F.COMMAND_ERROR | 0x1F | 1 << 9, "XYZTUVRSWK")
    assert line == "t=12.5s X123kD Y-.1MD Z1.0MD T-2GD U2.1GD V0~ R-999~ S9999 W12k K-2k  err ovt Y"


@settings(max_examples=300, deadline=None)
@given(positions=st.lists(st.integers(-2**31, 2**31 - 1), min_size=10, max_size=10),
       done=st.lists(st.booleans(), min_size=10, max_size=10),
       moving=st.lists(st.booleans(), min_size=10, max_size=10),
       doorbell=st.integers(0, 2**27 - 1), seconds=st.floats(0, 1e6))
def test_the_status_line_always_fits_and_always_shows_every_axis(positions, done, moving,
                                                                 doorbell, seconds):
    from maxk.controllers.maxk.console import status_line

    statuses = [AxisStatus(letter, *values) for letter, values in zip(
        "XYZTUVRSWK", [(p, p, 0, d, m, 0, "") for p, d, m in zip(positions, done, moving,
                                                                  strict=True)], strict=True)]
    line = status_line(seconds, statuses, doorbell, "XYZTUVRSWK")
    assert len(line) <= 80 and A000_TOKENS.match(line), line


# ---- history ------------------------------------------------------------------------
def test_no_history_file_when_home_is_missing_or_unwritable(tmp_path, monkeypatch):
    from prompt_toolkit.history import FileHistory, InMemoryHistory

    from maxk.repl import _history

    monkeypatch.setenv("HOME", str(tmp_path / "missing"))
    monkeypatch.delenv("MAXK_HISTORY", raising=False)
    assert isinstance(_history(None), InMemoryHistory)
    assert isinstance(_history(tmp_path / "missing" / "h"), InMemoryHistory)
    assert isinstance(_history(tmp_path / "h"), FileHistory)
    monkeypatch.setenv("HOME", str(tmp_path))
    assert isinstance(_history(None), FileHistory)


def test_the_terminal_repl_runs_without_a_home_directory(tmp_path):
    """On a real terminal (a pty) with $HOME missing: replies, and no prompt_toolkit
    exception after Enter."""
    import os
    import pty
    import select
    import time

    master, slave = pty.openpty()
    env = dict(os.environ, HOME=str(tmp_path / "missing"), TERM="xterm")
    env.pop("MAXK_HISTORY", None)
    proc = subprocess.Popen([sys.executable, "-m", "maxk", "repl", "--manual-time",
                             "--no-archive"], stdin=slave, stdout=slave, stderr=slave,
                            env=env, cwd=ROOT)
    os.close(slave)
    out = b""

    def read_until(marker, seconds=30):
        nonlocal out
        end = time.monotonic() + seconds
        while marker not in out and time.monotonic() < end:
            if select.select([master], [], [], 0.2)[0]:
                try:
                    out += os.read(master, 65536)
                except OSError:
                    return
    try:
        read_until(b"AX>")
        os.write(master, b"WY\r")
        read_until(b"FPGA:20")
        os.write(master, b"AX RP\r")
        read_until(b"AX RP")
        os.write(master, b"quit\r")
        assert proc.wait(timeout=30) == 0
        read_until(b"\x00", 1)  # whatever is left
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        os.close(master)
    text = out.decode(errors="replace")
    assert "MAXk-8000, ver:1.33" in text
    assert "Exception" not in text and "No such file" not in text, text


def test_a_fault_inside_the_emulator_does_not_end_the_repl(monkeypatch):
    """Whatever a line makes the emulator raise, the REPL reports it and goes on."""
    s = ReplSession(manual_time=True)

    def broken(line):
        raise ZeroDivisionError("boom")

    monkeypatch.setattr(s.console, "execute", broken)
    assert s.handle("AX RP") == [
        "! internal error: ZeroDivisionError: boom (the line was lost; please report it)"]
    monkeypatch.undo()
    assert s.handle("AX RP") == ["0"]


def test_every_repl_word_of_every_model_answers_bad_input_plainly(tmp_path, monkeypatch):
    """A person's typo in a `:` word gets a plain answer, never an internal error: each
    model's REPL words with operands that are not numbers, negative, huge, a NUL, or a
    file in a folder that does not exist."""
    monkeypatch.chdir(tmp_path)  # words that write files write them here
    bad = ["x", "-3", "nan", "1 2 3", "\x00", "99999999999999999999", "-1 s",
           str(tmp_path / "missing" / "out.csv")]
    for model in ("MAXk-8000", "MM4005", "MC405", "PoKeys57CNC"):
        session = ReplSession(model, manual_time=True)
        lines = session.handle("help") + list(getattr(session.console, "repl_help",
                                                          lambda: [])())
        words = {line.split()[0][1:] for line in (x.strip() for x in lines)
                 if line.startswith(":") and len(line) > 1}
        words -= {"quit", "exit", "reset"}
        assert words, model
        for tracing in (False, True):  # then again with a trace running (":trace")
            if tracing:
                session.handle(":trace")
            for word in sorted(words):
                for operand in bad:
                    out = session.handle(f":{word} {operand}")
                    assert not any("internal error" in line for line in out), (
                        model, word, operand, out)
        session.handle(":trace off")  # (a PoKeys trace file left open is closed)

"""The REPL's behaviour without a terminal: lines in, lines out, clock injected."""

import subprocess
import sys

from maxk.firmware_model import flags as F
from maxk.repl import MnemonicCompleter, ReplSession


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
    assert s.maxk.tick == 8192


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
    assert s.maxk.board.firmware_flags == (F.FIRMWARE_RUNNING | F.ARCHIVE_CHECKSUM_ERROR
                                           | F.FACTORY_DEFAULTS_LOADED)
    out = s.handle("RDP")
    assert len(out) == 1 and out[0].startswith("! command error")
    assert s.handle("WY") == ["MAXk-8000, ver:1.33, S/N: 000001, FPGA:20"]

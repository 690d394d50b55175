"""The maxk command as a user runs it (in-process main(), and once as a real process)."""

import subprocess
import sys
from pathlib import Path

from maxk import __version__
from maxk.cli import main

ROOT = Path(__file__).parent.parent


def test_version(capsys):
    try:
        main(["--version"])
    except SystemExit as exit_:
        assert exit_.code == 0
    assert capsys.readouterr().out.strip() == f"maxk {__version__}"


def test_run_prints_replies(tmp_path, capsys):
    script = tmp_path / "move.maxk"
    script.write_text("AX; VL5000; AC50000; MA10000; GO; ID;\n@wait until X done\nAX RP\nWY\n")
    assert main(["run", str(script)]) == 0
    assert capsys.readouterr().out == "10000\nMAXk-8000, ver:1.33, S/N: 000001, FPGA:20\n"


def test_run_model_override_and_verbose(tmp_path, capsys):
    script = tmp_path / "m.maxk"
    script.write_text("AA RP\n")
    assert main(["run", "-v", "--model", "MAXk-3000", str(script)]) == 0
    assert capsys.readouterr().out == "[       0] > AA RP\n0,0,0\n"


def test_run_failure_exit_code_and_diff(tmp_path, capsys):
    script = tmp_path / "f.maxk"
    script.write_text("AX RP\n< 5\n")
    assert main(["run", str(script)]) == 1
    err = capsys.readouterr().err
    assert "f.maxk:line 2" in err and "expected: 5" in err and "actual:   0" in err


def test_run_malformed_script_is_a_clear_error(tmp_path, capsys):
    script = tmp_path / "bad.maxk"
    script.write_text("@wait whenever\n")
    assert main(["run", str(script)]) == 2
    err = capsys.readouterr().err
    assert "bad.maxk:1: not a duration" in err
    assert "Traceback" not in err


def test_commands_listing_and_single_help(capsys):
    assert main(["commands", "VL"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("VL#  —  Peak (slew) velocity")
    assert main(["commands", "NOPE"]) == 1


def test_generated_reference_is_up_to_date(capsys):
    assert main(["commands", "--markdown"]) == 0
    generated = capsys.readouterr().out
    on_disk = (ROOT / "docs" / "commands.md").read_text()
    assert generated == on_disk, "run: maxk commands --markdown > docs/commands.md"


def test_console_script_runs_as_a_process(tmp_path):
    script = tmp_path / "s.maxk"
    script.write_text("AXMR10;GDID\n@wait until X done\nAXRP\n")
    result = subprocess.run([sys.executable, "-m", "maxk", "run", str(script)],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout == "10\n"


def test_record_then_run_passes(tmp_path, capsys):
    script = tmp_path / "rec.maxk"
    script.write_text("AY; MR-25; GO; ID;\n@wait until Y done\nAY RP\n< 0\nQI\n")
    assert main(["run", str(script)]) == 1
    assert main(["run", "--record", str(script)]) == 0
    assert script.read_text() == ("AY; MR-25; GO; ID;\n@wait until Y done\nAY RP\n< -25\nQI\n"
                                  "< PNNN,MDNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN\n")
    assert main(["run", str(script)]) == 0


def test_trace_csv_per_event_and_per_period(tmp_path):
    import csv

    script = tmp_path / "t.maxk"
    script.write_text("@board MAXk-1000\nAX; VL1000; AC10000; MR500; GO; ID;\n"
                      "@wait until X done\n")
    trace = tmp_path / "t.csv"
    assert main(["run", "--trace", str(trace), str(script)]) == 0
    rows = list(csv.DictReader(trace.read_text().splitlines()))
    assert rows[0]["note"] == "start"
    assert [r["note"] for r in rows[1:]] == ["line 2", "event", "line 3"]
    assert rows[2]["X_position"] == "500" and rows[2]["X_done"] == "1"
    assert main(["run", "--trace", str(trace), "--trace-every", "0.1 s", str(script)]) == 0
    rows = list(csv.DictReader(trace.read_text().splitlines()))
    samples = [r for r in rows if r["note"] == "sample"]
    assert [r["tick"] for r in samples[:3]] == ["820", "1640", "2460"]
    positions = [int(r["X_position"]) for r in samples]
    assert positions == sorted(positions) == [50, 150, 250, 350, 450]
    assert rows[-1]["note"] == "line 3" and rows[-1]["X_position"] == "500"


def test_run_malformed_wait_timeout_is_a_script_error(tmp_path, capsys):
    for timeout in ("abc", "-1 s"):
        script = tmp_path / "bad.maxk"
        script.write_text(f"AX RP\n@wait until X done within {timeout}\n")
        assert main(["run", str(script)]) == 2
        captured = capsys.readouterr()
        assert f"bad.maxk:2: not a duration: {timeout!r}" in captured.err
        assert "Traceback" not in captured.err and captured.out == ""


def test_the_repl_options_work_without_the_word_repl(monkeypatch, capsys):
    """The README's `python3 -m maxk --manual-time`: no command means the REPL."""
    import io

    monkeypatch.setattr(sys, "stdin", io.StringIO("AX; MR10; GO; ID;\n:run\nAX RP\nWY\nquit\n"))
    assert main(["--manual-time", "--model", "MAXk-4000", "--no-archive"]) == 0
    assert capsys.readouterr().out.splitlines() == [
        "idle at tick 37", "10", "MAXk-4000, ver:1.33, S/N: 000001, FPGA:20"]


def test_python_m_maxk_manual_time_as_a_process():
    result = subprocess.run([sys.executable, "-m", "maxk", "--manual-time", "--no-archive"],
                            input="WY\n:time\nquit\n", capture_output=True, text=True,
                            timeout=60, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "MAXk-8000, ver:1.33, S/N: 000001, FPGA:20"
    assert lines[1].startswith("tick 0, 0.000000 s virtual (manual")


def test_run_traces_and_plots_another_controller(tmp_path):
    """`maxk run --trace/--plot` on an MM4005 script: the path samples, the pulse trace
    beside them (11 pulses, the manual's example), and the path with the pulses marked."""
    import csv

    import pytest

    from maxk.cli import main

    trace = tmp_path / "path.csv"
    script = Path(__file__).parent.parent / "examples" / "mm4005_trajectory_pulses.maxk"
    assert main(["run", str(script), "--trace", str(trace)]) == 0
    pulses = list(csv.DictReader((tmp_path / "path.pulses.csv").read_text().splitlines()))
    assert len(pulses) == 11
    assert (pulses[0]["x_counts"], pulses[0]["y_counts"]) == ("10000", "0")
    assert trace.read_text().startswith("tick,x_counts,y_counts\n")
    pytest.importorskip("matplotlib")
    plot = tmp_path / "path.png"
    assert main(["run", str(script), "--plot", str(plot)]) == 0
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

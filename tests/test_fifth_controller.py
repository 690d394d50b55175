"""A fifth controller (tests/tinystep.py, written from the architecture doc alone) gets
every door by one registry line: served, scripted, run by the pytest plugin, traced and
plotted, in the REPL. Nothing in a door names it."""

import re
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest
import tinystep

from maxk.cli import main
from maxk.controllers.registry import build, register, unregister
from maxk.repl import ReplSession
from maxk.script import ScriptError, parse_script, run_script

HERE = Path(__file__).parent

SCRIPT = """\
@board TinyStep
@world 1 plus-limit 700
1VL1000
< OK
1MA1000
< OK
@wait until 1 position >= 300
@expect 1 moving
@expect 1 velocity 1000
@wait until 1 done within 5 s
1TP
< 1TP700
1MS
< 1MSL
@expect 1 overtravel
2MR-50
< OK
@wait until 2 done
@expect 2 position -50
VE
< TinyStep 1.0
"""


@pytest.fixture
def tiny():
    register(tinystep.KIND)
    yield
    unregister("TinyStep")


def test_scripted_with_the_shared_directives(tiny):
    transcript = run_script(parse_script(SCRIPT))
    assert transcript.failures == []
    # 1 ms ticks: the limit at 700 is met on the slewing stretch (a 0.1 s ramp of 50
    # steps, then 1000 steps/s): 0.1 + 0.65 s in, on tick 750
    engine = transcript.board.engine
    assert engine.tick > 750 and build("TinyStep").engine.period == 0.001


def test_refused_where_it_does_not_fit(tiny):
    with pytest.raises(ScriptError, match="the TinyStep runs at 1000 Hz, not 8192"):
        parse_script("@board TinyStep\n@rate 8192\n")
    with pytest.raises(ScriptError, match="no axis 'X'"):
        parse_script("@board TinyStep\n@expect X position 0\n")


def test_run_by_maxk_run_with_a_trace_and_a_plot(tiny, tmp_path, capsys):
    script = tmp_path / "tiny.maxk"
    script.write_text(SCRIPT)
    trace = tmp_path / "tiny.csv"
    assert main(["run", str(script), "--trace", str(trace)]) == 0
    header, *rows = trace.read_text().splitlines()
    assert header == ("tick,time_s,1_position,1_encoder,1_velocity,1_done,2_position,"
                      "2_encoder,2_velocity,2_done,note")
    assert rows[-1].split(",")[2] == "700" and rows[-1].split(",")[6] == "-50"
    pytest.importorskip("matplotlib")
    plot = tmp_path / "tiny.png"
    assert main(["run", str(script), "--plot", str(plot), "--plot-axes", "1,2"]) == 0
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_repl_speaks_to_it(tiny):
    repl = ReplSession("TinyStep", manual_time=True)
    assert repl.handle("1MR25") == ["OK"]
    assert repl.handle(":world 2 minus-limit -10") == ["2 minus-limit -10"]
    assert repl.handle(":run") == ["idle at tick 100"]  # a triangle: 25 steps in 0.1 s
    assert repl.handle("1TP") == ["1TP25"]
    assert repl.handle("help MA") == ["MA: move to an absolute position (steps)",
                                      "  source: tests/tinystep.py (invented) (D)"]
    assert repl.status_lines()[1].split() == ["1", "25", "-", "0", "done"]


def test_served_behind_a_real_socket():
    code = (f"import sys; sys.path.insert(0, {str(HERE)!r}); import tinystep; "
            "from maxk.controllers.registry import register; register(tinystep.KIND); "
            "from maxk.cli import main; sys.exit(main(sys.argv[1:]))")
    proc = subprocess.Popen([sys.executable, "-c", code, "serve", "--model", "TinyStep",
                             "--port", "0", "--no-archive", "--speed", "10"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        m = re.match(r"board 1: TinyStep tcp 127\.0\.0\.1:(\d+)$", line.strip())
        assert m, line
        with socket.create_connection(("127.0.0.1", int(m[1])), timeout=10) as sock:
            sock.sendall(b"VE\n1MR10\r\nBAD\r")
            data = b""
            while data.count(b"\r\n") < 3:
                data += sock.recv(100)
        assert data == b"TinyStep 1.0\r\nOK\r\nE?\r\n"
    finally:
        proc.send_signal(signal.SIGTERM)
        _out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err


def test_run_by_the_pytest_plugin(pytester: pytest.Pytester):
    pytester.makeconftest(
        f"import sys\nsys.path.insert(0, {str(HERE)!r})\nimport tinystep\n"
        "from maxk.controllers.registry import register\nregister(tinystep.KIND)\n")
    pytester.makefile(".maxk", tiny=SCRIPT, wrong=SCRIPT.replace("< 1TP700", "< 1TP701"))
    result = pytester.runpytest_subprocess("-v")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(["*tiny.maxk::script PASSED*",
                                 "*wrong.maxk on TinyStep at 1000 Hz: 1 failure(s)*",
                                 "*expected: 1TP701*", "*actual:   1TP700*"])

"""The MC405 controller: the Console contract, the Python API in virtual time, program
storage across restarts, the process scheduler's timing, traces, and properties of the
motion (merged moves end exactly, gates toggle on the exact tick, traces equal readings).
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.controllers.contract import BuildOptions, Console, Controller
from maxk.controllers.registry import build, canonical_model, kind_of
from maxk.controllers.trio.controller import MC405, program_directory
from tests.trio_helpers import EXAMPLE_1


# ---- contract and registry -------------------------------------------------------------------
def test_registry_builds_an_mc405_that_meets_the_contract(tmp_path) -> None:
    assert canonical_model("mc405") == "MC405" and kind_of("MC405").name == "MC405"
    trio = build("MC405", BuildOptions(archive=str(tmp_path / "MC405-board1.params.json")))
    controller: Controller = trio
    assert (controller.kind, controller.model, tuple(controller.transports),
            controller.packet_size) == ("MC405", "MC405", ("tcp",), None)
    assert controller.engine.period == 0.001
    console: Console = controller.console()
    assert console.execute("?1+1") == ["2"]
    console.execute('SELECT "P",0')
    assert (tmp_path / "MC405-board1.programs" / "directory.json").exists()
    assert program_directory(None) is None
    assert program_directory(tmp_path / "progs") == tmp_path / "progs"


def test_console_lines_errors_help_words_status() -> None:
    trio = MC405()
    console = trio.console()
    assert console.prompt() == ">>"
    assert console.execute("?1/3") == ["0.3333"]
    assert console.execute("FOO") == [] and console.new_errors() == ["! Syntax error"]
    assert console.new_errors() == []
    assert console.execute("PWM_CYCLE AXIS(9)=100") == []
    assert console.new_errors() == ["! Axis 9 has no PWM output"]
    assert trio.send("?1+") == ["! Syntax error"]  # the API shows both
    assert console.execute("a=5: ?a*2; : ?a") == ["10.00005.0000"]  # a is FLOAT
    assert console.execute("") == []
    assert "PWM_CONTROL" in console.words() and "CAMBOX" in console.words()
    helped = console.help("pwm_control")
    assert helped is not None and helped[0].startswith("PWM_CONTROL (command)")
    assert console.help("NOSUCH") is None
    assert any("axis parameter" in line for line in console.help("") or [])
    assert console.repl_word("nosuch", "") is None
    assert len(console.repl_word("pwm", "") or []) == 5
    assert console.summary("MERGE").startswith("Merge consecutive moves")
    assert console.summary("NOSUCH") == ""
    assert any(":trace" in line for line in console.repl_help())
    assert console.after_reset()[0].startswith("reset: MC405 powered up")
    assert console.is_idle()
    console.execute("BASE(0,1): SPEED=100: MOVE(10000,-20000)")
    assert not console.is_idle()
    trio.advance(1.0)
    assert len(console.status_line(30)) <= 30
    line = console.status_line()
    assert len(line) <= 80 and line.startswith("MC405 1.000s 0:") and "1:-" in line
    assert any(s.startswith("axis 0: DPOS") and "MOVING" in s for s in console.status_lines())
    console.execute("RAPIDSTOP")
    assert trio.run_until_idle(5)
    assert console.is_idle()


def test_status_line_fits_80_columns_with_everything_busy() -> None:
    trio = MC405()
    for axis in range(5):
        trio.send(f"BASE({axis}): ATYPE=35: PWM_MARK=12345: PWM_CONTROL(1)")
        trio.send(f"BASE({axis}): SPEED=1234.5678: MOVE(-123456.789)")
    trio.advance(0.5)
    assert len(trio.console().status_line()) <= 80


def test_a_typed_wait_runs_virtual_time_in_the_console() -> None:
    trio = MC405()
    assert trio.send("WA(250): ?2") == ["2"]
    assert trio.tick == 250
    trio.send("BASE(0): SPEED=1000: ACC(10000): MOVE(100)")
    assert trio.send("WAIT IDLE: ?DPOS") == ["100"]
    assert trio.tick == 250 + 200  # 0.1 s ramps at 10000 reach 1000 in 50 units


def test_a_console_wait_that_never_ends_is_abandoned() -> None:
    trio = MC405()
    trio.send("TABLE(10,0,5): CAMBOX(10,11,1,100,0) AXIS(1)")  # axis 0 never moves
    assert trio.send("BASE(0,1): MOVE(5,5)") == ["! still waiting after 600 s: abandoned"]
    assert trio.time == pytest.approx(600.0)
    assert trio.query("?IDLE AXIS(0)") == "-1"  # nothing half-done: the move never loaded


def test_query_refuses_anything_but_one_line() -> None:
    trio = MC405()
    with pytest.raises(ValueError):
        trio.query("FOO")
    with pytest.raises(ValueError):
        trio.query("a=1")


# ---- program storage ------------------------------------------------------------------------
def test_programs_survive_a_restart_of_the_emulator(tmp_path) -> None:
    first = MC405(archive=tmp_path)
    assert first.load("EX1", EXAMPLE_1) == []
    first.send('SELECT "AUTO",0')
    first.send("!AUTO,0RVR(3)=33")
    first.send('RUNTYPE"AUTO",1,4')
    checksum = first.query("?CHECKSUM")
    second = MC405(archive=tmp_path)  # a new process on the same directory
    assert second.query("?CHECKSUM") == checksum
    assert second.send('LIST "EX1"') == EXAMPLE_1.splitlines()
    second.advance(ticks=1)
    assert second.query("?VR(3)") == "33.0000"  # the autorun program ran at power-up
    assert MC405().query('?IS_PROG "EX1"') == "0"  # memory only: nothing stored


def test_reset_stops_programs_and_motion_and_starts_autorun() -> None:
    trio = MC405()
    trio.load("EX1", EXAMPLE_1)
    trio.send('RUN "EX1"')
    trio.advance(0.5)
    assert trio.query("?VP_SPEED AXIS(0)") == "5000"
    trio.send("SERVO_PERIOD=500")
    trio.reset()
    assert trio.send("PROCESS") == [] and trio.query("?VP_SPEED AXIS(0)") == "0"
    assert trio.query("?DPOS AXIS(0)") == "0" and trio.query("?SERVO_PERIOD") == "500"
    assert trio.machine.period == 0.0005 and trio.time == pytest.approx(0.5)


# ---- the scheduler: exact servo cycles --------------------------------------------------------
def test_a_loop_pass_takes_one_servo_cycle_and_wa_wakes_on_its_tick() -> None:
    trio = MC405()
    trio.load("LOOP", "WHILE TRUE\nVR(1)=VR(1)+1\nWEND")
    trio.load("NAP", "WA(5)\nVR(2)=1\nWA(7)\nVR(2)=2")
    trio.send('RUN "LOOP"')
    trio.send('RUN "NAP"')
    trio.advance(ticks=5)
    assert trio.query("?VR(1)") == "5.0000" and trio.query("?VR(2)") == "0.0000"
    trio.advance(ticks=1)
    assert trio.query("?VR(2)") == "1.0000"  # first cycle tick 1, WA(5) until tick 6
    trio.advance(ticks=6)
    assert trio.query("?VR(2)") == "1.0000"
    trio.advance(ticks=1)
    assert trio.query("?VR(2)") == "2.0000" and trio.query("?VR(1)") == "13.0000"


def test_wait_idle_ends_on_the_tick_the_move_ends_and_after_a_cancel() -> None:
    trio = MC405()
    trio.load("W", "BASE(2)\nSPEED=100\nACC(1000)\nMOVE(50)\nWAIT IDLE\nVR(5)=DPOS\n"
              "MOVE(1000)\nWAIT IDLE\nVR(6)=1")
    trio.send('RUN "W"')
    # MOVE(50) from tick 1: 0.1 s ramps to 100 cover 5 each, then 40 at 100: 0.6 s in all
    trio.advance(ticks=600)
    assert trio.query("?VR(5)") == "0.0000"
    trio.advance(ticks=1)
    assert trio.query("?VR(5)") == "50.0000"  # WAIT IDLE ended on tick 601
    trio.advance(ticks=100)  # MOVE(1000) from tick 601 is at 100 units/s by now
    trio.send("CANCEL AXIS(2)")  # ramps down at DECEL: 0.1 s, at rest on tick 801
    trio.advance(ticks=99)
    assert trio.query("?VR(6)") == "0.0000"
    trio.advance(ticks=1)
    assert trio.query("?VR(6)") == "1.0000"
    assert trio.query("?IDLE AXIS(2)") == "-1"


def test_a_full_move_buffer_holds_the_program_until_a_move_ends() -> None:
    trio = MC405()
    moves = "\n".join(["MOVE(10)"] * 20)
    trio.load("BUF", f"BASE(3)\nSPEED=1000\nACC(1000000)\n{moves}\nVR(9)=1")
    trio.send('RUN "BUF"')
    trio.advance(ticks=1)
    assert trio.query("?VR(9)") == "0.0000"  # 16 moves buffered (MERGE OFF: one after another)
    assert trio.run_until_idle(5)
    assert trio.query("?VR(9)") == "1.0000" and trio.query("?DPOS AXIS(3)") == "200"


def test_a_merged_path_frees_a_buffer_slot_on_the_tick_a_move_finishes() -> None:
    trio = MC405()
    moves = "\n".join(["MOVE(10)"] * 20)
    trio.load("MRG", f"BASE(3)\nSPEED=1000\nACC(1000000)\nMERGE=ON\n{moves}\nVR(9)=1")
    trio.send('RUN "MRG"')
    # 16 moves load on tick 1; the path reaches 1000/s in 1 ms (0.5 units), so move k
    # finishes at 10k units, 10k + 0.5 ms after tick 1: the 20th loads on tick 42
    trio.advance(ticks=41)
    assert trio.query("?VR(9)") == "0.0000"
    trio.advance(ticks=1)
    assert trio.query("?VR(9)") == "1.0000"
    assert trio.run_until_idle(5) and trio.query("?DPOS AXIS(3)") == "200"


# ---- traces ----------------------------------------------------------------------------------
def test_trace_csv_and_plot_of_example_1(tmp_path) -> None:
    trio = MC405()
    trio.load("EX1", EXAMPLE_1)
    trio.send('RUN "EX1"')
    trace = trio.trace()
    trio.advance(8.2)
    path = trace.write_csv(tmp_path / "pwm.csv")
    rows = list(csv.DictReader(path.read_text().splitlines()))
    assert len(rows) == 8201 and list(rows[0]) == ["tick", "time", "x", "y", "mark4", "gate4",
                                                   "duty4"]
    row = rows[4000]
    assert (row["tick"], row["time"], row["mark4"], row["duty4"]) == ("4000", "4.000000",
                                                                       "500", "0.500000")
    # 250 on the ramp, then 5000/s from 0.1 s: 19745 along the square at 4.0 s
    assert float(row["x"]) == 10000 and float(row["y"]) == pytest.approx(-9745)
    pytest.importorskip("matplotlib")
    image = trace.plot(tmp_path / "pwm.png")
    assert image.stat().st_size > 10_000


# ---- properties ---------------------------------------------------------------------------------
moves = st.lists(st.tuples(st.integers(-5000, 5000), st.integers(-5000, 5000)), min_size=1,
                 max_size=6)


@settings(max_examples=25, deadline=None)
@given(moves, st.integers(100, 20000), st.integers(1000, 500000), st.booleans())
def test_moves_end_exactly_and_never_exceed_speed(deltas, speed, accel, merge) -> None:
    trio = MC405()
    trio.send(f"BASE(0,1): SPEED={speed}: ACC({accel}): MERGE={'ON' if merge else 'OFF'}")
    for dx, dy in deltas:
        trio.send(f"MOVE({dx},{dy})")
    trace = trio.trace(pwm_axes=(0,), xy=(0, 1))
    ticks = []
    while not trio.console().is_idle():
        trio.advance(ticks=97)
        ticks.append(float(trio.query("?VP_SPEED")))
        assert trio.tick < 10**6
    assert max(ticks) <= speed + 1e-6
    assert trio.query("?DPOS AXIS(0)") == str(sum(d[0] for d in deltas))
    assert trio.query("?DPOS AXIS(1)") == str(sum(d[1] for d in deltas))
    x = trace.column("x")
    steps = np.abs(np.diff(x))
    assert steps.max() <= speed * 0.001 + 1e-6  # no jumps: the path is continuous


@settings(max_examples=25, deadline=None)
@given(st.lists(st.integers(1, 299), min_size=1, max_size=8, unique=True),
       st.integers(50, 2000), st.integers(200, 20000))
def test_gates_toggle_on_the_exact_tick_the_encoder_passes(positions, speed, accel) -> None:
    positions = sorted(positions)
    trio = MC405()
    trio.send(f"BASE(1): ATYPE=35: UNITS=4: SPEED={speed}: ACC({accel}): PWM_CONTROL(5)")
    trio.send(f"TABLE(100,{','.join(map(str, positions))})")
    trio.send(f"PWM_CONTROL(3,1,ON,100,{99 + len(positions)}): MOVEABS(300)")
    encoder = [0]
    while len(encoder) < 400000 and not trio.console().is_idle():
        trio.advance(ticks=1)
        encoder.append(int(trio.query("?PWM_ENCODER AXIS(1)")))
    edges = [(e.tick, e.position) for e in trio.machine.gate_edges]
    assert [p for _t, p in edges] == [p * 4 for p in positions]
    for tick, position in edges:
        assert encoder[tick - 1] <= position < encoder[tick]


def test_trace_equals_readings_every_cycle_through_events() -> None:
    trio = MC405()
    trio.send("BASE(0,1): SPEED=3000: ACC(20000): MERGE=ON: MOVE(3000,0): MOVE(0,2000)")
    trio.send("BASE(4): ATYPE=35: WDOG=ON: PWM_CONTROL(2,0.2,10,700,0)")
    trace = trio.trace()
    readings = []
    for _ in range(3000):
        trio.advance(ticks=1)
        readings.append((trio.machine.mark(4), trio.machine.dpos(0), trio.machine.dpos(1)))
        if trio.tick == 700:
            trio.send("BASE(0,1): MOVE(-1000,-1000)")  # merged in mid-path: a re-plan
    marks, x, y = trace.column("mark4"), trace.column("x"), trace.column("y")
    assert [(int(m), float(a), float(b)) for m, a, b in zip(marks[1:], x[1:], y[1:],
                                                            strict=True)] == readings
    assert max(m for m, _a, _b in readings) == 610 and readings[-1][0] == 10
    assert math.isclose(readings[-1][1], 2000) and math.isclose(readings[-1][2], 1000)


# ---- the REPL and command scripts (written against the console) ---------------------------------
def test_the_repl_drives_an_mc405() -> None:
    from maxk.repl import ReplSession

    repl = ReplSession("MC405", manual_time=True)
    assert repl.handle("?1+1") == ["2"]
    assert repl.handle("FOO") == ["! Syntax error"]
    assert repl.prompt() == ">>"
    repl.handle("BASE(0,1): SPEED=1000: ACC(10000): MOVE(500,500)")
    assert repl.handle(":trace")[0].startswith("tracing every servo cycle")
    assert repl.handle(":run 5 s")[0].startswith("idle at tick")
    assert repl.handle("?DPOS AXIS(1)") == ["500"]
    assert any(line.startswith("PWM4:") for line in repl.handle(":pwm"))
    assert repl.handle(":reset")[0].startswith("reset: MC405")
    assert len(repl.toolbar(60)) <= 60


def test_the_example_script_passes_and_a_wrong_reply_fails(tmp_path) -> None:
    from pathlib import Path

    from maxk.script import load_script, parse_script, run_script

    example = Path(__file__).parent.parent / "examples" / "mc405_pwm_speed_link.maxk"
    transcript = run_script(load_script(example))
    assert transcript.failures == []
    failed = run_script(parse_script("@board MC405\n?2*2\n< 5\n"))
    assert [(f.expected, f.actual) for f in failed.failures] == [("5", "4")]
    fast = build("MC405", BuildOptions(update_rate_hz=2000))
    assert fast.engine.period == 0.0005 and fast.console().execute("?SERVO_PERIOD") == ["500"]
    with pytest.raises(ValueError):
        MC405(update_rate_hz=3000)
    with pytest.raises(ValueError, match="the MC405 runs at 500, 1000, 2000, 4000 Hz"):
        build("MC405", BuildOptions(update_rate_hz=8192))  # a MAXk's rate is refused


# ---- robustness: any mix of motion commands and time ---------------------------------------------
_AXES = st.integers(0, 9)
_NUM = st.sampled_from(["0", "1", "-1", "10", "2.5", "-300", "1000", "1e6", "0.001"])
_COMMANDS = st.one_of(
    st.builds("BASE({},{}): MOVE({},{})".format, _AXES, _AXES, _NUM, _NUM),
    st.builds("MOVEABS({}) AXIS({})".format, _NUM, _AXES),
    st.builds("MERGE AXIS({})={}".format, _AXES, st.sampled_from(["ON", "OFF"])),
    st.builds("SPEED AXIS({})={}".format, _AXES, _NUM),
    st.builds("ACC({}) AXIS({})".format, _NUM, _AXES),
    st.builds("UNITS AXIS({})={}".format, _AXES, _NUM),
    st.builds("CANCEL AXIS({})".format, _AXES),
    st.just("RAPIDSTOP"),
    st.builds("CONNPATH({}) AXIS({})".format, _AXES, _AXES),
    st.builds("CAMBOX(10,14,{},{},{}) AXIS({})".format, _NUM, _NUM, _AXES, _AXES),
    st.builds("DEFPOS({}) AXIS({})".format, _NUM, _AXES),
    st.builds("PWM_CONTROL({}) AXIS({})".format, st.sampled_from(
        ["0", "1", "4", "5", "6", "2,0.1,50,500,0", "8,0.001,5,900,0,9", "3,1,ON,10,14",
         "3,0,OFF,10,12"]), st.integers(0, 4)),
    st.builds("?DPOS AXIS({}), VP_SPEED AXIS({}), PWM_MARK AXIS({})".format, _AXES, _AXES,
              st.integers(0, 4)),
)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(_COMMANDS, st.integers(0, 300)), max_size=12))
def test_any_mix_of_commands_and_time_never_breaks_the_machine(steps) -> None:
    trio = MC405()
    trio.send("TABLE(10,0,5,-3,8,1): BASE(4): ATYPE=35: WDOG=ON")
    trace = trio.trace(pwm_axes=(0, 4), xy=(0, 1))
    for command, ticks in steps:
        for line in trio.send(command):  # output or a TrioBASIC error, never an exception
            assert isinstance(line, str)
        trio.advance(ticks=ticks)
    trio.send("RAPIDSTOP")
    trio.advance(2.0)
    assert len(trace) == trio.tick + 1
    for axis in range(10):
        assert math.isfinite(float(trio.query(f"?DPOS AXIS({axis})")))


def test_a_loop_of_cambox_links_is_refused_and_time_goes_on() -> None:
    """Axis 7 follows 9, so 9 may not follow 7 (nor 7 itself through a chain): each
    position would depend on itself (hypothesis found the recursion). Refused whole (D)."""
    from tests.test_review_doors import Fed, trio_output

    fed = Fed("MC405")
    assert trio_output(fed("CAMBOX(10,14,0,2.5,9) AXIS(7)")) == b""
    assert trio_output(fed("CAMBOX(10,14,10,2.5,7) AXIS(9)")) == (
        b"%[COMMAND LINE] - Parameter out of range\r\n")
    assert trio_output(fed("CAMBOX(10,14,0,2.5,7) AXIS(8)")) == b""  # 8 -> 7 -> 9: no loop
    assert trio_output(fed("CAMBOX(10,14,0,2.5,8) AXIS(9)")) == (
        b"%[COMMAND LINE] - Parameter out of range\r\n")
    fed.advance(1000)
    assert trio_output(fed("?DPOS AXIS(9)")) == b"0\r\n"

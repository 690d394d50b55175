"""The MM4005 on the shared engine: real profiles, the world's switches, the trajectory on
the path planner and its synchronized pulses, exact to the tick (0.5 ms servo cycle)."""

from __future__ import annotations

import math

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from maxk.controllers.mm4005.controller import MM4005Controller, axis_count_of
from maxk.controllers.registry import build
from maxk.personalities.mm4005.machine import UPDATE_RATE_HZ

PERIOD = 1.0 / UPDATE_RATE_HZ
SEED_PATH = "NT;LX10;CR10,CA90;LY20;CX10,CY30"
SEED_PULSES = "NB2,NE3,NI10.1,NN11"


def _mm(model: str = "MM4005-2") -> MM4005Controller:
    return MM4005Controller(model)


def _ticks(seconds: float) -> int:
    return math.ceil(seconds / PERIOD - 1e-9)


def _run_seed(mm: MM4005Controller) -> int:
    """The seed's example as written; returns the tick ET ran on."""
    assert mm.send(SEED_PATH) == []
    assert mm.send(SEED_PULSES) == []
    assert mm.send("NS;ET") == []
    assert mm.query("TE") == "TE@"
    return mm.tick


# ---- the seed's example -----------------------------------------------------------------
def test_seed_example_pulses_count_and_ends() -> None:
    mm = _mm()
    _run_seed(mm)
    assert mm.query("AT") == "AT1"
    assert mm.run_until_idle()
    pulses = mm.pulses
    assert len(pulses) == 11  # NN
    first, last = pulses[0], pulses[-1]
    assert (first.x_counts, first.y_counts) == (10_000, 0)  # start of element 2 (10, 0)
    assert first.element == 2 and last.element == 3
    assert abs(last.x_counts - 20_000) <= 1 and abs(last.y_counts - 20_000) <= 1  # end of 3
    assert mm.query("TP") == "1TP10.0000,2TP30.0000"  # the end of element 4
    assert mm.query("AT") == "AT0"


def test_seed_example_pulses_equally_spaced_within_one_count() -> None:
    """Each pulse's X/Y (whole counts, read on its tick) is within one count of the point
    at k x CPTL / 10 along elements 2 and 3, computed here from the geometry."""
    mm = _mm()
    _run_seed(mm)
    mm.run_until_idle()
    cptl = 5 * math.pi + 10.0
    for k, pulse in enumerate(mm.pulses):
        s = k * cptl / 10
        if s <= 5 * math.pi:  # the quarter arc, centre (10, 10), from (10, 0)
            angle = -math.pi / 2 + s / 10.0
            ideal = (10 + 10 * math.cos(angle), 10 + 10 * math.sin(angle))
        else:  # the line up X = 20
            ideal = (20.0, 10.0 + s - 5 * math.pi)
        assert abs(pulse.x_counts - ideal[0] * 1000) <= 1, (k, pulse)
        assert abs(pulse.y_counts - ideal[1] * 1000) <= 1, (k, pulse)


def test_seed_example_pulse_ticks_are_exact() -> None:
    """VV 1, VS 10 (the defaults): the path ramps for 0.1 s (0.05 units), then cruises at
    1 unit/s, so distance d is reached at t = 0.1 + (d - 0.05) s; each pulse fires on
    the first 0.5 ms tick at or after its distance."""
    mm = _mm()
    start = _run_seed(mm)
    mm.run_until_idle()
    cptl = 5 * math.pi + 10.0
    expected = [start + _ticks(0.1 + (10.0 + k * cptl / 10 - 0.05)) for k in range(11)]
    assert [p.tick for p in mm.pulses] == expected
    run = mm.machine.execution
    assert run is not None
    for pulse in mm.pulses:  # and the plan agrees: reached on the tick, not the one before
        assert run.plan.state((pulse.tick - start) * PERIOD)[0] >= pulse.distance - 1e-9
        assert run.plan.state((pulse.tick - 1 - start) * PERIOD)[0] < pulse.distance


def test_seed_example_mpn_substitution_runs_with_the_mpn() -> None:
    mm = _mm()
    mm.send(SEED_PATH)
    mm.send("NB2,NE3,NN2;NS;ET")
    assert mm.query("TE") == "TEP"
    mpn = int(mm.query("NI?")[2:])
    assert mpn == math.floor((5 * math.pi + 10) / 0.002)  # 2 x TU beats VV x 0.5 ms
    assert mm.run_until_idle()
    pulses = mm.pulses
    assert len(pulses) == mpn
    ticks = [p.tick for p in pulses]
    assert ticks == sorted(ticks) and len(set(ticks)) == mpn  # at most one per cycle


def test_stopping_a_trajectory_ramps_down_on_the_path_and_ends_the_pulses() -> None:
    mm = _mm()
    _run_seed(mm)
    mm.advance(15.0)  # inside element 2, pulses under way
    fired = len(mm.pulses)
    assert 0 < fired < 11
    assert mm.query("AT") == "AT2"
    mm.send("ST")
    assert mm.query("MS") == "1MSE,2MSE"
    mm.advance(0.1)  # 1 unit/s at VS 10: 0.1 s to rest
    assert mm.query("MS")[3] in "D@" and mm.machine.is_idle()
    assert mm.query("AT") == "AT0"
    assert len(mm.pulses) == fired  # no pulse after the stop point
    run = mm.machine.execution
    assert run is not None
    x, y = mm.machine.position(1), mm.machine.position(2)
    centre_distance = math.hypot(x - 10, y - 10)
    assert abs(centre_distance - 10) <= 0.002  # it stopped on the arc


def test_trajectory_refused_while_an_axis_moves() -> None:
    mm = _mm()
    mm.send("1PA5")
    mm.send(SEED_PATH)
    mm.send("ET")
    assert mm.query("TE") == "TED"
    assert mm.query("AT") == "AT0"


def test_trajectory_with_different_resolutions_keeps_arcs_round() -> None:
    """X counts 0.5 um, Y 1 um: each axis follows its coordinate in its own counts."""
    mm = _mm()
    mm.machine.axis(1).resolution = 0.0005
    mm.send("NT;CR5,CA180")
    mm.send("ET")
    mm.advance(3.0)
    x, y = mm.machine.position(1), mm.machine.position(2)
    assert abs(math.hypot(x, y - 5) - 5) <= 0.0015
    assert mm.run_until_idle()
    assert mm.query("TP") == "1TP0.00000,2TP10.0000"


# ---- PA / PR / ST / OR with real motion ---------------------------------------------------
def test_pa_is_a_trapezoid_at_va_and_ac() -> None:
    mm = _mm()
    mm.send("1AC5.00000;1VA1.00000;1PA2.50000;")
    assert mm.query("MS") == "1MSE,2MSD"
    mm.advance(1.0)  # 0.2 s ramp (0.1 units) then 0.8 s at 1 unit/s
    assert mm.query("1TP") == "1TP0.9000"
    assert mm.query("1TH") == "1TH0.9000"
    assert mm.query("1DP") == "1DP2.5000"
    end = _ticks(0.2 + 2.3 + 0.2)
    mm.advance(ticks=end - mm.tick - 1)
    assert mm.query("MS") == "1MSE,2MSD"
    mm.advance(ticks=1)
    assert mm.query("MS") == "1MSD,2MSD"
    assert mm.query("TP") == "1TP2.5000,2TP0.0000"


def test_pr_adds_to_the_destination_and_sets_the_direction_bit() -> None:
    mm = _mm()
    mm.send("2PR-0.5;2PR-0.25")
    assert mm.run_until_idle()
    assert mm.query("2TP") == "2TP-0.7500"
    assert mm.query("MS") == "1MSD,2MS@"  # last motion negative


def test_st_decelerates_at_ac() -> None:
    mm = _mm()
    mm.send("1VA1;1AC5;1PA100")
    mm.advance(1.0)
    mm.send("1ST")
    assert mm.query("1DP") == "1DP1.0000"  # 0.9 + 1^2 / (2 x 5)
    mm.advance(ticks=_ticks(0.2) - 1)
    assert mm.query("1MS") == "1MSE"
    mm.advance(ticks=1)
    assert mm.query("1MS") == "1MSD"
    assert mm.query("1TP") == "1TP1.0000"


def test_pa_while_moving_stops_then_goes() -> None:
    mm = _mm()
    mm.send("1VA1;1AC5;1PA100")
    mm.advance(1.0)
    mm.send("1PA-1")
    assert mm.query("1DP") == "1DP-1.0000"
    assert mm.run_until_idle()
    assert mm.query("1TP") == "1TP-1.0000"


def test_or_finds_the_world_home_switch_and_reads_the_preset() -> None:
    mm = _mm()
    mm.stage(1).set_home(3000, 3100)
    mm.send("1SH5;1VA2;1AC10;1OR")
    assert mm.query("1MS") == "1MSE"
    assert mm.run_until_idle()
    assert mm.machine.axis(1).steps == 3000  # on the switch's first count, physically
    assert mm.query("1TP") == "1TP5.0000"
    assert mm.query("1MS") == "1MS`"  # 0x60: bit 6 + home signal, last motion negative
    # from inside the window the search runs down out of it and comes back
    mm.send("1PA5.05")
    mm.run_until_idle()
    mm.send("1OR")
    assert mm.query("1MS") == "1MSa"  # 0x61: moving, negative, on the switch
    assert mm.run_until_idle()
    assert mm.machine.axis(1).steps == 3000
    assert mm.query("1TP") == "1TP5.0000"


def test_hardware_limit_stops_the_axis_and_refuses_moves_into_it() -> None:
    mm = _mm()
    mm.stage(2).set_plus_limit(2000)
    mm.send("2VA1;2AC5;2PA50")
    assert mm.run_until_idle()
    steps = mm.machine.axis(2).steps
    assert 2000 <= steps <= 2000 + 100  # braked at AC from 1 unit/s: 0.1 unit
    assert mm.query("2MS") == "2MSL"  # 0x4C: bit 6, + limit, direction +
    mm.send("2PA60")
    assert mm.query("TE") == "TED"
    mm.send("2PA0")
    assert mm.run_until_idle()
    assert mm.query("2TP") == "2TP0.0000"


def test_mf_stops_at_once_and_sets_the_power_off_bit() -> None:
    mm = _mm()
    mm.send("1VA1;1AC5;1PA10")
    mm.advance(1.0)
    mm.send("1MF")
    assert mm.query("1MS") == "1MSF"  # 0x46: power off, direction +, not moving
    assert mm.query("1TP") == "1TP0.9000"
    mm.send("1PA2")
    assert mm.query("TE") == "TED"
    mm.send("1MO")
    assert mm.query("1MS") == "1MSD"


def test_reset_stops_everything_and_counters_read_zero() -> None:
    mm = _mm()
    mm.send("1PA3;2PA-2")
    mm.advance(1.0)
    mm.send(SEED_PATH)
    mm.reset()
    assert mm.query("TP") == "1TP0.0000,2TP0.0000"
    assert mm.query("XT") == "XT0"
    assert mm.machine.is_idle()
    assert mm.machine.axis(1).steps > 0  # the stage stayed where it was


@settings(max_examples=40, deadline=None)
@given(target=st.integers(-99_000, 99_000).filter(lambda n: n != 0),
       speed=st.sampled_from([0.1, 0.5, 1.0, 2.5, 10.0]),
       accel=st.sampled_from([0.5, 2.0, 5.0, 50.0]))
@example(target=1234, speed=0.1, accel=0.5)  # ends on the home switch's first count
def test_moves_end_exactly_on_their_target(target: int, speed: float, accel: float) -> None:
    """Any PA lands on its count on the tick the profile's end rounds up to, and MS
    shows it moving until then."""
    mm = _mm()
    mm.send(f"1VA{speed};1AC{accel};1PA{target / 1000:.3f}")
    motion = mm.machine.axis(1).motion
    assert motion is not None and motion.end_time is not None
    end = _ticks(motion.end_time)
    direction = 0x04 if target > 0 else 0
    mm.advance(ticks=end - 1)
    home = 0x20 if 1234 <= mm.machine.axis(1).steps_now(mm.machine) <= 1333 else 0
    assert mm.query("1MS") == "1MS" + chr(0x41 | direction | home)  # the home window too
    mm.advance(ticks=1)
    home = 0x20 if 1234 <= target <= 1333 else 0
    assert mm.query("1MS") == "1MS" + chr(0x40 | direction | home)
    assert mm.machine.axis(1).counts(mm.machine) == target


# ---- the controller contract and the console ---------------------------------------------
def test_models_and_registry() -> None:
    assert [axis_count_of(m) for m in ("MM4005", "mm4005-1", "MM4005-3")] == [4, 1, 3]
    controller = build("mm4005-2")
    assert (controller.kind, controller.model) == ("MM4005", "MM4005-2")
    assert controller.transports == ("tcp", "pty") and controller.packet_size is None
    with pytest.raises(ValueError):
        axis_count_of("MM4005-5")


def test_console() -> None:
    mm = MM4005Controller()
    console = mm.console()
    assert console.execute("1PA99.9999;2PA-99.9999;3PA99.9999;4PA-99.9999") == []
    mm.advance(0.5)
    line = console.status_line()
    assert len(line) <= 80 and line.startswith("0.500s 1:") and "*" in line
    assert console.new_errors() == []
    assert console.execute("1PA500") == []
    assert console.new_errors() == ["! C Parameter out of limits"]
    assert console.new_errors() == []
    assert console.execute("TE") == ["TEC"]  # the console saw it without clearing it
    session = mm.open_session()  # a host's error shows too
    session.feed(b"ZZ\r")  # not a command of the manual's list
    assert console.new_errors() == ["! A Unknown message code"]
    assert console.help("ms")[0].startswith("MS: ")
    assert console.help("ZZ") is None
    assert "NN" in console.words() and console.summary("nn").startswith("number of pulses")
    assert any(":pulses" in line for line in console.repl_help())
    assert len(console.status_line(40)) <= 40
    assert not console.is_idle()
    assert console.repl_word("status", "") is None
    lines = console.status_lines()  # the contract's axis table, then the MM4005's own
    assert lines[1] == "axis  position   encoder  velocity  state"
    assert lines[2].split() == ["1", "375", "375", "1000", "moving"]
    assert len(lines) == 1 + 5 + 4 + 7  # + XY, time-based, pulses, servo, I/O, errors, programs
    assert "I/O: outputs SB0, inputs RB0; global trace GQ0 SQ1, 0 taken" in lines
    mm.run_until_idle()
    assert console.is_idle()
    mm.reset()
    assert console.after_reset()[0].startswith("reset: 4 axes")


def test_pulse_log_csv_and_repl_word(tmp_path) -> None:  # type: ignore[no-untyped-def]
    mm = _mm()
    _run_seed(mm)
    mm.run_until_idle()
    lines = mm.console().repl_word(":pulses", "")
    assert lines is not None and len(lines) == 12
    assert lines[0] == "pulse,tick,time_s,distance,element,x_counts,y_counts,x,y"
    assert lines[1].split(",")[4:7] == ["2", "10000", "0"]
    target = tmp_path / "pulses.csv"
    assert mm.console().repl_word("pulses-csv", str(target)) == [
        f"11 pulses written to {target}; later pulses are appended as they fire "
        "(:pulses-csv off stops)"]
    assert target.read_text().splitlines() == lines


def test_path_trace_samples_the_trajectory_and_the_pulses_lie_on_it() -> None:
    mm = _mm()
    trace = mm.trace_path(every_ticks=2)  # every 1 ms: under a count apart at VV 1
    _run_seed(mm)
    mm.run_until_idle()
    trace.detach()
    samples = trace.samples
    assert samples[0][1:] == (0, 0) and samples[-1][1:] == (10_000, 30_000)
    by_tick = {t: (x, y) for t, x, y in samples}
    for pulse in mm.pulses:  # a pulse's position is the path's at its tick
        near = by_tick.get(pulse.tick) or by_tick.get(pulse.tick + 1)
        assert near is not None
        assert abs(near[0] - pulse.x_counts) <= 1 and abs(near[1] - pulse.y_counts) <= 1
    assert trace.csv().splitlines()[0] == "tick,x_counts,y_counts"


def test_or_without_a_usable_home_switch_runs_until_a_limit() -> None:
    mm = _mm()
    mm.stage(1).set_home(None, None)
    mm.stage(1).set_plus_limit(500)
    mm.send("1VA1;1AC5;1OR")
    assert mm.run_until_idle()
    assert 500 <= mm.machine.axis(1).steps <= 600  # braked at AC past the switch
    assert mm.query("1MS") == "1MSL"  # on the + limit, nothing homed
    assert mm.query("1TP") == f"1TP{mm.machine.axis(1).steps / 1000:.4f}"


def test_et_while_a_trajectory_runs_is_refused_and_changes_nothing() -> None:
    mm = _mm()
    _run_seed(mm)
    mm.send("3AX;4AY")  # two idle axes (MM4005-2 has none: refused as B)
    assert mm.query("TE") == "TEB"
    mm.send(SEED_PULSES + ";NS;ET")
    assert mm.query("TE") == "TED"
    assert mm.machine.trajectory.pulses.armed  # NS still waits for the next ET
    assert mm.run_until_idle() and len(mm.pulses) == 11

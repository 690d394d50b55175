"""The MM4005's outputs (SB), analog inputs (RA) and global trace mode (GQ, SQ read back
with NQ and TQ, manual 3.137), and the I/O, trace, display and special-motion commands
whose pages were found nowhere (Q). Expected values are worked out here from the
manual's numbers and the move's own arithmetic, not read from the code."""

from __future__ import annotations

import io

import pytest

from maxk.commands.mm4005 import COMMANDS
from maxk.controllers.mm4005.controller import MM4005Controller
from maxk.trace import TraceWriter

PERIOD = 0.0005  # manual 7.1.1: the servo cycle, one tick


def _mm(model: str = "MM4005-2") -> MM4005Controller:
    return MM4005Controller(model)


def _error(mm: MM4005Controller, line: str) -> str:
    assert mm.send(line) == [], line
    return mm.query("TE")


# ---- SB: the outputs on the shared world -----------------------------------------------
def test_sb_drives_the_worlds_outputs_and_reads_them_back() -> None:
    mm = _mm()
    view = mm.world_view()
    assert mm.send("SB?") == ["SB0"]  # all low at power-up
    assert mm.send("SB5;SB?") == ["SB5"]
    # bit 1 is the least significant (as RB's byte): 5 = bits 1 and 3
    assert [view.output_level(bit) for bit in range(1, 9)] == [
        True, False, True, False, False, False, False, False]
    assert view.output_level(0) is None and view.output_level(9) is None
    assert mm.machine.world.outputs[3] is True  # the world holds the level itself
    assert view.describe()[-1] == ("outputs 1 high 2 low 3 high 4 low 5 low 6 low 7 low "
                                   "8 low")
    assert mm.send("SB128;SB?") == ["SB128"]
    assert view.output_level(8) and not view.output_level(1)
    assert mm.send("SB255;SB?") == ["SB255"]
    mm.reset()  # power-up: every output low again
    assert mm.send("SB?") == ["SB0"] and not view.output_level(8)


@pytest.mark.parametrize(("line", "code"), [
    ("SB256", "C"), ("SB-1", "C"), ("SB1.5", "C"), ("SB", "C"), ("1SB5", "B"),
])
def test_sb_refuses_what_is_no_port_byte_and_changes_nothing(line: str, code: str) -> None:
    mm = _mm()
    mm.send("SB6")
    assert _error(mm, line) == f"TE{code}"
    assert mm.send("SB?") == ["SB6"]


def test_outputs_show_in_the_trace_and_the_control_doors_view() -> None:
    from maxk.host.control import _outputs

    mm = _mm()
    view = mm.world_view()
    stream = io.StringIO()
    writer = TraceWriter(stream, mm)
    writer.attach()
    mm.send("SB9")
    writer.sample("after SB9")
    writer.detach()
    header, first, second = stream.getvalue().splitlines()
    column = header.split(",").index("outputs")
    assert first.split(",")[column] == "0" and second.split(",")[column] == "9"
    assert _outputs(view) == {str(b): b in (1, 4) for b in range(1, 9)}


# ---- RA: analog inputs 1..4 ----------------------------------------------------------------
def test_ra_reads_the_worlds_analog_inputs_in_volts() -> None:
    mm = _mm()
    view = mm.world_view()
    view.set_analog(2, 1.25)
    view.set_analog(4, -7.5)
    assert mm.send("2RA;4RA;1RA") == ["2RA1.2500", "4RA-7.5000", "1RA0.0000"]
    assert mm.send("RA") == ["1RA0.0000,2RA1.2500,3RA0.0000,4RA-7.5000"]
    assert _error(mm, "5RA") == "TEE"  # no analog input 5 (E, as RB's bit 9)
    with pytest.raises(ValueError):
        view.set_analog(5, 1.0)
    with pytest.raises(ValueError):
        view.set_analog(1, 10.5)  # beyond the +/-10 V the world allows


# ---- GQ / SQ: the global trace mode ------------------------------------------------------------
def _profile(t: float, velocity: float = 1.0, accel: float = 5.0) -> float:
    """A trapezoid from rest: where the profile is at t seconds (before deceleration)."""
    ramp = velocity / accel
    if t <= ramp:
        return 0.5 * accel * t * t
    return 0.5 * accel * ramp * ramp + velocity * (t - ramp)


def test_gq_samples_every_sq_cycles_from_its_own_tick_exactly() -> None:
    mm = _mm()
    mm.send("1VA1;1AC5")
    mm.machine.advance(37)  # start off tick 0
    start = mm.machine.tick
    assert mm.send("SQ130;1PA2;GQ6") == []
    assert mm.send("NQ") == ["NQ1"]  # the first sample on GQ's own tick
    mm.machine.advance(129)
    assert mm.send("NQ") == ["NQ1"]
    mm.machine.advance(1)
    assert mm.send("NQ") == ["NQ2"]  # 130 cycles later, on that very tick
    mm.machine.advance(5 * 130)
    assert mm.send("NQ;GQ?;SQ?") == ["NQ6", "GQ6", "SQ130"]  # then it stops
    points = mm.trace_points
    assert [p.tick for p in points] == [start + 130 * k for k in range(6)]
    for k in range(1, 7):
        t = (k - 1) * 130 * PERIOD
        th = _profile(t)
        counts = int(th / 0.001 + 1e-9)  # the encoder's whole counts (TU 0.001)
        assert mm.send(f"{k}TQ") == [f"{k}TQ,1TH{th:.4f},1TP{counts * 0.001:.4f},"
                                     "2TH0.0000,2TP0.0000"], k
    assert _error(mm, "7TQ") == "TEC"


def test_the_trace_follows_a_servo_axis_too() -> None:
    mm = _mm()
    mm.send("1KP0.1;1KI0.1;1KD0.16;1UF;1VA1;1AC5;SQ100;1PA0.5;GQ3")
    mm.run_until_idle()
    points = mm.trace_points
    assert len(points) == 3
    assert [round(p.theoretical[0], 6) for p in points] == [
        round(_profile(k * 100 * PERIOD), 6) for k in range(3)]
    assert points[0].actual[0] == 0.0 and 0.0 < points[2].actual[0] < 0.2


def test_gq0_ends_early_and_sq_waits_for_the_end() -> None:
    mm = _mm()
    mm.send("SQ10;GQ100")
    mm.machine.advance(25)
    assert _error(mm, "SQ5") == "TED"  # not while acquiring
    assert mm.send("GQ0;NQ;SQ?") == ["NQ3", "SQ10"]  # samples at 0, 10, 20 kept
    mm.machine.advance(100)
    assert mm.send("NQ;GQ?") == ["NQ3", "GQ100"]
    assert mm.send("SQ5;SQ?") == ["SQ5"]


@pytest.mark.parametrize(("line", "code"), [
    ("GQ20001", "C"), ("GQ-1", "C"), ("GQ", "C"), ("1GQ5", "B"), ("SQ0", "C"),
    ("SQ10001", "C"), ("SQ2.5", "C"), ("2SQ5", "B"),
])
def test_gq_and_sq_refuse_out_of_range(line: str, code: str) -> None:
    mm = _mm()
    assert _error(mm, line) == f"TE{code}"
    assert mm.send("GQ?;SQ?;NQ") == ["GQ0", "SQ1", "NQ0"]


def test_a_new_gq_starts_the_buffer_afresh_and_power_up_clears_it() -> None:
    mm = _mm()
    mm.send("SQ2;GQ5")
    mm.machine.advance(20)
    mm.send("1PA0.1;GQ2")
    mm.machine.advance(20)
    assert mm.send("NQ") == ["NQ2"]
    mm.reset()
    assert mm.send("NQ;GQ?;SQ?") == ["NQ0", "GQ0", "SQ1"]
    mm.machine.advance(100)
    assert mm.send("NQ") == ["NQ0"]


def test_a_trajectory_run_takes_the_buffer_over() -> None:
    mm = _mm()
    mm.send("SQ1000;GQ10")
    mm.machine.advance(1500)  # two samples, at 0 and 1000 cycles
    assert mm.send("NQ") == ["NQ2"]
    mm.send("NC;1DC1;UC0.1;1DT0.5;1DX0.25;MB1;ME1;MN2;VC")
    assert mm.send("TE") == ["TE@"]
    mm.send("0EC1")
    mm.run_until_idle()
    assert not mm.machine.global_trace.acquiring
    assert mm.send("NQ") == ["NQ1"]  # the run's own pulse, not the acquisition's samples


# ---- TM / SP / TT / XN: the trace mode (manual 3.140 TT) ------------------------------------
def test_the_tt_pages_example_sp_tm_pr_then_tt() -> None:
    """The page's own sequence, our numbers: SP0.002, 2TM500, a 0.1 move on axis 2."""
    mm = _mm()
    mm.send("2VA1;2AC10")
    assert mm.send("SP0.002;SP?") == ["SP0.002"]
    start = mm.machine.tick
    assert mm.send("2TM500;2PR0.1;XN;2TM?;1TM?") == ["XN1", "2TM500", "1TM0"]
    mm.run_until_idle()  # the move takes 0.2 s: 100 samples of the 500
    assert mm.send("XN") == ["XN101"]
    mm.machine.advance(2 * 4 * 500)
    assert mm.send("XN") == ["XN500"]
    # sample n at t = (n - 1) * 2 ms: 0.5*10*t^2 up to 0.1 s, then decelerating to 0.1
    for n, th in ((1, 0.0), (9, 0.5 * 10 * 0.016 ** 2), (26, 0.5 * 10 * 0.05 ** 2),
                  (76, 0.1 - 0.5 * 10 * 0.05 ** 2), (500, 0.1)):
        counts = int(th / 0.001 + 1e-9)
        assert mm.send(f"{n}TT") == [f"{n}TT,TH{th:.4f},TP{counts * 0.001:.4f}"], n
    assert mm.machine.axis_trace.samples[8][0] == start + 8 * 4  # on its own tick
    every = mm.send("TT")
    assert len(every) == 500 and every[0] == "1TT,TH0.0000,TP0.0000"
    assert mm.send("0TT") == every
    assert _error(mm, "501TT") == "TEC"


def test_tt_waits_for_its_samples_and_tm_refuses_what_it_should() -> None:
    mm = _mm()
    mm.send("SP0.01;1TM10")
    assert mm.send("2TT") == [] and mm.send("TE") == ["TED"]  # not taken yet
    mm.machine.advance(20)
    assert mm.send("2TT;XN") == ["2TT,TH0.0000,TP0.0000", "XN2"]
    assert _error(mm, "SP0.002") == "TED"  # not while acquiring
    assert mm.send("1TM0;XN") == ["XN2"]  # ended early: the samples at 0 and 10 ms kept
    mm.machine.advance(100)
    assert mm.send("XN") == ["XN2"]
    for line, code in (("TM5", "B"), ("5TM5", "B"), ("1TM20001", "C"), ("1TM", "C"),
                       ("SP0.0001", "C"), ("SP6", "C"), ("1SP0.1", "B")):
        assert _error(mm, line) == f"TE{code}", line
    mm.reset()
    assert mm.send("XN;SP?;1TM?") == ["XN0", "SP0.0005", "1TM0"]


# ---- the commands found nowhere ----------------------------------------------------------
MINE_Q = ["AM", "CB", "FT", "RO", "SO", "TG", "YO", "YP", "YR",  # inputs and outputs
          "AQ", "XQ", "XS",  # trace mode
          "DS", "DY", "FB", "FC", "FD", "NP", "RD", "RE",  # display
          "DM", "DO", "MH", "PB", "PE", "PI", "PS", "SE", "OA", "VB", "SC", "SF", "PW",
          "WI", "WN"]  # special motion parameters, trajectory execution


def test_the_pages_found_nowhere_answer_q_and_say_so() -> None:
    mm = _mm()
    for word in MINE_Q:
        spec = COMMANDS[word]
        assert "searched for" in spec.note and spec.note.endswith("answers Q"), word
        assert "page not found" in spec.summary, word
        assert _error(mm, f"1{word}") == "TEQ", word
    for word in ("SB", "RA", "GQ", "SQ", "TM", "SP", "XN", "TT"):
        assert COMMANDS[word].confidence == ("C" if word == "TT" else "I"), word
        assert "answers Q" not in COMMANDS[word].note, word


def test_help_shows_the_source_of_the_new_entries() -> None:
    console = mm_console = _mm().console()
    lines = console.help("SB")
    assert lines is not None and lines[0].startswith("SB: set the GPIO output bits")
    assert "ESP300" in lines[1] and lines[1].endswith("(I)")
    gq = mm_console.help("gq")
    assert gq is not None and "3.137 TQ" in gq[1]


# ---- through the doors: a host on TCP, the control door's view -------------------------------
def test_outputs_and_analog_through_tcp_and_the_control_door(maxk_served) -> None:
    import socket

    served = maxk_served("MM4005-2")
    host, port = served.doors[0].tcp
    served.client.world(1, "analog 2 1.5")
    with socket.create_connection((host, port), timeout=10) as sock:
        def ask(line: bytes, replies: int) -> bytes:
            sock.sendall(line)
            data = b""
            while data.count(b"\r") < replies:
                chunk = sock.recv(4096)
                assert chunk, "closed"
                data += chunk
            return data

        assert ask(b"SB129;SB?;2RA\r", 2) == b"SB129\r2RA1.5000\r"
    outputs = served.client.board(1)["outputs"]
    assert outputs == {str(b): b in (1, 8) for b in range(1, 9)}
    assert ("outputs 1 high 2 low 3 low 4 low 5 low 6 low 7 low 8 high"
            in served.client.board(1)["world"])

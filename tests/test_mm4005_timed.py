"""The time-based trajectory as the EPICS MM4005 trajectory scan drives it, the framing
forms of every host style, the other host mnemonics, the pulse ring and the overflow sweep."""

from __future__ import annotations

import math

import pytest

from maxk.commands.mm4005.session import MM4005Session
from maxk.controllers.mm4005.controller import MM4005Controller

TICK = 0.0005


def define(mm: MM4005Controller, points: list[tuple[float, float]], dt: float,
           pulses: int) -> None:
    """What the scan's Build sends, CR CR framed, several lines a segment."""
    s = mm.open_session()
    out = [b"NC\r\r", b"1DC1\r\r2DC1\r\rUC0.500000\r\r"]
    for i in range(1, len(points)):
        dx = points[i][0] - points[i - 1][0]
        dy = points[i][1] - points[i - 1][1]
        out.append(f"{i}DT{dt:f}\r\r1DX{dx:f}\r\r2DX{dy:f}\r\r".encode())
    n = len(points) - 1
    out.append(f"MB1,ME{n},MN{pulses + 1}\r\r".encode())
    out.append(b"VC\r\r")
    for chunk in out:
        s.feed(chunk)
    assert s.read() == b""
    s.feed(b"TB\r\r")
    assert s.read() == b"TB@ No error\r"


def test_build_execute_readback_exact() -> None:
    mm = MM4005Controller("MM4005-2")
    points = [(0.1 * i, math.sin(i / 10)) for i in range(101)]
    define(mm, points, 0.05, 100)
    s = mm.open_session()
    s.feed(b"1RC3\r\r")
    v_max = max(abs(points[i + 1][0] - points[i][0]) / 0.05 for i in range(100))
    assert s.read().startswith(b"1RC")
    s.feed(b"1RC4\r\r")
    assert float(s.read()[3:]) == pytest.approx(v_max, abs=1e-6)
    s.feed(b"LS,0EC1.000000\r\r")
    s.feed(b"MS\r\r")
    assert s.read() == b"1MSE,2MSE\r"  # both moving (bit 0), bit 6, direction +
    mm.engine.advance(4000)  # 2 s: 40 elements
    s.feed(b"XC1\r\r")
    assert s.read() == b"XC40\r"
    mm.run_until_idle()
    assert mm.engine.tick == 10000  # 100 x 0.05 s
    s.feed(b"XC1\rMS\rNQ\r")
    assert s.read() == b"XC100\r1MSD,2MSD\rNQ100\r"
    for i in (1, 2, 50, 100):
        s.feed(f"{i}TQ\r\r".encode())
        reply = s.read().decode().rstrip("\r").split(",")
        assert reply[0] == f"{i}TQ"
        assert [r[:3] for r in reply[1:]] == ["1TH", "1TP", "2TH", "2TP"]
        x, y = points[i - 1]  # pulse i marks the start of element i
        assert float(reply[1][3:]) == pytest.approx(x, abs=1e-4)
        assert float(reply[3][3:]) == pytest.approx(y, abs=1e-4)
        assert abs(float(reply[2][3:]) - x) <= 0.001 + 1e-9
    s.feed(b"TP\r")
    end = s.read().decode().strip().split(",")
    assert float(end[0][3:]) == pytest.approx(10.0, abs=1e-3)
    assert float(end[1][3:]) == pytest.approx(math.sin(10), abs=1e-3)


def test_pulse_ticks_exact() -> None:
    mm = MM4005Controller("MM4005-2")
    define(mm, [(0, 0), (1, 0), (2, 0), (3, 0), (4, 0)], 0.3, 4)
    s = mm.open_session()
    start = mm.engine.tick
    s.feed(b"0EC1\r")
    mm.run_until_idle()
    ticks = [p.tick - start for p in mm.engine.trace_points]
    assert ticks == [0, 600, 1200, 1800]


def test_verify_errors_and_rc_even_on_failure() -> None:
    mm = MM4005Controller("MM4005-2")
    s = mm.open_session()
    s.feed(b"NC\rVC\rTB\r")
    assert s.read() == b"TBK Trajectory not defined\r"
    s.feed(b"NC\r1DC1\r1DT0.1\r1DX50\rVC\rTB\r1RC4\r")  # 500 units/s > VU 100
    assert s.read() == b"TBH Trajectory velocity too large\r1RC500.000000\r"
    s.feed(b"1VU1000\rVC\rTE\r1GC1\r2DT0.1\r1DX10\rVC\rTB\r1RC1\r")
    assert s.read() == b"TE@\rTBG Trajectory speed change too large\r1RC2\r"
    s.feed(b"EC1\rTB\r")
    assert s.read() == b"TBJ Trajectory not verified\r"
    s.feed(b"1GC0\rMB1,ME3,MN5\rVC\rTB\r")
    assert s.read() == b"TBN Pulse start or end element incorrect\r"


def test_abort_at_any_point() -> None:
    mm = MM4005Controller("MM4005-2")
    define(mm, [(0, 0), (1, 1), (2, 2), (3, 3), (4, 4)], 0.5, 4)
    s = mm.open_session()
    s.feed(b"0EC1\r")
    mm.engine.advance(1500)  # 0.75 s: pulses at 0 and 0.5 s have fired
    s.feed(b"AB\rMS\rTP\rNQ\r")
    assert s.read() == b"1MSD,2MSD\r1TP1.5000,2TP1.5000\rNQ2\r"
    mm.engine.advance(10000)
    s.feed(b"NQ\rTP\r")
    assert s.read() == b"NQ2\r1TP1.5000,2TP1.5000\r"


@pytest.mark.parametrize("end", [b"\r", b"\n", b"\r\n", b"\r\r"])
def test_line_endings(end: bytes) -> None:
    mm = MM4005Controller("MM4005-2")
    s = mm.open_session()
    s.feed(b"1tp" + end + b"Ve;" + end + b"1va2;1pa0.5 ; 1 TP" + end)
    assert s.read() == b"1TP0.0000\rVE MM4005 Version 2.42\r1TP0.0000\r"
    mm.run_until_idle()
    s.feed(b"1dp,2ms" + end)
    assert s.read() == b"1DP0.5000\r2MSD\r"


def test_every_host_mnemonic_is_known() -> None:
    mm = MM4005Controller("MM4005-2")
    s: MM4005Session = mm.open_session()
    for query in ("TS", "1TN", "1TA", "1DA", "1DF", "1DV", "1XB", "1XI", "1XP", "1XD", "1XF",
                  "1TF", "1KS?", "1OL?", "1OH?", "1VU?", "1SN?", "1SU?", "SD?", "1SY?", "TX",
                  "1GC?", "UC?", "MB?", "ME?", "MN?", "XC", "NQ"):
        s.feed(query.encode() + b"\r")
        assert s.read(), query
        s.feed(b"TE\r")
        assert s.read() == b"TE@\r", query
    for command in ("1KP0.1", "1KI0.1", "1KD0.5", "1UF", "1BA0.01", "1SY1", "1OL0.5", "1OH2",
                    "2SN2", "SD50", "1ZP", "LS", "AB"):
        s.feed(command.encode() + b"\r")
        s.feed(b"TE\r")
        assert s.read() == b"TE@\r", command
    s.feed(b"1XP;1XB\r")
    assert s.read() == b"1XP0.1\r1XB0.01\r"


@pytest.mark.parametrize("operand", ["1e308", "-1e308", "1e-320", "NaN", "inf",
                                     str(2**63), "9" * 250])
@pytest.mark.parametrize("command", ["1DT", "1DX", "UC", "1GC", "EC", "1KP", "1VU",
                                     "MB", "MN", "1DC", "1RC", "1PA", "1VA", "NN"])
def test_overflow_sweep(command: str, operand: str) -> None:
    """Every extreme operand is refused with the controller's own error or taken as the
    value it is, never a traceback; the state stays sane."""
    mm = MM4005Controller("MM4005-2")
    s = mm.open_session()
    s.feed(b"NC\r1DC1\r1DT0.1\r1DX0.1\r")
    s.feed(f"{command}{operand}\r".encode())
    s.feed(b"TB\r")
    reply = s.read()
    assert reply.startswith(b"TB") and reply.endswith(b"\r")
    if operand != "1e-320" or command in ("1DT", "UC", "1VU", "EC", "1VA"):
        assert reply != b"TB@ No error\r", (command, operand)
    s.feed(b"VC\rEC1\r")
    mm.run_until_idle()
    s.feed(b"1TP\r1RC4\r1RC6\r")
    replies = s.read().split(b"\r")
    assert replies[0].startswith(b"1TP")
    assert all(math.isfinite(float(r[3:])) for r in replies[:3]), replies


def test_pulse_ring_is_bounded_and_streams() -> None:
    mm = MM4005Controller("MM4005-2")
    mm.engine.pulse_trace.capacity = 10
    from collections import deque
    mm.engine.pulse_trace.records = deque(maxlen=10)
    seen: list[object] = []
    mm.engine.pulse_trace.sink = seen.append
    define(mm, [(0.01 * i, 0) for i in range(51)], 0.01, 50)
    s = mm.open_session()
    s.feed(b"0EC1\r")
    mm.run_until_idle()
    s.feed(b"NQ\r1TQ\r50TQ\rTB\r")
    out = s.read().split(b"\r")
    assert out[0] == b"NQ50" and out[1].startswith(b"50TQ,")
    assert out[2] == b"TBC Parameter out of limits"  # point 1 left the ring
    assert len(seen) == 50 and len(mm.engine.pulse_trace.records) == 10


def test_servo_follows_with_lag_and_factory_gains_stay_exact() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("1KP0.1;1KI0.1;1KD0.16;2VA1;2AC4;1VA1;1AC4;1PA1;2PA1") == []
    mm.engine.advance(1000)  # 0.5 s: axis 1 still profile-only (no UF yet)
    assert mm.send("1TP;1TH;1DF") == ["1TP0.3750", "1TH0.3750", "1DF0.0000"]
    mm.run_until_idle()
    assert mm.send("1UF;2UF;1PA0;2PA0") == []
    mm.engine.advance(1000)
    tp, th, df = mm.send("1TP;1TH;1DF")
    assert th == "1TH0.6250" and tp != "1TP0.6250"
    assert -0.05 < float(df[3:]) < -0.005  # moving down, the loop lags its profile
    assert mm.send("2TP;2TH") == ["2TP0.6250", "2TH0.6250"]  # KP 0 axis: exact


def test_following_error_turns_the_motor_off() -> None:
    mm = MM4005Controller("MM4005-2")
    mm.send("1KP0.1;1KI0.1;1KD0.16;1FE0.005;1UF;1PA1")
    mm.engine.advance(400)
    assert mm.send("1MS;TB") == ["1MSF", "TBT Following error"]  # off, direction +
    assert mm.send("1PA2") == [] and mm.send("TE") == ["TED"]  # refused: power off
    assert mm.send("1MO;1FE1;1UF;1PA0;TE") == ["TE@"]
    mm.run_until_idle()
    mm.engine.advance(4000)
    assert abs(float(mm.send("1TP")[0][3:])) < 0.01


def test_ec_refuses_a_run_outside_the_travel_limits_and_bad_forms() -> None:
    mm = MM4005Controller("MM4005-2")
    s = mm.open_session()
    s.feed(b"1SR5\rNC\r1DC1\r1DT1\r1DX3\r2DT1\r1DX3\rVC\rTB\r0EC1\rTB\r1MS\r")
    assert s.read() == b"TB@ No error\rTBR Trajectory outside travel limits\r1MSD\r"
    for line, code in ((b"0DT1", b"C"), (b"5DT1", b"L"), (b"1RC7", b"C"), (b"RC1", b"B"),
                       (b"9GC?", b"B"), (b"1EC1", b"R"), (b"2EC1", b"C"), (b"1TQ", b"C"),
                       (b"1DC2", b"C"),
                       (b"MN2002", b"P"), (b"1234567890TQ", b"B"), (b"1RC?", b"C"),
                       (b"1RC", b"C")):
        s.feed(line + b"\rTE\r")
        assert s.read() == b"TE" + code + b"\r", line
    s.feed(b"1SR100\rNC\r1DC1\r1DT1\r1DX90\rVC\r0EC0.5\rTB\r0EC1e-320\rTE\r")
    assert s.read() == b"TBH Trajectory velocity too large\rTEC\r"  # 180 > VU 100
    s.feed(b"NC\rDX1\rTE\r1DX1\rTE\r")  # DX without an axis, then before any DT
    assert s.read() == b"TEB\rTEK\r"


def test_two_hosts_one_runs_the_other_aborts() -> None:
    mm = MM4005Controller("MM4005-2")
    define(mm, [(0, 0), (1, 0), (2, 0), (3, 0), (4, 0)], 0.5, 4)
    a, b = mm.open_session(), mm.open_session()
    a.feed(b"0EC1\r")
    mm.engine.advance(1100)  # 0.55 s: element 1 done
    b.feed(b"1PA3\rTE\r0EC1\rTE\rNT;LX1;ET\rTE\r")  # busy axes: refused
    assert b.read() == b"TED\rTED\rTED\r"
    b.feed(b"AB\r")
    a.feed(b"MS\rXC\r")
    assert a.read() == b"1MSD,2MSD\rXC1\r"
    mm.engine.advance(10000)
    a.feed(b"XC\rNQ\r1TP\r")
    assert a.read() == b"XC1\rNQ2\r1TP1.1000\r"


def test_settings_reports_and_moves_of_the_other_host_mnemonics() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("TS;1TN;1TA;1SU?;1XP") == ["TS@", "1TNmm", "1TADC", "1SU0.001", "1XP0"]
    assert mm.send("1VU?;1XF;1KS?") == ["1VU100", "1XF1", "1KS1"]
    assert mm.send("VU?") == ["1VU100,2VU100"]  # without an axis: every axis
    assert mm.send("1KP-1") == [] and mm.send("TE") == ["TEC"]  # out of range: unchanged
    assert mm.send("1SN2.5") == [] and mm.send("TE") == ["TEC"]  # an integer setting
    assert mm.send("1SU0.01") == [] and mm.send("TE") == ["TEC"]  # TU is fixed
    assert mm.send("1XP;1SN?") == ["1XP0", "1SN2"]  # 2 = mm (sibling ESP300 codes)
    assert mm.send("1BA0.02;1XB;1DA;1VA2;1AC8;1MV1;TS") == ["1XB0.02", "1DA4", "TSA"]
    mm.engine.advance(1000)  # 0.5 s: at VA 2 after a 0.25 s ramp at AC 8
    assert mm.send("1DV;1DV1;1MS") == ["1DV2.0000", "1DV100.0000", "1MSE"]
    assert mm.send("1ST") == []
    mm.run_until_idle()
    assert mm.send("1MV-;TE") == ["TE@"]
    assert mm.send("1MV0") == [] and mm.send("TE") == ["TEC"]
    mm.send("1ST")
    mm.run_until_idle()
    assert mm.send("1ZP;1TP;1TL;1TR") == ["1TP0.0000", "1TL-100.0000", "1TR100.0000"]


def test_servo_axes_in_a_time_based_run_read_back_their_lag() -> None:
    mm = MM4005Controller("MM4005-2")
    mm.send("1KP0.1;1KI0.1;1KD0.16;1UF")
    define(mm, [(0.5 * i, 0.25 * i) for i in range(9)], 0.25, 8)
    mm.send("0EC1")
    mm.run_until_idle()
    points = mm.engine.trace_points
    assert len(points) == 8
    for k, p in enumerate(points):
        assert p.theoretical[0] == pytest.approx(0.5 * k, abs=1e-9)
        assert p.theoretical[1] == pytest.approx(0.25 * k, abs=1e-9)
        assert abs(p.actual[1] - 0.25 * k) <= 0.001 + 1e-9  # axis 2: profile-only
    lags = [p.theoretical[0] - p.actual[0] for p in points[1:]]
    assert all(0.001 < lag < 0.2 for lag in lags), lags  # axis 1 follows behind, moving up


@pytest.mark.parametrize("gains", ["0.2", "0.02", "1"])
def test_gains_in_the_manuals_range_give_a_loop_that_follows(gains: str) -> None:
    """The EPICS model 1 driver writes a motor record's PCOF/ICOF/DCOF (0..1) as
    `nKP%f;nUF;`: every value of the manual's range must give a loop that reaches the
    target, with no following-error trip on a 1 mm/s move."""
    mm = MM4005Controller("MM4005-2")
    assert mm.send(f"1KP{gains};1UF;1KI{gains};1UF;1KD{gains};1UF;1AC5;1VA1;1PA2.5") == []
    mm.engine.advance(2000 * 10)
    assert mm.send("1MS;TB") == ["1MSD", "TB@ No error"]
    assert abs(float(mm.send("1TP")[0][3:]) - 2.5) <= 0.01  # within ten counts


def test_a_gain_above_the_manuals_range_is_refused_whole() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("1KP1.5") == [] and mm.send("TE") == ["TEC"]
    assert mm.send("1UF;1XP") == ["1XP0"]

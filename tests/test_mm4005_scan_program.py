# ruff: noqa: UP031  -- the commands are built with the C program's own printf formats
"""The EPICS MM4005 trajectory scan (motorNewport MM4005_trajectoryScan.st) command by
command: a host written here sends each command exactly as the program formats it
(sprintf '%d' / '%f', its own CR plus the port's CR) and parses each reply with the
program's own rules, re-stated in Python (C atoi/atof from a fixed offset, strtok on ',',
a status byte's bit 0, byte 2 of a TB reply). One test per command and reply pair, in
the program's order: init (nGC?), the MDVS monitor (nGC%f), Build (NC, nDC, UC, iDT,
nDX, TB every 20th element, MB,ME,MN, VC, TB, nRC1..6), Execute (LS,sEC%f then TP, XC1,
MS, TB each pass), Readback (NQ, iTQ) and Abort (AB). The MM4000 drivers' and a
StreamDevice host's mnemonics are checked to be known at the end.
"""

from __future__ import annotations

import re

import pytest

from maxk.commands.mm4005 import COMMANDS
from maxk.controllers.mm4005.controller import MM4005Controller

TICK = 0.0005  # the servo cycle: engine ticks are 0.5 ms


def c_atof(text: str) -> float:
    """C atof: leading blanks, the longest number prefix, 0.0 when there is none."""
    match = re.match(r"\s*([+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?)", text)
    return float(match.group(1)) if match else 0.0


def c_atoi(text: str) -> int:
    """C atoi: leading blanks, sign and digits, 0 when there are none."""
    match = re.match(r"\s*([+-]?\d+)", text)
    return int(match.group(1)) if match else 0


def strtok(text: str, sep: str = ",") -> list[str]:
    """epicsStrtok_r: tokens between separators, empty ones skipped."""
    return [token for token in text.split(sep) if token]


class Scan:
    """The program's writeOnly/writeRead over one session, in virtual time."""

    def __init__(self, model: str = "MM4005-2") -> None:
        self.mm = MM4005Controller(model)
        self.session = self.mm.open_session()
        self.num_axes = self.mm.machine.axis_count

    def write_only(self, command: str) -> None:
        self.session.feed(command.encode() + b"\r\r")  # its CR, then the port's
        assert self.session.read() == b"", command  # a write-only command is not answered

    def write_read(self, command: str) -> str:
        self.session.feed(command.encode() + b"\r\r")
        reply = self.session.read()
        assert reply.endswith(b"\r") and reply.count(b"\r") == 1, (command, reply)
        return reply[:-1].decode()

    def advance(self, seconds: float) -> None:
        self.mm.engine.advance(round(seconds / TICK))

    # the program's helpers
    def motor_positions(self) -> list[float]:
        tokens = strtok(self.write_read("TP"))
        return [c_atof(tokens[j][3:]) for j in range(min(self.num_axes, len(tokens)))]

    def motor_moving(self) -> int:
        result = 0
        for j, token in enumerate(strtok(self.write_read("MS"))[:self.num_axes]):
            if ord(token[3]) & 0x01:
                result |= 1 << j
        return result

    def build(self, steps: list[list[float]], times: list[float], accel: float = 0.5,
              pulses: tuple[int, int, int] | None = None) -> str:
        """Relative mode: steps[axis][i] is axis's displacement in element i."""
        self.write_only("NC")
        moving = [1 if j < len(steps) else 0 for j in range(self.num_axes)]
        for i in range(self.num_axes):
            self.write_only("%dDC%d" % (i + 1, moving[i]))
        self.write_only("UC%f" % accel)
        for i, dt in enumerate(times):
            self.write_only("%dDT%f" % (i + 1, dt))
            for j, axis_steps in enumerate(steps):
                self.write_only("%dDX%f" % (j + 1, axis_steps[i]))
            if (i + 1) % 20 == 0:
                self.write_read("TB")
        if pulses is not None:
            self.write_only("MB%d,ME%d,MN%d" % pulses)
        self.write_only("VC")
        return self.write_read("TB")


def velocities(steps: list[float], times: list[float]) -> list[float]:
    return [d / t for d, t in zip(steps, times, strict=True)]


# ---------------------------------------------------------------- init and MDVS monitor
def test_1_gc_query_parses_from_offset_3_for_every_axis() -> None:
    scan = Scan("MM4005-4")
    replies = [scan.write_read("%dGC?" % (j + 1)) for j in range(scan.num_axes)]
    assert replies == ["1GC0", "2GC0", "3GC0", "4GC0"]
    assert [c_atof(r[3:]) for r in replies] == [0.0] * 4


def test_2_gc_write_is_silent_and_read_back_by_the_init_parse() -> None:
    scan = Scan()
    for j, value in enumerate((0.25, 1.5)):
        scan.write_only("%dGC%f" % (j + 1, value))  # '1GC0.250000'
    assert [c_atof(scan.write_read("%dGC?" % (j + 1))[3:]) for j in range(2)] == [0.25, 1.5]


# ---------------------------------------------------------------- build
def test_3_to_7_nc_dc_uc_dt_dx_are_silent_and_tb_after_every_20th_element_reads_clean() -> None:
    scan = Scan()
    n = 40
    times = [0.05] * n
    steps = [[0.01] * n, [-0.02] * n]
    scan.write_only("NC")
    for i in range(2):
        scan.write_only("%dDC%d" % (i + 1, 1))
    scan.write_only("UC%f" % 0.5)
    for i in range(n):
        scan.write_only("%dDT%f" % (i + 1, times[i]))
        for j in range(2):
            scan.write_only("%dDX%f" % (j + 1, steps[j][i]))
        if (i + 1) % 20 == 0:
            assert scan.write_read("TB") == "TB@ No error"  # read and ignored by the scan
    assert scan.mm.machine.timed.elements[39].moves == {1: 0.01, 2: -0.02}


def test_9_pulse_line_mb_me_mn_on_one_line_is_silent() -> None:
    scan = Scan()
    scan.write_only("MB%d,ME%d,MN%d" % (1, 8, 8 + 1))  # npulses + 1: "one fewer pulse"
    assert [scan.write_read(q) for q in ("MB?", "ME?", "MN?")] == ["MB1", "ME8", "MN9"]


def test_10_11_vc_then_tb_byte_2_is_at_sign_when_the_trajectory_verifies() -> None:
    scan = Scan()
    status = scan.build([[0.1] * 8, [0.05] * 8], [0.1] * 8, pulses=(1, 8, 9))
    assert status == "TB@ No error" and status[2] == "@"


def test_11_tb_after_a_refused_vc_fails_the_build_with_the_reply_as_message() -> None:
    scan = Scan()
    scan.write_only("1VU%f" % 1.0)  # axis 1 may not go faster than 1 unit/s
    status = scan.build([[0.5] * 4], [0.1] * 4)  # 5 units/s
    assert status[2] != "@"
    assert status == "TBH Trajectory velocity too large"[:39]


def test_12_rc1_to_rc6_parse_with_atoi_and_atof_from_offset_3() -> None:
    scan = Scan()
    times = [0.1, 0.2, 0.1, 0.1]
    steps = [[0.1, 0.1, -0.05, 0.2], [0.0, 0.0, 0.0, 0.0]]
    assert scan.build(steps, times, accel=0.25)[2] == "@"
    v = velocities(steps[0], times)  # 1, 0.5, -0.5, 2
    changes = [abs(v[i] - v[i - 1]) for i in range(1, len(v))]  # 0.5, 1, 2.5
    change_element = 2 + changes.index(max(changes))
    speeds = [abs(x) for x in v]
    accels = [abs(v[0]) / 0.25] + [c / 0.25 for c in changes]
    p = [scan.write_read("%dRC%d" % (1, k)) for k in range(1, 7)]
    assert c_atoi(p[0][3:]) == change_element == 4
    assert c_atof(p[1][3:]) == pytest.approx(max(changes))
    assert c_atoi(p[2][3:]) == 1 + speeds.index(max(speeds)) == 4
    assert c_atof(p[3][3:]) == pytest.approx(max(speeds))
    assert c_atoi(p[4][3:]) == 1 + accels.index(max(accels)) == 4
    assert c_atof(p[5][3:]) == pytest.approx(max(accels))
    # an axis that takes part without moving reads zeros through the same parse
    assert [c_atof(scan.write_read("2RC%d" % k)[3:]) for k in range(1, 7)] == [0.0] * 6


# ---------------------------------------------------------------- execute
def _run_until_done(scan: Scan, time_scale: float, expected: float) -> tuple[str, list[int]]:
    """The wait_execute loop: TP, XC1, MS, TB each pass (virtual 50 ms between passes)."""
    seen = []
    elapsed = 0.0
    while True:
        positions = scan.motor_positions()
        assert len(positions) == scan.num_axes
        seen.append(c_atoi(scan.write_read("XC1")[2:]))
        any_moving = scan.motor_moving()
        tb = scan.write_read("TB")
        if tb[2] != "@":
            return "Failure " + tb, seen
        if not any_moving:
            return "Success", seen
        if elapsed > expected * time_scale * 2.0:
            return "Timeout", seen
        scan.advance(0.05)
        elapsed += 0.05


def test_14_to_18_ls_ec_runs_and_the_loop_parses_tp_xc1_ms_tb_to_success() -> None:
    scan = Scan()
    n = 8
    steps = [[0.1] * n, [-0.05] * n]
    assert scan.build(steps, [0.1] * n, pulses=(1, n, n + 1))[2] == "@"
    scan.write_only("LS,%dEC%f" % (0, 1.0))
    scan.advance(0.1)  # the program's 0.1 s sleep: the axes must already read moving
    assert scan.motor_moving() == 0b11
    status, seen = _run_until_done(scan, 1.0, 0.8)
    assert status == "Success"
    assert seen == sorted(seen) and seen[-1] == n and seen[0] >= 1
    assert scan.motor_positions() == pytest.approx([0.8, -0.4])


def test_14_time_scale_stretches_the_run() -> None:
    scan = Scan()
    assert scan.build([[0.1] * 4], [0.1] * 4)[2] == "@"
    scan.write_only("LS,%dEC%f" % (0, 2.0))
    scan.advance(0.7)  # 0.8 s of motion at time scale 2
    assert scan.motor_moving() == 0b01
    scan.advance(0.2)
    assert scan.motor_moving() == 0 and c_atoi(scan.write_read("XC1")[2:]) == 4


def test_14_simulation_mode_moves_nothing_and_the_loop_ends_on_its_first_pass() -> None:
    scan = Scan()
    assert scan.build([[0.1] * 4, [0.2] * 4], [0.1] * 4, pulses=(1, 4, 5))[2] == "@"
    scan.write_only("LS,%dEC%f" % (1, 1.0))
    scan.advance(0.1)
    status, seen = _run_until_done(scan, 1.0, 0.4)
    assert status == "Success" and seen == [0]
    assert scan.motor_positions() == [0.0, 0.0]
    assert c_atoi(scan.write_read("NQ")[2:]) == 0


def test_14_simulation_mode_reports_what_the_real_run_would_refuse() -> None:
    scan = Scan()
    scan.write_only("1SR%f" % 0.2)
    assert scan.build([[0.1] * 4], [0.1] * 4)[2] == "@"
    scan.write_only("LS,%dEC%f" % (1, 1.0))
    status, _ = _run_until_done(scan, 1.0, 0.4)
    assert status == "Failure TBR Trajectory outside travel limits"
    scan.write_only("LS,%dEC%f" % (0, 1.0))  # the real run refuses with the same letter
    assert scan.write_read("TB")[2] == "R" and scan.motor_moving() == 0


def test_16_xc1_before_any_run_parses_as_zero() -> None:
    assert c_atoi(Scan().write_read("XC1")[2:]) == 0


# ---------------------------------------------------------------- readback
def test_20_21_nq_then_itq_tokens_give_th_and_tp_of_every_axis() -> None:
    scan = Scan("MM4005-3")  # the third axis does not move: its tokens are still there
    n = 8
    steps = [[0.1] * n, [0.05] * n]
    assert scan.build(steps, [0.1] * n, pulses=(1, n, n + 1))[2] == "@"
    scan.write_only("LS,%dEC%f" % (0, 1.0))
    assert _run_until_done(scan, 1.0, 0.8)[0] == "Success"
    nactual = c_atoi(scan.write_read("NQ")[2:])
    assert nactual == n  # MN n+1: n pulses, one at the start of each element
    for i in range(nactual):
        tokens = strtok(scan.write_read("%dTQ" % (i + 1)))
        assert tokens[0] == "%dTQ" % (i + 1)
        for j in range(scan.num_axes):
            th = c_atof(tokens[1 + 2 * j][3:])
            tp = c_atof(tokens[2 + 2 * j][3:])
            ideal = (0.1, 0.05, 0.0)[j] * i  # the start of element i + 1
            assert th == pytest.approx(ideal, abs=1e-4)
            assert abs(tp - th) <= 0.0011  # within one count (TU 0.001)


def test_20_nq_before_any_run_is_zero() -> None:
    assert c_atoi(Scan().write_read("NQ")[2:]) == 0


# ---------------------------------------------------------------- abort
def test_22_ab_is_silent_and_stops_the_run_where_it_is() -> None:
    scan = Scan()
    assert scan.build([[0.5] * 8], [0.1] * 8)[2] == "@"
    scan.write_only("LS,%dEC%f" % (0, 1.0))
    scan.advance(0.3)
    scan.write_only("AB")
    here = scan.motor_positions()
    scan.advance(1.0)
    assert scan.motor_moving() == 0 and scan.motor_positions() == here
    assert 0.0 < here[0] < 4.0 and c_atoi(scan.write_read("XC1")[2:]) < 8


# ---------------------------------------------------------------- the other hosts
SCAN_PROGRAM = ("GC", "NC", "DC", "UC", "DT", "DX", "TB", "MB", "ME", "MN", "VC", "RC", "LS",
                "EC", "TP", "XC", "MS", "NQ", "TQ", "AB")
MM4000_DRIVERS = ("AC", "VA", "OR", "ST", "PA", "PR", "MF", "MO", "MS", "SH", "DH", "SL", "SR",
                  "TC", "TL", "TR", "TU", "XH", "TE", "TP", "TH", "VE", "KP", "KI", "KD", "UF")
MM4006_STREAM_HOST = ("VE", "TE", "MS", "MF", "MO", "TS", "TP", "OR", "PA", "PR")


@pytest.mark.parametrize("mnemonic", sorted(set(SCAN_PROGRAM + MM4000_DRIVERS
                                               + MM4006_STREAM_HOST)))
def test_every_mnemonic_a_public_host_sends_is_in_the_table(mnemonic: str) -> None:
    assert mnemonic in COMMANDS


def test_the_stream_host_reads_ts_at_sign_when_idle_and_powered() -> None:
    scan = Scan("MM4005-4")
    reply = scan.write_read("TS")
    assert reply == "TS@"  # its 'ready' value is '@'
    scan.write_only("2PA%f" % 1.0)
    assert scan.write_read("TS") == "TSB"  # bit 1: axis 2 moving
    scan.mm.run_until_idle()
    scan.write_only("3MF")
    assert scan.write_read("TS") == "TSP"  # bit 4: motor power off


def test_a_cpp_gpib_client_reads_all_axes_with_0tp_and_0ms_at_fixed_offsets() -> None:
    # its sscanf "1TP%lf,2TP%lf,3TP%lf" and the status bytes at offsets 3, 8 and 13
    scan = Scan("MM4005-3")
    scan.write_only("%1dPA%s" % (2, "%f" % 1.5))
    scan.advance(0.1)
    tp = scan.write_read("0TP")
    match = re.fullmatch(r"1TP([-.\d]+),2TP([-.\d]+),3TP([-.\d]+)", tp)
    assert match is not None and float(match.group(1)) == 0.0
    assert 0.0 < float(match.group(2)) < 1.5
    ms = scan.write_read("0MS")
    assert [ms[0:3], ms[5:8], ms[10:13]] == ["1MS", "2MS", "3MS"]
    assert [ord(ms[i]) & 1 for i in (3, 8, 13)] == [0, 1, 0]
    scan.write_only("ST")
    scan.write_only("%1dM%1c" % (3, "F"))
    assert ord(scan.write_read("0MS")[13]) & 0x02  # power off


def test_a_tcl_gpib_driver_reads_its_commands_with_a_cmd_regexp() -> None:
    # each read is matched by ^<command>(.*)$ ; errors by TE's first character
    scan = Scan("MM4005-4")

    def get(command: str) -> str:
        reply = scan.write_read(command)
        match = re.fullmatch(re.escape(command.rstrip("?")) + r"(.*)", reply)
        assert match is not None, (command, reply)
        return match.group(1)

    def set_and_check(command: str) -> None:
        scan.write_only(command)
        assert scan.write_read("TE")[2] == "@", command

    assert float(get("4TU")) == 0.001
    for axis_command in ("TA", "TC", "TL", "TN", "TR", "XB", "XH", "DP", "TH", "TP", "DF"):
        get(f"1{axis_command}")
    for command in ("4SL-20000", "4SR20000", "4VA5000", "4ZP", "4SH0", "1SY1", "SD50",
                    "1OR0", "MO"):
        set_and_check(command)
    assert get("4VA?") == "5000.0000" and get("SD?") == "50" and get("1SY?") == "1"
    assert get("TB") == "@ No error" and get("VE").startswith(" MM4005")
    scan.mm.run_until_idle()
    set_and_check("1PA1,2PA2")  # its XY move: two commands, one line
    scan.mm.run_until_idle()
    assert [get("1TP"), get("2TP")] == ["1.0000", "2.0000"]
    for bad in ("WT", "YA", "CB1"):  # listed, not modelled: the driver sees 'Q'
        scan.write_only(bad)
        assert scan.write_read("TE") == "TEQ", bad

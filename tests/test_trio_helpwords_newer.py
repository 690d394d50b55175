"""The TrioBASIC help's words that are newer than the MC405's token table (helpwords.py,
NEWER_WORDS): each is a keyword, so a program naming one never makes a local variable; the
ones modelled do what their pages say. Figures are worked out by hand in each test."""

from __future__ import annotations

import pytest

from maxk.commands.trio.helpwords import NEWER_WORDS
from maxk.commands.trio.keywords import KEYWORDS, Kind
from maxk.controllers.trio import MC405

NAMES = [row.split()[1] for row in NEWER_WORDS.splitlines()
         if not row.startswith(" ")]


def mc405(*lines: str) -> MC405:
    trio = MC405()
    for line in lines:
        assert trio.send(line) == [], line
    return trio


def read(trio: MC405, what: str) -> float:
    return float(trio.query(f"?{what}"))


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


# ---- every word is a keyword --------------------------------------------------------------
def test_the_44_words_are_keywords_from_their_pages_and_say_so() -> None:
    assert len(NAMES) == len(set(NAMES)) == 44
    for name in NAMES:
        entry = KEYWORDS[name]
        assert entry.source == f"TrioBASIC help {name}", name
        assert "not the MC405's token table" in entry.note, name
        assert "not modelled yet: the machine" not in entry.note, name  # a reason each
        assert entry.note.startswith("Not modelled: ") == (entry.confidence == "D"), name


def test_a_program_writing_them_sets_the_controllers_parameters_not_variables() -> None:
    trio = mc405()
    trio.load("P", "FASTJERK = 2000\nSPEED_FACTOR AXIS(4) = 0.5\nOPEN_WINB = -40\n"
                   "IN_DEBOUNCE = 10\nMOVE_COUNT_INC = -1")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    assert [trio.query(q) for q in ("?FASTJERK", "?SPEED_FACTOR AXIS(4)", "?SPEED_FACTOR",
                                    "?OPEN_WINB", "?IN_DEBOUNCE", "?MOVE_COUNT_INC")] == [
        "2000", "0.5000", "1", "-40", "10", "-1"]


@pytest.mark.parametrize("line", ["REMAIN_TIME = 1", "STOPPING_DISTANCE = 0",
                                  "VP_DEMAND_SPEED = 3", "MOVE_FORCE_SPEED = 5",
                                  "GTASIZE = 2", "VP_ERROR = 1"])
def test_the_read_only_ones_refuse_a_write(line: str) -> None:
    assert mc405().send(line) == ["! Parameter is read only"]


@pytest.mark.parametrize("line", ["SPEED_FACTOR = 1.5", "ACCEL_FACTOR = -0.1",
                                  "AXIS_BLENDING = 5", "FORCE_ACCEL = -2",
                                  "DRIVE_BRAKE_OUTPUT = 1024", "FASTJERK = -1"])
def test_values_outside_their_pages_ranges_are_refused(line: str) -> None:
    trio = mc405()
    name = line.split()[0]
    before = trio.query(f"?{name}")
    assert trio.send(line) == ["! Parameter out of range"]
    assert trio.query(f"?{name}") == before


def test_power_up_values_from_the_pages() -> None:
    trio = mc405()
    # FORCE_* -1 "not used", the factors 1 (100 %), AXIS_BLENDING 1 (Low, default)
    assert [read(trio, w) for w in ("FORCE_ACCEL", "FORCE_DECEL", "FORCE_JERK",
                                    "SPEED_FACTOR", "ACCEL_FACTOR", "JERK_FACTOR",
                                    "AXIS_BLENDING", "VP_ERROR")] == [
        -1, -1, -1, 1, 1, 1, 1, 0]


def test_the_commands_run_with_their_pages_arguments() -> None:
    trio = mc405()
    for line in ("IN_FILTER(0, 5)", "IN_FILTER(0, 4, 7)", "COMBINE_AXES(2, 3)",
                 "COMBINE_CONTROL(2, 0, 0)", "MOVETEST(0)", "COMPENSATE_ENC()"):
        assert trio.send(line) == [], line
    assert KEYWORDS["MOVEADD"].kind is Kind.COMMAND and KEYWORDS["MOVEADD"].axis_modifier
    assert trio.send("IN_FILTER(0)") == ["! Syntax error"]


# ---- SET_MOTION / SET_MOTIONSP ------------------------------------------------------------
def test_set_motion_example_runs_the_move_at_the_rates_it_set() -> None:
    """SET_MOTION page, example 1: speed 20, accel 100, decel 120 on axis 3, then MOVE(150).
    Ramp up 20/100 = 0.2 s over 0.5*100*0.2^2 = 2 units; down 20/120 s over
    20^2/(2*120) = 5/3 units; the cruise at 20 covers the rest."""
    trio = mc405("SET_MOTION(3, 20, 100, 120)")
    assert [read(trio, f"{w} AXIS(3)") for w in ("SPEED", "ACCEL", "DECEL", "JERK")] == [
        20, 100, 120, 0]
    assert read(trio, "SPEED AXIS(0)") != 20  # the BASE axis is untouched
    start = trio.tick
    assert trio.send("BASE(3): MOVE(150)") == []
    at(trio, start + 100)  # 0.1 s: 0.5*100*0.1^2
    assert read(trio, "DPOS AXIS(3)") == pytest.approx(0.5, abs=1e-9)
    at(trio, start + 1000)  # 2 units up, then 0.8 s at 20
    assert read(trio, "DPOS AXIS(3)") == pytest.approx(18.0, abs=1e-9)
    cruise = (150 - 2 - 5 / 3) / 20  # s
    end = 0.2 + cruise + 20 / 120  # 7.68333 s
    at(trio, start + 7583)  # 0.100333 s before the end: 0.5*120*t^2 to go
    left = end - 7.583
    assert trio.machine.axis_parameter("DPOS", 3) == pytest.approx(150 - 60 * left * left,
                                                                   abs=1e-9)
    at(trio, start + 7684)
    assert trio.machine.axis_parameter("DPOS", 3) == 150


def test_set_motion_refuses_bad_values_whole_and_a_bad_axis() -> None:
    trio = mc405("SET_MOTION(3, 20, 100, 120)")
    assert trio.send("SET_MOTION(3, 5, 50, -1)") == ["! Parameter out of range"]
    assert [read(trio, f"{w} AXIS(3)") for w in ("SPEED", "ACCEL", "DECEL")] == [20, 100, 120]
    assert trio.send("SET_MOTION(99, 5)") == ["! Invalid axis number"]
    assert trio.send("SET_MOTION(3)") == ["! Syntax error"]
    assert trio.send("SET_MOTION(3, 1, 2, 3, 4, 5)") == ["! Syntax error"]


def test_set_motionsp_sets_the_sp_parameters_of_the_named_axis() -> None:
    trio = mc405()
    trio.load("P", "SET_MOTIONSP(1, 50, 10, 20, 300, 400, 5000)\nBASE(1)\nMOVESP(100)")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=2)
    assert [read(trio, f"{w} AXIS(1)") for w in (
        "FORCE_SPEED", "STARTMOVE_SPEED", "ENDMOVE_SPEED", "FORCE_ACCEL", "FORCE_DECEL",
        "FORCE_JERK")] == [50, 10, 20, 300, 400, 5000]
    assert read(trio, "FORCE_SPEED AXIS(0)") == 1000  # power-up, untouched


# ---- MOVE_COUNT_INC -----------------------------------------------------------------------
def test_move_count_inc_is_what_each_move_adds() -> None:
    """MOVE_COUNT_INC page: -50 takes 50 off MOVE_COUNT for each move that starts."""
    trio = mc405("SPEED = 1000: ACCEL = 1e6: DECEL = 1e6", "MOVE_COUNT_INC = -50")
    assert trio.send("MOVE(10): MOVE(10): MOVE(10)") == []
    trio.advance(ticks=5)  # the first running
    assert read(trio, "MOVE_COUNT") == -50
    trio.advance(ticks=40)  # 10 units at 1000/s: 10 ms each, all three done
    assert read(trio, "MOVE_COUNT") == -150
    assert trio.send("MOVE_COUNT_INC = 0: MOVE(5)") == []
    trio.advance(ticks=20)
    assert read(trio, "MOVE_COUNT") == -150


# ---- OPEN_WINB / CLOSE_WINB: REGIST windows 5 and 6 -----------------------------------------
SPEED, ACCEL = 100.0, 1e6


def position(tick: int) -> float:
    """FORWARD at 100 units/s, ACCEL 1e6: 0.1 a tick, less the ramp's 100^2 / 2e6."""
    return SPEED * tick / 1000 - SPEED * SPEED / (2 * ACCEL)


def edge(trio: MC405, tick: int, number: int, level: bool) -> None:
    at(trio, tick)
    trio.world_view().set_input(number, level)


@pytest.mark.parametrize("window, captured_at", [(5, 1200), (6, 500)])
def test_regist_window_5_and_6_use_open_winb_to_close_winb(window: int,
                                                           captured_at: int) -> None:
    """OPEN_WINB page: the second window 100..150 (and the first, 0..60, to show it is
    not the one used). Input 7's rising edges at ticks 500 (49.995) and 1200 (119.995):
    window 5 takes only the one inside 100..150, window 6 only the one outside."""
    trio = mc405(f"BASE(1): SPEED={SPEED:g}: ACCEL={ACCEL:g}: DECEL={ACCEL:g}",
                 "OPEN_WIN = 0: CLOSE_WIN = 60: OPEN_WINB = 100: CLOSE_WINB = 150",
                 f"REGIST(20, 7, 4, 0, {window}): FORWARD")
    edge(trio, 500, 7, True)
    edge(trio, 550, 7, False)
    assert read(trio, "MARK") == (-1 if window == 6 else 0)
    edge(trio, 1200, 7, True)
    assert read(trio, "MARK") == -1
    assert trio.machine.registration.read("REG_POS", 1) == pytest.approx(position(captured_at))


def test_regist_window_7_is_refused() -> None:
    assert mc405().send("REGIST(20, 7, 4, 0, 7)") == ["! Parameter out of range"]


# ---- FASTJERK: the jerk of a stop in VP_MODE 5 and 6 ---------------------------------------
def cancelled(*lines: str, at_tick: int = 3000) -> tuple[MC405, int]:
    """Axis 0 (UNITS 1) cruising at 50 after its ramp, then CANCEL at `at_tick`."""
    trio = mc405("SPEED = 50: ACCEL = 1000: DECEL = 100: FASTDEC = 1000", *lines,
                 "MOVEABS(10000)")
    at(trio, at_tick)
    assert trio.send("CANCEL") == []
    return trio, trio.tick


def dpos(trio: MC405) -> float:
    return trio.machine.axis_parameter("DPOS", 0)


def test_fastjerk_example_cancel_ramps_down_at_the_fast_jerk() -> None:
    """FASTJERK page: JERK 200, FASTJERK 2000, a CANCEL mid-move. VP_MODE 5: the ramp up
    peaks at sqrt(50 x 200) = 100 over 2 sqrt(50/200) = 1 s, 25 units, so at 3 s the
    axis is at 25 + 2 x 50 = 125, cruising. The stop (at DECEL 100: FASTDEC 0 here, so
    CANCEL takes DECEL, its page) rises to 100 at 2000/s^3 over 0.05 s:
    s(t) = 50 t - 2000 t^3 / 6 then; it lasts 50/100 + 100/2000 = 0.55 s and covers
    50 x 0.55 / 2 = 13.75 (symmetric)."""
    trio, start = cancelled("VP_MODE = 5: JERK = 200: FASTJERK = 2000: FASTDEC = 0")
    assert dpos(trio) == 125
    at(trio, start + 50)
    assert dpos(trio) == pytest.approx(125 + 50 * 0.05 - 2000 * 0.05 ** 3 / 6, abs=1e-9)
    at(trio, start + 549)  # 1 ms before rest: 2000 x 0.001^3 / 6 still to go
    assert dpos(trio) == pytest.approx(125 + 13.75 - 2000 * 0.001 ** 3 / 6, abs=1e-9)
    at(trio, start + 560)
    assert dpos(trio) == 139  # at rest, on the whole count past 138.75 (CANCEL's end)
    assert trio.query("?IDLE") == "-1"


@pytest.mark.parametrize("fastjerk", [0, 150])
def test_fastjerk_not_above_jerk_leaves_the_moves_jerk(fastjerk: int) -> None:
    """FASTJERK 0 (not used) or below JERK: the stop rises at JERK 200 over 0.5 s and
    lasts 0.5 + 0.5 = 1 s, covering 50 x 1 / 2 = 25."""
    trio, start = cancelled(f"VP_MODE = 5: JERK = 200: FASTJERK = {fastjerk}")
    at(trio, start + 50)
    assert dpos(trio) == pytest.approx(125 + 50 * 0.05 - 200 * 0.05 ** 3 / 6, abs=1e-9)
    at(trio, start + 1000)
    assert dpos(trio) == 150


def test_fastjerk_is_ignored_in_vp_mode_0() -> None:
    """VP_MODE 0, no SRAMP: a trapezoid; CANCEL ramps linearly at FASTDEC 1000 (above DECEL
    100, the CANCEL page): 50 x 0.05 - 1000 x 0.05^2 / 2 after 50 ms, whatever FASTJERK
    says."""
    trio, start = cancelled("FASTJERK = 2000", at_tick=2000)
    here = dpos(trio)
    at(trio, start + 25)
    assert dpos(trio) == pytest.approx(here + 50 * 0.025 - 1000 * 0.025 ** 2 / 2, abs=1e-9)
    at(trio, start + 50)
    assert dpos(trio) == pytest.approx(here + 50 * 0.05 - 1000 * 0.05 ** 2 / 2, abs=1e-9)


def test_vp_mode_6_with_sramp_stops_at_fastdec_over_sramp() -> None:
    """FASTJERK page: with SRAMP set in VP_MODE 6, FASTJERK is FASTDEC / SRAMP and any
    FASTJERK written is ignored. SRAMP 50 ms: the move's jerk is ACCEL / SRAMP = 20000, up
    in 0.1 s over 2.5 units (at 3 s: 2.5 + 2.9 x 50 = 147.5); FASTDEC 4000 (above DECEL:
    CANCEL's rate) gives 80000, above it, so the stop from 50 is a triangle of
    acceleration peaking at sqrt(50 x 80000) = 2000 after 25 ms: s(t) = 50 t - 80000 t^3 / 6
    then, and it covers 50 x 0.05 / 2 = 1.25 in 50 ms, at rest on the whole count (D)."""
    trio, start = cancelled("VP_MODE = 6: SRAMP = 50: FASTDEC = 4000: FASTJERK = 1e9")
    assert dpos(trio) == pytest.approx(147.5, abs=1e-9)
    at(trio, start + 25)
    assert dpos(trio) == pytest.approx(147.5 + 50 * 0.025 - 80000 * 0.025 ** 3 / 6, abs=1e-9)
    at(trio, start + 60)
    assert dpos(trio) == 149


# ---- REMAIN_TIME and STOPPING_DISTANCE ----------------------------------------------------
def test_remain_time_example_move_45_and_a_buffered_move() -> None:
    """REMAIN_TIME page, example 1: SPEED 10, ACCEL = DECEL = 200, MOVE(45): 45/10 + 10/200
    = 4.55 s; a MOVE(10) buffered behind it from rest adds 10/10 + 10/200 = 1.05 s."""
    trio = mc405("SPEED = 10: ACCEL = 200: DECEL = 200")
    assert read(trio, "REMAIN_TIME") == 0
    assert trio.send("MOVE(45): MOVE(10)") == []
    start = trio.tick
    assert trio.machine.axis_parameter("REMAIN_TIME", 0) == pytest.approx(5.6, abs=1e-9)
    at(trio, start + 3800)  # the page's 0.75 s before the first move ends, plus 1.05
    assert trio.machine.axis_parameter("REMAIN_TIME", 0) == pytest.approx(0.75 + 1.05,
                                                                         abs=1e-9)
    at(trio, start + 4551)  # the second move 1 ms in
    assert trio.machine.axis_parameter("REMAIN_TIME", 0) == pytest.approx(1.049, abs=1e-9)
    at(trio, start + 5600)
    assert read(trio, "REMAIN_TIME") == 0


def test_remain_time_drives_the_pages_program_slowing_in_the_last_750_ms() -> None:
    """The page's program: once REMAIN_TIME < 0.75 it writes SPEED = 1. REMAIN_TIME falls
    below 0.75 on the first tick after 3.8 s into the move (4.55 - 0.75), where the axis
    is at 10 x 3.801 - 10 x 0.05 / 2 = 37.76 and still at 10 units/s."""
    trio = mc405()
    trio.load("P", "SPEED = 10\nACCEL = 200\nDECEL = 200\nMOVE(45)\nWAIT LOADED\n"
                   "WAIT UNTIL REMAIN_TIME < 0.750\nVR(1) = DPOS\nVR(2) = REMAIN_TIME\n"
                   "SPEED = 1\nWAIT IDLE\nVR(3) = 1")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=3000)
    assert trio.machine.vr_read(1) == 0
    trio.advance(ticks=20000)
    start_to_vr = trio.machine.vr_read(1)
    left = trio.machine.vr_read(2)
    assert left == pytest.approx(0.749, abs=1e-9)  # the first whole tick below 0.75
    # 0.749 s left: 0.05 s of ramp (0.25) and 0.699 s at 10 still to run
    assert start_to_vr == pytest.approx(45 - (0.25 + 10 * 0.699), abs=1e-9)
    assert trio.machine.vr_read(3) == 1  # the slowed move ends, at 1 unit/s


def test_stopping_distance_linear_and_jerk_limited() -> None:
    """Linear ramps: v^2 / (2 DECEL): 10^2 / 400 = 0.25 cruising, 2^2 / 400 = 0.01 at
    10 ms into the ramp up (v = 200 x 0.01 = 2). VP_MODE 5 with JERK 200 and FASTJERK
    2000, cruising at 50 with DECEL 100: 50 x (50/100 + 100/2000) / 2 = 13.75, as far as
    the CANCEL of the FASTJERK test runs."""
    trio = mc405("SPEED = 10: ACCEL = 200: DECEL = 200")
    assert read(trio, "STOPPING_DISTANCE") == 0
    assert trio.send("MOVE(45)") == []
    start = trio.tick
    at(trio, start + 10)
    assert trio.machine.axis_parameter("STOPPING_DISTANCE", 0) == pytest.approx(0.01,
                                                                              abs=1e-12)
    at(trio, start + 1000)
    assert trio.machine.axis_parameter("STOPPING_DISTANCE", 0) == pytest.approx(0.25,
                                                                              abs=1e-12)
    jerky = mc405("SPEED = 50: ACCEL = 1000: DECEL = 100", "VP_MODE = 5: JERK = 200",
                  "FASTJERK = 2000", "MOVEABS(10000)")
    at(jerky, 3000)
    assert jerky.machine.axis_parameter("STOPPING_DISTANCE", 0) == pytest.approx(13.75,
                                                                               abs=1e-9)
    assert jerky.send("FASTJERK = 0") == []  # JERK alone: 50 x (0.5 + 0.5) / 2
    assert jerky.machine.axis_parameter("STOPPING_DISTANCE", 0) == pytest.approx(25,
                                                                               abs=1e-9)


# ---- V_LIMIT ------------------------------------------------------------------------------
def test_v_limit_example_each_axis_within_its_limit() -> None:
    """V_LIMIT page: x (axis 0) at most 40, y (axis 1) at most 80, SPEED 200. MOVE(0, 500)
    runs at 80, MOVE(500, 0) at 40, MOVE(500, 500) at 40 x sqrt(2) = 56.5685. With ACCEL =
    DECEL = 8000 the first takes 500/80 + 80/8000 = 6.26 s: at 1 s y is at
    0.5 x 8000 x 0.01^2 + 80 x 0.99 = 79.6."""
    trio = mc405("V_LIMIT AXIS(0) = 40: V_LIMIT AXIS(1) = 80",
                 "BASE(0, 1): SPEED = 200: ACCEL = 8000: DECEL = 8000",
                 "MOVE(0, 500): MOVE(500, 0): MOVE(500, 500)")
    start = trio.tick
    at(trio, start + 1000)
    assert read(trio, "VP_SPEED") == 80
    assert trio.machine.axis_parameter("DPOS", 1) == pytest.approx(79.6, abs=1e-9)
    at(trio, start + 6260)  # the first move done; the second starts
    assert trio.machine.axis_parameter("DPOS", 1) == 500
    at(trio, start + 6260 + 1000)  # 40 ramps in 5 ms: 0.5 x 8000 x 0.005^2 + 40 x 0.995
    assert read(trio, "VP_SPEED") == 40
    assert trio.machine.axis_parameter("DPOS", 0) == pytest.approx(39.9, abs=1e-9)
    second = 500 / 40 + 40 / 8000  # 12.505 s
    at(trio, start + 6260 + round(second * 1000) + 2000)
    assert float(trio.query("?VP_SPEED")) == pytest.approx(40 * 2 ** 0.5, abs=1e-4)


def test_v_limit_off_and_in_vp_mode_5_the_move_runs_at_speed() -> None:
    trio = mc405("V_LIMIT AXIS(0) = 0: V_LIMIT AXIS(1) = -5",
                 "BASE(0, 1): SPEED = 200: ACCEL = 8000: DECEL = 8000", "MOVE(500, 500)")
    trio.advance(ticks=1000)
    assert read(trio, "VP_SPEED") == 200
    jerky = mc405("V_LIMIT AXIS(0) = 40", "BASE(0, 1): SPEED = 200: VP_MODE = 5",
                  "MOVE(500, 0)")
    jerky.advance(ticks=1000)
    assert read(jerky, "VP_SPEED") == 200  # the page: not supported in VP_MODE 5


# ---- FWD_START / REV_START ----------------------------------------------------------------
def test_fwd_start_jogs_at_jogspeed_and_stops_at_decel() -> None:
    """FWD_START page's table: FWD_JOG -1 and FWD_START 1: MTYPE 14. JOGSPEED 20, ACCEL =
    DECEL = 1000: up in 0.02 s over 0.2, so at 1 s 0.2 + 20 x 0.98 = 19.8; FWD_START 0
    ramps down over 0.02 s, 0.2 more: at rest at 20."""
    trio = mc405("BASE(2): JOGSPEED = 20: ACCEL = 1000: DECEL = 1000")
    assert trio.send("FWD_START = 1") == []
    start = trio.tick
    assert read(trio, "MTYPE AXIS(2)") == 14
    at(trio, start + 1000)
    assert trio.machine.axis_parameter("DPOS", 2) == pytest.approx(19.8, abs=1e-9)
    assert trio.send("FWD_START = 0") == []
    stop = trio.tick
    at(trio, stop + 10)  # 20 x 0.01 - 1000 x 0.01^2 / 2 more
    assert trio.machine.axis_parameter("DPOS", 2) == pytest.approx(19.95, abs=1e-9)
    at(trio, stop + 25)
    assert (read(trio, "MTYPE AXIS(2)"), trio.machine.axis_parameter("DPOS", 2)) == (0, 20)


def test_rev_start_and_the_start_ignored_with_an_input_declared() -> None:
    trio = mc405("BASE(2): JOGSPEED = 20: ACCEL = 1000: DECEL = 1000", "REV_START = 1")
    assert read(trio, "MTYPE AXIS(2)") == 15
    trio.advance(ticks=1000)
    assert trio.machine.axis_parameter("DPOS", 2) == pytest.approx(-19.8, abs=1e-9)
    other = mc405("BASE(3): JOGSPEED = 20", "FWD_START = 2")
    assert read(other, "MTYPE AXIS(3)") == 0  # "Not Equ 1": idle (the page's table)
    other.world_view().set_input(7, True)  # the jog input high: it asks for no jog
    assert other.send("FWD_JOG = 7: FWD_START = 1") == []  # an input declared: no function
    other.advance(ticks=100)
    assert read(other, "MTYPE AXIS(3)") == 0
    assert other.send("FWD_JOG = -1") == []  # no input: FWD_START 1 jogs
    assert read(other, "MTYPE AXIS(3)") == 14


def test_fwd_start_example_program_follows_vr_10() -> None:
    """The page's example: a program jogs axis 2 as VR(10) says (1 forward, 2 reverse,
    0 stop, 99 end)."""
    trio = mc405("JOGSPEED AXIS(2) = 20: ACCEL AXIS(2) = 1000: DECEL AXIS(2) = 1000")
    trio.load("P", "BASE(2)\nFWD_JOG = -1\nREV_JOG = -1\nIF IDLE THEN\n  REPEAT\n"
                   "    SELECT_CASE VR(10)\n    CASE 0\n      FWD_START = 0\n"
                   "      REV_START = 0\n    CASE 1\n      FWD_START = 1\n"
                   "      REV_START = 0\n    CASE 2\n      FWD_START = 0\n"
                   "      REV_START = 1\n    END_CASE\n  UNTIL VR(10) = 99\nENDIF")
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=50)
    assert read(trio, "MTYPE AXIS(2)") == 0
    assert trio.send("VR(10) = 1") == []
    trio.advance(ticks=500)
    assert read(trio, "MTYPE AXIS(2)") == 14 and read(trio, "VP_SPEED AXIS(2)") == 20
    assert trio.send("VR(10) = 0") == []
    trio.advance(ticks=100)
    assert read(trio, "MTYPE AXIS(2)") == 0
    here = trio.machine.axis_parameter("DPOS", 2)
    assert trio.send("VR(10) = 2") == []
    trio.advance(ticks=500)
    assert read(trio, "MTYPE AXIS(2)") == 15
    assert trio.machine.axis_parameter("DPOS", 2) < here
    assert trio.send("VR(10) = 99") == []


# ---- FORCE_ACCEL / FORCE_DECEL / FORCE_JERK -----------------------------------------------
def test_an_sp_move_ramps_at_force_accel_and_force_decel() -> None:
    """FORCE_SPEED 50, FORCE_ACCEL 2000, FORCE_DECEL 500 (ACCEL = DECEL = 100 not used):
    MOVESP(100) is up in 0.025 s over 0.625, down in 0.1 s over 2.5, cruising the
    96.875 between in 1.9375 s: 2.0625 s in all."""
    trio = mc405("ACCEL = 100: DECEL = 100: FORCE_SPEED = 50",
                 "FORCE_ACCEL = 2000: FORCE_DECEL = 500", "MOVESP(100)")
    start = trio.tick
    at(trio, start + 10)
    assert dpos(trio) == pytest.approx(0.5 * 2000 * 0.01 ** 2, abs=1e-12)
    at(trio, start + 1000)
    assert dpos(trio) == pytest.approx(0.625 + 50 * 0.975, abs=1e-9)
    at(trio, start + 2062)  # 0.5 ms before the end
    assert dpos(trio) == pytest.approx(100 - 0.5 * 500 * 0.0005 ** 2, abs=1e-12)
    at(trio, start + 2063)
    assert (dpos(trio), read(trio, "MTYPE")) == (100, 0)
    # a plain MOVE keeps ACCEL: 0.5 x 100 x 0.01^2 after 10 ms
    assert trio.send("SPEED = 50: MOVE(10)") == []
    again = trio.tick
    at(trio, again + 10)
    assert dpos(trio) == pytest.approx(100 + 0.005, abs=1e-12)


def test_force_jerk_shapes_an_sp_move_in_vp_mode_5() -> None:
    """VP_MODE 5, JERK 200 but FORCE_JERK 50000: the SP move's acceleration rises at 50000,
    so 10 ms in it has gone 50000 x 0.01^3 / 6 (JERK's 200 would give 1/250 of that)."""
    trio = mc405("VP_MODE = 5: JERK = 200: ACCEL = 100: DECEL = 100",
                 "FORCE_SPEED = 50: FORCE_ACCEL = 2000: FORCE_JERK = 50000", "MOVESP(100)")
    trio.advance(ticks=10)
    assert dpos(trio) == pytest.approx(50000 * 0.01 ** 3 / 6, abs=1e-12)


# ---- MOVE_FORCE_SPEED / ACCEL / DECEL -----------------------------------------------------
def test_move_force_readings_follow_the_move_running() -> None:
    """Two SP moves then a MOVE. The first, MOVESP(10) at 50 with FORCE_ACCEL 2000 (DECEL
    1000): up 0.025 s (0.625), down 0.05 s (1.25), the 8.125 between at 50 in 0.1625 s:
    0.2375 s, so it is done on tick 238 and the second runs from there; it (at 20, ACCEL
    1000, FORCE_DECEL 300) takes 0.02 + 9.1333/20 + 0.0667 = 0.54333 s, to tick 782."""
    trio = mc405("ACCEL = 1000: DECEL = 1000: SPEED = 10",
                 "FORCE_SPEED = 50: FORCE_ACCEL = 2000: MOVESP(10)",
                 "FORCE_SPEED = 20: FORCE_ACCEL = -1: FORCE_DECEL = 300: MOVESP(10)",
                 "MOVE(5)")
    start = trio.tick
    names = ("MOVE_FORCE_SPEED", "MOVE_FORCE_ACCEL", "MOVE_FORCE_DECEL")
    assert [read(trio, n) for n in names] == [50, 2000, -1]
    at(trio, start + 237)
    assert [read(trio, n) for n in names] == [50, 2000, -1]
    at(trio, start + 238)
    assert [read(trio, n) for n in names] == [20, -1, 300]
    at(trio, start + 781)
    assert read(trio, "MOVE_FORCE_SPEED") == 20
    at(trio, start + 782)  # the plain MOVE: no forced values
    assert [read(trio, n) for n in names] == [-1, -1, -1]
    assert read(trio, "MTYPE") == 1


def test_move_force_readings_of_merged_sp_moves_follow_the_move_index() -> None:
    """MERGE ON: the two SP moves run as one path; the readings change where the second
    begins (the first's 10 units take about 0.2 s, the second's about 0.5 s more)."""
    trio = mc405("ACCEL = 1000: DECEL = 1000: MERGE = ON",
                 "FORCE_SPEED = 50: FORCE_ACCEL = 2000: MOVESP(10)",
                 "FORCE_SPEED = 20: FORCE_ACCEL = -1: FORCE_DECEL = 300: MOVESP(10)")
    start = trio.tick
    at(trio, start + 100)
    assert read(trio, "MOVE_FORCE_SPEED") == 50 and read(trio, "DPOS") < 10
    at(trio, start + 500)
    assert read(trio, "DPOS") > 10
    assert [read(trio, n) for n in ("MOVE_FORCE_SPEED", "MOVE_FORCE_DECEL")] == [20, 300]


# ---- SPEED_FACTOR / ACCEL_FACTOR / JERK_FACTOR --------------------------------------------
def test_speed_and_accel_factors_in_vp_mode_5_and_a_live_change() -> None:
    """VP_MODE 5 (no JERK: linear ramps), SPEED 100, ACCEL = DECEL = 1000, both factors
    0.5: MOVE(100) at 50 with 500: up 0.1 s over 2.5, at 1 s 2.5 + 45 = 47.5. SPEED_FACTOR
    1 then: from 50 to 100 at 500 over 0.1 s, 5 + 2.5 more, then 10 a 0.1 s."""
    trio = mc405("VP_MODE = 5: SPEED = 100: ACCEL = 1000: DECEL = 1000",
                 "SPEED_FACTOR = 0.5: ACCEL_FACTOR = 0.5", "MOVE(100)")
    start = trio.tick
    at(trio, start + 100)
    assert dpos(trio) == pytest.approx(2.5, abs=1e-9)
    at(trio, start + 1000)
    assert (dpos(trio), read(trio, "VP_SPEED")) == (pytest.approx(47.5, abs=1e-9), 50)
    assert trio.send("SPEED_FACTOR = 1") == []
    at(trio, start + 1100)
    assert dpos(trio) == pytest.approx(55, abs=1e-9)
    at(trio, start + 1200)
    assert (dpos(trio), read(trio, "VP_SPEED")) == (pytest.approx(65, abs=1e-9), 100)


def test_the_factors_are_ignored_in_vp_mode_0() -> None:
    """VP_MODE 0: MOVE at SPEED 100, ACCEL 1000: 0.5 x 1000 x 0.1^2 = 5 at 0.1 s."""
    trio = mc405("SPEED = 100: ACCEL = 1000: DECEL = 1000",
                 "SPEED_FACTOR = 0.5: ACCEL_FACTOR = 0.5: JERK_FACTOR = 0.5", "MOVE(100)")
    trio.advance(ticks=100)
    assert dpos(trio) == pytest.approx(5, abs=1e-9)


def test_jerk_factor_halves_the_jerk_of_a_move() -> None:
    """VP_MODE 5, JERK 2000 x JERK_FACTOR 0.5 = 1000: 10 ms in, 1000 x 0.01^3 / 6."""
    trio = mc405("VP_MODE = 5: SPEED = 100: ACCEL = 1000: DECEL = 1000: JERK = 2000",
                 "JERK_FACTOR = 0.5", "MOVE(100)")
    trio.advance(ticks=10)
    assert dpos(trio) == pytest.approx(1000 * 0.01 ** 3 / 6, abs=1e-12)


def test_a_speed_written_during_a_v_limited_move_stays_within_the_limit() -> None:
    trio = mc405("V_LIMIT = 40: SPEED = 200: ACCEL = 8000: DECEL = 8000", "MOVE(500)")
    trio.advance(ticks=500)
    assert read(trio, "VP_SPEED") == 40
    assert trio.send("SPEED = 300") == []
    trio.advance(ticks=500)
    assert read(trio, "VP_SPEED") == 40
    assert trio.send("SPEED = 20") == []  # below the limit: taken
    trio.advance(ticks=500)
    assert read(trio, "VP_SPEED") == 20


# ---- IN_DEBOUNCE --------------------------------------------------------------------------
def test_in_debounce_delays_a_change_and_drops_a_glitch() -> None:
    """IN_DEBOUNCE page, example 1's setting: 10 servo cycles. Input 0 rises on tick T: IN
    reads it from T + 10. A low glitch of 3 cycles is never seen; a low that holds 10 is."""
    trio = mc405("IN_DEBOUNCE = 10")
    trio.advance(ticks=5)
    rise = trio.tick
    trio.world_view().set_input(0, True)
    at(trio, rise + 9)
    assert trio.query("?IN(0)") == "0"
    at(trio, rise + 10)
    assert trio.query("?IN(0)") == "1"
    low = trio.tick
    trio.world_view().set_input(0, False)
    at(trio, low + 3)
    trio.world_view().set_input(0, True)
    for k in (5, 12, 20):
        at(trio, low + k)
        assert trio.query("?IN(0)") == "1", k
    low = trio.tick
    trio.world_view().set_input(0, False)
    at(trio, low + 9)
    assert trio.query("?IN(0)") == "1"
    at(trio, low + 10)
    assert trio.query("?IN(0)") == "0"
    assert trio.send("IN_DEBOUNCE = 0") == []  # off: the level at once
    trio.world_view().set_input(0, True)
    assert trio.query("?IN(0)") == "1"


def test_in_debounce_leaves_registration_alone() -> None:
    """The page: registration is not affected: the edge is captured on its own tick."""
    trio = mc405("IN_DEBOUNCE = 50", "BASE(1): SPEED = 100: ACCEL = 1e6: DECEL = 1e6",
                 "REGIST(20, 7, 4, 0, 0): FORWARD")
    at(trio, 300)
    trio.world_view().set_input(7, True)
    assert read(trio, "MARK") == -1
    assert trio.machine.registration.read("REG_POS", 1) == pytest.approx(
        100 * 300 / 1000 - 100 * 100 / 2e6)
    assert trio.query("?IN(7)") == "0"  # IN still waits out the 50 cycles


# ---- AXIS_ENABLE_OVERRIDE -----------------------------------------------------------------
def test_axis_enable_override_moves_an_axis_with_wdog_off() -> None:
    """AXIS_ENABLE_OVERRIDE page: ON enables the axis though WDOG (and AXIS_ENABLE) are
    OFF. A servo axis (ATYPE 36) with WDOG OFF refuses a move; with the override it runs
    MOVE(10) at 100 (ACCEL 1e6): done in 0.1 s + 0.1 ms."""
    trio = mc405("BASE(1): ATYPE = 36: SERVO = ON: WDOG = OFF",
                 "SPEED = 100: ACCEL = 1e6: DECEL = 1e6")
    assert trio.send("MOVE(10)") == ["! Axis not enabled"]
    assert trio.send("AXIS_ENABLE_OVERRIDE = ON: MOVE(10)") == []
    trio.advance(ticks=101)
    assert trio.machine.axis_parameter("DPOS", 1) == 10
    assert trio.send("AXIS_ENABLE = OFF: MOVE(10)") == []
    trio.advance(ticks=101)
    assert trio.machine.axis_parameter("DPOS", 1) == 20
    assert trio.send("AXIS_ENABLE_OVERRIDE = OFF") == []
    assert trio.send("MOVE(10)") == ["! Axis not enabled"]


# ---- MOVETEST -----------------------------------------------------------------------------
def test_movetest_cycles_forward_and_back_with_dwells() -> None:
    """MOVETEST page: 10 forward at 100 with 1000, 50 ms, 10 back the same, 50 ms, again.
    Each move is a triangle: up 0.1 s over 5, down 0.1 s over 5: 0.2 s. So forward
    0..200, dwell to 250, back 250..450, dwell to 500, forward from 500."""
    trio = mc405("SPEED = 7: ACCEL = 3: DECEL = 3",
                 "MOVETEST(1, 10, 1000, 100, 50, 10, 1000, 100, 50)")
    start = trio.tick
    expected = {100: (5.0, 1), 199: (10 - 0.5 * 1000 * 0.001 ** 2, 1), 200: (10, 0),
                249: (10, 0), 251: (10 - 0.0005, 1), 350: (5, 1), 450: (0, 0),
                499: (0, 0), 501: (0.0005, 1), 600: (5, 1)}
    for tick, (where, mtype) in expected.items():
        at(trio, start + tick)
        assert dpos(trio) == pytest.approx(where, abs=1e-9), tick
        assert read(trio, "MTYPE") == mtype, tick
    assert [read(trio, w) for w in ("SPEED", "ACCEL", "DECEL")] == [7, 3, 3]
    assert trio.send("MOVETEST(0)") == []  # ends after the move back: 700, 750..950
    at(trio, start + 949)
    assert read(trio, "MTYPE") == 1
    at(trio, start + 3000)
    assert (dpos(trio), read(trio, "MTYPE")) == (0, 0)


def test_movetest_ends_on_cancel_and_refuses_bad_arguments() -> None:
    trio = mc405("MOVETEST(1, 10, 1000, 100, 50, 10, 1000, 100, 50)")
    trio.advance(ticks=100)  # at 5, at 100: CANCEL ramps down over 5 more at 1000
    assert trio.send("CANCEL") == []
    trio.advance(ticks=2000)
    assert (dpos(trio), read(trio, "MTYPE")) == (10, 0)
    for line in ("MOVETEST(1, 10, 0, 100, 50, 10, 1000, 100, 50)", "MOVETEST(2)",
                 "MOVETEST(1, 2)", "MOVETEST(1, 10, 1000, 100, -1, 10, 1000, 100, 50)"):
        assert trio.send(line) == ["! Parameter out of range"], line
    trio.advance(ticks=500)
    assert read(trio, "MTYPE") == 0


# ---- COMBINE_AXES / COMBINE_CONTROL -------------------------------------------------------
def test_combine_axes_example_1_the_hypotenuse_of_two_axes() -> None:
    """COMBINE_AXES page, example 1: axis 5's DPOS is sqrt(a^2 + b^2) of axes 2 and 3
    (COMBINE_CONTROL(2, 0, 0)): at 3 and 4 it reads 5; axis 2 moved to 12: sqrt(160)."""
    trio = mc405("BASE(5)", "COMBINE_AXES(2, 3): COMBINE_CONTROL(2, 0, 0)",
                 "DEFPOS(3) AXIS(2): DEFPOS(4) AXIS(3)")
    trio.advance(ticks=2)
    assert (read(trio, "DPOS AXIS(5)"), read(trio, "MTYPE AXIS(5)")) == (5, 26)
    assert trio.send("SPEED AXIS(2) = 100: ACCEL AXIS(2) = 1e6: DECEL AXIS(2) = 1e6") == []
    assert trio.send("MOVE(9) AXIS(2)") == []
    start = trio.tick
    at(trio, start + 50)  # axis 2 at 3 + 100 x 0.05 - 100^2 / 2e6
    a = 3 + 5 - 0.005
    assert trio.machine.axis_parameter("DPOS", 5) == pytest.approx((a * a + 16) ** 0.5,
                                                                   abs=1e-9)
    at(trio, start + 100)
    assert trio.machine.axis_parameter("DPOS", 5) == pytest.approx(160 ** 0.5, abs=1e-9)


def test_combine_control_modes_and_their_ratios() -> None:
    """COMBINE_CONTROL page: mode 0 a x n1/d1 + b x n2/d2 (example 1's 0.5 and 2), 1 the
    difference, 3 the average; a running COMBINE_AXES takes each at once."""
    trio = mc405("BASE(6): COMBINE_CONTROL(0, 1, 1, 1, 2, 2, 1): COMBINE_AXES(0, 1)",
                 "DEFPOS(12) AXIS(0): DEFPOS(4) AXIS(1)")
    trio.advance(ticks=1)
    assert read(trio, "DPOS AXIS(6)") == 12 * 0.5 + 4 * 2
    assert trio.send("COMBINE_CONTROL(1, 0, 0)") == []
    trio.advance(ticks=1)
    assert read(trio, "DPOS AXIS(6)") == 8
    assert trio.send("COMBINE_CONTROL(3, 0, 0)") == []
    trio.advance(ticks=1)
    assert read(trio, "DPOS AXIS(6)") == 8
    for line in ("COMBINE_CONTROL(0, 0, 0, 1, 0, 2, 1)", "COMBINE_CONTROL(4, 0, 0)",
                 "COMBINE_CONTROL(2, 1, 0, 0)", "COMBINE_CONTROL(0, 2, 0)"):
        assert trio.send(line) == ["! Parameter out of range"], line
    assert trio.send("COMBINE_CONTROL(2, 1)") == ["! Syntax error"]  # 3 to 7 arguments
    trio.advance(ticks=1)
    assert read(trio, "DPOS AXIS(6)") == 8  # the refused ones changed nothing
    assert trio.send("CANCEL") == []
    trio.advance(ticks=1)
    assert read(trio, "MTYPE AXIS(6)") == 0
    assert trio.send("DEFPOS(0) AXIS(0)") == []
    trio.advance(ticks=1)
    assert read(trio, "DPOS AXIS(6)") == 8  # no longer combined


def test_combine_axes_refuses_itself_as_a_source() -> None:
    assert mc405("BASE(6)").send("COMBINE_AXES(6, 1)") == ["! Invalid axis number"]

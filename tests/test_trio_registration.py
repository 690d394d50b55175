"""Registration as the REGIST help page gives it (modes 1..17, 20 and 21), REG_INPUTS,
REGIST_CONTROL, REGIST_SPEED, R_MARK/R_REGPOS/R_REGISTSPEED, and links that start on an
R_MARK (CAMBOX, MOVELINK option 512).

The registered axis runs FORWARD at 100 units/s with ACCEL 1e6 (UNITS 1), so at servo
tick k (1 ms) it stands at 0.1 k - 0.005 (the 0.1 ms ramp loses v^2 / 2a), moving 0.1 a
tick: 0.1 units per ms is its speed. Every expected figure is that arithmetic and the
page's words.
"""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405

SPEED, ACCEL = 100.0, 1e6
LOSS = SPEED * SPEED / (2 * ACCEL)  # 0.005


def position(tick: int) -> float:
    return SPEED * tick / 1000 - LOSS


def machine(axis: int = 1) -> MC405:
    trio = MC405()
    assert trio.send(f"BASE({axis}): SPEED={SPEED:g}: ACCEL={ACCEL:g}: DECEL={ACCEL:g}") == []
    return trio


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.tick)


def read(trio: MC405, what: str) -> float:
    return float(trio.query(f"?{what}"))


def edge(trio: MC405, tick: int, number: int, level: bool) -> None:
    """The world sets input `number` to `level` on servo tick `tick`."""
    at(trio, tick)
    trio.world_view().set_input(number, level)


def test_reg_inputs_power_up_as_the_pages_mc405_table() -> None:
    trio = MC405()
    # axis n: first input n, second n + 4 (axis 4: 4 and 0)
    assert [read(trio, f"REG_INPUTS AXIS({a})") for a in range(5)] == [
        0x40, 0x51, 0x62, 0x73, 0x04]


def test_mode_6_ra_rising_into_reg_pos_and_the_z_mark_into_reg_posb() -> None:
    trio = machine()
    stage = trio.machine.world.axes[1]
    stage.index_offset, stage.index_period, stage.index_width = 1000, 100000, 4
    assert trio.send("REGIST(6): FORWARD") == []
    edge(trio, 3000, 1, True)  # RA of axis 1 is input 1 (REG_INPUTS $51)
    assert (read(trio, "MARK"), read(trio, "MARKB")) == (-1, 0)
    assert trio.machine.registration.read("REG_POS", 1) == pytest.approx(position(3000))
    assert read(trio, "REGIST_SPEED") == pytest.approx(0.1, abs=1e-9)
    at(trio, 10000)  # at 999.995: the mark at count 1000 is next
    assert read(trio, "MARKB") == 0
    at(trio, 10001)
    assert (read(trio, "MARKB"), read(trio, "REG_POSB")) == (-1, 1000)


def test_modes_14_to_17_use_only_channel_b_and_rb() -> None:
    trio = machine()
    assert trio.send("REGIST(16): FORWARD") == []  # RB rising: input 5 for axis 1
    edge(trio, 500, 1, True)  # RA: not armed
    edge(trio, 700, 5, True)
    assert (read(trio, "MARK"), read(trio, "MARKB")) == (0, -1)
    assert trio.machine.registration.read("REG_POSB", 1) == pytest.approx(position(700))


def test_mode_20_example_3_z_on_a_and_a_windowed_falling_input_on_b() -> None:
    trio = machine(axis=0)
    stage = trio.machine.world.axes[0]
    stage.index_offset, stage.index_period, stage.index_width = 100, 100000, 4
    assert trio.send("OPEN_WIN = 200: CLOSE_WIN = 400: REG_INPUTS = $10") == []
    assert trio.send("REGIST(20, 0, 1, 0, 0): REGIST(20, 1, 0, 1, 2)") == []
    # A: Z (bit 0 clear), enabled (bit 2), rising; B: input (4), enabled (6), falling (7)
    assert read(trio, "REGIST_CONTROL") == 4 + 16 + 64 + 128
    assert trio.send("FORWARD") == []
    at(trio, 1000)  # the Z mark at count 100: 0.1 k - 0.005 >= 100 from tick 1001
    assert read(trio, "MARK") == 0
    at(trio, 1001)
    assert (read(trio, "MARK"), read(trio, "REG_POS")) == (-1, 100)
    edge(trio, 2500, 0, True)  # B's input is input 0 (REG_INPUTS bits 0..3)
    edge(trio, 3000, 0, False)  # falls at 299.995: inside the window, passed over
    assert read(trio, "MARKB") == 0
    edge(trio, 5000, 0, True)
    edge(trio, 5001, 0, False)  # falls at 500.095: outside, captured
    assert read(trio, "MARKB") == -1
    assert trio.machine.registration.read("REG_POSB", 0) == pytest.approx(position(5001))
    assert read(trio, "REGIST_CONTROL") == 0  # both captured: nothing armed


def test_mode_20_captures_a_quantity_into_the_table_and_mark_counts_them() -> None:
    """The MARK page's example 2, with three captures of input 7 from TABLE(400)."""
    trio = machine()
    assert trio.send("REGIST(20, 7, 4, 0, 0, 3, 400): FORWARD") == []
    for k, tick in enumerate((100, 300, 500, 700)):
        edge(trio, tick, 7, True)
        edge(trio, tick + 50, 7, False)
        assert read(trio, "MARK") == -min(k + 1, 3)
    table = [trio.machine.table_read(400 + k) for k in range(4)]
    assert table == pytest.approx([position(100), position(300), position(500), 0.0])


def test_mode_20_window_3_takes_edges_only_while_the_gate_input_is_high() -> None:
    trio = machine()
    assert trio.send("REGIST(20, 4 + (6 << 16), 4, 0, 3): FORWARD") == []
    edge(trio, 200, 4, True)  # gate input 6 low: passed over
    edge(trio, 250, 4, False)
    edge(trio, 300, 6, True)
    edge(trio, 400, 4, True)
    assert read(trio, "MARK") == -1
    assert trio.machine.registration.read("REG_POS", 1) == pytest.approx(position(400))


def test_mode_21_time_based_channel_and_r_mark_in_a_program() -> None:
    """The page's example 5 on axis 2 (input 7, falling), and example 8's source 256 + n
    on another axis with the same input."""
    trio = machine(axis=2)
    trio.load("P", "BASE(2)\nREGIST(21, 7, 0, 1, 0)\nREGIST(21, 2, 256 + 1, 0, 0) AXIS(5)\n"
              "FORWARD\nWAIT UNTIL R_MARK(7)\nVR(1) = R_REGPOS(7)\nVR(2) = R_REGISTSPEED(7)"
              "\nWAIT UNTIL R_MARK(2) AXIS(5)\nVR(3) = TICKS")
    trio.world_view().set_input(7, True)
    assert trio.send('RUN "P"') == []
    edge(trio, 800, 7, False)  # (the program's FORWARD ran on tick 1: at 0.1 x 799 ...)
    trio.advance(ticks=5)
    assert read(trio, "VR(1)") == pytest.approx(position(800 - 1), abs=1e-9)
    assert read(trio, "VR(2)") == pytest.approx(0.1, abs=1e-9)
    assert (read(trio, "R_MARK(7) AXIS(2)"), read(trio, "R_MARK(2) AXIS(5)")) == (-1, 0)
    edge(trio, 900, 1, True)
    assert read(trio, "R_MARK(2) AXIS(5)") == -1
    assert read(trio, "R_MARK(7) AXIS(5)") == 0  # each axis has its own channels


def test_regist_control_reads_the_armed_bits_and_its_enable_bit_disarms() -> None:
    trio = machine(axis=2)
    trio.load("P", 'BASE(2)\nREGIST(20, 1, 0, 1, 0)\nIF REGIST_CONTROL.4 = 1 THEN PRINT '
              '"input"\nIF REGIST_CONTROL.6 = 1 THEN PRINT "enabled"\n'
              'IF REGIST_CONTROL.7 = 1 THEN PRINT "falling"')
    assert trio.send('RUN "P"') == []
    trio.advance(ticks=10)
    assert trio.send("?REGIST_CONTROL") == ["input", "enabled", "falling", "208"]
    stage = trio.machine.world.axes[2]
    stage.index_offset, stage.index_period, stage.index_width = 100, 100000, 4
    assert trio.send("REGIST(1): REGIST_CONTROL.2 = 0: FORWARD") == []
    at(trio, 2000)  # past the Z mark at 100: channel A was disabled
    assert read(trio, "MARK") == 0
    assert read(trio, "REGIST_CONTROL") == 16 + 64 + 128  # B still armed


def test_a_cambox_starts_on_the_link_axis_r_mark() -> None:
    """CAMBOX option 512, channel 3 in link pos: the profile 0, 100, 300, 400 over 10
    units starts where R_MARK(3) of the link axis captured."""
    trio = machine()
    assert trio.send("TABLE(0, 0, 100, 300, 400)") == []
    assert trio.send("REGIST(21, 3, 0, 0, 0) AXIS(1)") == []
    assert trio.send("CAMBOX(0, 3, 1, 10, 1, 512, 3) AXIS(0): FORWARD AXIS(1)") == []
    edge(trio, 250, 3, True)  # the link at 24.995
    start = position(250)
    assert trio.machine.dpos(0) == 0
    at(trio, 300)  # 5 units on: half way, 1.5 segments into 0, 100, 300, 400: 200
    assert position(300) - start == pytest.approx(5.0)
    assert trio.machine.dpos(0) == pytest.approx(200.0, abs=1e-6)
    assert read(trio, "MTYPE AXIS(0)") == 20


def test_a_movelink_starts_on_the_link_axis_r_mark() -> None:
    trio = machine()
    assert trio.send("REGIST(21, 0, 0, 1, 0) AXIS(1)") == []
    trio.world_view().set_input(0, True)
    assert trio.send("MOVELINK(10, 20, 0, 0, 1, 512, 0) AXIS(0): FORWARD AXIS(1)") == []
    edge(trio, 400, 0, False)  # falls with the link at 39.995
    at(trio, 500)  # 10 units of link since: half the move
    assert trio.machine.dpos(0) == pytest.approx((position(500) - position(400)) / 2,
                                                 abs=1e-6)


@pytest.mark.parametrize("line", [
    "REGIST(5)",  # reserved
    "REGIST(18)",
    "REGIST(22, 0, 0, 0, 0)",  # the Flexaxis's eight channels
    "REGIST(20, 2, 0, 0, 0)",  # channels A and B only
    "REGIST(20, 0, 3, 0, 0)",  # no source 3
    "REGIST(20, 0, 0, 0, 7)",  # no window 7 on the page (5/6: OPEN_WINB)
    "REGIST(21, 8, 0, 0, 0)",  # channels 0..7
    "REGIST(20, 0, 0, 0, 0, 10, 511995)",  # past the end of TABLE
    "REGIST(1, 2)",
    "MOVELINK(1, 10, 0, 0, 1, 512, 9) AXIS(0)",  # R_MARK channels 0..7
    "CAMBOX(0, 3, 1, 10, 1, 512 + 1, 3) AXIS(0)",  # two start events
])
def test_bad_registration_is_refused_and_arms_nothing(line: str) -> None:
    trio = machine()
    assert trio.send("REGIST(3)") == []  # armed before: stays as it was
    reply = trio.send(line)
    assert reply and "Parameter out of range" in reply[0], reply
    assert read(trio, "REGIST_CONTROL") == 1 + 4
    assert read(trio, "MTYPE AXIS(0)") == 0 and read(trio, "NTYPE AXIS(0)") == 0
    assert trio.send("?R_MARK(8)")[0].endswith("Parameter out of range")


def test_the_z_mark_of_an_encoder_axis_on_the_steppers_shaft() -> None:
    """A calibration stage's index check: REGIST(20, 0, 1, 0, 0) on the encoder axis 2
    (ATYPE 76, UNITS -1.5625) while the stepper axis 6 (UNITS 16) moves; the encoder
    turns -1.5625 / 16 counts a step. The stepper runs 6300 t - 315 units after its 0.1 s
    ramp; the encoder's index at -7000..-6997 counts is met going down at -6997, i.e. at
    6997 / 1.5625 = 4478.08 units: t = 4793.08 / 6300 = 0.76081 s, tick 761."""
    trio = MC405()
    assert trio.send("ATYPE AXIS(2) = 76: UNITS AXIS(2) = -1.5625") == []
    assert trio.send("ATYPE AXIS(6) = 43: UNITS AXIS(6) = 16: SPEED AXIS(6) = 6300: "
                     "ACCEL AXIS(6) = 63000: DECEL AXIS(6) = 63000") == []
    trio.world_view().set_shaft_encoder("2", "6", -1.5625 / 16)
    stage = trio.machine.world.axes[2]
    stage.index_period, stage.index_offset, stage.index_width = 10000, -7000, 4
    assert trio.send("BASE(2): REGIST(20, 0, 1, 0, 0): MOVE(7500) AXIS(6)") == []
    at(trio, 760)
    assert read(trio, "MARK AXIS(2)") == 0
    at(trio, 761)
    assert read(trio, "MARK AXIS(2)") == -1
    assert trio.machine.registration.read("REG_POS", 2) == pytest.approx(4478.08, abs=1e-9)

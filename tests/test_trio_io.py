"""The MC405's inputs as wired, from the help pages: the inputs FWD_IN, REV_IN and
DATUM_IN name are active low (their function is on while IN reads 0), the world's
switches are wired normally closed, and INVERT_IN inverts an input in software for
what IN reads and for the functions it drives.

Figures as in test_trio_drive: SPEED 1000 counts/s reached at ACCEL 100000 in 10 servo
cycles (5 counts), so a move from rest passes count p (p >= 5) on tick 5 + p."""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405
from tests.test_trio_drive import FAST, at, dpos, mc405


def ask(trio: MC405, query: str) -> str:
    return trio.query(query)


def test_a_limit_input_reads_1_away_and_0_at_the_limit() -> None:
    """FWD_IN's page: the input is active low; AXISSTATUS bit 4 while it is active."""
    trio = mc405(FAST, "FWD_IN=19")
    trio.world_view().set_limits("0", plus=300)
    assert (ask(trio, "?IN(19)"), ask(trio, "?AXISSTATUS")) == ("1", "0")
    trio.send("MOVE(1000)")
    at(trio, 304)
    assert (ask(trio, "?IN(19)"), ask(trio, "?AXISSTATUS")) == ("1", "0")  # count 299
    at(trio, 305)  # count 300: the switch opens, the input goes low, the move is cancelled
    assert (dpos(trio), ask(trio, "?IN(19)"), ask(trio, "?AXISSTATUS")) == (300.0, "0", "16")


def test_an_input_nothing_is_wired_to_reads_0() -> None:
    trio = mc405()
    assert ask(trio, "?IN(12)") == "0"
    trio.send("REV_IN=12")  # now the reverse limit switch (far away, closed) drives it
    assert ask(trio, "?IN(12)") == "1"


def test_invert_in_reads_and_sets_the_inversion() -> None:
    """INVERT_IN's page: one argument reads ON/OFF; the two-argument form sets it (and
    as a function returns TRUE)."""
    trio = mc405("REV_IN=6")
    assert (ask(trio, "?INVERT_IN(6)"), ask(trio, "?IN(6)")) == ("0", "1")
    trio.send("INVERT_IN(6, ON)")
    assert (ask(trio, "?INVERT_IN(6)"), ask(trio, "?IN(6)")) == ("1", "0")
    assert ask(trio, "?INVERT_IN(6, OFF)") == "-1"
    assert (ask(trio, "?INVERT_IN(6)"), ask(trio, "?IN(6)")) == ("0", "1")
    trio.send("INVERT_IN(30, ON)")  # an input nothing drives reads 1 inverted
    assert ask(trio, "?IN(30)") == "1"


def test_an_inverted_limit_input_is_active_away_from_its_switch() -> None:
    """A normally closed switch on an inverted input: the limit is on where the switch
    is closed, so a move towards it is cancelled as it starts (no step)."""
    trio = mc405(FAST, "FWD_IN=3", "INVERT_IN(3, ON)")
    trio.world_view().set_limits("0", plus=300)
    assert ask(trio, "?AXISSTATUS") == "16"
    trio.send("MOVE(100)")
    assert trio.run_until_idle()
    assert dpos(trio) == 0.0
    trio.send("INVERT_IN(3, OFF)")
    assert ask(trio, "?AXISSTATUS") == "0"
    trio.send("MOVE(100)")
    assert trio.run_until_idle() and dpos(trio) == 100.0


def test_a_world_level_on_a_limit_input_acts_when_it_goes_low() -> None:
    trio = mc405(FAST, "FWD_IN=7")
    trio.world_view().set_input(7, True)  # the sensor holds the input high: no limit
    trio.send("FORWARD")
    at(trio, 1000)
    assert ask(trio, "?AXISSTATUS") == "0"
    trio.world_view().set_input(7, False)
    assert ask(trio, "?AXISSTATUS") == "16"
    assert trio.run_until_idle()
    assert trio.machine.tick == 1100  # looked at on its tick, ramped down over 100 cycles


def test_datum_homes_on_a_normally_open_sensor_through_an_inverted_input() -> None:
    """DATUM_IN's second example, with our own numbers: a normally open proximity sensor
    (the world drives input 5 high while the axis is on it, counts 600..700) needs its
    input inverted; DATUM(3) then homes exactly as on a normally closed switch."""
    def sensor(board: object) -> bool:
        steps = trio.machine.demand(0)
        return 600 <= steps <= 700

    trio = mc405("SPEED=2000", "ACCEL=20000", "DECEL=20000", "CREEP=100")
    trio.world_view().set_input(5, sensor)
    trio.send("INVERT_IN(5, 1)")
    trio.send("DATUM_IN = 5")
    assert ask(trio, "?IN(5)") == "1"  # off the sensor: inverted low reads 1
    trio.send("DATUM(3)")
    assert trio.run_until_idle(5)
    # forward onto the sensor, back off it at CREEP: zero where it lets go, ending on its
    # edge count 600 (inside 600..700: the sensor is on, the inverted input reads 0)
    assert (trio.world_view().reading("0").position, dpos(trio), ask(trio, "?IN(5)")) == \
        (600, 0.0, "0")
    # the same as the world's own home switch on the same counts, wired normally closed
    closed = mc405("SPEED=2000", "ACCEL=20000", "DECEL=20000", "CREEP=100", "DATUM_IN = 5")
    closed.world_view().set_home("0", 600, 700)
    closed.send("DATUM(3)")
    assert closed.run_until_idle(5)
    assert (closed.machine.tick, closed.world_view().reading("0").position,
            ask(closed, "?IN(5)")) == (trio.machine.tick, 600, "0")


# ---- encoder axes and negative UNITS ------------------------------------------------
ONE_REV = 200 * 32 * 16  # a 200-step motor at 1/32 microstepping, x16 in the controller
ENCODER_REV = 2500 * 4  # a 2500-line encoder in quadrature


def stage_with_shaft_encoder() -> MC405:
    """A stepper on axis 4 with an encoder on its shaft wired to axis 0's encoder input
    (ATYPE 76), counting the other way: the encoder axis's UNITS is negative so that it
    reads in the stepper's direction, microsteps on both axes."""
    trio = mc405("ATYPE AXIS(0) = 76", "ATYPE AXIS(4) = 43", "UNITS AXIS(4) = 16",
                 "SPEED AXIS(4) = 6400", "ACCEL AXIS(4) = 64000", "DECEL AXIS(4) = 64000",
                 "UNITS AXIS(0) = -1.5625")
    trio.world_view().set_shaft_encoder("0", "4", -ENCODER_REV / ONE_REV)
    return trio


def test_an_encoder_axis_reads_the_encoder_on_another_axiss_motor() -> None:
    trio = stage_with_shaft_encoder()
    assert ask(trio, "?MPOS AXIS(0)") == "0"
    trio.send("MOVE(6400) AXIS(4)")  # one revolution of the motor
    assert trio.run_until_idle()
    # the encoder turned one revolution backwards: -10000 counts / -1.5625 = 6400
    assert (ask(trio, "?MPOS AXIS(0)"), ask(trio, "?DPOS AXIS(0)"), ask(trio, "?FE AXIS(0)"),
            ask(trio, "?DPOS AXIS(4)")) == ("6400", "6400", "0", "6400")


def test_defpos_on_the_encoder_axis_zeroes_its_encoder_reading() -> None:
    trio = stage_with_shaft_encoder()
    trio.send("MOVE(1000) AXIS(4)")
    assert trio.run_until_idle()
    trio.send("DEFPOS(0) AXIS(0)")
    assert ask(trio, "?MPOS AXIS(0)") == "0"
    trio.send("MOVE(-3200) AXIS(4)")
    assert trio.run_until_idle()
    assert ask(trio, "?MPOS AXIS(0)") == "-3200"


def test_the_shaft_encoder_sees_the_steps_a_stalled_motor_missed() -> None:
    """What a stall detector compares: the stepper's demand ran on, its shaft (and the
    encoder on it) did not."""
    trio = stage_with_shaft_encoder()
    trio.send("MOVE(640) AXIS(4)")  # 10240 counts
    assert trio.run_until_idle()
    trio.world_view().miss_steps("4", 1024)  # the motor slipped 64 microsteps
    # 10240 - 1024 counts turned: 9216 * -10000/102400 = -900 encoder counts -> 576
    assert (ask(trio, "?DPOS AXIS(4)"), ask(trio, "?MPOS AXIS(0)")) == ("640", "576")


def test_an_axis_of_another_type_keeps_its_own_position() -> None:
    trio = stage_with_shaft_encoder()
    trio.send("ATYPE AXIS(0) = 43")
    trio.send("MOVE(100) AXIS(4)")
    assert trio.run_until_idle()
    assert ask(trio, "?MPOS AXIS(0)") == "0"


def test_negative_units_refuse_rates_and_zero_units_is_refused() -> None:
    trio = stage_with_shaft_encoder()
    for rate in ("SPEED", "ACCEL", "DECEL", "CREEP", "FASTDEC"):
        assert trio.send(f"{rate} AXIS(0) = 10") != [], rate
    trio.send("SPEED AXIS(0) = 0")  # 0 is no rate in either direction
    assert trio.send("UNITS AXIS(0) = 0") != []
    assert ask(trio, "?UNITS AXIS(0)") == "-1.5625"
    assert trio.send("MOVE(5) AXIS(0)") != []  # (D: no planner for a negative UNITS)
    trio.send("UNITS AXIS(0) = 1.5625")
    assert trio.send("SPEED AXIS(0) = 10") == []


def test_the_shaft_encoder_world_setting() -> None:
    from maxk.controllers.world_settings import parse_world

    trio = mc405("ATYPE AXIS(1) = 76")
    assert parse_world("1 shaft-encoder 3 -0.5")(trio) == "1 shaft-encoder 3 -0.5"
    trio.send("MOVE(1000) AXIS(3)")
    assert trio.run_until_idle()
    assert ask(trio, "?MPOS AXIS(1)") == "-500"
    assert parse_world("1 shaft-encoder none")(trio) == "1 shaft-encoder none"
    assert ask(trio, "?MPOS AXIS(1)") == "0"
    for bad in ("1 shaft-encoder 3 0", "1 shaft-encoder 3 x", "1 shaft-encoder 99"):
        try:
            parse_world(bad)(trio)
        except (ValueError, KeyError):
            continue
        raise AssertionError(bad)


# ---- SCOPE and TRIGGER --------------------------------------------------------------
def test_scope_samples_parameters_into_their_table_blocks_after_trigger() -> None:
    """SCOPE's first example with our numbers: two parameters over TABLE 0..200 have 100
    values each (0..99 and 100..199), a sample every 10 servo cycles from TRIGGER."""
    trio = mc405(FAST, "SCOPE(ON, 10, 0, 200, DPOS, VP_SPEED)")
    trio.send("TRIGGER")
    start = trio.machine.tick
    trio.send("MOVE(5000)")
    at(trio, start + 100)
    # sample k is taken on tick start + 10k; the move passes count p on tick 5 + p
    dpos_samples = [float(trio.query(f"?TABLE({k})")) for k in range(11)]
    assert dpos_samples == [0.0] + [10.0 * k - 5 for k in range(1, 11)]
    assert [float(trio.query(f"?TABLE({100 + k})")) for k in (0, 1, 10)] == [0, 1000, 1000]
    assert trio.query("?SCOPE_POS") == "11"


def test_scope_fills_its_blocks_once_then_stops() -> None:
    trio = mc405("SCOPE(ON, 1, 50, 53, TICKS)", "TABLE(54, 7)")
    trio.send("TRIGGER")
    trio.advance(ticks=20)
    assert trio.query("?SCOPE_POS") == "4"  # 50..53: table_stop is the last one used
    assert trio.query("?TABLE(54)") == "7.0000"  # past table_stop: untouched


def test_scope_off_prevents_trigger_and_a_new_period_applies() -> None:
    trio = mc405("SCOPE(ON, 5, 0, 10, DPOS)", "SCOPE(OFF)", "TABLE(1, -1)")
    trio.send("TRIGGER")
    trio.advance(ticks=20)
    assert trio.query("?TABLE(1)") == "-1.0000"  # nothing captured
    trio.send("SCOPE(ON, 5, 0, 10, MPOS)")
    trio.send("SCOPE(ON, 2)")  # the period changed before the capture
    trio.send("TRIGGER")
    trio.advance(ticks=9)
    assert trio.query("?SCOPE_POS") == "5"  # samples on ticks 0, 2, 4, 6, 8 of the scan

"""TIME, DATE, DAY, RND, RNDF, RANDOMIZE and INPUTS0/1 from their help pages (own
figures, derived by hand): the real time clock starts at 00:00:00 on Saturday
01/01/2000 at power up and runs with virtual time."""

from __future__ import annotations

import pytest

from tests.trio_helpers import Rig


def ask(rig: Rig, expr: str) -> str:
    return rig.command("?" + expr).decode()


def test_the_clock_at_power_up_and_after_virtual_time() -> None:
    rig = Rig()
    assert (ask(rig, "TIME"), ask(rig, "DATE"), ask(rig, "DAY"), ask(rig, "DAY$")) == \
        ("0", "0", "6", "Saturday")  # 01/01/2000 was a Saturday
    rig.cycles(2500)  # 2.5 s at the fake's 1 ms servo cycle
    assert ask(rig, "TIME") == "2"


def test_time_is_set_in_24_hour_form_and_read_in_seconds() -> None:
    rig = Rig()
    rig.command("TIME = 7:45:10")
    assert ask(rig, "TIME") == str(7 * 3600 + 45 * 60 + 10)
    assert ask(rig, "TIME$") == "07:45:10"
    assert b"Parameter out of range" in rig.send("TIME = 24:00:00")
    assert ask(rig, "TIME$") == "07:45:10"  # nothing set


def test_time_set_from_variables_in_a_program() -> None:
    rig = Rig()
    rig.load("CLK", "hh = 21\nmm = 5\nss = 59\nTIME = hh:mm:ss\nVR(1) = TIME")
    rig.command('RUN "CLK"')
    rig.cycles(10)
    assert ask(rig, "VR(1)") == f"{21 * 3600 + 5 * 60 + 59}.0000"  # a VR is FLOAT


def test_date_set_two_and_four_digit_years_and_read_back() -> None:
    rig = Rig()
    rig.command("DATE = 03:02:2001")
    # 2000 had 366 days, then 31 of January and 2 more: 399 days after 01/01/2000
    assert (ask(rig, "DATE"), ask(rig, "DATE$")) == ("399", "03/02/2001")
    assert (ask(rig, "DATE(0)"), ask(rig, "DATE(1)"), ask(rig, "DATE(2)")) == \
        ("3", "2", "2001")
    assert ask(rig, "DAY") == "6"  # 03/02/2001 was a Saturday too: 399 = 57 weeks
    rig.command("DATE = 04:02:01")
    assert (ask(rig, "DATE"), ask(rig, "DAY"), ask(rig, "DAY$")) == ("400", "0", "Sunday")
    for bad in ("DATE = 30:02:2001", "DATE = 01:01:2100", "DATE = 01:13:01"):
        assert b"Parameter out of range" in rig.send(bad), bad
    assert ask(rig, "DATE") == "400"


def test_rnd_ranges() -> None:
    rig = Rig()
    draws = [float(ask(rig, "RND(1 << 8)")) for _ in range(200)]
    assert all(0 <= d < 256 and d == int(d) for d in draws) and len(set(draws)) > 50
    signed = [float(ask(rig, "RND(-100, 100)")) for _ in range(200)]
    assert min(signed) < 0 <= max(signed) < 100 and min(signed) >= -100
    whole = float(ask(rig, "RND"))
    assert 0 <= whole < 2 ** 32
    fractions = [float(ask(rig, "RNDF(2.5, 3)")) for _ in range(50)]
    assert all(2.5 <= f < 3 for f in fractions)
    assert b"Parameter out of range" in rig.send("?RND(5, 5)")


def test_randomize_with_a_seed_repeats_the_sequence() -> None:
    rig = Rig()
    rig.command("RANDOMIZE(0)")
    first = [ask(rig, "RND(1000)") for _ in range(5)]
    rig.command("RANDOMIZE(0)")
    assert [ask(rig, "RND(1000)") for _ in range(5)] == first
    rig.command("RANDOMIZE(1)")
    assert [ask(rig, "RND(1000)") for _ in range(5)] != first


@pytest.mark.parametrize(("high", "expected"), [((), "0\t0"), ((3,), "8\t0"),
                                                 ((3, 18), "8\t4")])
def test_inputs0_and_inputs1_sum_the_inputs(high: tuple[int, ...], expected: str) -> None:
    rig = Rig()
    for n in high:
        rig.machine.inputs[n] = True
    assert ask(rig, "INPUTS0, INPUTS1") == expected


# ---- TIMER and CONTROL ----------------------------------------------------------------
def test_timer_turns_an_output_on_for_its_time() -> None:
    """TIMER's first example with our numbers: output 9 on for 30 ms (30 servo cycles
    of 1 ms), then off on its own."""
    rig = Rig()
    rig.command("TIMER(0, 9, 1, 30)")
    assert ask(rig, "READ_OP(9)") == "1"
    rig.cycles(29)
    assert ask(rig, "READ_OP(9)") == "1"
    rig.cycles(1)
    assert ask(rig, "READ_OP(9)") == "0"


def test_timer_pattern_and_option_1_turn_a_group_off_then_on() -> None:
    """TIMER's second example: pattern 13 (1101) from output 10 is outputs 10, 12, 13;
    option 1 turns them off for the time, output 11 is left alone."""
    rig = Rig()
    for n in (10, 11, 12, 13):
        rig.command(f"OP({n}, ON)")
    rig.command("TIMER(5, 10, 13, 70, 1)")
    assert ask(rig, "READ_OP(10, 13)") == str(0b0010)
    rig.cycles(70)
    assert ask(rig, "READ_OP(10, 13)") == str(0b1111)
    assert b"Parameter out of range" in rig.send("TIMER(128, 1, 1, 10)")


def test_a_timer_ends_on_its_tick_on_the_mc405_engine() -> None:
    from tests.test_trio_drive import at, mc405

    trio = mc405()
    trio.send("TIMER(1, 4, 1, 250)")
    start = trio.machine.tick
    at(trio, start + 249)
    assert trio.query("?READ_OP(4)") == "1"
    at(trio, start + 250)
    assert trio.query("?READ_OP(4)") == "0"


def test_control_is_the_mc405s_id() -> None:
    assert ask(Rig(), "CONTROL") == "405"


# ---- small functions and parameters from their pages --------------------------------
def test_acos_and_asin() -> None:
    rig = Rig()
    assert ask(rig, "ACOS(-1)") == "3.1416"  # the page's example: PI
    assert ask(rig, "ASIN(0.5) * 6") == "3.1416"  # asin(1/2) = PI/6
    assert b"Parameter out of range" in rig.send("?ACOS(1.5)")


def test_is_nan_and_is_inf_of_held_values() -> None:
    rig = Rig()
    rig.command("VR(7) = 1e300")
    assert ask(rig, "IS_NAN(VR(7)), IS_INF(VR(7))") == "0\t0"


def test_analog_channels_as_parameters() -> None:
    rig = Rig()
    rig.machine.analog[1] = 5.0  # half of 10 V: 2047 / 2, rounded
    assert ask(rig, "AIN1, AINBI1, AIN(1)") == "1024\t1024\t1024"
    rig.command("AOUT2 = 300")
    assert ask(rig, "AOUT(2), AOUT2") == "300\t300"
    assert ask(rig, "NIN, NOP") == "32\t32"

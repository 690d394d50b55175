"""The MC405 PWM personality: registers, PWM_CONTROL modes, the gating FIFO, PWM_ENCODER."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.personalities.trio import (
    GATE_FIFO_DEPTH,
    PWM_ENCODER_MODULUS,
    GateEntry,
    PwmBank,
    PwmError,
    PwmMode,
    PwmOutput,
    TableMemory,
    VrMemory,
)
from maxk.personalities.trio.memory import MemoryRangeError
from maxk.personalities.trio.pwm import DECISIONS


def output_with_table(*values: float, start: int = 1000) -> tuple[PwmOutput, TableMemory]:
    table = TableMemory()
    table.write(start, values)
    return PwmOutput(0), table


def test_frequency_from_the_20mhz_clock() -> None:
    pwm = PwmOutput(0)
    pwm.set_cycle(1000)
    assert pwm.frequency_hz == 20_000.0
    pwm.set_cycle(200)
    assert pwm.frequency_hz == 100_000.0


@pytest.mark.parametrize("value", [0, -1, 65536, 1e9, float("nan")])
def test_cycle_out_of_range_is_refused_and_unchanged(value: float) -> None:
    pwm = PwmOutput(0)
    pwm.set_cycle(500)
    with pytest.raises(PwmError):
        pwm.set_cycle(value)
    assert pwm.cycle == 500


@pytest.mark.parametrize("value", [-1, 65536])
def test_mark_out_of_range_is_refused_and_unchanged(value: float) -> None:
    pwm = PwmOutput(0)
    pwm.set_mark(400)
    with pytest.raises(PwmError):
        pwm.set_mark(value)
    assert pwm.mark == 400


def test_register_limits_accepted_and_fractions_truncate() -> None:
    pwm = PwmOutput(0)
    pwm.set_cycle(65535)
    pwm.set_mark(65535)
    assert (pwm.cycle, pwm.mark) == (65535, 65535)
    pwm.set_mark(400.9)
    assert pwm.mark == 400


def test_duty_needs_mode_wdog_and_a_pwm_atype() -> None:
    pwm, table = output_with_table()
    pwm.set_cycle(1000)
    pwm.set_mark(250)
    assert pwm.duty(wdog=True, atype=35) == 0.0  # mode 0: off
    pwm.control([1], table, 1.0, 16)
    assert pwm.duty(wdog=True, atype=35) == 0.25
    assert pwm.duty(wdog=True, atype=36) == 0.25
    assert pwm.duty(wdog=False, atype=35) == 0.0
    assert pwm.duty(wdog=True, atype=43) == 0.0


@pytest.mark.parametrize("mark, duty", [(999, 0.999), (1000, 1.0), (5000, 1.0), (0, 0.0)])
def test_mark_at_or_above_cycle_is_continuously_on(mark: int, duty: float) -> None:
    pwm, table = output_with_table()
    pwm.control([1], table, 1.0, 16)
    pwm.set_cycle(1000)
    pwm.set_mark(mark)
    assert pwm.duty(True, 35) == duty


def test_mode_2_mark_follows_vp_speed_with_limit() -> None:
    """Seed example 1: mark = VP_SPEED*0.1 + 50, limited at 500 (above speed 4500)."""
    pwm, table = output_with_table()
    pwm.control([2, 0.1, 50, 500, 0], table, 1.0, 16)
    assert pwm.mode is PwmMode.SPEED and pwm.links == (0, None)
    for speed, mark in [(0, 50), (2000, 250), (4500, 500), (5000, 500), (1234.5, 173)]:
        pwm.servo_cycle(speed)
        assert pwm.mark == mark


def test_mode_8_mark_is_speed_times_amplitude() -> None:
    """Seed example 2: VP_SPEED(link) * DPOS(9) * mult + offset, limited."""
    pwm, table = output_with_table()
    pwm.control([8, 1 / 10000, 50, 500, 0, 9], table, 1.0, 16)
    assert pwm.links == (0, 9)
    pwm.servo_cycle(5000, 500)
    assert pwm.mark == 300
    pwm.servo_cycle(5000, 1000)
    assert pwm.mark == 500  # 550 limited
    pwm.servo_cycle(5000, 0)
    assert pwm.mark == 50


def test_computed_mark_clamped_to_register() -> None:
    pwm, table = output_with_table()
    pwm.control([2, -1, 0, 100000, 0], table, 1.0, 16)
    pwm.servo_cycle(10)
    assert pwm.mark == 0
    pwm.control([2, 100, 0, 1e9, 0], table, 1.0, 16)
    pwm.servo_cycle(10000)
    assert pwm.mark == 65535


def test_mark_stays_after_leaving_speed_mode() -> None:
    pwm, table = output_with_table()
    pwm.control([2, 0.1, 50, 500, 0], table, 1.0, 16)
    pwm.servo_cycle(2000)
    pwm.control([1], table, 1.0, 16)
    pwm.servo_cycle(4000)  # mode 1: no reload
    assert pwm.mark == 250


@pytest.mark.parametrize("args", [
    [], [9], [2.5], [-1], [7], [2, 0.1, 50, 500], [2, 0.1, 50, 500, 16], [2, 1, 2, 3, 0.5],
    [8, 1, 2, 3, 0], [8, 1, 2, 3, 0, 99], [1, 0], [3, 1, 1, 1003, 1000],
])
def test_refused_control_changes_nothing(args: list[float]) -> None:
    pwm, table = output_with_table(1, 2, 3, 4)
    pwm.control([1], table, 1.0, 16)
    pwm.set_mark(77)
    with pytest.raises(PwmError):
        pwm.control(args, table, 1.0, 16)
    assert (pwm.mode, pwm.mark, len(pwm.fifo), pwm.gating) == (PwmMode.MARK, 77, 0, False)


def test_gate_fifo_loads_toggling_levels_in_counts() -> None:
    """Seed example 3: positions 110,115,195,220 (user units, UNITS=16), GT, starting ON."""
    pwm, table = output_with_table(110, 115, 195, 220)
    pwm.control([3, 1, 1, 1000, 1003], table, 16.0, 16)
    assert [(e.position, e.greater, e.level) for e in pwm.pending_gates()] == [
        (1760, True, True), (1840, True, False), (3120, True, True), (3520, True, False)]


def test_gates_fire_in_order_as_the_encoder_passes() -> None:
    pwm, table = output_with_table(110, 115, 195, 220)
    pwm.control([5], table, 1.0, 16)
    pwm.encoder = 100
    pwm.control([3, 1, 1, 1000, 1003], table, 1.0, 16)
    assert not pwm.gate_open
    assert pwm.move_encoder(10) == []  # at 110: not yet past
    assert [e.level for e in pwm.move_encoder(1)] == [True]
    assert pwm.gate_open
    assert pwm.next_gate() == GateEntry(115, True, False)
    assert pwm.next_gate().counts_to_pass(pwm.encoder) == 5  # type: ignore[union-attr]
    fired = pwm.move_encoder(100)  # 211: passes 115 and 195 in one step
    assert [e.position for e in fired] == [115, 195]
    assert pwm.gate_open
    pwm.move_encoder(10)
    assert not pwm.gate_open and pwm.next_gate() is None


def test_lt_gates_for_the_reverse_pass() -> None:
    pwm, table = output_with_table(220, 195, 115, 110)
    pwm.control([5], table, 1.0, 16)
    pwm.encoder = 300
    pwm.control([3, 0, 1, 1000, 1003], table, 1.0, 16)
    levels = []
    for _ in range(300):
        levels += [(pwm.encoder, e.level) for e in pwm.move_encoder(-1)]
    assert levels == [(219, True), (194, False), (114, True), (109, False)]


def test_combined_output_is_pwm_and_gate() -> None:
    pwm, table = output_with_table(10, 20)
    pwm.control([1], table, 1.0, 16)
    pwm.set_mark(400)
    assert pwm.duty(True, 35) == 0.4  # gating off: the PWM alone
    pwm.control([5], table, 1.0, 16)
    assert pwm.duty(True, 35) == 0.0  # gate closed
    pwm.control([3, 1, 1, 1000, 1001], table, 1.0, 16)
    pwm.move_encoder(11)
    assert pwm.duty(True, 35) == 0.4
    pwm.move_encoder(10)
    assert pwm.duty(True, 35) == 0.0


def test_fifo_depth_512_and_overflow_refused_whole() -> None:
    table = TableMemory()
    table.write(0, [float(i + 1) for i in range(600)])
    pwm = PwmOutput(0)
    pwm.control([3, 1, 1, 0, 499], table, 1.0, 16)
    assert len(pwm.fifo) == 500
    with pytest.raises(PwmError):
        pwm.control([3, 1, 1, 0, 12], table, 1.0, 16)  # 13 more: 513
    assert len(pwm.fifo) == 500
    pwm.control([3, 1, 1, 0, 11], table, 1.0, 16)
    assert len(pwm.fifo) == GATE_FIFO_DEPTH


def test_mode_4_empties_fifo_keeps_gate_mode_6_clears_encoder() -> None:
    pwm, table = output_with_table(5, 50)
    pwm.control([5], table, 1.0, 16)
    pwm.control([3, 1, 1, 1000, 1001], table, 1.0, 16)
    pwm.move_encoder(6)
    pwm.control([4], table, 1.0, 16)
    assert pwm.next_gate() is None and pwm.gate_level
    pwm.control([6], table, 1.0, 16)
    assert pwm.encoder == 0
    pwm.control([0], table, 1.0, 16)
    assert pwm.mode is PwmMode.OFF and not pwm.gating


def test_encoder_is_29_bits_and_wraps() -> None:
    pwm = PwmOutput(0)
    pwm.move_encoder(-1)
    assert pwm.encoder == PWM_ENCODER_MODULUS - 1 == 536870911
    pwm.move_encoder(2)
    assert pwm.encoder == 1


def test_gate_compare_across_the_wrap() -> None:
    table = TableMemory()
    table.write(0, [-2])  # -2 user units: just below zero
    pwm = PwmOutput(0)
    pwm.control([3, 0, 1, 0, 0], table, 1.0, 16)
    assert pwm.next_gate() == GateEntry(PWM_ENCODER_MODULUS - 2, False, True)
    assert pwm.move_encoder(-2) == []
    assert len(pwm.move_encoder(-1)) == 1


@given(st.lists(st.integers(-50, 50), min_size=1, max_size=60))
def test_encoder_tracks_the_sum_of_moves(steps: list[int]) -> None:
    pwm = PwmOutput(0)
    for s in steps:
        pwm.move_encoder(s)
    assert pwm.encoder == sum(steps) % PWM_ENCODER_MODULUS


@given(st.lists(st.integers(1, 400), min_size=1, max_size=20, unique=True))
def test_sweeping_past_sorted_gates_fires_each_once_alternating(positions: list[int]) -> None:
    positions.sort()
    table = TableMemory()
    table.write(0, positions)
    pwm = PwmOutput(0)
    pwm.control([3, 1, 1, 0, len(positions) - 1], table, 1.0, 16)
    fired = []
    for _ in range(401):
        fired += [(pwm.encoder, e.level) for e in pwm.move_encoder(1)]
    assert [p for p, _ in fired] == [p + 1 for p in positions]
    assert [lvl for _, lvl in fired] == [i % 2 == 0 for i in range(len(positions))]


def test_bank_covers_axes_0_to_4_and_updates_linked_marks() -> None:
    bank = PwmBank(16)
    assert sorted(bank.outputs) == [0, 1, 2, 3, 4]
    with pytest.raises(PwmError):
        bank[5]
    table = TableMemory()
    bank[4].control([2, 0.1, 50, 500, 0], table, 1.0, 16)
    bank[3].control([8, 0.001, 0, 1000, 1, 9], table, 1.0, 16)
    bank.servo_cycle(lambda a: {0: 2000.0, 1: 3000.0}.get(a, 0.0),
                     lambda a: 100.0 if a == 9 else 0.0)
    assert (bank[4].mark, bank[3].mark) == (250, 300)


def test_memory_ranges() -> None:
    table, vr = TableMemory(10), VrMemory(4)
    table.write(8, [1, 2])
    assert table.read_run(8, 9) == [1.0, 2.0]
    with pytest.raises(MemoryRangeError):
        table.write(9, [1, 2])
    assert table.read(9) == 2.0
    vr.write(3, 5)
    with pytest.raises(MemoryRangeError):
        vr.read(4)


def test_every_decision_has_a_confidence_and_source() -> None:
    assert DECISIONS and all(d.confidence in "CID" and d.source for d in DECISIONS)

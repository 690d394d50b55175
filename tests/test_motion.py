"""Stepper motion on the board: exact positions, tick-true timing, multi-axis starts."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk import MAXk


def done_tick(board: MAXk, axis: str = "X", timeout: float = 60.0) -> int:
    assert board.run_until_done(axis, timeout=timeout)
    return board.tick


def test_manual_single_axis_example(board):
    # Appendix C: AX; VL5000; AC50000; MA10000; GO; ID;  (2.1 s trapezoid)
    board.send("AX; VL5000; AC50000; MA10000; GO; ID;")
    assert board.query("RP") == "0"
    assert done_tick(board) == math.ceil(2.1 * 8192)  # 17204: analytic time, next tick
    assert board.query("RP") == "10000"
    assert board.query("RE") == "10000"
    assert board.query("QA") == "PDNN"


def test_position_and_velocity_mid_move_follow_the_profile(board):
    board.send("AX; VL5000; AC50000; MA10000; GO;")
    board.advance(ticks=8192)  # exactly 1 s: ramp 0.1 s (250 steps) + 0.9 s slew
    assert board.query("RP") == str(250 + 4500)
    assert board.query("RV") == "5000"
    board.advance(ticks=8192 + 819)  # 2.09998 s: in the ramp down
    assert 9990 < int(board.query("RP")) < 10000
    assert 0 < int(board.query("RV")) < 5000


def test_triangle_profile_timing(board):
    board.send("AX; VL5000; AC50000; MR100; GO; ID;")
    analytic = 2 * math.sqrt(100 * 50_000) / 50_000 * 8192
    tick = done_tick(board)
    assert analytic <= tick < analytic + 1
    assert board.position("X") == 100


@settings(max_examples=60, deadline=None)
@given(st.integers(-3_000_000, 3_000_000), st.integers(1, 4_176_000), st.integers(1, 8_000_000),
       st.sampled_from(["LA", "PN", "SC", "CN"]), st.sampled_from([1024, 8192]))
def test_point_to_point_moves_end_exactly_on_target(target, vl, ac, ramp, rate):
    board = MAXk("MAXk-1000", rate)
    board.send(f"AX; {ramp}; VL{vl}; AC{ac}; MA{target}; GO; ID;")
    motion = board.board.axes[0].motion
    expected_end = 0 if motion is None else math.ceil(motion.end_time * rate - 1e-9)
    assert board.run_until_done("X", timeout=1e8)  # VL1 moves take days
    assert board.query("RP") == str(target)
    assert board.tick == expected_end
    assert board.query("RV") == "0"


def test_vb_start_and_decimal_relative_move(board):
    board.send("AX; VB100; VL4000; AC19500; MR-200.9; GD; ID;")
    done_tick(board)
    assert board.position("X") == -200  # the .9 work-around: truncation toward zero
    assert board.query("QA") == "MDNN"


def test_dc_sets_a_separate_deceleration(board):
    board.send("AX; AC10000; DC40000; VL1000000; MR10000; GO; ID;")
    vp = math.sqrt(2 * 10_000 * 10_000 * 40_000 / 50_000)
    tick = done_tick(board)
    analytic = (vp / 10_000 + vp / 40_000) * 8192
    assert analytic <= tick < analytic + 1


def _positions(board: MAXk, letters: str, seconds: float) -> dict[str, list[tuple[int, int]]]:
    """Every update cycle's position of each axis over `seconds` (what a host polling RP
    every cycle would see), as (tick, position) pairs."""
    seen: dict[str, list[tuple[int, int]]] = {x: [] for x in letters}

    def sample(_engine) -> None:
        for x in letters:
            seen[x].append((board.tick, board.position(x)))

    board.board.add_observer(sample, every_ticks=1)
    board.advance(seconds)
    board.board.remove_observer(sample)
    return seen


def _first(samples: list[tuple[int, int]], test) -> int | None:
    return next((t for t, p in samples if test(p)), None)


def test_aa_mode_starts_every_axis_on_the_same_tick(board):
    reference = MAXk()  # the same AA move from rest at tick 0: when its first step shows
    reference.send("AA; VL5000,5000,5000; MR1000,2000,3000; GO;")
    first_step = _first(_positions(reference, "X", 1.0)["X"], lambda p: p != 0)
    board.send("AY; VL1000; MR5000; GO;")  # Y busy for 5 s
    board.send("AA; VL5000,5000,5000; MR1000,2000,3000; GO; ID;")
    seen = _positions(board, "XYZ", 1.0)
    # AA GO waits for Y: nothing else has started yet
    assert board.query("PP").split(",")[:3] == ["0", board.query("AY RP"), "0"]
    assert _first(seen["X"], lambda p: p != 0) is None
    seen = _positions(board, "XYZ", 10.0)
    assert board.query("PP").split(",")[:3] == ["1000", "7000", "3000"]
    # X and Z started on the tick Y's first move ended, when Y reached the AA GO
    y_end = _first(seen["Y"], lambda p: p == 5000)
    x_moved = _first(seen["X"], lambda p: p != 0)
    assert x_moved == _first(seen["Z"], lambda p: p != 0) == y_end + first_step


def test_aa_go_starts_together_when_idle(board):
    board.send("AA; VL5000,5000,5000; AC50000,50000,50000; MR1000,2000,3000; GO;")
    seen = _positions(board, "XYZ", 0.5)
    reference = MAXk()
    reference.send("AX; VL5000; AC50000; MR1000; GO;")
    alone = _first(_positions(reference, "X", 0.5)["X"], lambda p: p != 0)
    assert alone is not None
    assert all(_first(seen[x], lambda p: p != 0) == alone for x in "XYZ")
    assert board.run_until_idle()
    assert board.query("PP") == "1000,2000,3000,0,0,0,0,0"


def test_am_mode_axes_run_their_own_queues(board):
    board.send("AY; VL1000; MR5000; GO;")
    board.send("AM; VL5000,5000; MR1000,2000; GO; ID;")
    assert board.run_until_done("X", timeout=5)
    assert board.position("X") == 1000  # X did not wait for Y
    assert not board.done("Y")
    assert board.run_until_done("Y", timeout=30)
    assert board.position("Y") == 7000


def test_manual_multi_axis_example_with_mr_in_am(board):
    board.send("AM; VL5000,5000,5000; AC50000,50000,50000; MR1000,2000,3000; GO; ID;")
    assert board.run_until_done("X", "Y", "Z", timeout=10)
    assert board.query("PP") == "1000,2000,3000,0,0,0,0,0"


def test_empty_slots_leave_axes_alone(board):
    board.send("AA; MR,100,200; GO; ID;")
    assert board.run_until_idle()
    assert board.query("PP") == "0,100,200,0,0,0,0,0"


def test_stop_decelerates_flushes_and_id_waits_for_rest(board):
    board.send("AX; VL10000; AC100000; MR100000; GO; MR5; GO;")
    board.advance(1.0)
    board.send("AX AC200000; ST ID;")
    assert board.query("RQC") == str(2559 - 1)  # ST flushed MR5/GO; ID queued
    assert board.query("RC") == "200000"  # the AC queued just before ST was applied first
    assert not board.done("X")
    assert board.velocity("X") > 0
    tick0 = board.tick
    assert board.run_until_done("X", timeout=1)
    # decelerates at the host's AC200000 (evidence E4): 10000 / 200000 = 0.05 s
    assert board.tick - tick0 == pytest.approx(0.05 * 8192, abs=1)
    assert board.query("RV") == "0"
    assert 9400 <= board.position("X") <= 10100


def test_kill_stops_at_once_and_flushes(board):
    board.send("AX; VL10000; MR100000; GO; ID;")
    board.advance(0.5)
    before = board.position("X")
    board.send("KL")
    assert board.query("AX RV") == "0"
    assert board.position("X") == before
    board.advance(1.0)
    assert board.position("X") == before
    assert not board.done("X")
    assert board.query("RQC") == "2559"


def test_ks_kills_selected_axes(board):
    board.send("AA; VL10000,10000,10000; MR100000,100000,100000; GO;")
    board.advance(0.5)
    board.send("KS1,,1;")
    vel = board.query("RV").split(",")
    assert vel[0] == "0" and vel[2] == "0" and vel[1] != "0"


def test_sa_stops_every_axis(board):
    board.send("AM; VL10000,10000; MR100000,-100000; GO;")
    board.advance(0.5)
    board.send("SA")
    assert board.run_until_idle(timeout=1)
    assert board.query("RV") == "0,0,0,0,0,0,0,0"


def test_jog_reverse_and_jog_zero(board):
    board.send("AX; AC50000; JG5000;")
    board.advance(1.0)
    assert board.query("RV") == "5000"
    board.send("JG-5000;")
    board.advance(ticks=819)  # 0.09998 s: the 0.1 s ramp down is nearly through zero
    assert abs(int(board.query("RV"))) <= 5
    board.advance(0.1)
    assert board.query("RV") == "-5000"
    board.send("JG0 ID")
    assert board.run_until_done("X", timeout=1)
    assert board.query("RV") == "0"
    assert board.query("QA") == "MDNN"


def test_go_waits_for_a_jog_to_be_stopped(board):
    board.send("AX; JG1000; MA0; GO; ID;")
    board.advance(1.0)
    assert board.velocity("X") == 1000
    board.send("AX FL; JG0; MA0; GO; ID;")
    assert board.run_until_done("X", timeout=5)
    assert board.position("X") == 0


def test_mp_mm_mo_single_steps(board):
    board.send("AX; MPMO; MO; MMMO;")
    board.advance(ticks=3)
    assert board.query("RP") == "1"
    assert board.query("QA")[0] == "M"


def test_load_positions(board):
    board.send("AX; LP1000;")
    assert (board.query("RP"), board.query("RE")) == ("1000", "1000")
    board.send("LPE5000;")
    assert (board.query("RP"), board.query("RE")) == ("1000", "5000")
    board.send("LO0;")
    assert (board.query("RP"), board.query("RE")) == ("0", "5000")
    board.send("MR100;GO;ID")
    board.run_until_done("X")
    assert (board.query("RP"), board.query("RE")) == ("100", "5100")


def test_wait_in_update_cycles(board):
    """SySal sends WT with its milliseconds times the update cycles per ms (?UR)."""
    board.send("AX; WT2048; ID;")
    assert board.run_until_done("X")
    assert board.tick == 2048
    board.send("AX; CA; #UR1024; WT1024; ID;")
    start = board.tick
    assert board.run_until_done("X")
    assert board.tick - start == 1024  # one second at 1024 Hz


def test_loops_repeat_and_nest(board):
    board.send("AX; VL100000; LS3; MR10; GO; LS2; MR1; GO; LE; LE; ID;")
    assert board.run_until_done("X", timeout=10)
    assert board.position("X") == 3 * (10 + 2)
    assert board.query("RQC") == "2559"  # loop entries released once the loop ended


def test_queue_units_and_a_full_queue_is_refused(board):
    board.send("AX; JG0;")  # nothing running: the queue drains at once
    board.send("AX; WT100000;")  # blocks the queue for 100 s
    free = int(board.query("RQC"))
    assert free == 2559 - 2
    board.send("MR1;" * (free // 2))
    assert board.query("RQC") == "1"
    assert not board.command_error
    board.send("MR1;")
    assert board.command_error
    assert "queue full" in board.last_error.reason
    assert board.query("RQC") == "1"  # nothing half-queued
    board.send("ID")  # one unit still fits
    assert board.query("RQC") == "0"


def test_flush_keeps_the_running_move(board):
    board.send("AX; VL1000; MR1000; GO; MR5000; GO; ID;")
    board.send("FL")
    assert board.query("RQC") == "2559"
    assert board.run_until_idle()
    assert board.position("X") == 1000


def test_update_rate_changes_the_tick(board):
    board.send("#UR1024")
    assert board.query("#UR?") == "1024"
    board.send("AX; VL5000; AC50000; MA10000; GO; ID;")
    assert done_tick(board) == math.ceil(2.1 * 1024)
    board.send("#UR3000")
    assert board.command_error


def test_ten_axis_board(board):
    b = MAXk("MAXk-A000")
    b.send("AA; MR1,2,3,4,5,6,7,8,9,10; GO; ID;")
    assert b.run_until_done()
    assert b.query("PP") == "1,2,3,4,5,6,7,8,9,10"
    assert b.doorbell == 0xFF | (1 << 25) | (1 << 26)


def test_aa_go_inside_a_loop_starts_together_on_every_pass():
    b = MAXk("MAXk-2000")
    b.send("AA; LS3,3; MR100,100; GO; LE; ID;")
    assert b.run_until_idle()
    assert b.query("PP") == "300,300"
    assert all(a.pending_target is None for a in b.board.axes)


def test_a_zero_time_loop_cannot_freeze_the_board():
    b = MAXk()
    b.send("AX; LS2147483647; LE;")  # returns at once: each jump back takes a tick
    b.advance(1.0)
    # the first jump back happens on tick 0, then one per tick
    assert b.board.axes[0].queue.loops[0][1] == 2147483647 - 8193
    b.send("KL")
    assert b.query("RQC") == "2559"


def test_loop_of_ids_takes_a_tick_per_pass():
    b = MAXk()
    b.send("AX; LS1000; ID; LE; WT0;")
    assert b.run_until_idle()
    assert b.tick == 999  # 999 jumps back, one tick each


def test_counters_wrap_at_32_bits():
    b = MAXk()
    b.send("AX; LP2147483647; MO;")
    b.advance(ticks=1)
    assert b.query("RP") == "-2147483648"
    b.send("LP2147483000; JG4000000;")
    b.advance(1.0)
    assert -2147483648 <= int(b.query("RP")) < -2146000000
    b.send("KL; LP-2147483647; MM; MO; MO;")
    b.advance(ticks=2)
    assert b.query("RP") == "2147483647"
    assert not b.command_error


def test_jog_reversal_with_base_velocity_stops_at_vb_not_zero():
    b = MAXk()
    b.send("AX; VB1000; AC100000; JG5000;")
    b.advance(0.5)
    b.send("JG-5000")
    speeds = []
    for _ in range(200):  # 0.098 s: 0.04 s down to VB, turn, 0.04 s up to 5000
        b.advance(ticks=4)
        speeds.append(b.velocity("X"))
    assert min(abs(v) for v in speeds) >= 1000 - 1e-6  # never crawls below VB
    assert speeds[-1] == -5000


def test_update_rate_is_refused_while_busy_and_time_stays_continuous():
    b = MAXk()
    b.send("AX; WT8192; ID;")
    b.send("#UR1024")
    assert b.command_error and "idle" in b.last_error.reason
    b.send("IC")
    assert b.run_until_done("X")
    assert b.time == pytest.approx(1.0, abs=1 / 8192)
    t0 = b.time
    b.send("#UR1024")
    assert not b.command_error
    assert b.time == t0
    b.advance(1.0)
    assert b.time == pytest.approx(t0 + 1.0)
    assert b.tick == 8192 + 1024

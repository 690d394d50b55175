"""Limits met by an axis whose demand comes from a link (TrioBASIC help FWD_IN, FS_LIMIT,
RS_LIMIT, CANCEL, CONNECT, ADDAX, AXIS_MODE bits 1, 3 and 17).

Figures by hand: the link axis 1 runs MOVEs at SPEED 1000 counts/s reached at ACCEL 100000
in 10 servo cycles (5 counts): from rest on tick 0 it stands on count t - 5 on tick t >= 10
and makes one count a cycle. FASTDEC 100000 stops 1000 counts/s in 10 cycles over 5 counts.
"""

from __future__ import annotations

from maxk.controllers.trio.controller import MC405

FAST = "SPEED=1000: ACCEL=100000: DECEL=10000"


def mc405(*lines: str) -> MC405:
    trio = MC405()
    for line in (f"BASE(1): {FAST}: BASE(0)", *lines):
        assert trio.send(line) == [], line
    return trio


def dpos(trio: MC405, axis: int) -> float:
    return round(trio.machine.dpos(axis), 6)


def at(trio: MC405, tick: int) -> None:
    trio.advance(ticks=tick - trio.machine.tick)


def linked(trio: MC405, axis: int = 0) -> bool:
    return trio.machine.axes[axis].link is not None


def test_a_connect_meets_fs_limit_and_is_cancelled_on_that_tick() -> None:
    """Ratio 2: the axis reaches 500 when the link axis is on 250, tick 255."""
    trio = mc405("FS_LIMIT=500", "CONNECT(2, 1)", "MOVE(2000) AXIS(1)")
    at(trio, 254)
    assert (dpos(trio, 0), linked(trio)) == (498.0, True)
    at(trio, 255)
    assert (dpos(trio, 0), dpos(trio, 1), linked(trio)) == (500.0, 250.0, False)
    at(trio, 2100)  # the link axis ran on; the axis stayed where the link ended
    assert (dpos(trio, 0), dpos(trio, 1)) == (500.0, 2000.0)


def test_a_limit_switch_cancels_a_connect_and_shows_in_axisstatus() -> None:
    trio = mc405("FWD_IN=3", "CONNECT(2, 1)")
    trio.world_view().set_limits("0", plus=300)
    trio.send("MOVE(2000) AXIS(1)")
    at(trio, 154)
    assert (dpos(trio, 0), trio.query("?AXISSTATUS"), trio.query("?IN(3)")) == (298.0, "0", "1")
    at(trio, 155)
    assert (dpos(trio, 0), trio.query("?AXISSTATUS"), trio.query("?IN(3)")) == (300.0, "16", "0")
    assert not linked(trio)
    at(trio, 1000)
    assert dpos(trio, 0) == 300.0


def test_a_negative_ratio_meets_rs_limit() -> None:
    trio = mc405("RS_LIMIT=-300", "CONNECT(-1, 1)", "MOVE(2000) AXIS(1)")
    at(trio, 305)
    assert (dpos(trio, 0), linked(trio)) == (-300.0, False)
    at(trio, 600)
    assert dpos(trio, 0) == -300.0


def test_a_cambox_meets_the_limit_on_its_rise_exactly() -> None:
    """TABLE 0, 400, 0 over 1000 link counts: the axis rises 0.8 count a link count for
    the first 500; FS_LIMIT 300 is met on link count 375, tick 380."""
    trio = mc405("FS_LIMIT=300", "TABLE(0, 0, 400, 0)", "CAMBOX(0, 2, 1, 1000, 1)",
                 "MOVE(2000) AXIS(1)")
    at(trio, 379)
    assert (dpos(trio, 0), linked(trio)) == (299.2, True)
    at(trio, 380)
    assert (dpos(trio, 0), linked(trio)) == (300.0, False)
    at(trio, 1100)
    assert dpos(trio, 0) == 300.0


def test_a_cam_that_turns_back_under_the_limit_runs_whole() -> None:
    trio = mc405("FS_LIMIT=450", "TABLE(0, 0, 400, 0)", "CAMBOX(0, 2, 1, 1000, 1)",
                 "MOVE(2000) AXIS(1)")
    at(trio, 505)
    assert (dpos(trio, 0), linked(trio)) == (400.0, True)  # its peak, under 450
    at(trio, 1100)
    assert (dpos(trio, 0), linked(trio)) == (0.0, False)  # the cam ended by itself


def test_a_movelink_is_cancelled_and_the_one_buffered_takes_over() -> None:
    """The first MOVELINK (1:1) meets FS_LIMIT 600 on tick 605; the next one buffered
    (-500 over 1000 link counts) starts there and moves the axis back half a count a
    link count."""
    trio = mc405("FS_LIMIT=600", "MOVELINK(1000, 1000, 0, 0, 1)",
                 "MOVELINK(-500, 1000, 0, 0, 1)", "MOVE(3000) AXIS(1)")
    at(trio, 605)
    assert dpos(trio, 0) == 600.0
    at(trio, 1105)
    assert (dpos(trio, 0), dpos(trio, 1)) == (350.0, 1100.0)
    at(trio, 1605)
    assert (dpos(trio, 0), linked(trio)) == (100.0, False)


def test_a_link_standing_beyond_the_limit_moves_away_but_not_further_in() -> None:
    trio = mc405("DEFPOS(1000)", "FS_LIMIT=500", "CONNECT(2, 1)", "MOVE(-100) AXIS(1)")
    at(trio, 300)
    assert (dpos(trio, 0), linked(trio), trio.query("?AXISSTATUS")) == (800.0, True, "512")
    trio.send("MOVE(100) AXIS(1)")  # further in: cancelled on its first cycle
    at(trio, 600)
    assert (dpos(trio, 0), dpos(trio, 1), linked(trio)) == (800.0, 0.0, False)


def test_axis_mode_bit_1_holds_the_connect_at_ratio_0_while_the_limit_is_on() -> None:
    trio = mc405("FWD_IN=3", "AXIS_MODE=2", "CONNECT(2, 1)")
    trio.world_view().set_limits("0", plus=300)
    trio.send("MOVE(2000) AXIS(1)")
    at(trio, 155)
    at(trio, 200)
    assert (dpos(trio, 0), dpos(trio, 1), linked(trio)) == (300.0, 195.0, True)
    trio.world_view().set_limits("0", plus=None)  # the limit goes off: ratio 2 again
    at(trio, 210)
    assert round(dpos(trio, 0), 6) == 300.0 + 2 * 10


def test_addax_ignores_the_limit_by_default_its_own_move_is_cancelled() -> None:
    """Own MOVE and ADDAX of axis 1 both at a count a cycle: 1000 on tick 505. The own
    move ramps down at FASTDEC (5 counts more); what ADDAX adds runs on."""
    trio = mc405(FAST, "FS_LIMIT=1000: FASTDEC=100000", "ADDAX(1)", "MOVE(5000) AXIS(1)",
                 "MOVE(5000) AXIS(0)")
    at(trio, 505)
    assert dpos(trio, 0) == 1000.0
    at(trio, 3000)
    assert (dpos(trio, 0), dpos(trio, 1)) == (505.0 + 2995.0, 2995.0)


def test_axis_mode_bits_17_and_3_cancel_the_master_and_end_the_addax() -> None:
    trio = mc405("BASE(1): FASTDEC=100000: BASE(0)", FAST,
                 "FS_LIMIT=1000: FASTDEC=100000: AXIS_MODE=131072+8", "ADDAX(1)",
                 "MOVE(5000) AXIS(1)", "MOVE(5000) AXIS(0)")
    at(trio, 3000)
    # each ramps down over 5 counts from 500; ADDAX kept what it added up to tick 505
    assert (dpos(trio, 0), dpos(trio, 1)) == (505.0 + 500.0, 505.0)
    assert 0 not in trio.machine.links.addax


def test_a_linked_axis_in_a_disable_group_stops_its_group_on_a_limit_error() -> None:
    trio = mc405("FWD_IN=3: ERRORMASK=268+16", "DISABLE_GROUP(0)", "DISABLE_GROUP(1)",
                 "WDOG=ON", "CONNECT(2, 1)")
    trio.world_view().set_limits("0", plus=300)
    trio.send("MOVE(2000) AXIS(1)")
    at(trio, 155)
    assert [trio.query(q) for q in ("?MOTION_ERROR", "?AXIS_ENABLE", "?AXIS_ENABLE AXIS(1)",
                                    "?WDOG")] == ["1", "0", "1", "1"]
    at(trio, 1000)
    assert (dpos(trio, 0), dpos(trio, 1), linked(trio)) == (300.0, 995.0, False)


def test_a_limit_acts_on_the_sum_with_addax_not_on_the_own_move_alone() -> None:
    """Axis 0 moves forward from tick 0; from tick 100 ADDAX adds axis 1 moving back at
    the same speed: the sum stays at 100 from tick 110, so its own move passes 1000
    (tick 1005) without meeting FS_LIMIT 1000."""
    trio = mc405(FAST, "FS_LIMIT=1000", "MOVE(5000)")
    at(trio, 100)
    trio.send("ADDAX(1)")
    trio.send("MOVE(-5000) AXIS(1)")
    at(trio, 2000)
    assert (dpos(trio, 0), trio.machine.axis_idle(0)) == (100.0, False)
    assert trio.query("?AXISSTATUS") == "0"


def test_connpath_and_flexlink_axes_are_cancelled_at_the_limit_too() -> None:
    """Both follow the link axis 1:1 here (a CONNPATH on axis 1's path distance, a
    FLEXLINK of base distance 1000 over 1000 link counts): FS_LIMIT 400 on tick 405."""
    for link in ("CONNPATH(1, 1)", "FLEXLINK(1000, 0, 1000, 0, 0, 0, 0, 1)"):
        trio = mc405("FS_LIMIT=400", link, "MOVE(2000) AXIS(1)")
        at(trio, 404)
        assert (dpos(trio, 0), linked(trio)) == (399.0, True), link
        at(trio, 405)
        assert (dpos(trio, 0), linked(trio)) == (400.0, False), link
        at(trio, 1000)
        assert (dpos(trio, 0), dpos(trio, 1)) == (400.0, 995.0), link

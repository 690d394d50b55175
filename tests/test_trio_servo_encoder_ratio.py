"""ENCODER_RATIO on a servo axis (TrioBASIC help ENCODER_RATIO): MPOS counts mpos_count /
input_count x the encoder's edges and the position loop closes on MPOS, so the ratio
affects every motion command and the gains act per MPOS count.

The loop with a ratio r and gains G moves the motor exactly as the loop without one, with
gains r x G and every demand divided by r (its error and so its output are the same on
every servo cycle): an exact equivalence, checked on every tenth cycle of a move.
"""

from __future__ import annotations

from maxk.controllers.trio import MC405

TICKS = range(20, 900, 10)


def run(*lines: str, move: str) -> list[tuple[float, float, float, float]]:
    trio = MC405()
    for line in lines:
        assert trio.send(line) == [], line
    trio.advance(ticks=10)
    trio.send(move)
    out = []
    for tick in TICKS:
        trio.advance(ticks=tick - trio.machine.tick)
        out.append(tuple(float(trio.query(f"?{name}"))
                         for name in ("ENCODER", "MPOS", "DPOS", "FE")))
    return out  # type: ignore[return-value]


def test_a_ratio_of_2_is_the_loop_with_twice_the_gains_on_half_the_demand() -> None:
    scaled = run("ATYPE=77: P_GAIN=4: D_GAIN=60: SERVO=ON: WDOG=ON: SPEED=2000: "
                 "ACCEL=40000: DECEL=40000", "ENCODER_RATIO(2,1)", move="MOVE(600)")
    plain = run("ATYPE=77: P_GAIN=8: D_GAIN=120: SERVO=ON: WDOG=ON: SPEED=1000: "
                "ACCEL=20000: DECEL=20000", move="MOVE(300)")
    for tick, (a, b) in zip(TICKS, zip(scaled, plain, strict=True), strict=True):
        assert a[0] == b[0], tick  # the same motor, edge for edge
        assert abs(a[1] - 2 * b[1]) < 1e-3 and abs(a[2] - 2 * b[2]) < 1e-3, tick
        assert abs(a[3] - 2 * b[3]) < 1e-3, tick
    assert scaled[-1][0] > 250  # (the motor went most of the way)


def test_the_page_s_rotary_table_turns_once_for_360_degrees() -> None:
    """Example 1: 8192 edges a turn scaled to 7200 MPOS counts, UNITS 20: degrees."""
    trio = MC405()
    for line in ("ATYPE=77: P_GAIN=8: I_GAIN=0.05: D_GAIN=120: SERVO=ON: WDOG=ON",
                 "ENCODER_RATIO(7200,8192)", "UNITS=20", "SPEED=90: ACCEL=1800: DECEL=1800"):
        assert trio.send(line) == [], line
    trio.send("MOVE(360)")
    trio.advance(ticks=6000)  # 4 s of move, 2 to settle on the integral gain
    assert (trio.query("?ENCODER"), trio.query("?MPOS"), trio.query("?DPOS")) == (
        "8192", "360", "360")


def test_a_ratio_is_refused_while_the_servo_axis_moves_and_kept_at_rest() -> None:
    trio = MC405()
    assert trio.send("ATYPE=77: P_GAIN=8: D_GAIN=120: SERVO=ON: WDOG=ON: SPEED=1000: "
                     "ACCEL=20000: DECEL=20000") == []
    trio.send("MOVE(300)")
    trio.advance(ticks=100)
    assert trio.send("ENCODER_RATIO(2,1)") == ["! Parameter out of range"]
    assert trio.run_until_idle()
    trio.advance(ticks=2000)
    dpos, mpos, edges = trio.query("?DPOS"), float(trio.query("?MPOS")), trio.query("?ENCODER")
    assert trio.send("ENCODER_RATIO(3,1)") == []
    assert trio.query("?DPOS") == dpos and abs(float(trio.query("?MPOS")) - mpos) <= 0.5
    assert trio.query("?ENCODER") == edges  # the motor did not move
    trio.send("MOVE(30)")  # 30 MPOS counts: 10 edges
    assert trio.run_until_idle()
    trio.advance(ticks=2000)
    assert abs(int(trio.query("?ENCODER")) - (int(edges) + 10)) <= 5  # (friction's error)

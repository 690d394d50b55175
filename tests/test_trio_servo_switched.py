"""The switched terms of an MC405 servo axis's filter: the D_ZONE_MIN/D_ZONE_MAX dead band
and the POS_OFFSET/NEG_OFFSET output offsets (TrioBASIC help D_ZONE_MIN, D_ZONE_MAX,
POS_OFFSET, NEG_OFFSET), checked on every servo cycle of a move and its settling.

Each cycle's output is worked out here from the loop's own measured position and the
demand (as tests/test_trio_servo_output.py does): P e + D (e - e_prev), in DAC_OUT's
units (the shared output / 16), then the page's rule. MOVE(300) at SPEED 2000, ACCEL and
DECEL 40000 counts/s^2 runs 50 + 100 + 50 = 200 servo cycles.
"""

from __future__ import annotations

from maxk.controllers.trio import MC405

P, D = 8.0, 120.0
LOOP = (f"ATYPE=77: P_GAIN={P}: D_GAIN={D}: SERVO=ON: WDOG=ON: SPEED=2000: ACCEL=40000: "
        "DECEL=40000")
MOVE_CYCLES = 200


def replay(*settings: str, cycles: int = 700) -> list[tuple[int, float, float, float]]:
    """(cycle from the move's start, e, the linear output, DAC_OUT) for each cycle."""
    trio = MC405()
    for line in (LOOP, *settings):
        assert trio.send(line) == [], line
    trio.advance(ticks=10)
    trio.send("MOVE(300)")
    m = trio.machine
    loop = m.axes[0].servo
    assert loop is not None
    start = m.tick
    out = []
    e_prev = m.demand(0) - loop.p
    for k in range(cycles):
        e = m.demand(0) - loop.p
        trio.advance(ticks=1)
        linear = (P * e + D * (e - e_prev)) / 16.0
        out.append((k, e, linear, float(m.drive.following.dac_out(0))))
        e_prev = e
    assert m.tick == start + cycles
    return out


def test_the_dead_band_clamps_the_idle_output_until_a_move_or_the_live_band() -> None:
    clamped = False
    seen_clamp = 0  # (the motor's friction holds it about 13.65 counts short: inside 15)
    for k, e, linear, dac_out in replay("D_ZONE_MIN=15: D_ZONE_MAX=20"):
        if k < MOVE_CYCLES or (clamped and abs(e) > 20):
            clamped = False
        elif not clamped and abs(e) < 15:
            clamped = True
        expected = 0.0 if clamped else linear
        assert abs(dac_out - expected) < 1e-6, k
        seen_clamp += clamped and abs(linear) > 1e-3
    assert seen_clamp > 100  # the clamp held a nonzero output at 0 (friction keeps an error)


def test_without_the_dead_band_the_idle_output_is_the_filter_s() -> None:
    rows = replay()
    assert all(abs(dac_out - linear) < 1e-6 for _k, _e, linear, dac_out in rows)
    assert any(abs(linear) > 1e-3 for k, _e, linear, _d in rows if k > 600)


def test_the_offsets_go_with_the_sign_of_the_output_put_out() -> None:
    for scale in (1, 2):  # (DAC_SCALE multiplies the gains; the offset is added after)
        signs = set()
        for k, _e, linear, dac_out in replay(f"DAC_SCALE={scale}",
                                             "POS_OFFSET=20: NEG_OFFSET=-15", cycles=300):
            out = linear * scale
            offset = 20.0 if out > 0 else -15.0 if out < 0 else 0.0
            assert abs(dac_out - (out + offset)) < 1e-6, (scale, k)
            signs.add(out > 0)
        assert signs == {True, False}  # both offsets were put out

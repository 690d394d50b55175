"""Real-time position capture: home edges, index marks, input edges, the 55-entry ring."""

import struct

from maxk import MAXk
from maxk.personalities.maxk.capture import (
    ENCODER_HOME,
    HOME_FALLING,
    HOME_RISING,
    RING_BYTES,
    RING_ENTRIES,
    CaptureEntry,
)


def capture(b, letter, io_rising=None, io_falling=None, **kw):
    b.capture(letter, inputs_rising=io_rising, inputs_falling=io_falling, **kw)


def test_home_edges_both_ways_at_the_exact_edge_positions():
    b = MAXk()
    b.send("AX; PSE; LPE5000;")  # encoder counts are offset from the stage by 5000
    capture(b, "X", home="both")
    b.send("VL20000; MR3000; GO; MR-3000; GO;")
    assert b.run_until_idle(timeout=5)
    entries = b.board.capture_ring.read()
    assert entries == [
        CaptureEntry(5000 + 1234, 0, HOME_RISING), CaptureEntry(5000 + 1334, 0, HOME_FALLING),
        CaptureEntry(5000 + 1333, 0, HOME_RISING), CaptureEntry(5000 + 1233, 0, HOME_FALLING),
    ]
    assert not b.board.capture_ring.signal


def test_index_marks_every_period():
    b = MAXk()
    b.send("AX; PSE;")
    capture(b, "X", index=True)
    b.send("VL100000; MR13000; GO;")
    assert b.run_until_idle(timeout=5)
    assert [e.encoder for e in b.board.capture_ring.read()] == [1280, 5280, 9280]
    b.send("MR-13000; GO;")
    b.run_until_idle(timeout=5)
    assert [(e.encoder, e.home_events) for e in b.board.capture_ring.read()] == [
        (9283, ENCODER_HOME), (5283, ENCODER_HOME), (1283, ENCODER_HOME)]


def test_capture_needs_an_encoder():
    b = MAXk()
    capture(b, "X", home="both", index=True)
    b.send("AX; VL20000; MR3000; GO;")
    b.run_until_idle(timeout=5)
    assert len(b.board.capture_ring) == 0


def test_input_edges():
    b = MAXk()
    b.send("AY; PSE; LPE-40;")
    capture(b, "Y", io_rising=0b101, io_falling=0b100)
    b.set_input(0, True)
    b.set_input(1, True)  # not selected
    b.set_input(2, True)
    b.set_input(2, False)
    entries = b.board.capture_ring.read()
    assert entries == [CaptureEntry(-40, 1, 0, 0b001, 0), CaptureEntry(-40, 1, 0, 0b100, 0),
                       CaptureEntry(-40, 1, 0, 0, 0b100)]


def test_input_edge_from_a_time_function_is_caught_on_its_update_cycle():
    b = MAXk()
    b.send("AX; PSE; VL8192; MR100000; GO;")  # one step per tick
    capture(b, "X", io_rising=1 << 3)
    b.set_input(3, lambda board: board.time >= 0.25)
    b.advance(0.5)
    (entry,) = b.board.capture_ring.read()
    # at tick 2048: 0.25 s at 8192 steps/s less the 4 ms ramp at the factory AC (~17 steps)
    assert entry.io_rising == 1 << 3 and entry.encoder == 2031


def test_ring_overruns_when_the_host_is_slow():
    b = MAXk()
    b.send("AX; PSE;")
    capture(b, "X", index=True)
    b.board.world.axes[0].index_period = 10
    b.board.world.axes[0].index_offset = 0
    b.send("VL10000; MR1000; GO;")
    b.run_until_idle(timeout=5)
    ring = b.board.capture_ring
    assert len(ring) == RING_ENTRIES - 1  # a full ring holds 54: insert == removal is empty
    assert ring.lost == 100 - 54
    entries = ring.read()
    assert [e.encoder for e in entries] == list(range(470, 1010, 10))  # marks 10..1000


def test_ring_bytes_are_table_3_5_big_endian():
    b = MAXk()
    b.send("AX; PSE; LPE-2;")
    capture(b, "X", home="rising")
    b.send("VL20000; MR2000; GO;")
    b.run_until_idle(timeout=5)
    raw = b.board.capture_ring.to_bytes()
    assert len(raw) == RING_BYTES == 552
    assert raw[0] == 1 and raw[1] == 0  # insert index, removal index
    assert struct.unpack(">iBBHH", raw[2:12]) == (1232, 0, HOME_RISING, 0, 0)


def test_a_bouncing_home_switch_makes_a_burst_of_captured_edges():
    b = MAXk()
    b.send("AX; PSE;")
    b.bounce("X", "home", 3)
    capture(b, "X", home="both")
    b.send("VL20000; MR2000; GO;")
    assert b.run_until_idle(timeout=5)
    edges = [(e.encoder, e.home_events) for e in b.board.capture_ring.read()]
    # chatter 3 steps deep inside each edge (1234..1333): on 1234, off 1235, on 1236 ...
    # ... on 1331, off 1332, on 1333, then off for good at 1334
    assert edges == [(1234, HOME_RISING), (1235, HOME_FALLING), (1236, HOME_RISING),
                     (1332, HOME_FALLING), (1333, HOME_RISING), (1334, HOME_FALLING)]


def test_bounce_does_not_change_where_homing_stops_looking():
    b = MAXk()
    b.bounce("X", "home", 5)
    b.send("AX; PSE; VL1000; HM0; ID;")
    assert b.run_until_done("X", timeout=5)
    assert b.encoder("X") - b.board.axes[0].steps == -1234  # the first active count


def test_every_index_mark_is_captured_even_several_per_update_cycle():
    b = MAXk()
    b.send("AX; PSE;")
    b.set_index("X", 100, 4, 0)
    capture(b, "X", index=True)
    b.send("VL2457600; AC8000000; MR30000; GO;")  # ~300 counts per update cycle
    assert b.run_until_idle(timeout=5)
    marks = [e.encoder for e in b.board.capture_ring.read()]
    assert len(b.board.capture_ring) == 0
    assert b.board.capture_ring.lost == 300 - 54
    assert marks == list(range(30000 - 53 * 100, 30001, 100))


def test_enabling_input_capture_records_no_edge_that_did_not_happen():
    b = MAXk()
    b.send("AX; PSE;")
    b.set_input(3, True)
    capture(b, "X", io_rising=1 << 3)
    assert b.board.capture_ring.read() == []
    b.set_input(3, False)
    b.set_input(3, True)
    assert [e.io_rising for e in b.board.capture_ring.read()] == [1 << 3]

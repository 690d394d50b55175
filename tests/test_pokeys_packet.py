"""The frame codec, the session's framing and the command table's records."""

from __future__ import annotations

import io

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.commands.pokeys import ENTRIES, PoKeysSession, checksum, make_request, parse_request
from maxk.commands.pokeys.pev2_commands import decode_entries
from maxk.personalities.pokeys import AxisConfigBits, EngineState, PoKeysDevice
from maxk.personalities.pokeys.trace import CsvSlotTrace


def test_checksum_is_the_byte_sum_of_the_header() -> None:
    assert checksum(bytes.fromhex("bb 85 01 00 00 00 07")) == 0x48
    assert make_request(0x85, 0x02, 0x03, request_id=0x12)[:8] == bytes.fromhex(
        "bb 85 02 03 00 00 12 57")


@given(st.binary(min_size=64, max_size=64))
def test_only_well_formed_requests_parse(frame: bytes) -> None:
    request = parse_request(frame)
    ok = frame[0] == 0xBB and frame[7] == sum(frame[:7]) & 0xFF
    assert (request is not None) == ok


@pytest.mark.parametrize("length", [0, 63, 65])
def test_wrong_length_is_not_a_request(length: int) -> None:
    assert parse_request(bytes([0xBB]) + bytes(length - 1 if length else 0)) is None


@given(st.lists(st.integers(1, 63), max_size=8), st.integers(0, 255))
def test_any_split_gives_the_same_reply(cuts: list[int], request_id: int) -> None:
    frame = make_request(0x85, 0x00, 0x21, request_id=request_id)
    session = PoKeysSession(PoKeysDevice.create())
    points = sorted(set(cuts))
    for a, b in zip([0, *points], [*points, 64], strict=True):
        session.feed(frame[a:b])
    reply = session.read()
    assert len(reply) == 64 and reply[6] == request_id and reply[63] == (0x21 + 0x5A) & 0xFF
    assert session.read() == b""


def test_two_requests_in_one_write_get_two_replies_in_order() -> None:
    session = PoKeysSession(PoKeysDevice.create())
    session.feed(make_request(0x00, request_id=7) + make_request(0x8F, request_id=8)
                 + make_request(0x85)[:10])
    out = session.read()
    assert len(out) == 128 and out[6] == 7 and out[64 + 6] == 8


def test_multipart_out_of_order_is_silent_and_the_next_group_works() -> None:
    device = PoKeysDevice.create()
    device.engine.setup(1, 0, 0, 0, 0, 0)  # type: ignore[union-attr]
    session = PoKeysSession(device)
    def part(i: int, flags: int) -> bytes:
        return make_request(0xB0, i | flags, 0xFF, 4, 1, request_id=i + 20,
                            payload=bytes([1]) * 56)
    session.feed(part(0, 0x08) + part(2, 0))
    assert session.read() == b""
    session.feed(b"".join(part(i, 0x08 if i == 0 else 0x10 if i == 7 else 0)
                          for i in range(8)))
    reply = session.read()
    assert len(reply) == 64 and reply[6] == 27 and reply[2] == 4


def test_decode_entries_sign_and_width() -> None:
    assert decode_entries(bytes([0x85, 0x05, 0xFF]), 1, 3, False).tolist() == [[-5, 5, -127]]
    assert decode_entries(bytes.fromhex("ff7f 0180"), 1, 2, True).tolist() == [[32767, -1]]
    assert decode_entries(bytes(5), 2, 3, False) is None


def test_discovery_reply_forms() -> None:
    pk57 = PoKeysSession(PoKeysDevice.create("PoKeys57CNC")).discovery((127, 0, 0, 1))
    assert pk57 == bytes([0, 0x7D, 0x7B, 0x33, 6, 127, 0, 0, 1, 0, 127, 0, 0, 1,
                          0x7B, 0x7D, 0, 0, 32])
    pk56 = PoKeysSession(PoKeysDevice.create("PoKeys56E")).discovery((10, 0, 0, 9))
    assert len(pk56) == 14 and pk56[1] * 256 + pk56[2] == 27431 and pk56[10:14] == bytes(
        [10, 0, 0, 9])


def test_every_command_entry_says_where_it_comes_from() -> None:
    keys = set()
    for entry in ENTRIES:
        assert entry.source and entry.confidence in ("C", "I", "D")
        assert (entry.command, entry.sub) not in keys
        keys.add((entry.command, entry.sub))
        # PoKeysLib's function, or the specification's name for a request it never sends
        assert entry.name.startswith("PK_") or "protocol specification" in entry.source


def test_csv_trace() -> None:
    device = PoKeysDevice.create()
    e = device.engine
    e.setup(2, 0, 0, 0, 0, 0)  # type: ignore[union-attr]
    for a in e.axes[:2]:
        a.settings.config = AxisConfigBits.ENABLED
    out = io.StringIO()
    e.trace = CsvSlotTrace(out, 2)
    e.fill(np.array([[3, -2], [1, 0]], dtype=np.int32))
    e.set_state(EngineState.RUNNING, 0, 0)  # type: ignore[call-arg]
    device.run_to(3)
    assert out.getvalue().splitlines() == [
        "slot,engine_state,pulses0,dir0,state0,pulses1,dir1,state1",
        "0,3,3,0,2,-2,1,2", "1,3,1,0,1,0,1,1", "2,3,0,0,1,0,1,1"]


def test_the_docs_request_table_is_the_command_table() -> None:
    """docs/pokeys.md lists every request of the table, generated from it, and what every
    other request gets; regenerate with `python3 -m maxk.commands.pokeys.table_doc`."""
    from pathlib import Path

    from maxk.commands.pokeys.table_doc import table

    page = (Path(__file__).parent.parent / "docs" / "pokeys.md").read_text()
    assert table() in page
    for entry in ENTRIES:
        sub = "" if entry.sub < 0 else f" 0x{entry.sub:02X}"
        assert f"| `0x{entry.command:02X}{sub}` |" in page
    assert "(any other command or sub-command)" in page

"""A hostile review of the PoKeys doors (PoKeys56E, PoKeys57E, PoKeys57CNC).

Hosts that are careless or hostile: malformed 64-byte frames (wrong length, header,
checksum, command), every pulse-engine request with absurd operands (NaN and infinite
axis speeds and ramps, counters at the int32 edge, buffer fills past the depth or with
pulse counts no slot can carry, bad multi-part groups), state changes mid-motion, many
UDP hosts, floods, a TCP host that never reads, and the console language with extreme
operands. Each test either reproduces a defect the review found (``test_fixed_...``:
its docstring says the severity, what goes wrong and what is expected instead) or guards
a behaviour that held under attack (``test_holds_...``).

Door tests use `maxk serve`'s server in-process (tests/hosting.py, a manual clock:
virtual time moves only when the test moves it); session tests feed the device's own
64-byte frames (`PoKeys.request`, `open_datagram_session`). What the host needs is
shared/reference/pokeys-protocol.md (cited as "reference N").
"""

from __future__ import annotations

import gc
import math
import socket
import struct
import time
import tracemalloc
from collections.abc import Callable

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from maxk.commands.pokeys.packet import make_request
from maxk.commands.pokeys.session import is_discovery
from maxk.controllers.pokeys.controller import PoKeys
from tests.hosting import HostedBoards

PEV2, PEV1, LARGE = 0x85, 0x80, 0xB0
MAX_PULSES = {"PoKeys57CNC": 125, "PoKeys57E": 125, "PoKeys56E": 25}  # status [57], seed v1
INT32 = 1 << 32


# ---- helpers ----------------------------------------------------------------------------
def header_sum(frame: bytes | bytearray) -> int:
    return sum(frame[0:7]) & 0xFF


def valid_reply(reply: bytes, request_id: int) -> bool:
    """What PoKeysLib accepts (reference 2): 64 bytes, 0xAA, the request's ID, checksum."""
    return (len(reply) == 64 and reply[0] == 0xAA and reply[6] == request_id
            and reply[7] == header_sum(reply))


def axis_config(config: int = 0x01, switches: int = 0, max_speed: float = 10.0,
                accel: float = 0.05, decel: float = 0.05, homing: int = 50, back: int = 50,
                soft: tuple[int, int] = (0, 0)) -> bytes:
    """AxisConfigurationSet bytes [8..52] as the library packs them (reference 6)."""
    raw = bytearray(45)
    raw[0], raw[1], raw[5], raw[6] = config, switches, homing, back
    struct.pack_into("<fffii", raw, 8, max_speed, accel, decel, *soft)
    return bytes(raw)


class Dev:
    """A device driven by raw request frames through its own session: an exception out of
    the session or the engine is a defect (the door would lose the host's request)."""

    def __init__(self, model: str = "PoKeys57CNC") -> None:
        self.pk = PoKeys(model)

    def ask(self, command: int, p1: int = 0, p2: int = 0, p3: int = 0, p4: int = 0,
            payload: bytes = b"") -> bytes | None:
        reply = self.pk.request(command, p1, p2, p3, p4, payload)
        assert reply is None or valid_reply(reply, self.pk._request_id), reply
        return reply

    def status(self) -> bytes:
        """PK_PEv2_StatusGet with its test byte; the reply must carry [63] = test + 0x5A."""
        test = (0x10 + self.pk._request_id + 1) % 199
        reply = self.ask(PEV2, 0x00, test)
        assert reply is not None, "StatusGet got no reply"
        assert reply[63] == (test + 0x5A) & 0xFF
        return reply

    def positions(self) -> tuple[int, ...]:
        return struct.unpack_from("<8i", self.status(), 24)

    def slots(self, n: int) -> None:
        self.pk.advance(slots=n)

    def one_axis(self, config: int = 0x01, **fields: object) -> None:
        """Axis X alone in the pulse engine, configured as given."""
        assert self.ask(PEV2, 0x01, payload=bytes([1, 0, 1])) is not None
        assert self.ask(PEV2, 0x11, 0, payload=axis_config(config, **fields)) is not None  # type: ignore[arg-type]

    def running(self) -> None:
        assert self.ask(PEV2, 0x02, 3) is not None


def fill8(dev: Dev, rows: list[list[int]]) -> bytes | None:
    data = bytes((abs(v) & 0x7F) | (0x80 if v < 0 else 0) for r in rows for v in r)
    return dev.ask(PEV2, 0xFF, len(rows), len(rows[0]), payload=data)


def fill16(dev: Dev, rows: list[list[int]]) -> bytes | None:
    data = b"".join(struct.pack("<H", v) for r in rows for v in r)  # raw u16 words
    return dev.ask(PEV2, 0xFE, len(rows), len(rows[0]), payload=data)


def wrapped(value: int) -> int:
    """An int32 counter that counted `value` pulses (C arithmetic on the device)."""
    return (value + (1 << 31)) % INT32 - (1 << 31)


def peak_bytes(action: Callable[[], object]) -> int:
    """The highest allocation above the start while `action` runs (tracemalloc)."""
    gc.collect()
    tracemalloc.start()
    tracemalloc.reset_peak()
    start = tracemalloc.get_traced_memory()[0]
    try:
        action()
    finally:
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    return peak - start


def udp_socket() -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.settimeout(5)
    return sock


def udp_ask(sock: socket.socket, port: int, frame: bytes, timeout: float = 5.0) -> bytes | None:
    """Send one datagram; the first reply carrying its ID, or None after the timeout
    (a liveness bound only: a passing test returns at its reply)."""
    sock.sendto(frame, ("127.0.0.1", port))
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        sock.settimeout(max(0.01, deadline - time.monotonic()))
        try:
            reply = sock.recv(4096)
        except TimeoutError:
            return None
        if len(reply) == 64 and reply[6] == frame[-64 + 6]:
            return reply
    return None


def tcp_ask(sock: socket.socket, frame: bytes, timeout: float = 5.0) -> bytes:
    """Send one request on a stream and read its 64-byte reply (b'' if none came)."""
    sock.sendall(frame)
    sock.settimeout(timeout)
    data = b""
    try:
        while len(data) < 64:
            chunk = sock.recv(64 - len(data))
            if not chunk:
                break
            data += chunk
    except TimeoutError:
        pass
    return data


@pytest.fixture
def hosted():
    boards = HostedBoards(models=("PoKeys57CNC",))
    yield boards
    boards.close()


def status_frame(request_id: int) -> bytes:
    return make_request(PEV2, 0x00, (0x10 + request_id) % 199, request_id=request_id)


# =========================================================================================
# Defects
# =========================================================================================

def test_fixed_counter_past_int32_silences_every_status_for_good() -> None:
    """CRITICAL. A position counter that passes 2^31-1 (PositionSet to 2147483647, then
    one buffered pulse; or, with no trick at all, a speed-mode axis at 125 kHz for 4.8 h,
    10 kHz for 60 h) makes the status block raise struct.error ('i' format requires
    -2147483648 <= number <= 2147483647): StatusGet and every BufferFill reply (they carry
    the block, reference 7) are lost from then on, so the host's poll gets -10 for good
    and cannot even feed the buffer. Expected: the counter is the device's int32 (status
    [24..55] are i32, reference 7) and wraps as C arithmetic does: the status answers and
    carries -2147483648 (D: wrap rather than saturate, the firmware's counter is C).
    The v1 status (0x80/0x00 [8..19]) and v1 fill reply ([9..20]) pack the same way."""
    dev = Dev()
    dev.one_axis()
    assert dev.ask(PEV2, 0x03, 0x01, payload=struct.pack("<8i", 2**31 - 1, *[0] * 7))
    dev.running()
    assert fill8(dev, [[1]]) is not None
    dev.slots(2)
    assert dev.positions()[0] == wrapped(2**31)
    assert fill8(dev, [[-1]]) is not None  # and back over the edge
    dev.slots(2)
    assert dev.positions()[0] == 2**31 - 1


def test_fixed_speed_mode_axis_after_five_hours_silences_the_status() -> None:
    """CRITICAL. The same with no trick: axis X in speed mode (internal planner) at its
    125 pulses/ms runs 125000 pulses/s; after 17180 s (4.8 h) its counter is past 2^31
    and StatusGet raises struct.error (no reply, ever again). A spindle-like axis of a
    machine left on does this. Expected: the status answers with the int32 counter."""
    dev = Dev()
    dev.one_axis(0x05, max_speed=125.0, accel=1.0, decel=1.0)  # enabled, internal, speed
    dev.running()
    assert dev.ask(PEV2, 0x20, payload=struct.pack("<8i", 125000, *[0] * 7)) is not None
    dev.pk.advance(17180.0)
    emitted = dev.pk.pulse_engine.axes[0].position  # what the engine counted
    assert emitted > 2**31
    assert dev.positions()[0] == wrapped(emitted)


@pytest.mark.parametrize("max_speed", [math.nan, -math.inf])
@pytest.mark.parametrize("model", ["PoKeys57CNC", "PoKeys56E"])
def test_fixed_homing_at_nan_or_minus_infinite_max_speed_faults_the_engine(
        model: str, max_speed: float) -> None:
    """CRITICAL. An axis whose max speed is NaN or -inf (any f32 the host sends in
    AxisConfigurationSet [16], or 0x80/0x11 on v1; the console's `axis X max nan`) is
    accepted; HomingStart then plans a constant speed of NaN/-inf pulses/s and the next
    slot raises ValueError / OverflowError in motion.whole_pulses (math.floor of NaN or
    infinity): the engine cannot advance any more, ever. Minimal: `setup 1`, `axis X
    max nan switches home`, `home X`, one slot. Expected: as motion._limits decides for
    moves (D: an absurd setting makes an absurd motion, never a fault): no exception,
    no axis emits more than the engine's pulses per slot, the status answers."""
    dev = Dev(model)
    dev.pk.configure_axis(0, max_speed=max_speed, switches=0x04)  # the home switch
    if model != "PoKeys56E":
        dev.ask(PEV2, 0x01, payload=bytes([1, 0, 1]))
    before = dev.pk.pulse_engine.axes[0].position
    dev.pk.home([0])
    failures = []
    try:
        dev.slots(3)
    except (ValueError, OverflowError) as error:
        failures.append(f"{type(error).__name__}: {error}")
    assert not failures, failures
    assert abs(dev.pk.pulse_engine.axes[0].position - before) <= 3 * MAX_PULSES[model]
    dev.pk.status()


@pytest.mark.parametrize("max_speed", [math.nan, -math.inf])
def test_fixed_probing_at_nan_or_minus_infinite_max_speed_faults_the_engine(
        max_speed: float) -> None:
    """CRITICAL. The same for ProbingStart (0x85/0x23): the probe speed is a fraction of
    the NaN/-inf max speed, the first probing slot raises ValueError / OverflowError in
    whole_pulses and the engine is dead. Expected: no exception; at most 125 pulses a
    slot; the status answers."""
    dev = Dev()
    dev.one_axis(0x0D, max_speed=max_speed)  # enabled, internal, position mode
    dev.running()
    dev.pk.probe({0: -5000}, speed=1.0)
    failures = []
    try:
        dev.slots(3)
    except (ValueError, OverflowError) as error:
        failures.append(f"{type(error).__name__}: {error}")
    assert not failures, failures
    assert abs(dev.pk.pulse_engine.axes[0].position) <= 3 * 125
    dev.status()


@pytest.mark.parametrize("model", ["PoKeys57CNC", "PoKeys56E"])
def test_fixed_homing_at_a_negative_max_speed_emits_1e37_pulses_a_slot(model: str) -> None:
    """MAJOR. A negative max speed (-1e38 pulses/ms, a finite f32) passes the cap
    min(max_speed, 125): homing then runs at -1e38 x 10 % pulses/ms, the wrong way, and
    one slot moves the counter by ~1e37 pulses (which then also kills the status, see
    the int32 test). A slot carries at most 125 pulses (25 on v1: status [57], seed
    v1), and a speed below zero is no speed. Expected: no axis moves more than the
    engine's pulses per slot; the status answers."""
    dev = Dev(model)
    if model != "PoKeys56E":
        dev.ask(PEV2, 0x01, payload=bytes([1, 0, 1]))
    dev.pk.configure_axis(0, max_speed=-1e38, switches=0x04)
    dev.pk.home([0])
    dev.slots(1)
    moved = dev.pk.pulse_engine.axes[0].position
    assert abs(moved) <= MAX_PULSES[model], moved
    dev.pk.status()


def test_fixed_one_hosts_nan_axis_speed_kills_both_doors_for_every_host(
        hosted: HostedBoards) -> None:
    """CRITICAL. Over UDP one host configures axis X with max speed NaN and a home switch
    and starts homing (three valid requests, each answered). From the next slot on the
    pacer's engine.advance raises in every pass (stderr gets ~1000 tracebacks a second),
    and the doors call the same sync outside their guard: every UDP request of every
    host is answered with silence (PoKeysLib: -10 for good) and a TCP host's connection
    is closed at its first request (protocol.data_received() fails). Expected: the
    device keeps answering every valid request within the host's 100 ms (reference 3)."""
    port = hosted.udp_ports[0]
    with udp_socket() as sock:
        assert udp_ask(sock, port, make_request(PEV2, 0x01, request_id=1,
                                                payload=bytes([1, 0, 1])))
        assert udp_ask(sock, port, make_request(PEV2, 0x11, 0, request_id=2, payload=axis_config(
            0x01, switches=0x04, max_speed=math.nan)))
        assert udp_ask(sock, port, make_request(PEV2, 0x21, 0x01, request_id=3))
        hosted.clock.now += 0.01  # ten slots later (the server catches up by itself)
        with udp_socket() as other:
            reply = udp_ask(other, port, status_frame(4), timeout=2.0)
        assert reply is not None and valid_reply(reply, 4), "UDP: no reply after the fault"
    with socket.create_connection(("127.0.0.1", hosted.ports[0]), timeout=5) as tcp:
        reply = tcp_ask(tcp, status_frame(5), timeout=2.0)
        assert valid_reply(reply, 5), f"TCP: {reply!r} after the fault"


@pytest.mark.parametrize("max_speed", [math.inf, math.nan])
def test_fixed_mpg_jogging_at_an_infinite_or_nan_max_speed_faults_the_engine(
        max_speed: float) -> None:
    """CRITICAL. JOGGING with an MPG encoder on an axis whose max speed is +inf or NaN:
    the first MPG count makes the slot loop take int(max_speed) for its per-slot cap
    (engine._emit) and raise OverflowError / ValueError: the engine is dead from then
    on (every door goes silent, see the door test). Expected: no exception; the MPG
    pulses go out at no more than 125 a slot."""
    dev = Dev()
    raw = bytearray(axis_config(0x01, max_speed=max_speed))
    raw[7] = 1  # MPG encoder 1
    struct.pack_into("<h", raw, 28, 1)  # MPG multiplier [36] = 1
    assert dev.ask(PEV2, 0x01, payload=bytes([1, 0, 1])) is not None
    assert dev.ask(PEV2, 0x11, 0, payload=bytes(raw)) is not None
    assert dev.ask(PEV2, 0x02, 10) is not None  # JOGGING
    dev.slots(1)
    dev.pk.device.engine.world.mpg[1] = 1000  # the wheel turned 1000 counts
    failures = []
    try:
        dev.slots(4)
    except (ValueError, OverflowError) as error:
        failures.append(f"{type(error).__name__}: {error}")
    assert not failures, failures
    assert 0 < dev.positions()[0] <= 4 * 125


def test_fixed_console_fill_builds_every_offered_slot_before_the_device_takes_128() -> None:
    """MAJOR (console). `fill 1 x 100000000` builds a hundred million rows (a list per
    row, twice: the console's and the API's copy) and scans them all before the first
    request goes out, though the buffer takes at most 128 slots and the fill stops at
    the first partial accept: ~88 MB and 5 s for x 1000000, so x 1e8 takes the REPL
    down (out of memory). Expected: the rows offered are bounded by what the device can
    take (the answer `accepted 128 of N` stays as it is): x 100000 costs no more than a
    few hundred rows' worth of memory (1 MB here; today ~9 MB)."""
    pk = PoKeys("PoKeys57CNC")
    console = pk.console()
    assert console.execute("setup 1") == []
    assert console.execute("axis X") == []
    out: list[list[str]] = []
    peak = peak_bytes(lambda: out.append(console.execute("fill 1 x 100000")))
    assert out == [["accepted 128 of 100000, buffer 128/128"]]
    assert peak < 1_000_000, peak


def test_fixed_a_reversal_runs_its_whole_stop_slot_by_slot() -> None:
    """MINOR (work). An internal-planner axis told to go back while it runs (move X
    1000000, then move X 0) stops and comes back in one motion; while it stops,
    `_motion_span` sees both directions in the span ahead and returns 1, so the engine
    emits the whole deceleration one slot at a time (2500 steps for the 2.5 s stop at
    0.05 pulses/ms^2; at 1e-4 pulses/ms^2 every 10 s of virtual time costs 10000 steps,
    and advancing an hour of a slow stop takes minutes of CPU). The engine's own rule
    (engine.py: a stretch where no input can change is emitted at once) says otherwise.
    Expected: the span ends at the stop segment's end, so 2 s of the stop take a
    handful of steps (counted here, not timed)."""
    dev = Dev()
    dev.one_axis(0x0D, max_speed=125.0, accel=0.05, decel=0.05)
    dev.running()
    assert dev.ask(PEV2, 0x20, payload=struct.pack("<8i", 1_000_000, *[0] * 7)) is not None
    dev.pk.advance(3.0)
    assert dev.ask(PEV2, 0x20, payload=struct.pack("<8i", 0, *[0] * 7)) is not None
    engine = dev.pk.pulse_engine
    steps = []
    emit = engine._emit
    engine._emit = lambda n: (steps.append(n), emit(n))  # type: ignore[method-assign]
    dev.pk.advance(2.0)
    assert sum(steps) == 2000
    assert len(steps) <= 20, f"{len(steps)} steps for 2000 slots"
    dev.pk.run_until_idle(60)
    assert dev.positions()[0] == 0


# =========================================================================================
# What held
# =========================================================================================

@pytest.mark.parametrize("bad", [
    b"\xbb" * 63,  # short
    make_request(PEV2, 0x00, 0x10, request_id=9) + b"\0",  # long
    b"\xbc" + make_request(PEV2, 0x00, 0x10, request_id=9)[1:],  # header
    make_request(PEV2, 0x00, 0x10, request_id=9)[:7] + b"\0" + bytes(56),  # checksum
    make_request(LARGE, 0x0F, 0xFF, 1, 1, request_id=9),  # a lone multi-part frame
])
def test_holds_malformed_datagrams_get_silence_and_change_nothing(bad: bytes) -> None:
    """Every malformed datagram is silent (reference 3: never an old ID), as is a
    multi-part frame whose group has not ended, and leaves the engine as it was."""
    pk = PoKeys("PoKeys57CNC")
    session = pk.open_datagram_session()
    before = (pk.pulse_engine.state, pk.pulse_engine.enabled_axes, pk.pulse_engine.buffer.count)
    session.feed(bad)
    assert session.read() == b""
    assert (pk.pulse_engine.state, pk.pulse_engine.enabled_axes,
            pk.pulse_engine.buffer.count) == before


@pytest.mark.parametrize("bad,status", [
    (make_request(0x42, request_id=9), 0xFF),  # a command the device does not know
    (make_request(PEV2, 0x77, request_id=9), 0xFF),  # an unknown pulse-engine sub
    (make_request(PEV2, 0x10, 8, request_id=9), 1),  # axis 8
    (make_request(PEV2, 0x01, request_id=9, payload=bytes([9])), 1),  # 9 axes
    (make_request(PEV2, 0x02, 20, request_id=9), 1),  # HOME cannot be set
    (make_request(PEV2, 0xFF, 57, 1, request_id=9), 0),  # 57 entries: 0 accepted
    (make_request(PEV2, 0xFF, 1, 0, request_id=9), 0),  # AX 0
    (make_request(PEV2, 0xFF, 1, 9, request_id=9), 0),  # AX 9
    (make_request(PEV2, 0xFE, 29, 1, request_id=9), 0),  # 58 bytes
])
def test_holds_refused_datagrams_are_answered_and_change_nothing(bad: bytes,
                                                                 status: int) -> None:
    """Every refused request is answered at once with its own ID and the error status in
    [2] (a fill: 0 accepted), and leaves the engine as it was."""
    pk = PoKeys("PoKeys57CNC")
    session = pk.open_datagram_session()
    before = (pk.pulse_engine.state, pk.pulse_engine.enabled_axes, pk.pulse_engine.buffer.count)
    session.feed(bad)
    reply = session.read()
    assert len(reply) == 64 and reply[0] == 0xAA and reply[6] == 9 and reply[2] == status
    assert reply[7] == sum(reply[:7]) & 0xFF and session.refused == 1
    assert (pk.pulse_engine.state, pk.pulse_engine.enabled_axes,
            pk.pulse_engine.buffer.count) == before
    session.feed(status_frame(10))
    assert valid_reply(session.read(), 10)


def test_holds_overfill_takes_exactly_the_free_slots_and_says_so() -> None:
    """20 fills of 18 slots: 128 accepted in all ([2] = accepted, reference 8), then 0
    each; after 50 slots run, exactly 50 more are taken."""
    dev = Dev()
    dev.one_axis()
    dev.running()
    assert fill8(dev, [[1]]) is not None  # the first slot starts at once
    dev.pk.advance(slots=1)
    accepted = []
    for _ in range(20):
        reply = fill8(dev, [[1]] * 56)
        assert reply is not None
        accepted.append(reply[2])
    assert sum(accepted) == 128 and accepted[-1] == 0
    dev.slots(50)
    assert fill8(dev, [[1]] * 56)[2] == 50  # type: ignore[index]
    assert dev.positions()[0] == 51


def test_holds_absurd_pulse_counts_are_clipped_to_125_a_slot() -> None:
    """16-bit entries of 0x7FFF and 0xFFFF (32767 pulses each way) on two axes: each
    slot emits at most 125 (status [57]); 4 slots each way end 500 out and back."""
    dev = Dev()
    assert dev.ask(PEV2, 0x01, payload=bytes([2, 0, 1])) is not None
    for axis in range(2):
        assert dev.ask(PEV2, 0x11, axis, payload=axis_config()) is not None
    dev.running()
    assert fill16(dev, [[0x7FFF, 0xFFFF]] * 4)[2] == 4  # type: ignore[index]
    dev.slots(4)
    assert dev.positions()[:2] == (500, -500)
    assert fill16(dev, [[0xFFFF, 0x7FFF]] * 4)[2] == 4  # type: ignore[index]
    dev.slots(10)
    assert dev.positions()[:2] == (0, 0)


def _parts(n: int, ax: int, first_id: int, order: list[int], flags: dict[int, int]) -> bytes:
    out = b""
    for k, i in enumerate(order):
        out += make_request(LARGE, i | flags.get(i, 0), 0xFF, n, ax, request_id=first_id + k,
                            payload=bytes([1]) * 56)
    return out


@pytest.mark.parametrize("order,flags", [
    ([0, 1, 2, 3, 4, 5, 6, 7], {7: 0x10}),  # no first flag
    ([0, 1, 2, 3, 4, 5, 6, 7], {0: 0x08}),  # no last flag
    ([0, 1, 2, 4, 3, 5, 6, 7], {0: 0x08, 7: 0x10}),  # out of order
    ([0, 1, 2, 3, 5, 6, 7], {0: 0x08, 7: 0x10}),  # one missing
    ([0, 1, 1, 2, 3, 4, 5, 6, 7], {0: 0x08, 7: 0x10}),  # one twice
])
def test_holds_broken_multipart_groups_are_refused_whole(order: list[int],
                                                        flags: dict[int, int]) -> None:
    """A 0xB0 group that is not 8 frames in order with first/last flags fills nothing and
    is refused at its last frame (D); a good group right after is answered once, with its
    last ID."""
    pk = PoKeys("PoKeys57CNC")
    pk.setup(1)
    session = pk.open_session()
    session.feed(_parts(100, 1, 1, order, flags))
    refusal = session.read()  # refused at its last frame (0 accepted); no last: nothing
    assert pk.pulse_engine.buffer.count == 0
    assert refusal == b"" if 7 not in flags else (len(refusal) == 64 and refusal[2] == 0)
    session.feed(_parts(100, 1, 20, list(range(8)), {0: 0x08, 7: 0x10}))
    reply = session.read()
    assert valid_reply(reply, 27) and reply[2] == 100
    assert pk.pulse_engine.buffer.count == 100


def test_holds_state_changes_mid_motion() -> None:
    """Mid-move: STOPPED freezes the counter at once; RUNNING again and the same target
    finishes the move; PositionSet mid-move shifts the target with the counter; Reboot
    mid-buffer stops, empties the buffer and zeroes the counter."""
    dev = Dev()
    dev.one_axis(0x0D, max_speed=10.0, accel=0.05, decel=0.05)
    dev.running()
    move = struct.pack("<8i", 20000, *[0] * 7)
    assert dev.ask(PEV2, 0x20, payload=move) is not None
    dev.pk.advance(0.5)
    assert dev.ask(PEV2, 0x02, 0) is not None
    frozen = dev.positions()[0]
    dev.pk.advance(1.0)
    assert 0 < frozen == dev.positions()[0] < 20000
    dev.running()
    assert dev.ask(PEV2, 0x20, payload=move) is not None
    dev.pk.advance(0.5)
    assert dev.ask(PEV2, 0x03, 0x01, payload=struct.pack("<8i", 0, *[0] * 7)) is not None
    shift = -dev.pk.pulse_engine.axes[0].stage
    assert dev.pk.run_until_idle(60)
    assert dev.positions()[0] == 20000 + shift
    dev.one_axis()
    dev.running()
    assert fill8(dev, [[100]] * 50) is not None
    dev.slots(10)
    assert dev.ask(PEV2, 0x05) is not None
    dev.slots(10)
    status = dev.status()
    assert status[10] == 0 and struct.unpack_from("<i", status, 24)[0] == 0
    assert dev.pk.pulse_engine.buffer.count == 0


def test_holds_extreme_position_targets_move_at_the_axis_speed() -> None:
    """Targets at the int32 ends, reversed mid-flight, on an axis at 125 pulses/ms: no
    slot carries more than 125 pulses and the status answers throughout."""
    dev = Dev()
    dev.one_axis(0x0D, max_speed=125.0, accel=3.4e38, decel=3.4e38)
    dev.running()
    records: list[int] = []
    dev.pk.pulse_engine.trace = lambda r: records.append(r.pulses[0])
    for target in (2**31 - 1, -(2**31), 2**31 - 1):
        assert dev.ask(PEV2, 0x20, payload=struct.pack("<8i", target, *[0] * 7)) is not None
        dev.slots(40)
        dev.status()
    assert len(records) == 120 and max(abs(p) for p in records) == 125
    assert dev.positions()[0] == sum(records)


def test_holds_a_hundred_udp_hosts_each_get_their_own_replies(hosted: HostedBoards) -> None:
    """100 unbound UDP sockets (more than the 64 sessions the door remembers), three
    status requests each, interleaved: every request is answered once, to its sender,
    with its own ID and test byte (reference 1, 2)."""
    port = hosted.udp_ports[0]
    socks = [udp_socket() for _ in range(100)]
    try:
        for round_ in range(3):
            for n, sock in enumerate(socks):
                sock.sendto(status_frame(n + round_), ("127.0.0.1", port))
            for n, sock in enumerate(socks):
                reply = sock.recv(4096)
                assert valid_reply(reply, n + round_)
                assert reply[63] == ((0x10 + n + round_) % 199 + 0x5A) & 0xFF
    finally:
        for sock in socks:
            sock.close()


def test_holds_a_udp_flood_then_the_next_request_is_answered(hosted: HostedBoards) -> None:
    """3000 requests from one socket without reading, 300 malformed ones among them:
    every reply the socket kept is valid and answers a good request; a new host after
    the flood is answered within PoKeysLib's five sends (reference 2: a datagram the
    kernel dropped while the door's socket was full is resent with a new ID)."""
    port = hosted.udp_ports[0]
    with udp_socket() as sock:
        for n in range(3000):
            frame = status_frame(n & 0xFF)
            if n % 10 == 0:
                frame = frame[:7] + bytes([frame[7] ^ 1]) + frame[8:]
            sock.sendto(frame, ("127.0.0.1", port))
        with udp_socket() as other:
            answered = None
            for request_id in range(0xF0, 0xF5):
                reply = udp_ask(other, port, status_frame(request_id), timeout=1.0)
                if reply is not None:
                    answered = (request_id, reply)
                    break
            assert answered is not None and valid_reply(answered[1], answered[0])
        sock.setblocking(False)
        kept = []
        try:
            while True:
                kept.append(sock.recv(4096))
        except BlockingIOError:
            pass
        assert 0 < len(kept) <= 2700 and all(valid_reply(r, r[6]) for r in kept)
        assert all(r[63] == ((0x10 + r[6]) % 199 + 0x5A) & 0xFF for r in kept)


def test_holds_a_tcp_host_that_never_reads_does_not_stall_the_others(
        hosted: HostedBoards) -> None:
    """A TCP host writes status requests until its socket refuses more and never reads:
    another TCP host and a UDP host are answered at once; the device's own memory does
    not grow with what the silent host wrote (back-pressure holds its input)."""
    hog = socket.create_connection(("127.0.0.1", hosted.ports[0]), timeout=5)
    hog.setblocking(False)
    frame = status_frame(1) * 256
    sent = 0
    try:
        for _ in range(4000):
            try:
                sent += hog.send(frame)
            except BlockingIOError:
                break
        assert sent >= 64 * 1024
        with socket.create_connection(("127.0.0.1", hosted.ports[0]), timeout=5) as other:
            assert valid_reply(tcp_ask(other, status_frame(2)), 2)
        with udp_socket() as sock:
            reply = udp_ask(sock, hosted.udp_ports[0], status_frame(3))
            assert reply is not None and valid_reply(reply, 3)
    finally:
        hog.close()
    with socket.create_connection(("127.0.0.1", hosted.ports[0]), timeout=5) as other:
        assert valid_reply(tcp_ask(other, status_frame(4)), 4)


# ---- fuzzing ----------------------------------------------------------------------------
@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.binary(min_size=0, max_size=600), max_size=8))
def test_holds_any_datagram_bytes_get_a_valid_reply_or_silence(datagrams: list[bytes]) -> None:
    """Arbitrary datagrams at the UDP session: nothing raises; the only answers are the
    discovery form to an empty datagram and valid 64-byte replies with the ID of a frame
    that came in."""
    pk = PoKeys("PoKeys57CNC")
    session = pk.open_datagram_session()
    for data in datagrams:
        session.feed(data)
        out = session.read()
        if is_discovery(data):  # empty, or the text form "Discovery request"
            assert len(out) == 19
            continue
        ids = {data[i + 6] for i in range(0, len(data) - 63, 64)}
        assert len(out) % 64 == 0
        for i in range(0, len(out), 64):
            assert out[i] == 0xAA and out[i + 7] == header_sum(out[i:i + 64])
            assert out[i + 6] in ids


FINITE_F32 = st.floats(width=32, allow_nan=False, allow_infinity=False)
SANE_SPEED = st.floats(min_value=0.0010000000474974513, max_value=125.0, width=32)


@settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.sampled_from(["move", "fill", "set", "state", "config", "clear"]),
                          st.integers(-(2**31), 2**31 - 1), st.integers(0, 100),
                          SANE_SPEED, FINITE_F32, FINITE_F32), min_size=1, max_size=10))
def test_holds_requests_with_absurd_finite_operands_mid_motion(
        steps: list[tuple[str, int, int, float, float, float]]) -> None:
    """Moves to any int32, fills, PositionSet, state changes and reconfiguration (sane
    positive max speed, any finite f32 ramps) at random slots, on a buffered and an
    internal axis: nothing raises, every request is answered, no slot carries more than
    125 pulses and the counters are what the slots emitted."""
    dev = Dev()
    assert dev.ask(PEV2, 0x01, payload=bytes([2, 0, 1])) is not None
    assert dev.ask(PEV2, 0x11, 0, payload=axis_config(0x0D)) is not None
    assert dev.ask(PEV2, 0x11, 1, payload=axis_config(0x01)) is not None
    dev.running()
    records: list[tuple[int, ...]] = []
    offset = [0, 0]  # PositionSet to 0 takes the counters back by what was emitted
    dev.pk.pulse_engine.trace = lambda r: records.append(r.pulses)
    for word, value, wait, speed, accel, decel in steps:
        if word == "move":
            reply = dev.ask(PEV2, 0x20, payload=struct.pack("<8i", value, *[0] * 7))
        elif word == "fill":
            reply = fill16(dev, [[0, value & 0xFFFF]] * 14)
        elif word == "set":
            reply = dev.ask(PEV2, 0x03, 0x03, payload=struct.pack("<8i", 0, 0, *[0] * 6))
            offset = [-sum(r[i] for r in records) for i in range(2)]
        elif word == "state":
            reply = dev.ask(PEV2, 0x02, (0, 3, 10)[wait % 3])
        elif word == "config":
            reply = dev.ask(PEV2, 0x11, 0, payload=axis_config(
                0x0D, max_speed=speed, accel=accel, decel=decel))
        else:
            reply = dev.ask(PEV2, 0xF0)
        assert reply is not None, word
        dev.slots(wait)
        positions = dev.positions()
        assert positions[:2] == tuple(offset[i] + sum(r[i] for r in records) for i in range(2))
    assert all(abs(p) <= 125 for r in records for p in r[:2])


NUMBERS = st.sampled_from(["0", "-1", "1e38", "-1e38", "3.5e38", "inf", "-inf", "nan", "1e-45",
                           "2147483647", "-2147483648", "2147483648", "99999999999999999999",
                           "0x10", "1_000", "", "--5", "256", "65535"])
WORDS_LINES = st.builds(
    lambda w, x, a, b, tail: f"{w} {x} {a} {b} {tail}",
    st.sampled_from(["axis", "move", "set", "fill", "state", "setup", "home", "probe", "world",
                     "input", "estop", "request", "status", "pos", "clear", "reboot", "bogus"]),
    st.sampled_from(["X", "Y", "V", "W", "9", "0", "max", "limits", "finish", "85", "when"]),
    NUMBERS, NUMBERS,
    st.sampled_from(["", "accel 1e-45", "decel nan", "at 1e9", "x 3", "16bit", "large",
                     "speed nan", "soft 5 -5", "homing 300 1", "switches lim- home", ": zz"]))


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.one_of(WORDS_LINES, st.text(max_size=40)), min_size=1, max_size=12))
def test_holds_console_lines_with_extreme_operands_answer_lines(lines: list[str]) -> None:
    """Console lines with extreme or unreadable operands (no time passing): each answers
    a list of strings (a `! ...` line for what it cannot do), never an exception, and the
    status line still renders."""
    pk = PoKeys("PoKeys57CNC")
    console = pk.console()
    for line in lines:
        out = console.execute(line)
        assert isinstance(out, list) and all(isinstance(x, str) for x in out)
    assert console.status_line().startswith("t=")

"""The `maxk_served` fixture (maxk.testing) on every kind: a real `maxk serve` process,
a host on the controller's own door, and the control door tripping a limit in the middle
of the host's move. The clock is the door's: paused, then stepped, so every position and
tick below is exact (no wall-clock waits)."""

from __future__ import annotations

import socket

import pytest

from maxk import testing
from tests.pokeys_host import Host
from tests.test_pokeys_doors import TcpSession, setup_three_axes, status

maxk_served = testing.maxk_served


def _ask(sock: socket.socket, text: str, end: bytes) -> str:
    sock.sendall(text.encode())
    data = b""
    while not data.endswith(end):
        chunk = sock.recv(4096)
        assert chunk, "the door hung up"
        data += chunk
    return data.decode("latin-1")


def _max(sock: socket.socket, text: str) -> str:
    """A MAX reply line, the board's unasked notifications (`%000 ...`) set aside as the
    EPICS driver does."""
    sock.sendall(text.encode())
    data = b""
    while True:
        while b"\n\r" not in data:
            chunk = sock.recv(4096)
            assert chunk, "the door hung up"
            data += chunk
        line, data = data.split(b"\n\r", 1)
        if not line.startswith(b"%"):
            assert not data, data
            return line.decode("latin-1")


def test_maxk_host_reads_the_limit_in_qa(maxk_served) -> None:
    served = maxk_served("MAXk-8000")
    c = served.client
    c.pause()
    with socket.create_connection(served.doors[0].tcp, timeout=10) as host:
        assert _max(host, "AX; VL10000; AC100000; MA20000; GO; RP\n") == "0"
        start = c.clock()[0]["tick"]  # paused: the move began on this tick
        trip = c.arm(1, "X fault plus active", axis="X", passes=12000)
        c.step(1.0)
        assert _max(host, "QA\n")[2] == "N"  # at 1 s not there yet
        c.step(2.0)
        qa = _max(host, "QA\n")
        assert qa[2] == "L", qa  # the limit, the MAXk's way
        fired = c.triggers(1)[0]
        # 0.1 s of ramp (500 steps) and 11500 steps at 10000/s: 1.25 s = 10240 ticks
        assert fired["id"] == trip["id"] and fired["fired_tick"] == start + 10240
        assert int(_max(host, "RP\n")) == 12000  # a hard stop where it tripped (factory)


def test_mm4005_host_reads_the_limit_in_ms(maxk_served) -> None:
    served = maxk_served("MM4005")
    c = served.client
    c.pause()
    with socket.create_connection(served.doors[0].tcp, timeout=10) as host:
        assert _ask(host, "1PA10\r1TP\r", b"\r") == "1TP0.0000\r"
        # the switch placed in front of the moving stage (a stuck-active fault set
        # mid-move is not yet seen by a running MM4005 move: see docs/control.md)
        c.arm(1, "1 plus-limit 4500", axis="1", passes=4000)
        c.step(30.0)
        assert _ask(host, "1MS\r", b"\r") == "1MSL\r"  # L: the plus limit, stopped
        position = float(_ask(host, "1TP\r", b"\r")[3:])
        assert 4.5 <= position < 5.0  # decelerated at the switch, short of 10 mm
        fired = c.triggers(1)[0]["fired_tick"]
        assert fired is not None


def test_mc405_host_reads_the_limit_in_axisstatus(maxk_served) -> None:
    served = maxk_served("MC405")
    c = served.client
    c.pause()
    with socket.create_connection(served.doors[0].tcp, timeout=10) as host:
        _ask(host, "BASE(0): SPEED=1000: ACCEL=10000: DECEL=10000: FWD_IN=3: MOVE(5000)\r",
             b">>")
        trip = c.arm(1, "0 fault plus active", axis="0", passes=2000)
        c.step(1.0)
        assert c.triggers(1)[0]["fired_tick"] is None
        c.step(2.0)
        fired = c.triggers(1)[0]
        assert fired["id"] == trip["id"] and fired["did"] == "0 fault plus active"
        board = c.board(1)
        assert board["axes"][0]["switches"]["plus"]["fault"] == "active"
        reply = _ask(host, "?AXISSTATUS AXIS(0)\r", b">>")
        assert int(float(reply.split("\r\n")[1])) & 16, reply  # FWD_IN's bit, its way


def test_pokeys_host_reads_the_limit_stop_in_its_status(maxk_served) -> None:
    served = maxk_served("PoKeys57CNC")
    c = served.client
    c.pause()
    session = TcpSession(served.doors[0].tcp[1])
    try:
        host = Host(session)  # type: ignore[arg-type]
        setup_three_axes(host, switches=0x02)  # limit+ enabled
        assert host.pev2(0x02, 3) is not None  # running
        for _ in range(4):  # 56 slots of 7 pulses: 392 would pass 100
            result = host.buffer_fill([[7, 0, 0]] * 14, 3)
            assert result is not None and result[0] == 14
        c.arm(1, "X fault plus active", axis="X", passes=100)
        c.step(0.1)
        s = status(host)
        assert s["state"] == 100 and s["axis_states"][0] == 30  # STOP_LIMIT, axis LIMIT
        assert 100 <= s["positions"][0] < 392 and s["lim_p"] & 1
        fired = c.triggers(1)[0]["fired_tick"]
        assert fired is not None
    finally:
        session.close()


def test_the_fixture_serves_mixed_kinds_and_stops_them(maxk_served) -> None:
    served = maxk_served("MAXk-8000", "PoKeys57CNC", "MM4005")
    assert [d.model for d in served.doors] == ["MAXk-8000", "PoKeys57CNC", "MM4005"]
    assert served.doors[1].udp is not None and served.doors[0].udp is None
    assert [b["kind"] for b in served.client.boards()] == ["MAXk", "PoKeys", "MM4005"]
    served.stop()
    assert served.process.returncode is not None


def test_a_server_that_cannot_start_says_why() -> None:
    with pytest.raises(RuntimeError, match="not a model|unknown|model"):
        testing.serve("NoSuchBoard")


def test_beyond_loopback_serve_prints_a_token_and_asks_for_it(maxk_served) -> None:
    from maxk.control import Client, ControlError

    served = maxk_served("MAXk-8000", options=("--host", "0.0.0.0"))
    assert served.token and served.url.startswith("http://0.0.0.0:")
    with pytest.raises(ControlError) as refused:
        Client(served.url).boards()
    assert refused.value.status == 401 and "token" in refused.value.reason
    assert served.client.boards()[0]["model"] == "MAXk-8000"


def test_a_control_port_in_use_is_reported() -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        with pytest.raises(RuntimeError, match="control door"):
            testing.serve("MAXk-8000", options=("--control-port", str(port)))


def test_a_pokeys_library_host_reads_an_input_the_door_drives(maxk_served) -> None:
    from tests.pokeys_host import PK_OK
    from tests.pokeys_lib_host import LibHost

    served = maxk_served("PoKeys57CNC")
    session = TcpSession(served.doors[0].tcp[1])
    try:
        lib = LibHost(Host(session))  # type: ignore[arg-type]
        lib.pin_function[2] = 0x02  # pin 3: a digital input
        assert lib.PK_PinConfigurationSet() == PK_OK
        assert lib.PK_DigitalIOGetSingle(2) == (PK_OK, 0)
        assert served.client.world(1, input=3, level=True) == "input 3 high"
        assert lib.PK_DigitalIOGetSingle(2) == (PK_OK, 1)
        served.client.world(1, "input 3 low")
        assert lib.PK_DigitalIOGetSingle(2) == (PK_OK, 0)
    finally:
        session.close()

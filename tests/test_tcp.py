"""The MAXnet-style TCP door: the evidence exchanges over real sockets, framing,
notifications, several clients, and a server that survives bad clients."""

import socket

import pytest

from tests.hosting import Client, HostedBoards


@pytest.fixture
def hosted():
    h = HostedBoards()
    yield h
    h.close()


def test_e1_asyn_startup_over_tcp(hosted):
    c = hosted.connect()
    assert "ver:" in c.query("WY")
    for line in ("IC;", "AM SA;", "AX LH PSO;"):
        c.command(line)
    assert c.query("AA RP;") == "0,0,0,0,0,0,0,0"
    for axis in "XYZTUVRS":
        assert c.query(f"A{axis} PS?") == "=O"
        assert c.query(f"A{axis} LT?") == ("=h" if axis == "X" else "=l")
    assert c.query("AM PP;") == "0,0,0,0,0,0,0,0"
    assert c.query("#WS") == "=0"
    assert c.nothing_pending(hosted)


def test_replies_end_with_lf_cr_and_commands_without_reply_send_nothing(hosted):
    c = hosted.connect()
    c.command("AX;VL5000;")
    assert c.nothing_pending(hosted)
    c.send("AX RP\n")
    data = b""
    while not data.endswith(b"\n\r"):
        data += c.sock.recv(100)
    assert data == b"0\n\r"


def test_e3_move_with_done_notification_between_query_and_reply(hosted):
    c = hosted.connect()
    c.command("AX;AC200000;VL50000;VB1000;MA250000;GO;ID;")
    hosted.advance(10.0)  # the move ends and ID sets done: a notification goes out
    assert c.line() == "%000 00000001"
    assert c.query("AM;RI;") == "PDNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN"
    assert c.query("AX;RP;") == "250000"


def test_command_error_notification(hosted):
    c = hosted.connect()
    c.command("AX QQ;")
    assert c.line() == "%000 01000000"  # EPICS: "000 01" is CMD_ERR_FLAG
    c.command("IC;")
    assert c.query("AX RP") == "0"


def test_e4_jog_stop_home_over_tcp(hosted):
    c = hosted.connect()
    c.command("AX AC200000; JG-5000;")
    hosted.advance(1.0)
    assert c.query("AX RV") == "-5000"
    c.command("AX AC200000; ST ID;")
    hosted.advance(1.0)
    assert c.query("AM;RI;").startswith("MDNN")
    c.command("AX;CA;AC200000;VL10000;VB100;HM;MA0;GO;ID;")
    hosted.advance(5.0)
    assert c.query("AX RP") == "0"
    assert c.query("AX QA") == "MDNH"


def test_e5_classic_motion_messages(hosted):
    c = hosted.connect()
    c.command("AX  VL4000 VB100 AC19500 MA5100 GD ID;")
    hosted.advance(5.0)
    assert c.query("AX RA;") == "PDNN"
    c.command("AX  VL4000 VB100 AC19500 MR-200.9 GD ID;")
    hosted.advance(5.0)
    assert c.query("AX RP;") == "4900"


def test_e8_dll_strings_without_terminators_other_than_the_transport(hosted):
    c = hosted.connect()
    assert c.query(";WY;").startswith("MAXk-8000")
    c.command("AXMR10000;GDID")
    hosted.advance(1.0)
    assert c.query("AXRP") == "10000"


def test_several_clients_share_one_board_but_not_a_half_command(hosted):
    a, b = hosted.connect(), hosted.connect()
    a.send("AX;MR12")  # half a command from a...
    b.command("AX;MR5;GO;")  # ...does not mix with b's
    a.command("00;GO;")
    hosted.advance(2.0)
    assert a.query("AX RP") == b.query("AX RP") == "1205"


def test_ack_and_lf_framing_options():
    h = HostedBoards(eol="lf", ack=True)
    try:
        c = Client(h.ports[0], eol=b"\n")
        h.on_close(c.close)
        c.send("AX RP\n")
        assert c.line() == "\x060"
    finally:
        h.close()


def test_robustness_disconnects_floods_garbage_and_many_clients(hosted):
    # a client that disconnects mid-command
    quitter = hosted.connect()
    quitter.send("AX;MR10")
    quitter.close()
    # a client that sends 10 MB without a terminator
    flood = hosted.connect()
    chunk = b"1" * 65536
    flood.send(b"MR")
    for _ in range(160):
        flood.send(chunk)
    # garbage bytes
    junk = hosted.connect()
    junk.send(bytes(range(256)) * 4 + b"\n")
    # 50 more clients, all served
    clients = [hosted.connect() for _ in range(50)]
    for i, c in enumerate(clients):
        assert c.query(f"AY LP{i};AY RP") == str(i)
    assert hosted.connect().query("WY").startswith("MAXk-8000")
    # the flood was cut off as one bad command, and memory stays bounded
    service = hosted.services[0]
    assert hosted.call(lambda: service.controller.command_error)
    flood.send(b";\n")
    assert flood.query("AX RP") == "0"
    for c in [flood, junk, *clients]:
        c.close()


def test_client_that_never_reads_does_not_grow_memory(hosted):
    """A host that sends as much as it can and never reads: the server holds at most its
    input limit (plus the one read that crossed it) and the replies up to the high-water
    mark (plus one slice's replies), whatever the host sends; another host is still
    answered."""
    from maxk.host.server import HIGH_WATER, INBOX_LIMIT

    lazy = hosted.connect()
    lazy.sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 4096)
    lazy.sock.setblocking(False)
    sent = 0
    for _ in range(20_000):  # until the kernel's buffers are full too
        try:
            sent += lazy.sock.send(b"AA RP;" * 200)
        except BlockingIOError:
            break

    def held() -> int:
        return sum(c.held_input + c._unsent() for c in hosted.services[0].clients)

    for _ in range(50):  # let the server run what it will run
        hosted.advance(0.0)
    assert sent > INBOX_LIMIT + HIGH_WATER  # the host sent more than the server holds
    one_read = 256 * 1024  # asyncio reads up to this at once, before reading pauses
    assert hosted.call(held) <= INBOX_LIMIT + one_read + HIGH_WATER + 64 * 1024
    # another client is still answered at once
    assert hosted.connect().query("AX RP") == "0"
    lazy.close()


def test_four_boards_are_independent():
    h = HostedBoards(models=("MAXk-1000", "MAXk-2000", "MAXk-4000", "MAXk-A000"))
    try:
        answers = [h.connect(n).query("AA RP") for n in (1, 2, 3, 4)]
        assert answers == ["0", "0,0", "0,0,0,0", "0,0,0,0,0,0,0,0,0,0"]
        h.connect(2).command("AX;MR5;GO;")
        h.advance(1.0)
        assert h.connect(1).query("AX RP") == "0"
        assert h.connect(2).query("AX RP") == "5"
    finally:
        h.close()


def test_a_query_held_by_wq_is_answered_when_the_queue_empties(hosted):
    c = hosted.connect()
    c.command("AX;VL50000;AC500000;MR2000;GO;")  # run: the move waits for the clock
    c.send("WQ;RP;\n")
    board = hosted.services[0].controller.board
    for _ in range(1000):  # until the server has read it and holds the stream
        if hosted.call(lambda: bool(board.parser_waits)):
            break
    assert hosted.call(lambda: bool(board.parser_waits))
    hosted.advance(1.0)  # the move ends; the held RP runs and its reply goes out
    assert c.line() == "2000"


def test_a_stopping_server_hangs_up_on_its_hosts():
    """When `maxk serve` stops, a host still connected reads the end of the stream (its
    socket is closed by the server, not left to the process's exit)."""
    h = HostedBoards()
    c = Client(h.ports[0])  # (not the boards' own: it must outlive them)
    try:
        c.command("AX RP")
        assert c.line() == "0"
        h.close()
        c.sock.settimeout(5)
        assert c.sock.recv(100) == b""
    finally:
        c.close()

"""Issue 40: the OMS family's older host code on the MAXk. Control characters stand on
their own (^X clears the command error and keeps the axis select), EN echoes, the EPICS
motor record's VL-before-VB order moves at the new VL, a PC68-style host's unterminated
commands run, and a PC68-style stream host runs a whole session through `framing=pc68`;
each in-process and over TCP."""

from __future__ import annotations

import pytest

from maxk.commands.max.lexer import ControlCharacter, Lexer
from maxk.commands.max.session import Framing
from maxk.controllers.contract import BuildOptions
from maxk.controllers.registry import build
from tests.hosting import HostedBoards
from tests.pc68_host import CommandFailed, PC68Host, SessionTransport, SocketTransport

RATE = 8192  # the MAXk's default update rate: ticks a second


def _maxk(framing: str = "maxnet"):
    return build("MAXk-4000", BuildOptions(line_options={"framing": framing}))


def _read(session) -> bytes:
    return session.read()


# ---- control characters ------------------------------------------------------------------
def test_a_control_character_is_never_part_of_a_mnemonic():
    lexer = Lexer()
    items = lexer.feed("\x18AX QA\x04WY\x01RP;")
    names = [i.char if isinstance(i, ControlCharacter) else i.text for i in items]
    assert names == ["\x18", "AX", "QA", "\x04", "WY", "\x01", "RP"]
    # One ends an operand as a separator would.
    items = Lexer().feed("MA4000\x18")
    assert [i.text for i in items] == ["MA4000", "^X"]


def test_ctrl_x_keeps_the_axis_select_and_clears_the_error_in_process():
    c = _maxk()
    s = c.open_session()
    s.feed(b"AX LP5; AY LP77;\n")
    s.feed(b"AX XX;\n")  # an unknown command: the error flag sets
    assert c.command_error
    assert _read(s) == b"%000 01000000\n\r"
    s.feed(b"\x18AX QA RP\n")
    assert not c.command_error
    assert _read(s) == b"PNNN\n\r5\n\r"  # X's replies, not Y's; no new error
    s.feed(b"\x04WY\n")  # ^D stands alone: WY answers
    assert _read(s).startswith(b"MAXk-4000, ")
    assert not c.command_error


def test_ctrl_x_while_wq_holds_the_stream_acts_at_once():
    c = _maxk()
    s = c.open_session()
    s.feed(b"AX QQ; VL1000; MR1000; GO; WQ; RP;\n")
    assert c.command_error
    s.feed(b"\x18")
    assert not c.command_error  # before the held RP ran
    c.run_until_idle()
    assert _read(s).endswith(b"1000\n\r")


# ---- echo ----------------------------------------------------------------------------------
def test_en_echoes_each_later_write_before_its_replies_and_ef_ends_it():
    c = _maxk()
    s = c.open_session()
    s.feed(b"EN\n")
    assert _read(s) == b""  # EN's own bytes came while echo was off
    s.feed(b"AX LP12 RP\n")
    assert _read(s) == b"AX LP12 RP\n12\n\r"
    other = c.open_session()  # another host's stream is not echoed
    other.feed(b"AX RP\n")
    assert _read(other) == b"12\n\r"
    s.feed(b"EF\n")
    assert _read(s) == b"EF\n"  # its bytes arrived while echo was on
    s.feed(b"AX RP\n")
    assert _read(s) == b"12\n\r"


# ---- the motor record's order --------------------------------------------------------------
def _motor_record_move(send, advance, query):
    """After a move at VB5000 the motor record sends VL before VB. The move must run at
    the new VL4000: from 20000 to 4000 at AC18000 from VB400, ramps of (4000-400)/18000
    = 0.2 s over (400+4000)/2*0.2 = 440 steps each, 16000-880 = 15120 steps at 4000 in
    3.78 s: 4.18 s in all."""
    send("AX VL20000 VB5000 AC100000 MA20000 GD ID;")
    advance(2.0)
    assert query("AX RP") == "20000"
    send("AX  VL4000 VB400 AC18000 MA4000 GD ID;")
    advance(2.0)
    assert query("AX RV") == "-4000"
    advance(2.17)  # 4.17 s: 10 ms to go, about 5 steps (at 400 + 18000 * 0.01 = 580/s)
    assert 4000 < int(query("AX RP")) < 4010
    advance(0.02)  # 4.19 s
    assert query("AX RP") == "4000"
    assert query("AX RA").startswith("MD")


def test_motor_record_order_moves_at_the_new_vl_in_process():
    c = _maxk()
    s = c.open_session()

    def query(text):
        s.read()
        s.feed((text + "\n").encode())
        return s.read().decode().split("\n\r")[-2]

    def advance(seconds):
        c.engine.advance(round(seconds * RATE))

    _motor_record_move(lambda t: s.feed((t + "\n").encode()), advance, query)
    assert not c.command_error


def test_a_move_with_vb_not_below_vl_is_the_command_error():
    c = _maxk()
    s = c.open_session()
    s.feed(b"AX VL4000 VB400 MR100 GO; VB5000; MR100 GO;\n")
    c.run_until_idle()
    assert c.command_error
    assert c.last_error.reason == "VB5000 is not below VL4000"
    assert c.position("X") == 100


# ---- unterminated commands -----------------------------------------------------------------
def test_unterminated_commands_run_at_the_end_of_a_pc68_write():
    c = _maxk("pc68")
    s = c.open_session()
    s.feed(b"AX LP4000")
    assert c.position("X") == 4000
    s.feed(b"AX JG-4000")
    c.engine.advance(RATE)
    assert c.velocity("X") == -4000
    s.feed(b"AX ST")
    c.run_until_idle()
    s.feed(b"AX VL4000")
    assert c.board.axes[0].config.velocity == 4000
    assert not c.command_error
    # The MAXnet framing keeps waiting: a TCP segment may end mid-number.
    m = _maxk()
    t = m.open_session()
    t.feed(b"AX LP40")
    t.feed(b"00;")
    assert m.position("X") == 4000


def test_pc68_framing_puts_status_bytes_in_band():
    c = _maxk("pc68")
    s = c.open_session()
    s.feed(b"AX EA")  # X has no encoder: '#' at once, nothing else
    assert s.read() == b"#"
    s.feed(b"\x18AX MR10 GO ID")
    c.run_until_idle()
    s.feed(b"AX RP")
    assert s.read() == b"!\n\r10\n\r\r"  # done in the leading run; trailing run as long
    s.feed(b"AX RP")
    assert s.read() == b"\n\r10\n\r"
    with pytest.raises(ValueError):
        Framing.from_options({"framing": "pc68", "ack": ""})
    with pytest.raises(ValueError):
        Framing.from_options({"framing": "vme9"})


# ---- a PC68-style host's whole session -------------------------------------------------------
def _pc68_session(host: PC68Host, advance, set_home) -> None:
    """What a PC68 driver does (evidence E7), then a poll, a move in the motor record's
    order, a home search, a jog and a stop, all with no terminator."""
    (ident,) = host.ask("WY")
    assert ident.startswith("MAXk-4000, ")
    for text in ("EF", "IC", "AA SA"):
        host.write(text)
    assert host.ask("AA RP") == ["0,0,0,0"]
    for axis in "XYZT":  # no encoders: each answers '#'
        assert host.expect_failure(f"A{axis} EA")
        host.write("\x18")
    assert host.ask("AX QA RP", 2) == ["PNNN", "0"]
    host.write("AX VL20000 VB5000 AC100000 MA20000 GD ID")
    advance(2.0)
    assert host.ask("AX QA RP", 2) == ["PDNN", "20000"]
    assert host.status_seen == ["!"]
    host.write("AX  VL4000 VB400 AC18000 MA4000 GD ID")
    advance(2.0)
    assert host.ask("AX QA RP RV", 3)[2] == "-4000"
    advance(2.5)
    assert host.ask("AX QA RP", 2) == ["MDNN", "4000"]
    set_home(6000, 6100)
    host.write("AX VL1000 VB100 AC9000 HM0 GD ID")
    advance(4.0)
    qa, rp = host.ask("AX QA RP", 2)
    assert qa == "PDNH" and 0 <= int(rp) < 100  # found at 6000 and called 0
    host.write("AX JG-4000")
    advance(1.0)
    assert host.ask("AX QA RV", 2)[1] == "-4000"
    host.write("AX AC200000 ST ID")
    advance(1.0)
    assert host.ask("AX RV") == ["0"]
    host.write("AX LP4000")
    assert host.ask("AX QA RP", 2) == ["MDNN", "4000"]
    assert host.replies == 18  # every reply read, none lost, none extra
    with pytest.raises(CommandFailed):
        host.ask("AX EA")


def test_pc68_host_session_in_process():
    c = _maxk("pc68")
    host = PC68Host(SessionTransport(c.open_session()))
    _pc68_session(host, lambda s: c.engine.advance(round(s * RATE)),
                  lambda lo, hi: c.set_home("X", lo, hi))
    assert host.transport.read_byte() is None  # nothing left over


def test_pc68_host_session_over_tcp():
    hosted = HostedBoards(models=("MAXk-4000",))
    try:
        controller = hosted.services[0].controller
        hosted.call(lambda: setattr(controller, "framing", Framing(style="pc68")))
        sock = hosted.connect().sock
        transport = SocketTransport(sock)
        host = PC68Host(transport)

        def advance(seconds):
            hosted.until_run(transport)  # the door ran what the host wrote
            hosted.advance(seconds)

        def set_home(lo, hi):
            hosted.call(lambda: controller.set_home("X", lo, hi))

        _pc68_session(host, advance, set_home)
        sock.settimeout(0.2)
        assert transport.read_byte() is None
    finally:
        hosted.close()


# ---- the same host forms over TCP, default framing -------------------------------------------
def test_ctrl_x_echo_and_motor_record_order_over_tcp():
    hosted = HostedBoards(models=("MAXk-4000",))
    try:
        c = hosted.connect()
        controller = hosted.services[0].controller
        c.command("AX LP5; AY LP77; AX XX;")
        assert c.line() == "%000 01000000"
        assert hosted.call(lambda: controller.command_error)
        c.send("\x18AX QA RP\n")
        assert c.line() == "PNNN" and c.line() == "5"
        assert not hosted.call(lambda: controller.command_error)
        assert c.query("\x04WY").startswith("MAXk-4000, ")
        c.send("EN\n")
        c.send("AX RP\n")
        assert c.line() == "AX RP\n5"  # the echo, then the reply
        c.send("EF\n")  # its own bytes still come back (they came while echo was on)
        assert c.sock.recv(3) == b"EF\n"

        def query(text):
            return c.query(text)

        def advance(seconds):
            hosted.until_run(c)
            hosted.advance(seconds)

        _motor_record_move(c.command, advance, query)
        assert not hosted.call(lambda: controller.command_error)
    finally:
        hosted.close()


def test_unterminated_lp_runs_over_tcp_with_the_pc68_framing():
    hosted = HostedBoards(models=("MAXk-4000",))
    try:
        controller = hosted.services[0].controller
        hosted.call(lambda: setattr(controller, "framing", Framing(style="pc68")))
        transport = SocketTransport(hosted.connect().sock)
        transport.write(b"AX LP4000")
        hosted.until_run(transport)
        assert hosted.call(lambda: controller.position("X")) == 4000
        host = PC68Host(transport)
        assert host.ask("AX RP") == ["4000"]
    finally:
        hosted.close()


# ---- maxk serve --framing ------------------------------------------------------------------
def test_serve_framing_pc68_frames_a_maxk_and_refuses_ack_with_it():
    import re
    import signal
    import socket
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).parent.parent
    proc = subprocess.Popen(
        [sys.executable, "-m", "maxk", "serve", "--model", "MAXk-1000", "--port", "0",
         "--no-archive", "--framing", "pc68"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=root)
    try:
        port = int(re.search(r"tcp 127\.0\.0\.1:(\d+)", proc.stdout.readline())[1])
        with socket.create_connection(("127.0.0.1", port), timeout=10) as sock:
            host = PC68Host(SocketTransport(sock))
            host.write("AX LP4000")  # no terminator, no reply
            assert host.ask("AX RP") == ["4000"]
            assert host.expect_failure("AX EA")
    finally:
        proc.send_signal(signal.SIGTERM)
        _out, err = proc.communicate(timeout=20)
    assert proc.returncode == 0, err
    result = subprocess.run(
        [sys.executable, "-m", "maxk", "serve", "--framing", "pc68", "--ack", "--port", "0",
         "--seconds", "0.1", "--no-archive"], capture_output=True, text=True, timeout=30,
        cwd=root)
    assert result.returncode == 2
    assert result.stderr.strip() == ("maxk serve: ack is the MAXnet framing's; the pc68 "
                                     "framing has none")


def test_pyserial_url_takes_the_pc68_framing():
    import serial

    import maxk  # noqa: F401  (registers maxk://)

    port = serial.serial_for_url("maxk://MAXk-1000?framing=pc68&speed=1000", timeout=2)
    port.write(b"AX LP4000")  # each write() is whole commands
    port.write(b"AX RP")
    assert port.read(8) == b"\n\r4000\n\r"
    port.write(b"AX EA")
    assert port.read(1) == b"#"
    port.close()
    for bad in ("maxk://?framing=vme9", "maxk://?framing=pc68&ack"):
        with pytest.raises(serial.SerialException):
            serial.serial_for_url(bad)


def test_a_pc68_host_on_the_maxnet_framing_goes_one_line_off():
    """Why the framing exists (issue 40): the done notification is read as a poll's reply."""
    c = _maxk()
    host = PC68Host(SessionTransport(c.open_session()))
    host.write("AX MR10 GO ID")
    c.run_until_idle()
    assert host.ask("AX RP") == ["%000 00000001"]  # not the position


def test_an_archive_saved_with_vb_above_vl_loads_and_its_move_is_refused(tmp_path):
    from maxk import MAXk

    path = str(tmp_path / "flash.json")
    board = MAXk("MAXk-1000", archive=path)
    board.send("AX VL20000 VB5000 VL4000; APP;")  # between the host's VL and its VB
    assert not board.command_error
    again = MAXk("MAXk-1000", archive=path)
    assert again.query("AX RV") == "0"
    assert (again.board.axes[0].config.velocity,
            again.board.axes[0].config.base_velocity) == (4000, 5000)
    again.send("AX MR100 GO;")
    assert again.last_error.reason == "VB5000 is not below VL4000"
    again.send("IC; AX VB400 MR100 GO;")
    again.run_until_idle()
    assert again.position("X") == 100 and not again.command_error

"""The MM4005 behind the real doors: `maxk serve`'s server in-process (the registry builds
the controller, a manual clock paces it), a host on a real TCP socket or the pty. The
exchanges of /work/shared/reference/mm4005-epics-client.md are replayed byte for byte,
for the model 2 (drvMM4000Asyn) and model 1 (drvMM4000) drivers; every byte the
controller sends must be what the driver reads, CR only."""

from __future__ import annotations

import socket

import serial

from tests.hosting import Client, HostedBoards


class CrHost:
    """A host reading CR-terminated replies, as asyn does with input EOS "\\r". Every
    byte received is kept, so a stray LF or an unasked reply fails the exchange."""

    def __init__(self, port: int) -> None:
        self.sock = socket.create_connection(("127.0.0.1", port), timeout=5)
        self.received = b""

    def exchange(self, sent: bytes, reply: bytes) -> None:
        """Send one write; read exactly the reply's lines, and check them byte for byte."""
        self.sock.sendall(sent)
        data = b""
        while data.count(b"\r") < reply.count(b"\r"):
            chunk = self.sock.recv(65536)
            assert chunk, "closed"
            data += chunk
        self.received += data
        assert data == reply, (sent, data, reply)

    def close(self) -> None:
        self.sock.close()


MODEL2_INIT = [
    (b"VE;\r", b"VE MM4005 Version 2.42\r"),
    (b"TP;\r", b"1TP0.0000,2TP0.0000\r"),
    (b"1TC\r", b"1TC0\r"), (b"1TU\r", b"1TU0.001\r"), (b"1XH\r", b"1XH0.0000\r"),
    (b"1TL\r", b"1TL-100.0000\r"), (b"1TR\r", b"1TR100.0000\r"),
    (b"2TC\r", b"2TC0\r"), (b"2TU\r", b"2TU0.001\r"), (b"2XH\r", b"2XH0.0000\r"),
    (b"2TL\r", b"2TL-100.0000\r"), (b"2TR\r", b"2TR100.0000\r"),
    (b"1SR100.00000\r", b""), (b"1SL-100.00000\r", b""),
    (b"2SR100.00000\r", b""), (b"2SL-100.00000\r", b""),
]


def _model2_poll(ms: bytes, tp: bytes) -> list[tuple[bytes, bytes]]:
    """One poll: MS, TP, then TE once per axis."""
    return [(b"MS;\r", ms), (b"TP;\r", tp), (b"TE;\r", b"TE@\r"), (b"TE;\r", b"TE@\r")]


def _replay(host: CrHost, exchanges: list[tuple[bytes, bytes]]) -> None:
    for sent, reply in exchanges:
        host.exchange(sent, reply)


def test_model2_init_poll_and_motion_over_tcp() -> None:
    hosted = HostedBoards(models=("MM4005-2",))
    host = CrHost(hosted.ports[0])
    try:
        _replay(host, MODEL2_INIT + _model2_poll(b"1MSD,2MSD\r", b"1TP0.0000,2TP0.0000\r"))
        # VAL 2.5 at VELO 1, ACCL 0.2 s: a trapezoid of 0.2 + 2.3 + 0.2 s
        host.exchange(b"1AC5.00000;1VA1.00000;1PA2.50000;\r", b"")
        _replay(host, _model2_poll(b"1MSE,2MSD\r", b"1TP0.0000,2TP0.0000\r"))
        hosted.advance(1.0)
        _replay(host, _model2_poll(b"1MSE,2MSD\r", b"1TP0.9000,2TP0.0000\r"))
        hosted.advance(1.7)
        _replay(host, _model2_poll(b"1MSD,2MSD\r", b"1TP2.5000,2TP0.0000\r"))
        # JOGF then release: a PA to the TR read at init, then a stop at AC
        host.exchange(b"2AC5.00000;2VA1.00000;2PA100.00000;\r", b"")
        _replay(host, _model2_poll(b"1MSD,2MSE\r", b"1TP2.5000,2TP0.0000\r"))
        hosted.advance(1.0)
        host.exchange(b"2AC5.00000;2ST;\r", b"")
        _replay(host, _model2_poll(b"1MSD,2MSE\r", b"1TP2.5000,2TP0.9000\r"))
        hosted.advance(0.2)
        _replay(host, _model2_poll(b"1MSD,2MSD\r", b"1TP2.5000,2TP1.0000\r"))
        # STOP on a still axis: nothing happens
        host.exchange(b"1AC5.00000;1ST;\r", b"")
        # HOMF at HVEL 2: down through the home switch (counts 1234..1333), back onto it
        host.exchange(b"1AC10.00000; 1VA2.00000;1OR;\r", b"")
        _replay(host, _model2_poll(b"1MSA,2MSD\r", b"1TP2.5000,2TP1.0000\r"))
        hosted.advance(5.0)
        _replay(host, _model2_poll(b"1MSd,2MSD\r", b"1TP0.0000,2TP1.0000\r"))
        # SET + FOFF frozen: preset, define home, preset back
        host.exchange(b"2SH5.00000;2DH;2SH0.00000\r", b"")
        _replay(host, _model2_poll(b"1MSd,2MSD\r", b"1TP0.0000,2TP5.0000\r"))
        host.exchange(b"2XH\r", b"2XH0.0000\r")
        assert b"\n" not in host.received
    finally:
        host.close()
        hosted.close()


def test_model2_cnen_power_off_bit_and_its_ms_loop() -> None:
    """CNEN 0 sends MF; the driver then polls MS every 0.1 s until bit 1 (power OFF) is
    clear (reference, stall 4): the bit is set as the manual defines it, so the loop goes
    on until MO, as with a real MM4005."""
    hosted = HostedBoards(models=("MM4005-2",))
    host = CrHost(hosted.ports[0])
    try:
        _replay(host, MODEL2_INIT)
        host.exchange(b"1MF\r", b"")
        for _ in range(10):
            host.exchange(b"MS;\r", b"1MSF,2MSD\r")  # 0x46: power off, direction +
            hosted.advance(0.1)
        host.exchange(b"1MO\r", b"")
        host.exchange(b"MS;\r", b"1MSD,2MSD\r")
        # the MS offset rule: axis n's character at (n - 1) * 5 + 3
        host.exchange(b"2MF\r", b"")
        host.sock.sendall(b"MS;\r")
        reply = b""
        while not reply.endswith(b"\r"):
            reply += host.sock.recv(100)
        assert reply[0 * 5 + 3] == ord("D") and reply[1 * 5 + 3] == ord("F")
    finally:
        host.close()
        hosted.close()


MODEL1_INIT = [
    (b"TH;\r", b"1TH0.0000,2TH0.0000\r"),
    (b"ST;\r", b""),
    (b"VE;\r", b"VE MM4005 Version 2.42\r"),
    (b"TH;\r", b"1TH0.0000,2TH0.0000\r"),
    (b"MS;\r", b"1MSD,2MSD\r"),
    (b"TH;\r", b"1TH0.0000,2TH0.0000\r"),
    (b"TP;\r", b"1TP0.0000,2TP0.0000\r"),
    (b"1TC\r", b"1TC0\r"), (b"1TU\r", b"1TU0.001\r"), (b"1XH\r", b"1XH0.0000\r"),
    (b"1TL\r", b"1TL-100.0000\r"), (b"1TR\r", b"1TR100.0000\r"),
    (b"2TC\r", b"2TC0\r"), (b"2TU\r", b"2TU0.001\r"), (b"2XH\r", b"2XH0.0000\r"),
    (b"2TL\r", b"2TL-100.0000\r"), (b"2TR\r", b"2TR100.0000\r"),
    (b"TE;\r", b"TE@\r"),
]


def _model1_poll(ms: bytes, tp: bytes, th: bytes) -> list[tuple[bytes, bytes]]:
    return [(b"MS;\r", ms), (b"TP;\r", tp), (b"TH;\r", th), (b"TE;\r", b"TE@\r")]


def test_model1_init_poll_and_motion_over_tcp() -> None:
    """Model 1 reads its readback from TH (the theoretical position), TP only for a
    closed loop; a CR LF reply would shift every later reply by one byte (crash 6)."""
    hosted = HostedBoards(models=("MM4005-2",))
    host = CrHost(hosted.ports[0])
    try:
        _replay(host, MODEL1_INIT)
        # AC = (VELO - VBAS) / ACCL = 4.5: a 0.2222 s ramp over 0.1111 units
        host.exchange(b"1VA1.00000;1AC4.50000;1PA2.50000;\r", b"")
        _replay(host, _model1_poll(b"1MSE,2MSD\r", b"1TP0.0000,2TP0.0000\r",
                                   b"1TH0.0000,2TH0.0000\r"))
        hosted.advance(0.5)  # 0.1111 + 0.2778 = 0.3889 units: TP in whole counts, TH exact
        _replay(host, _model1_poll(b"1MSE,2MSD\r", b"1TP0.3880,2TP0.0000\r",
                                   b"1TH0.3889,2TH0.0000\r"))
        hosted.advance(2.5)
        _replay(host, _model1_poll(b"1MSD,2MSD\r", b"1TP2.5000,2TP0.0000\r",
                                   b"1TH2.5000,2TH0.0000\r"))
        # jog to DHLM, stop; home at HVEL 2; CNEN off and on (no wait loop in model 1)
        host.exchange(b"2AC5.00000;2VA1.00000;2PA100.00000;\r", b"")
        _replay(host, _model1_poll(b"1MSD,2MSE\r", b"1TP2.5000,2TP0.0000\r",
                                   b"1TH2.5000,2TH0.0000\r"))
        hosted.advance(1.0)
        host.exchange(b"2ST;\r", b"")
        _replay(host, _model1_poll(b"1MSD,2MSE\r", b"1TP2.5000,2TP0.9000\r",
                                   b"1TH2.5000,2TH0.9000\r"))
        hosted.advance(0.2)
        _replay(host, _model1_poll(b"1MSD,2MSD\r", b"1TP2.5000,2TP1.0000\r",
                                   b"1TH2.5000,2TH1.0000\r"))
        host.exchange(b"1VA2.00000;1AC9.50000;1OR;\r", b"")
        _replay(host, _model1_poll(b"1MSA,2MSD\r", b"1TP2.5000,2TP1.0000\r",
                                   b"1TH2.5000,2TH1.0000\r"))
        hosted.advance(5.0)
        _replay(host, _model1_poll(b"1MSd,2MSD\r", b"1TP0.0000,2TP1.0000\r",
                                   b"1TH0.0000,2TH1.0000\r"))
        host.exchange(b"1MF;\r", b"")
        host.exchange(b"MS;\r", b"1MSf,2MSD\r")
        host.exchange(b"1MO;\r", b"")
        host.exchange(b"MS;\r", b"1MSd,2MSD\r")
        assert b"\n" not in host.received
    finally:
        host.close()
        hosted.close()


def test_lines_split_anywhere_and_empty_lines_ignored() -> None:
    hosted = HostedBoards(models=("MM4005-2",))
    host = CrHost(hosted.ports[0])
    try:
        host.exchange(b"\r", b"")
        host.exchange(b"1T", b"")
        host.exchange(b"P", b"")
        host.exchange(b"\r", b"1TP0.0000\r")
        host.exchange(b"VE;TE\r\r", b"VE MM4005 Version 2.42\rTE@\r")
    finally:
        host.close()
        hosted.close()


def test_maxk_and_mm4005_served_together() -> None:
    """`maxk serve --model MAXk-8000,MM4005`: one server, each controller its own port and
    its own framing."""
    hosted = HostedBoards(models=("MAXk-8000", "MM4005"))
    maxk_host = Client(hosted.ports[0])
    mm_host = CrHost(hosted.ports[1])
    try:
        assert maxk_host.query("WY").startswith("MAXk-8000")
        mm_host.exchange(b"TP;\r", b"1TP0.0000,2TP0.0000,3TP0.0000,4TP0.0000\r")
        mm_host.exchange(b"3PA1;3MS\r", b"3MSE\r")
        hosted.advance(10.0)
        mm_host.exchange(b"3TP\r", b"3TP1.0000\r")
    finally:
        maxk_host.close()
        mm_host.close()
        hosted.close()


def test_pty_door() -> None:
    hosted = HostedBoards(models=("MM4005-2",), pty=True)
    try:
        port = serial.Serial(hosted.ptys[0], 9600, timeout=5)
        port.write(b"VE;\r")
        assert port.read_until(b"\r") == b"VE MM4005 Version 2.42\r"
        port.write(b"1PA0.5;MS\r")
        assert port.read_until(b"\r") == b"1MSE,2MSD\r"
        hosted.advance(2.0)
        port.write(b"TP\r")
        assert port.read_until(b"\r") == b"1TP0.5000,2TP0.0000\r"
        port.close()
    finally:
        hosted.close()

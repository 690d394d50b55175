"""The exchanges of /work/shared/reference/mm4005-epics-client.md, byte for byte, against
the language with the in-memory fake (2 axes, TU 0.001, limits +-100, as observed)."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from maxk.commands.mm4005 import FakeMM4005, MM4005Session
from maxk.personalities.mm4005 import AxisStatus


def _pair() -> tuple[FakeMM4005, MM4005Session]:
    machine = FakeMM4005(axis_count=2)
    return machine, MM4005Session(machine)


def _x(session: MM4005Session, sent: bytes) -> bytes:
    session.feed(sent)
    return session.read()


MODEL2_INIT = [
    (b"VE;\r", b"VE MM4005 Version 2.42\r"),
    (b"TP;\r", b"1TP0.0000,2TP0.0000\r"),
    (b"1TC\r", b"1TC0\r"), (b"1TU\r", b"1TU0.001\r"), (b"1XH\r", b"1XH0.0000\r"),
    (b"1TL\r", b"1TL-100.0000\r"), (b"1TR\r", b"1TR100.0000\r"),
    (b"2TC\r", b"2TC0\r"), (b"2TU\r", b"2TU0.001\r"), (b"2XH\r", b"2XH0.0000\r"),
    (b"2TL\r", b"2TL-100.0000\r"), (b"2TR\r", b"2TR100.0000\r"),
    # iocInit: the motor record writes the soft limits, no reply expected
    (b"1SR100.00000\r", b""), (b"1SL-100.00000\r", b""),
    (b"2SR100.00000\r", b""), (b"2SL-100.00000\r", b""),
]

MODEL2_POLL = [(b"MS;\r", b"1MSD,2MSD\r"), (b"TP;\r", b"1TP0.0000,2TP0.0000\r"),
               (b"TE;\r", b"TE@\r"), (b"TE;\r", b"TE@\r")]


def test_model2_init_and_idle_poll() -> None:
    _, s = _pair()
    for sent, reply in MODEL2_INIT + MODEL2_POLL:
        assert _x(s, sent) == reply, sent


def test_model2_parses_what_it_needs() -> None:
    """The driver's own parsing: 'MM' then atoi == 4005, atof(reply + 3), axis count."""
    _, s = _pair()
    version = _x(s, b"VE;\r")[2:-1].decode()
    assert int(version[version.index("MM") + 2 :].split()[0]) == 4005
    assert len(_x(s, b"TP;\r").rstrip(b"\r").split(b",")) >= 2
    assert float(_x(s, b"1TU\r")[3:-1]) == 0.001
    assert float(_x(s, b"1TL\r")[3:-1]) == -100.0


def test_model2_move_then_done() -> None:
    machine, s = _pair()
    assert _x(s, b"1AC5.00000;1VA1.00000;1PA2.50000;\r") == b""
    assert _x(s, b"MS;\r") == b"1MSE,2MSD\r"  # 0x45: moving, direction +
    machine.advance(1000)  # 1 s at 1 mm/s
    assert _x(s, b"TP;\r") == b"1TP1.0000,2TP0.0000\r"
    machine.advance(1500)
    assert _x(s, b"MS;\r") == b"1MSD,2MSD\r"
    assert _x(s, b"TP;\r") == b"1TP2.5000,2TP0.0000\r"
    assert _x(s, b"TE;\r") == b"TE@\r"


def test_model2_relative_move() -> None:
    machine, s = _pair()
    _x(s, b"2AC5.00000;2VA1.00000;2PR-0.50000;\r")
    machine.advance(10_000)
    assert _x(s, b"TP;\r") == b"1TP0.0000,2TP-0.5000\r"
    assert _x(s, b"MS;\r") == b"1MSD,2MS@\r"  # last motion negative: bit 2 clear


def test_model2_jog_is_a_move_to_the_limit_then_stop() -> None:
    machine, s = _pair()
    assert _x(s, b"2AC5.00000;2VA1.00000;2PA100.00000;\r") == b""
    machine.advance(3000)
    assert _x(s, b"2AC5.00000;2ST;\r") == b""
    assert _x(s, b"MS;\r") == b"1MSD,2MSD\r"
    assert _x(s, b"TP;\r") == b"1TP0.0000,2TP3.0000\r"


def test_model2_home_with_blank_after_separator() -> None:
    machine, s = _pair()
    _x(s, b"1PA1.00000;\r")
    machine.advance(2000)
    assert _x(s, b"1AC10.00000; 1VA2.00000;1OR;\r") == b""
    assert _x(s, b"MS;\r") == b"1MSA,2MSD\r"  # 0x41: moving, direction -
    machine.advance(500)  # 1 mm at 2 mm/s
    assert _x(s, b"MS;\rTP;\r") == b"1MS@,2MSD\r1TP0.0000,2TP0.0000\r"


def test_model2_set_position_with_frozen_offset() -> None:
    _, s = _pair()
    assert _x(s, b"2SH5.00000;2DH;2SH0.00000\r") == b""
    assert _x(s, b"TP;\r") == b"1TP0.0000,2TP5.0000\r"
    assert _x(s, b"2XH\r") == b"2XH0.0000\r"  # preset back to the XH read at init
    # DH moves the soft limits with the origin (Tcl driver evidence)
    assert _x(s, b"2TL\r2TR\r") == b"2TL-95.0000\r2TR105.0000\r"


def test_cnen_motor_off_sets_power_off_bit_and_on_clears_it() -> None:
    _, s = _pair()
    assert _x(s, b"1MF\r") == b""
    reply = _x(s, b"MS;\r")
    assert reply == b"1MSF,2MSD\r"
    assert reply[0 * 5 + 3] & 0x02  # what model 2 polls for after MF (its stall)
    assert _x(s, b"1PA1\rTE\r") == b"TED\r"  # no move with power off
    assert _x(s, b"1MO\r") == b""
    assert not _x(s, b"MS;\r")[3] & 0x02


def test_model1_init_poll_and_motion() -> None:
    machine, s = _pair()
    exchange = [
        (b"TH;\r", b"1TH0.0000,2TH0.0000\r"), (b"ST;\r", b""),
        (b"VE;\r", b"VE MM4005 Version 2.42\r"), (b"TH;\r", b"1TH0.0000,2TH0.0000\r"),
        (b"MS;\r", b"1MSD,2MSD\r"), (b"TH;\r", b"1TH0.0000,2TH0.0000\r"),
        (b"TP;\r", b"1TP0.0000,2TP0.0000\r"),
        (b"1TC\r", b"1TC0\r"), (b"1TU\r", b"1TU0.001\r"), (b"1XH\r", b"1XH0.0000\r"),
        (b"1TL\r", b"1TL-100.0000\r"), (b"1TR\r", b"1TR100.0000\r"), (b"TE;\r", b"TE@\r"),
        (b"1VA1.00000;1AC4.50000;1PA2.50000;\r", b""),
        (b"MS;\r", b"1MSE,2MSD\r"),
    ]
    for sent, reply in exchange:
        assert _x(s, sent) == reply, sent
    machine.advance(2500)
    assert _x(s, b"MS;\rTP;\rTH;\rTE;\r") == (
        b"1MSD,2MSD\r1TP2.5000,2TP0.0000\r1TH2.5000,2TH0.0000\rTE@\r")
    assert _x(s, b"1MF;\r") == b"" and _x(s, b"1MO;\r") == b""
    assert _x(s, b"2ST;\r") == b""


def test_model1_replies_never_carry_lf() -> None:
    machine, s = _pair()
    out = b""
    for sent, _ in MODEL2_INIT + MODEL2_POLL:
        out += _x(s, sent)
    machine.advance(10)
    out += _x(s, b"TH;\rMS;\rTE;\r")
    assert b"\n" not in out and out.endswith(b"\r")


@given(st.lists(st.integers(min_value=0, max_value=0x3F), min_size=1, max_size=4))
def test_ms_offset_rule_holds_for_any_status(bits: list[int]) -> None:
    """EPICS reads axis n's status at offset (n - 1) * 5 + 3; bit 6 is always set."""
    machine = FakeMM4005(axis_count=len(bits))
    s = MM4005Session(machine)
    statuses = [AxisStatus.from_byte(b | 0x40) for b in bits]
    machine.status = lambda axis: statuses[axis - 1]  # type: ignore[method-assign]
    reply = _x(s, b"MS;\r")
    for index, status in enumerate(statuses):
        assert reply[index * 5 + 3] == status.byte
        assert reply[index * 5 + 3] & 0x40
    assert reply.count(b",") == len(bits) - 1

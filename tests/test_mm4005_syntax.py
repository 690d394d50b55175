"""MM4005 command syntax (manual 3.3.1), framing, replies and the TE/TB error register."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from maxk.commands.mm4005 import COMMANDS, FakeMM4005, MM4005Session
from maxk.personalities.mm4005 import ERROR_CODES


def _session(axes: int = 4) -> tuple[FakeMM4005, MM4005Session]:
    machine = FakeMM4005(axis_count=axes)
    return machine, MM4005Session(machine)


def _ask(session: MM4005Session, text: str) -> bytes:
    session.feed(text.encode("latin-1") + b"\r")
    return session.read()


def test_blanks_are_ignored_even_inside_numbers() -> None:
    machine, s = _session()
    assert _ask(s, "2P A1. 43 6") == b""  # the manual's own example
    assert machine.target(2) == pytest.approx(1.436)
    assert _ask(s, " 2 D P ") == b"2DP1.4360\r"


def test_mnemonics_are_case_insensitive_and_echo_upper_case() -> None:
    _, s = _session()
    assert _ask(s, "1tp") == b"1TP0.0000\r"
    assert _ask(s, "te") == b"TE@\r"


def test_comma_and_semicolon_separate_commands_each_query_its_own_line() -> None:
    _, s = _session(2)
    assert _ask(s, "1TP,2TP;1TU;") == b"1TP0.0000\r2TP0.0000\r1TU0.001\r"


def test_only_queries_reply() -> None:
    _, s = _session()
    assert _ask(s, "1VA2;1AC4;1SL-50;1SR50;NT;LX5") == b""
    assert _ask(s, "1VA?;1AC?;1SL?;1SR?") == b"1VA2.0000\r1AC4.0000\r1SL-50.0000\r1SR50.0000\r"


def test_all_axes_query_lists_every_installed_axis() -> None:
    _, s = _session(4)
    assert _ask(s, "TP") == b"1TP0.0000,2TP0.0000,3TP0.0000,4TP0.0000\r"
    assert _ask(s, "0MS") == b"1MSD,2MSD,3MSD,4MSD\r"


def test_empty_lines_and_empty_commands_are_ignored() -> None:
    _, s = _session()
    s.feed(b"\r\r  \r;;,\r")
    assert s.read() == b""
    assert _ask(s, "TE") == b"TE@\r"


def test_lf_is_dropped_and_replies_end_with_cr_only() -> None:
    _, s = _session(2)
    s.feed(b"TP;\r\nVE;\r\n")
    out = s.read()
    assert out == b"1TP0.0000,2TP0.0000\rVE MM4005 Version 2.42\r"
    assert b"\n" not in out


@given(st.lists(st.integers(min_value=1, max_value=7), min_size=0, max_size=30))
def test_any_split_of_the_bytes_gives_the_same_replies(cuts: list[int]) -> None:
    data = b"1VA2.5;1VA?\rTP;MS\r2TB\rTE\r"
    _, whole = _session(2)
    whole.feed(data)
    expected = whole.read()
    _, pieces = _session(2)
    position, out = 0, b""
    for cut in cuts:
        pieces.feed(data[position : position + cut])
        out += pieces.read()
        position += cut
    pieces.feed(data[position:])
    out += pieces.read()
    assert out == expected
    assert expected.count(b"\r") == 4


def test_a_line_of_110_characters_runs_and_111_is_refused() -> None:
    machine, s = _session()
    ok = "1PA1" + " " * 106
    assert len(ok) == 110
    assert _ask(s, ok) == b""
    assert machine.target(1) == 1.0
    too_long = "1PA2" + " " * 107
    assert _ask(s, too_long) == b""
    assert machine.target(1) == 1.0
    assert _ask(s, "TE") == b"TEA\r"


def test_an_endless_line_without_cr_is_bounded_and_refused() -> None:
    machine, s = _session()
    s.feed(b"1PA3" + b" " * 10_000)
    s.feed(b"\r")
    assert machine.target(1) == 0.0
    assert _ask(s, "TE") == b"TEA\r"
    assert len(s._line) == 0


@pytest.mark.parametrize(("line", "code"), [
    ("1QQ", b"A"),  # unknown mnemonic
    ("1.5TP", b"A"),  # floating-point axis (manual 3.75: Error A)
    ("$Y1", b"A"),
    ("5TP", b"B"),  # only 4 axes
    ("PA1", b"B"),  # PA needs an axis
    ("0PA1", b"B"),
    ("1TE", b"B"),  # controller command with an axis number
    ("1PA", b"C"),  # missing value
    ("1PAx", b"C"),
    ("1PA1..2", b"C"),
    ("1ST5", b"C"),  # ST takes no value
    ("NB2.5", b"C"),  # NB is an integer
    ("1PA?", b"C"),  # PA cannot be queried
    ("1OR7", b"C"),  # OR mode 0..2
    ("TBAB", b"C"),  # TB takes one character
])
def test_malformed_commands_set_the_error_code(line: str, code: bytes) -> None:
    _, s = _session()
    assert _ask(s, line) == b""
    assert _ask(s, "TE") == b"TE" + code + b"\r"
    assert _ask(s, "TE") == b"TE@\r"  # read once, then clear


def test_a_malformed_command_rejects_the_whole_line() -> None:
    machine, s = _session()
    assert _ask(s, "1PA5;2PA6;3QQ;1TP") == b""
    assert machine.target(1) == 0.0 and machine.target(2) == 0.0
    assert _ask(s, "TE") == b"TEA\r"


def test_a_refused_command_stops_the_line_and_keeps_what_ran_before() -> None:
    machine, s = _session()
    # 2PA500 is outside the +-100 travel limits: 1PA5 ran, 3PA7 and 1TP do not
    assert _ask(s, "1PA5;2PA500;3PA7;1TP") == b""
    assert machine.target(1) == 5.0
    assert machine.target(2) == 0.0 and machine.target(3) == 0.0
    assert _ask(s, "TE") == b"TEC\r"


def test_the_error_register_keeps_only_the_last_error() -> None:
    _, s = _session()
    _ask(s, "9TP")
    _ask(s, "ZZ")  # not a command of the manual's list
    assert _ask(s, "TB") == b"TBA Unknown message code\r"
    assert _ask(s, "TB") == b"TB@ No error\r"


def test_tb_with_a_code_translates_without_clearing() -> None:
    _, s = _session()
    _ask(s, "9TP")
    assert _ask(s, "TBB") == b"TBB Axis Number not Correct\r"
    assert _ask(s, "TB@") == b"TB@ No error\r"
    assert _ask(s, "tbz") == b"TBZ Unknown error code\r"
    assert _ask(s, "TE") == b"TEB\r"


def test_error_table_and_command_table_carry_their_evidence() -> None:
    for code in ERROR_CODES.values():
        assert code.confidence in "CID" and code.source
        assert len(code.char) == 1 and "@" <= code.char <= "U"  # manual 3.126: @ to U
    for mnemonic, spec in COMMANDS.items():
        assert len(mnemonic) == 2 and mnemonic.isupper()
        assert spec.confidence in ("C", "I", "D") and spec.source and spec.summary


def test_setting_errors_change_nothing() -> None:
    machine, s = _session()
    assert _ask(s, "1VA0") == b""
    assert machine.velocity(1) == 1.0
    assert _ask(s, "TE") == b"TEC\r"
    assert _ask(s, "1SL200") == b""  # above TR
    assert machine.travel_limits(1) == (-100.0, 100.0)
    assert _ask(s, "TE") == b"TEC\r"

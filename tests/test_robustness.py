"""Any input either works or sets the command-error flag: never an exception, never a hang."""

from hypothesis import given, settings
from hypothesis import strategies as st

from maxk import MAXk

TOKENS = st.sampled_from([
    "AX", "AY", "AZ", "AA", "AM", "AK", "VL5000", "VL1", "VB100", "VB999999", "AC50000", "DC1000",
    "MA1000", "MA-2147483647", "MR-200.9", "MR2147483647", "MT100,200", "ML-5,,5", "GO", "GD",
    "ID", "CA", "IC", "FL", "ST", "SA", "KL", "KS1,,1", "KS", "JG5000", "JG-4176000", "JG0",
    "MP", "MM", "MO", "LP7", "LO-3", "LPE9", "WT1", "WT0", "LS3", "LS2147483647", "LE", "LA",
    "PN", "SC", "CN", "PF", "RP", "RE", "PP", "PE", "RV", "RC", "QA", "RA", "RI", "QI", "RQC",
    "EA", "QL", "WY", "#WS", "CC", "#UR1024", "#UR?", "?UR", "PS?", "PSE", "PSM", "LT?", "LTH",
    "LM?", "LMF", "CL?", "CL1", "?KA", "XX", "MA", "1,2,3", ";", " ", "\r", ",", "?", "#",
    "MA1e5", "LP 10,20", "\x00", "\xff",
])


@settings(max_examples=300, deadline=None)
@given(st.lists(TOKENS, max_size=40), st.lists(st.integers(0, 2000), max_size=5))
def test_random_command_streams_never_break_the_board(tokens, waits):
    b = MAXk("MAXk-A000" if len(tokens) % 2 else "MAXk-2000")
    stream = ";".join(tokens) + ";"
    cut = len(stream) // 2
    replies = b.write(stream[:cut])
    for ticks in waits:
        b.advance(ticks=ticks)
    replies += b.write(stream[cut:])
    assert all(isinstance(r, str) and "000 0" not in r for r in replies)
    b.advance(0.01)
    for axis in b.board.axes:
        assert -2**31 <= axis.motor_position(b.board) < 2**31
        assert 0 <= axis.queue.free_units <= 2559
    b.send("KL; IC")
    assert not b.command_error
    assert b.query("AA RP").count(",") == len(b.board.axes) - 1


@settings(max_examples=150, deadline=None)
@given(st.lists(TOKENS, max_size=25), st.data())
def test_splitting_a_stream_anywhere_gives_the_same_replies_and_state(tokens, data):
    stream = ";".join(tokens) + ";"
    whole = MAXk("MAXk-2000")
    expected = whole.write(stream)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(stream)), max_size=5)))
    split = MAXk("MAXk-2000")
    got = []
    last = 0
    for cut in [*cuts, len(stream)]:
        got += split.write(stream[last:cut])
        last = cut
    assert got == expected
    assert split.board.command_error == whole.board.command_error
    assert [str(e) for e in split.board.errors] == [str(e) for e in whole.board.errors]
    assert split.query("AA RP") == whole.query("AA RP")
    assert split.query("AM RQC") == whole.query("AM RQC")

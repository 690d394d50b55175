"""The command language: greedy splitting, operands, modes' lists, incremental feeding."""

from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.commands.max.lexer import Lexer, LexError, ParsedCommand


def lex(text: str) -> list[tuple[str, tuple, bool] | str]:
    out = []
    for item in Lexer().feed(text + "\r"):
        if isinstance(item, LexError):
            out.append(f"error:{item.reason}")
        else:
            out.append((item.mnemonic, item.slots, item.query))
    return out


def names(text: str) -> list[str]:
    return [x[0] if isinstance(x, tuple) else x for x in lex(text)]


def test_operand_less_commands_run_together_are_split_by_mnemonic():
    assert names("AXMA1000;GDID") == ["AX", "MA", "GD", "ID"]
    assert names("AXMPMO;") == ["AX", "MP", "MO"]
    assert names("AXLNJG5000;") == ["AX", "LN", "JG"]
    assert names("AXRP") == ["AX", "RP"]
    assert names("AAMAMR;RP") == ["AA", "error:MA needs an operand", "RP"]


def test_greedy_three_letter_mnemonics_win():
    assert names("LPE100 LP100") == ["LPE", "LP"]
    assert names("RQC") == ["RQC"]
    assert names("#WS;#UR?;?PS;?LS") == ["#WS", "#UR", "?PS", "?LS"]


def test_lower_case_and_separators_seen_in_the_wild():
    assert names("wy") == ["WY"]
    assert names(";AX;PSO;") == ["AX", "PS"]
    assert names("AX  VB100 VL4000 AC19500 MA5100 GD ID") == [
        "AX", "VB", "VL", "AC", "MA", "GD", "ID"]
    assert names("AX AC200000; ST ID;") == ["AX", "AC", "ST", "ID"]
    assert names("AX\tRP\nAY\rRP") == ["AX", "RP", "AY", "RP"]


def test_numbers_decimals_and_signs():
    assert lex("MR-200.9") == [("MR", ("-200.9",), False)]
    assert lex("KS") == [("KS", (), False)]
    assert lex("VL+5000") == [("VL", ("+5000",), False)]
    assert lex("MA.5") == [("MA", (".5",), False)]


def test_comma_lists_with_empty_slots_and_early_end():
    assert lex("MR,100,200;") == [("MR", (None, "100", "200"), False)]
    assert lex("MR1,,3") == [("MR", ("1", None, "3"), False)]
    assert lex("LMH,H,H") == [("LM", ("H", "H", "H"), False)]
    assert lex("LMH,,F") == [("LM", ("H", None, "F"), False)]


def test_query_forms():
    assert lex("PS?") == [("PS", (), True)]
    assert lex("LT?LM?") == [("LT", (), True), ("LM", (), True)]
    assert lex("#UR?") == [("#UR", (), True)]
    assert lex("psm") == [("PS", ("M",), False)]


def test_garbage_is_one_error_and_the_rest_still_runs():
    assert names("XX;RP") == ["error:unknown command 'XX'", "RP"]
    assert names("QQQ RP") == ["error:unknown command 'QQQ'", "RP"]
    assert names("MA RP") == ["error:MA needs an operand", "RP"]
    assert names("MA1.2.3;RP") == ["error:MA: malformed number '1.2.3'", "RP"]
    assert names("PSX RP") == ["error:PS needs one of O/E/M/?", "RP"]
    assert names("RQX;RP") == ["error:unknown command 'RQX'", "RP"]
    assert names("AXQQ;RP") == ["AX", "error:unknown command 'QQ'", "RP"]
    assert names("X" * 1000 + ";RP") == ["error:unknown command '" + "X" * 32 + "...'", "RP"]


def test_partial_input_is_held_until_it_cannot_change():
    lexer = Lexer()
    assert lexer.feed("AXL") == [ParsedCommand(lexer_spec("AX"), (), False, "AX")]
    assert lexer.pending == "L"
    assert lexer.feed("P") == []  # LP or LPE? and the operand may follow
    assert [c.mnemonic for c in lexer.feed("E10")] == []
    assert [c.mnemonic for c in lexer.feed(";")] == ["LPE"]
    assert lexer.pending == ""


def lexer_spec(m):
    from maxk.commands.max.table import COMMANDS

    return COMMANDS[m]


def test_unknown_token_is_reported_when_it_ends():
    lexer = Lexer()
    assert lexer.feed("ZZ") == []
    assert lexer.feed("Z RP;") == [LexError("ZZZ", "unknown command 'ZZZ'"),
                                   ParsedCommand(lexer_spec("RP"), (), False, "RP")]


def test_unterminated_garbage_is_bounded():
    lexer = Lexer()
    out = lexer.feed("MA" + "1" * 100_000)
    assert any(isinstance(x, LexError) for x in out)
    assert len(lexer.pending) < 300
    assert [c.mnemonic for c in lexer.feed(";RP;") if not isinstance(c, LexError)] == ["RP"]


STREAM = st.lists(
    st.sampled_from([
        "AX", "AY", "AA", "AM", "VL5000", "VB100", "AC50000", "MA1000", "MR-200.9", "GO",
        "GD", "ID", "RP", "RE", "PP", "RI", "QA", "LPE5", "LP7", "PS?", "PSO", "LT?", "LTH",
        "LMH,H", "MR,100,200", "#WS", "#UR?", "?PS", "RQC", "XX", "MA", ";", " ", "\r", "wy",
        "JG-5000", "ST", "KS1,,1", "1", ",", "?", "#", "q",
    ]),
    max_size=25,
)


@settings(max_examples=300, deadline=None)
@given(STREAM, st.data())
def test_any_split_gives_the_same_commands_as_one_write(parts, data):
    stream = "".join(parts) + ";"
    whole = Lexer().feed(stream)
    cuts = sorted(data.draw(st.lists(st.integers(0, len(stream)), max_size=6)))
    lexer = Lexer()
    pieces = []
    last = 0
    for cut in cuts + [len(stream)]:
        pieces.extend(lexer.feed(stream[last:cut]))
        last = cut
    assert pieces == whole
    assert lexer.pending == ""


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=200))
def test_arbitrary_bytes_never_raise(blob):
    lexer = Lexer()
    lexer.feed(blob)
    lexer.feed(b";")
    assert len(lexer.pending) < 300

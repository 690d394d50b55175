"""The fast command path (issue 19): a line's split is remembered, an operand's
conversion too; both give exactly what the state machine and the checks give."""

from __future__ import annotations

import random

import pytest

from maxk import MAXk
from maxk.commands.max import lexer as L

LINES = ["AX;VL5000;AC50000;MR1000;GO;ID;", "AM;RI;AM PP;", "AXMA1000GDID;", "LP", "E5;",
         "MA10", "00;", "VLabc;MR5;", "MA1e5;GO;", "XX QQ;AX;", "VP[2]A1,,3;VO[1]=50;",
         "AA;VL1000,2000,,4000;", "MR-200.9;", "BD00ff;", "LMH,H,H,H;", "  ;;", "A", "X;"]


@pytest.mark.parametrize("seed", range(20))
def test_a_remembered_split_is_the_state_machines(seed):
    rng = random.Random(seed)
    stream = [rng.choice(LINES) for _ in range(60)]
    L._SPLITS.clear()
    remembered, fresh = L.Lexer(), L.Lexer()
    for text in stream + stream:  # the second pass finds every clean-start split kept
        got = remembered.feed(text)
        want = fresh._split(fresh._buf + text)
        assert got == want
        assert remembered.pending == fresh.pending


def test_a_kept_split_is_not_shared_as_a_list():
    L._SPLITS.clear()
    first = L.Lexer().feed("AX;ID;")
    first.clear()
    assert len(L.Lexer().feed("AX;ID;")) == 2


def test_operands_refused_once_are_refused_again():
    board = MAXk()
    for _ in range(3):
        board.send("AX; VL9999999999;")
        assert board.command_error
        board.send("IC;")
    board.send("AX; UU2; VL1000;")
    assert not board.command_error

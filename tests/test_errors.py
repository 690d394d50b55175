"""Bad input: the command-error flag, no effect at all, and the rest of the stream runs."""

import pytest

from maxk import MAXk
from maxk.personalities.maxk.flags import COMMAND_ERROR


@pytest.mark.parametrize("bad,reason", [
    ("XX", "unknown command"),
    ("VL5000000", "out of range"),
    ("AC0", "out of range"),
    ("MA3000000000", "out of range"),
    ("VLabc", "needs an operand"),
    ("MA1.2.3", "malformed number"),
    ("MR1,2", "one operand in single-axis mode"),
    ("PSQ", "needs one of"),
    ("AK", "has no K axis"),
    ("#UR5000", "update rate must be"),
    ("KP40000", "out of range"),
])
def test_bad_command_sets_the_flag_and_changes_nothing(bad, reason):
    board = MAXk()
    before = board.query("AX RC"), board.query("AA RP"), board.query("AM RQC")
    replies = board.send(f"AX; {bad}; AX RP;")
    assert replies == ["0"]  # the rest of the stream still ran
    assert board.command_error
    assert board.doorbell & COMMAND_ERROR
    assert reason in board.last_error.reason
    assert (board.query("AX RC"), board.query("AA RP"), board.query("AM RQC")) == before
    assert board.board.mode == "AM"
    board.send("IC")
    assert not board.command_error
    assert board.doorbell == 0


def test_too_many_operands_in_aa_mode_queue_nothing():
    board = MAXk("MAXk-2000")
    board.send("AA; VL1,2,3;")
    assert board.command_error
    assert board.query("RQC") == "2559,2559"


def test_one_bad_slot_refuses_the_whole_list():
    board = MAXk("MAXk-4000")
    board.send("AA; VL1000,9000000,1000;")
    assert board.command_error
    board.send("IC; AA; MR5,5,5; GO; ID;")
    board.run_until_idle()
    assert board.query("PP") == "5,5,5,0"


def test_vb_not_below_vl_is_refused_when_a_move_uses_the_pair():
    """Issue 40: VL and VB are set alone without a check; the move that uses them is
    refused (and does not start) while VB is not below VL."""
    board = MAXk()
    board.send("AX; VL1000; VB1000;")
    assert not board.command_error
    board.send("MR500; GO;")
    assert board.command_error
    assert "VB1000 is not below VL1000" in board.last_error.reason
    board.run_until_idle()
    assert board.query("AX RP") == "0"
    board.send("IC; VL4000; MR500; GO;")
    assert not board.command_error
    board.run_until_idle()
    assert board.query("AX RP") == "500"


def test_relative_move_out_of_the_32_bit_range():
    board = MAXk()
    board.send("AX; LP2147483000; MR1000; GO;")
    assert board.command_error
    assert board.query("RP") == "2147483000"


def test_every_command_error_notifies_and_a_later_done_is_not_coloured_by_it():
    board = MAXk()
    words = []
    board.board.add_flag_listener(words.append)
    board.send("XX; YY;")
    assert words == [COMMAND_ERROR, COMMAND_ERROR]
    board.send("AX; MR10; GO; ID;")
    board.run_until_done("X")
    assert words[-1] == 0x1  # the done alone: EPICS reads "000 01" as a command error
    assert board.doorbell == COMMAND_ERROR | 0x1  # the flag itself stays until IC


def test_errors_keep_their_cause_for_the_repl():
    board = MAXk()
    board.send("AX; MR")
    record = board.last_error
    assert record.command == "MR"
    assert record.reason == "MR needs an operand"
    assert "MR needs an operand" in str(record)

"""LIST_GLOBAL prints each GLOBAL and CONSTANT name as it was typed (TrioBASIC help,
LIST_GLOBAL: the example defines lower-case names and lists them lower-case), while the
names themselves match whatever their case."""

from __future__ import annotations

from tests.trio_helpers import Rig


def _rows(reply: bytes) -> list[str]:
    return reply.decode().split("\r\n")


def test_list_global_keeps_the_spelling_of_each_definition() -> None:
    rig = Rig()
    rig.command('GLOBAL "FeedRate", 12')
    rig.command('CONSTANT "knife_Len", 2.5')
    rows = _rows(rig.command("LIST_GLOBAL"))
    # name column 33 wide, then the VR / the value with 5 decimals (page's layout)
    assert rows[2] == "FeedRate" + " " * (33 - 8) + "12"
    assert rows[5] == "knife_Len" + " " * (33 - 9) + "2.50000"


def test_a_name_matches_in_any_case_and_keeps_its_first_spelling() -> None:
    rig = Rig()
    rig.command('GLOBAL "Speed_Vr", 7')
    rig.command("VR(7) = 41")
    assert rig.command("?SPEED_VR + speed_vr") == b"82.0000"  # a VR is FLOAT
    rig.command('GLOBAL "SPEED_VR", 7')  # the same global again, typed otherwise
    assert _rows(rig.command("LIST_GLOBAL"))[2] == "Speed_Vr" + " " * (33 - 8) + "7"


def test_defconst_in_a_program_lists_as_typed() -> None:
    rig = Rig()
    rig.load("P", "DEFCONST MaxCuts 40\nPRINT maxcuts")
    rig.command('RUN "P"')
    assert rig.cycles(5) == b"40\r\n"
    assert _rows(rig.command("LIST_GLOBAL"))[2] == "MaxCuts" + " " * (33 - 7) + "40.00000"

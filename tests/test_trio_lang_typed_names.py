"""LIST_GLOBAL prints each GLOBAL and CONSTANT name as it was typed (TrioBASIC help,
LIST_GLOBAL: the example defines lower-case names and lists them lower-case), while the
names themselves match whatever their case; and the real-program checker names the words
it met that the table lacks or only accepts."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

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


# ---- the checker of real programs names the words a clean run may hide --------------------

def test_the_checker_lists_words_the_table_lacks_and_words_only_accepted(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A program that calls a keyword the table lacks only where the run never goes still
    runs clean; the summary names the word so the measure does not hide it."""
    project = tmp_path / "knife"
    project.mkdir()
    (project / "CUT.BAS").write_text(
        "n = 0\nIF n > 5 THEN\n  KNIFELINK(100, 50, 0)\nENDIF\nSERVO_OFFSET = 4\n"
        "PRINT n[0]\n")
    (project / "OTHER.BAS").write_text("KNIFELINK(1, 2, 3)\nmine = 2\nPRINT mine\n")
    sys.path.insert(0, str(Path(__file__).parent.parent / "tools"))
    try:
        import trio_corpus_check
    finally:
        sys.path.pop(0)
    assert trio_corpus_check.main([str(tmp_path), "--seconds", "1", "--hang", "0"]) == 0
    out = capsys.readouterr().out.splitlines()
    rows = {line.split()[0]: line for line in out if line.startswith("knife/")}
    assert rows["knife/CUT"].split()[3] == "clean"  # the call is never reached
    assert "Variable not defined" in rows["knife/OTHER"]
    assert out[-2] == "words not in the table, never declared: 1: KNIFELINK(2)"
    assert out[-1] == "words accepted only (Not modelled): 1: SERVO_OFFSET(1)"

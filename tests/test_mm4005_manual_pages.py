"""The MM4005 commands whose manual pages were found (TS 3.139, TX 3.142, BA 3.25, DV
3.43), the known-but-not-modelled RQ, the simulated execution 1EC, MV's sign operand,
SN's codes named by TN, and the table as `help` and `maxk commands` show it."""

from __future__ import annotations

import subprocess
import sys

import pytest

from maxk.commands.mm4005 import COMMANDS
from maxk.controllers.mm4005.controller import MM4005Controller


def test_ts_bits_follow_the_manual_table() -> None:
    mm = MM4005Controller("MM4005")  # 4 axes: bits 0..3
    assert mm.send("TS") == ["TS@"]  # bit 6 default high, everything else low
    assert mm.send("1PA1;4PA1;TS") == ["TSI"]  # 0x40 | 0x01 | 0x08
    mm.run_until_idle()
    assert mm.send("TS") == ["TS@"]
    assert mm.send("2MF;TS") == ["TSP"]  # 0x40 | 0x10: motor power off
    assert mm.send("2MO;TS") == ["TS@"]
    assert mm.send("1TS") == [] and mm.send("TE") == ["TEB"]  # no axis number


def test_tx_reads_remote_and_command_line_and_a_running_trajectory() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("TX") == ["TXJ"]  # the manual's example: remote mode, line executing
    mm.send("NC;1DC1;2DC0;UC0.5;1DT0.5;1DX0.1;VC")
    assert mm.send("TB") == ["TB@ No error"]
    assert mm.send("0EC1;TX") == ["TXZ"]  # bit 4: a trajectory is executing
    mm.run_until_idle()
    assert mm.send("TX") == ["TXJ"]
    assert mm.send("LX1;CR1,CA90;ET;TX") == ["TXZ"]  # the XY trajectory too
    mm.run_until_idle()
    assert mm.send("TX") == ["TXJ"]


def test_ba_missing_value_is_zero_and_the_limit_is_10000_counts() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("1BA0.0012;2BA0.0008;XB") == ["1XB0.0012,2XB0.0008"]
    assert mm.send("1BA;1XB") == ["1XB0"]  # nn missing: 0 disables it
    assert mm.send("1BA10;1XB") == ["1XB10"]  # 10000 counts of TU 0.001
    for bad, code in (("1BA10.001", "C"), ("1BA-0.1", "C"), ("BA0.1", "B"), ("5BA0.1", "B"),
                      ("1BA?", "C"), ("1.5BA1", "A")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    assert mm.send("1XB") == ["1XB10"]  # every refusal changed nothing


def test_dv_reads_the_programmed_velocity_or_the_maximum_allowed() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("2VA2.5;2DV") == ["2DV2.5000"]  # the manual's example, our decimals
    assert mm.send("2VU20;2DV1;2DV3") == ["2DV20.0000", "2DV20.0000"]  # pp >= 1: maximum
    mm.send("2PA5")
    mm.engine.advance(10)  # while it accelerates DV still reports VA
    assert mm.send("2DV0") == ["2DV2.5000"]
    for bad, code in (("DV", "B"), ("2DV-1", "C"), ("2DV0.5", "C")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad


def test_rq_is_known_and_answered_as_not_modelled() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("RQ") == []
    assert mm.send("TB") == ["TBQ Function not authorized"]
    for unknown in ("ZT", "QZ", "ZZ"):  # not in the manual's list: A
        assert mm.send(unknown) == [] and mm.send("TE") == ["TEA"], unknown
    console = mm.console()
    console.execute("RQ")
    assert console.new_errors()[-1] == "! Q Function not authorized"
    help_lines = console.help("RQ")
    assert help_lines is not None and "not modelled" in " ".join(help_lines)


def test_mv_takes_a_bare_sign_and_ml_goes_to_the_limit() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("1SR2;1SL-3;1MV+") == []
    mm.run_until_idle()
    assert mm.send("1TP") == ["1TP2.0000"]
    assert mm.send("1MV-") == []
    mm.run_until_idle()
    assert mm.send("1TP") == ["1TP-3.0000"]
    for bad in ("1MV", "1MV0", "1MV+-", "1MV++"):
        assert mm.send(bad) == [] and mm.send("TE") == ["TEC"], bad


def test_sn_codes_are_named_by_tn() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("TN") == ["1TNmm,2TNmm"]
    assert mm.send("2SN7;TN;2SN?") == ["1TNmm,2TNdeg", "2SN7"]
    assert mm.send("1SN0;1TN") == ["1TNcounts"]
    assert mm.send("1SN12") == [] and mm.send("TE;1SN?") == ["TEC", "1SN0"]


def _defined(mm: MM4005Controller, lines: str) -> None:
    mm.send(lines)
    assert mm.send("TB") == ["TB@ No error"]


def test_1ec_simulates_without_moving_and_refuses_as_0ec_would() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("1EC1") == [] and mm.send("TE") == ["TEJ"]  # not verified
    _defined(mm, "NC;1DC1;2DC1;UC0.5;1DT0.5;1DX0.5;2DX-0.25;2DT0.5;1DX0.5;2DX0;VC")
    assert mm.send("1EC1;TE;MS;1TP;2TP;XC;NQ") == ["TE@", "1MSD,2MSD", "1TP0.0000",
                                                   "2TP0.0000", "XC0", "NQ0"]
    mm.engine.advance(4000)  # 2 s later nothing has moved
    assert mm.send("TP") == ["1TP0.0000,2TP0.0000"]
    # every check of 0EC, in 1EC, with the same letter, and nothing changes
    cases = (("1VU1.5", "1EC0.5", "H", "1VU100"),  # 2 units/s at time scale 0.5 beats VU 1.5
             ("1SR0.9", "1EC1", "R", "1SR100"),  # the run would leave TL..TR
             ("2MF", "1EC1", "D", "2MO"),  # an axis off
             ("", "1EC0.001", "C", ""))  # time scale below 0.01
    for before, line, code, after in cases:
        if before:
            mm.send(before)
        assert mm.send(line) == [] and mm.send("TE") == [f"TE{code}"], line
        real = line.replace("1EC", "0EC")
        if code != "C":
            assert mm.send(real) == [] and mm.send("TE") == [f"TE{code}"], real
        assert mm.send("MS") == ["1MSD,2MSD"] or code == "D"
        if after:
            mm.send(after)
    assert mm.send("1EC1;TE;0EC1;TE") == ["TE@", "TE@"]  # then the real run starts
    mm.run_until_idle()
    assert mm.send("TP;XC") == ["1TP1.0000,2TP-0.2500", "XC2"]
    assert mm.send("2EC1") == [] and mm.send("TE") == ["TEC"]


def test_help_lists_every_table_entry_with_source_and_confidence() -> None:
    console = MM4005Controller("MM4005-2").console()
    assert console.words() == sorted(COMMANDS)
    for word in console.words():
        spec = COMMANDS[word]
        assert spec.confidence in ("C", "I", "D"), word
        assert spec.source and console.summary(word), word
        lines = console.help(word)
        assert lines is not None and f"({spec.confidence})" in lines[1], word
    for word in ("TS", "TX", "RQ", "BA", "XB", "DV", "EC"):
        assert word in console.words()


@pytest.mark.parametrize("word", ["TX", "BA"])
def test_maxk_commands_shows_the_table(word: str) -> None:
    listing = subprocess.run([sys.executable, "-m", "maxk", "commands", "--model", "MM4005"],
                             capture_output=True, text=True, check=True).stdout.splitlines()
    assert len(listing) == len(COMMANDS)
    assert any(line.split()[0] == word for line in listing)
    one = subprocess.run([sys.executable, "-m", "maxk", "commands", "--model", "MM4005", word],
                         capture_output=True, text=True, check=True).stdout
    assert "manual 3." in one and "(C)" in one


def test_xp_xi_xd_read_the_gains_in_force_until_uf() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("2KP0.005;2KI0.005;2KD0.05;2XP;2XI;2XD") == ["2XP0", "2XI0", "2XD0"]
    assert mm.send("2UF;2XP;2XI;2XD;1XP") == ["2XP0.005", "2XI0.005", "2XD0.05", "1XP0"]
    assert mm.send("2KS0.5;2KS?;2TF") == ["2KS0.5", "2TFKP0.005,KI0.005,KD0.05,KS1,FE1"]
    assert mm.send("2UF;2TF") == ["2TFKP0.005,KI0.005,KD0.05,KS0.5,FE1"]
    assert mm.send("2FE0.2;2XF") == ["2XF1"]  # FE takes effect at the next UF (3.56)
    assert mm.send("2UF;2XF;2TF") == ["2XF0.2", "2TFKP0.005,KI0.005,KD0.05,KS0.5,FE0.2"]
    for bad, code in (("2FE0.001", "C"), ("2FE200.1", "C"), ("2FE?", "C"), ("2FE", "C"),
                      ("FE0.1", "B")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    assert mm.send("2FE0.002;2FE200;2UF;2XF") == ["2XF200"]  # 2 x TU .. TR - TL
    assert mm.send("1FF?;1FF0.1;1FF?") == ["1FF1", "1FF0.1"]
    assert mm.send("1FF0.0001") == [] and mm.send("TE;1FF?") == ["TEC", "1FF0.1"]
    for bad, code in (("XP", "B"), ("5XD", "B"), ("2KD?", "C"), ("KD0.1", "B"), ("2KD", "C"),
                      ("2KP?", "C"), ("2KS2", "C"), ("2XP1", "C")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    assert mm.send("2XD") == ["2XD0.05"]


def test_ss_reads_every_axis_as_master_and_refuses_slaving_as_not_modelled() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("2SS?;1SS?") == ["2SS0", "1SS0"]
    assert mm.send("2SS;2SS0;2SS2;TE") == ["TE@"]  # master (n missing or 0, or itself)
    assert mm.send("2SS1") == [] and mm.send("TB") == ["TBQ Function not authorized"]
    assert mm.send("2SS11") == [] and mm.send("TE") == ["TEQ"]  # n 1, p 1 (real position)
    for bad, code in (("2SS5", "C"), ("2SS12", "C"), ("SS1", "B"), ("2SS-1", "C"),
                      ("2SS1.5", "C")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    assert mm.send("1CD360") == [] and mm.send("TE") == ["TEQ"]
    assert mm.send("2GR?;2GR100;2GR?;2GR;2GR?") == ["2GR1", "2GR100", "2GR1"]  # 3.60 example
    for bad, code in (("2GR0", "C"), ("2GR10001", "C"), ("GR2", "B")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad


def test_the_docs_table_lists_every_entry_with_its_confidence() -> None:
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / "mm4005.md").read_text()
    rows = {line.split("|")[1].strip(): line.rstrip().rstrip("|").split("|")[-1].strip()
            for line in text.splitlines() if line.startswith("| ") and line.count("|") >= 5}
    for word, spec in COMMANDS.items():
        assert rows.get(word) == spec.confidence, word


def test_every_command_of_the_manuals_list_is_known_and_the_unmodelled_answer_q() -> None:
    from maxk.commands.mm4005.manual_list import CATEGORIES, GROUP

    assert len(GROUP) == sum(len(names.split()) for _, names in CATEGORIES) == 189
    mm = MM4005Controller("MM4005-2")
    before = mm.send("TP;MS")
    unmodelled = [word for word in GROUP if COMMANDS[word].note.endswith("answers Q")]
    assert len(unmodelled) >= 40  # the loop below checks each one (86 after issue 36)
    for word in unmodelled:
        for form in (word, f"1{word}", f"{word}?", f"2{word}3.5", f"1{word}+"):
            assert mm.send(form) == [], form
            assert mm.send("TE") == ["TEQ"], form
    assert mm.send("TP;MS") == before  # nothing moved, nothing changed
    # a refused listed command stops its line there, as every refusal does
    assert mm.send("1TP;WT;2TP") == ["1TP0.0000"] and mm.send("TE") == ["TEQ"]
    for word in ("AB", "BA", "DV", "FE", "KS", "MS", "NQ", "SS", "TQ", "TX", "XP", "ZP"):
        assert not COMMANDS[word].note.endswith("answers Q"), word


def test_sd_sy_zp_from_the_list() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("SD?;SD50;SD?") == ["SD100", "SD50"]
    for bad, code in (("SD0", "C"), ("SD100.5", "C"), ("1SD50", "B"), ("SD", "C")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    assert mm.send("1SY?;1SY1;1SY?;2SY?") == ["1SY0", "1SY1", "2SY0"]
    assert mm.send("1SY2") == [] and mm.send("TE;1SY?") == ["TEC", "1SY1"]
    mm.send("1PA3")
    assert mm.send("1ZP") == [] and mm.send("TE") == ["TED"]  # moving: refused
    mm.run_until_idle()
    assert mm.send("1ZP;1TP;1TH;1TL;1TR;2TP") == ["1TP0.0000", "1TH0.0000", "1TL-100.0000",
                                                  "1TR100.0000", "2TP0.0000"]
    assert mm.send("1PA-1") == []
    mm.run_until_idle()
    assert mm.send("1TP") == ["1TP-1.0000"]


def test_rb_reads_the_worlds_inputs_as_the_manual_example() -> None:
    mm = MM4005Controller("MM4005-2")
    assert mm.send("RB;0RB;3RB") == ["RB0", "RB0", "3RB0"]
    view = mm.world_view()
    for bit in (1, 5, 7, 8):  # 11010001 = 209, bit 1 the least significant
        view.set_input(bit, True)
    assert mm.send("0RB;RB;1RB;2RB;8RB") == ["RB209", "RB209", "1RB1", "2RB0", "8RB1"]
    view.set_input(8, False)
    assert mm.send("RB") == ["RB81"]
    for bad, code in (("9RB", "E"), ("1RB1", "C"), ("1.5RB", "A")):
        assert mm.send(bad) == [] and mm.send("TE") == [f"TE{code}"], bad
    assert mm.send("TBE") == ["TBE Incorrect I/O channel number"]
    with pytest.raises(ValueError):
        view.set_input(9, True)  # the GPIO port has 8 inputs

"""Exact reply formats of the status and report commands (evidence 3.4, 3.5)."""

import re

from maxk import MAXk
from maxk.personalities.maxk import flags as F


def test_wy_satisfies_manual_asyn_sysal_and_classic_parsers(board):
    wy = board.query("WY")
    assert wy == "MAXk-8000, ver:1.33, S/N: 000001, FPGA:20"
    # asyn: strstr "ver:" then sscanf "ver:%d.%d.%d,"; needs >= 1.30, #WS used from .33
    m = re.search(r"ver:(\d+)\.(\d+)", wy)
    assert m and (int(m[1]), int(m[2])) >= (1, 33)
    assert "MAXk-" in wy  # SySal
    assert float(wy.split(":", 1)[1].split(",")[0]) == 1.33  # drvMAXv: %f after first ':'
    assert len(wy) < 121  # asyn's 122-byte input buffer
    assert MAXk("MAXk-A000").query("WY").startswith("MAXk-A000, ver:")


def test_position_lists_have_one_field_per_axis(board4):
    assert board4.query("AA RP") == "0,0,0,0"
    assert board4.query("AM PP;") == "0,0,0,0"
    assert board4.query("AX PP") == "0,0,0,0"  # PP always lists
    assert board4.query("AX RP") == "0"
    assert board4.query("PE") == "0,0,0,0"


def test_qa_ra_ri_qi_and_which_clear_done(board4):
    board4.send("AM; MR-10,10; GO; ID;")  # ID without operands: every axis in AM mode
    board4.run_until_idle()
    assert board4.query("QI") == "MDNN,PDNN,PDNN,PDNN"
    assert board4.query("QI") == "MDNN,PDNN,PDNN,PDNN"  # QI does not clear
    assert board4.query("AX QA") == "MDNN"  # QA does not clear
    assert board4.query("AX RA") == "MDNN"  # RA reports, then clears
    assert board4.query("AX QA") == "MNNN"
    assert board4.query("RI") == "MNNN,PDNN,PDNN,PDNN"  # RI reports, then clears
    assert board4.query("QI") == "MNNN,PNNN,PNNN,PNNN"
    assert board4.doorbell == 0


def test_done_sets_doorbell_and_notifies(board):
    words = []
    board.board.add_flag_listener(words.append)
    board.send("AY; MR10; GO; ID;")
    board.run_until_done("Y")
    assert board.doorbell == 1 << 1
    assert words == [0x2]
    board.send("CA")
    assert board.doorbell == 0
    board.send("ID")
    board.board.write_doorbell(1 << 1)  # write-one-to-clear
    assert board.doorbell == 0


def test_w_and_k_notification_bits(board):
    b = MAXk("MAXk-A000")
    words = []
    b.board.add_flag_listener(words.append)
    b.send("AW; ID; AK; ID;")
    assert b.doorbell == F.W_NOTIFY | F.K_NOTIFY
    assert words == [0x0200_0000, 0x0400_0000]  # MAXnet word spells W/K done out
    b.board.write_doorbell(F.W_NOTIFY)
    assert b.doorbell == F.K_NOTIFY


def test_velocity_acceleration_queue_reports(board4):
    assert board4.query("AX RV") == "0"
    assert board4.query("AX RC") == "2000000"
    assert board4.query("AM RC") == "2000000,2000000,2000000,2000000"
    assert board4.query("AX RQC") == "2559"
    board4.send("AX; VL1000; MR-100000; GO;")
    board4.advance(1.0)
    assert board4.query("AX RV") == "-1000"
    assert board4.query("AM;RV;") == "-1000,0,0,0"
    assert board4.query("AM;RQC") == "2555,2559,2559,2559"  # GO (4 units) is still running


def test_setting_queries(board4):
    assert board4.query("AX PS?") == "=O"
    assert board4.query("AX ?PS") == "=O"
    assert board4.query("AX LT?") == "=l"
    board4.send("AX LTH;")
    assert board4.query("AX LT?") == "=h"
    assert board4.query("AX ?LS") == "=h"
    board4.send("AY LH; AZ LL;")
    assert board4.query("AM LT?") == "=h,=h,=l,=l"
    assert board4.query("AX LM?") == "=h"
    board4.send("AA; LMF,S,H;")
    assert board4.query("AM LM?") == "=f,=s,=h,=h"
    board4.send("AX LMN")
    assert board4.query("AX LM?") == "=h"
    assert board4.query("AM;CL?;") == "off,off,off,off"
    assert board4.query("AX ?PM") == "=off"
    assert not board4.command_error


def test_encoder_status_needs_an_encoder(board4):
    board4.send("AX EA")
    assert board4.command_error  # the classic `EA ID` probe: error means no encoder
    board4.send("IC; AY PSE;")
    assert board4.query("AY EA") == "DDNNN"
    assert board4.query("AM;EA;") == ",DDNNN,,"
    assert board4.query("AY PS?") == "=E"


def test_pid_probe_on_a_stepper_is_a_command_error(board):
    board.send("AX ?KA ID")
    assert board.command_error
    assert board.done("X")  # the probe waits for the done bit, then tests the error


def test_limit_inputs_raw_levels(board):
    assert board.query("AM;QL;") == "ffff"  # inactive active-low inputs read high
    board.send("AX LTH")
    assert board.query("QL") == "fefe"
    ten = MAXk("MAXk-A000")
    assert ten.query("QL") == format(0xFFFF | 0x3 << 16 | 0x3 << 24, "x")


def test_watchdog_cycle_counter_update_rate(board):
    assert board.query("#WS") == "=0"
    assert board.query("CC") == "0"
    board.advance(ticks=1234)
    assert board.query("CC") == "1234"
    assert board.query("?UR") == "8192"
    assert board.query("#UR?") == "8192"


def test_no_reply_ever_looks_like_a_maxnet_notification(board):
    board.send("AX LP1000 AY LP-10000")
    for q in ("AA RP", "PP", "PE", "RI", "QI", "WY", "RQC", "QL", "AA RC"):
        assert "000 0" not in board.query(q)

"""Every mnemonic that real host code sends (reference/max-command-evidence.md and
max-command-reference-facts.md), in the forms host code sends it: none is an unknown
command, and those whose behaviour a source gives (or our recorded decision fixes) do it.
"""

from __future__ import annotations

import pytest

from maxk import MAXk
from maxk.commands.max.table import COMMANDS

# (board set-up, the host's string): the set-up gives the axis what the string needs
# (an encoder, a servo loop), as the host's own init would have.
HOST_FORMS: list[tuple[str, str]] = [
    # evidence 2.1 / E1 / E2: modes and the asyn poll
    ("", "AX LH PSO;"), ("", "AA RP;"), ("", "AM;RI;"), ("", "AM PP;"), ("", "AM PE;"),
    ("", "AM;CL?;"), ("", "AM;RV;"), ("", "AM;QL;"), ("", "#WS"), ("", "AX PS?"),
    ("", "AX ?PS"), ("", "AX LT?"), ("", "AX ?LS"), ("", "AX ?PM"),
    ("", "AY;AZ;AT;AU;AV;AR;AS;AW;AK;"),
    ("AX PSE;", "AM;EA;"), ("AX PSE;", "AX EA ID;"), ("AX PSM;", "AX ?KA ID;"),
    ("AX PSM;", "AX ?KP"), ("AX PSM;", "AX KK2 ID"),
    # E3 / E4 / E5: moves, jog, stop, home, positions, gains
    ("", "AX;AC200000;VL50000;VB1000;MA250000;GO;ID;"), ("", "AX;RE;"), ("", "AX;LO12345;"),
    ("", "AX AC200000; JG-5000;"), ("", "AX AC200000; ST ID;"),
    ("", "AX;AC200000;VL10000;VB100;HM;MA0;GO;ID;"), ("", "AX;AC200000;VL10000;VB100;HR;"),
    ("", "AX LP1000;"), ("", "AX LPE1000;"), ("", "AX CL1"), ("", "AX CL0"), ("", "AX HN"),
    ("", "AX HF"), ("", "AX KP0.000000;"), ("", "AX KI0.500000; KD0.000000;"),
    ("", "AX  VL4000 VB100 AC19500 MR-200.9 GD ID;"), ("", "AX  VL1000 VB100 MP MA5100 GD ID;"),
    ("", "AX  VL1000 VB100 AC9000 CA HM0 GD ID;"), ("", "AX  VB100 AC9000 CA JG-4000;"),
    ("", "AX FL AC200000; WQ ST ID;"), ("", "AX FLAC200000; WQ ST ID;"), ("", "AX LO1000 LPE1000;"),
    ("AX PSE;", "AX  ER1000,4000 UU0.250000;"), ("", "AX UF;"), ("", "AX  KP16383.5;"),
    ("", "IC;"), ("", "AA SA;"), ("", "WY;"),
    ("", "AA; LMH,H,H,H,H,H,H,H; AX LTH PSO; AY LTH PSO;"),
    ("", "AX LM?;"), ("", "AX LMH;"), ("", "AX QA;"), ("", "AX RA;"), ("", "AX RV;"),
    ("", "AX ST;"), ("", "AX LMF; LMN;"),
    # E6 / E7: older boards' probes and polls
    ("", "EF"), ("", "AX QA EA"), ("", "AX QA RP RE EA"), ("", "AX RB"),
    # E8: SySal and the vendor DLL
    ("", ";WY;"), ("", "?UR;"),
    ("", ";AX;PSE;ECI;ER10000,10000;RTL;LTL;LMH;CL1;SME;HV1000000;HD1;HG10000;BC0;"),
    ("", ";AT;SVB1;SVN;PSM;KO0;"), ("", ";AX;SME;AY;SME;AZ;SME;"),
    ("", ";AX;ST;AX;AC100000;DC200000;VL20000;MA15000;GO;"),
    ("", ";AX;AC100000;DC100000;VL20000;MA15000;wtc1000;GO;"),
    ("", "AX;AC100000;DC100000;wtc1000;;VL2000;GP1000;WT10;VL3000;TM-500"),
    ("", "AX;AC100000;DC100000;JG2000;"), ("", "AX;LP0;SME;"), ("", ";CC"),
    ("", "AXRP"), ("", "wy"), ("", "AXMA1000;GDID"), ("", "AXMR10000;GDID"), ("", "AXJG5000;"),
    ("", "AXJF500.600000;"), ("", "AXMPMO;"), ("", "AXMMMO;"), ("", "AAMA1,2,3;GDID"),
    ("", "AAMR1,2;GDID"), ("", "AMMA1,2;GDID"), ("", "AAMT10,20;GDID"), ("", "AAML10,20;GDID"),
    ("", "AMMT10,20;GDID"), ("", "AMML10,20;GDID"), ("", "AXST"), ("", "SA"), ("", "AXLP5;"),
    ("", "AXHH"), ("", "AXHL"), ("", "AXLNJG1000;"), ("", "AXLNJG-1000;"), ("", "AXHEHM0;ID"),
    ("", "AXHEHR0;ID"), ("", "AXHSHM0;ID"), ("", "AXHSHR0;ID"), ("", "AXRV"), ("", "AMRV"),
    ("", "AXVB10;"), ("", "AXVL20000;"), ("", "AXAC100000;"), ("", "AXRC"), ("", "AMRC"),
    ("", "CN"), ("", "AXLA"), ("", "PF"), ("", "PN"), ("", "PN5;"), ("", "AXSC"),
    ("", "AXPR5;"), ("", "AXSS5;"), ("", "AXQA"), ("", "QA"), ("", "AXIS"),
    ("AX PSE;", "AXEA"), ("", "AXHN"), ("", "AXHF"), ("AX PSE;", "AXER4000,1000;"),
    ("", "AXHD5;"), ("", "AXES10;"), ("", "AXHG100;"), ("", "AXHV1000;"), ("", "AXLN"),
    ("", "AXLF"), ("", "AXLH"), ("", "AXLL"), ("", "AXSL"), ("", "AXSF"), ("", "BDFF00;"),
    ("", "BX"), ("", "BS0F00;"), ("", "BH8;"), ("", "BL8;"), ("", "AXPA1;"), ("", "AXPA0;"),
    ("", "AXSE10;"), ("", "AXAN"), ("", "AXAF"), ("", "AMAN"), ("", "AMAF"),
    ("", ";#BB100000;"), ("", ";#BB;"), ("", ";#BN;"), ("", ";#BF"),
    # E9 / 2.8: the trajectory scan's contour
    ("", "AM; SI1,,1; AX; #UR?; VIO[1]0100,0000,0100; VID[1]1; VH[1]0; AX; SW0;"),
    ("", "VA[1]100000; VV[1]1000; VP[1]A,1000,,,; VE[1]; AM;VO[1]=100; AM;VG[1]; QI"),
    ("", "VH[1]1; KS1,,1;"), ("", "VRV[1];VRC[1];"), ("", "BD0001; IO5,0;"),
    # E10: VIPER and QViper on a MAXv
    ("", "AA ID"), ("", "AX LTL HTH MP PSO LP100;"),
    ("", "AX PSM SVB1; LP0; KP32.0; KI1.0; KD100.0; KA2.0; CL1;"), ("", "AX CL0;"),
    ("", "AX TF"), ("", "AX AC25000; VL50000; VB0;"), ("", "AX LMH"), ("", "AX PH"),
    ("", "AX PL"), ("", "AX MP IC VL50000; MA1000; GN"), ("", "AX MM IC VL50000; MR-10; GN"),
    ("", "AX CA JG100;"), ("", "AX SD ID"), ("", "AA; SD; ID;"), ("", "AX MP HH HS VL11 HM0"),
    ("", "AX AB?"), ("", "AX ?AB"), ("AX PSE;", "AX HV100; HD5; HG10; CL1; ES10; TN MA10; GN"),
    ("", "AX; IC; VL5000; WH; MA1000; GO; MA0; GO; WG;"), ("", "AM MR,,,1000; GO"),
    # facts Table 1: older OMS hosts (NMSU upper-cases, TALON sends lower case)
    ("", "AX ST; JF-00012.3456;"), ("", "ax ac10000 jf12.35"), ("", "AX JF000003.5000;"),
    ("", "ax lp1000 rs"), ("", "aa rs;"), ("", "RS;"), ("", "AX; CA; HV100; HG10; HD5; IP;"),
    ("AX PSE;", "AX VL1000; AC10000; ER4000,1000; HV100; HG10; HD5; HN; MA400; GD; IP;"),
    ("", "AX; PSE; ECA12,125000; AY; PSE; ECA9,250000;"), ("", "AX; PSE; ECB32,500000;"),
    ("", "AX EDI;"), ("", "AX EDN;"), ("", "AX KOD100;"), ("", "BW3;"), ("", "IOK;"),
    ("", "IOK1;"), ("", "DBI;"), ("", "EF; IO0,0; AX; DBI; LP0; SC; AY; DBI; LP0; SC;"),
    ("", "#WC;"), ("", "AX RL;"), ("", "ax st wq jg100"), ("", "AX ET;"),
    ("", "AA VL75000,50000; MA0,0,,; GD; ID;"), ("", "aa af1,1,1,1,1,1;"), ("", "aa an,,,1,1,1;"),
    ("", "at an; at af lp0;"), ("", "ax vl100; km; id;"), ("", "AX KL;"), ("", "AA ST;"),
    ("", "ax ic ln sl ac10000 vl1000 hl hs mr-2000 go ac10000 hm0 ma100 go vl100 hm0 ma0 goid"),
    ("", "sa cn"), ("", "ax sf; ay sf; az sf;"), ("", "ax hf; er1,1;"),
]


def _setup(setup: str) -> MAXk:
    board = MAXk()
    if setup:
        board.send(setup)
        board.run_until_idle(timeout=1)
        assert not board.command_error, (setup, board.last_error)
    return board


@pytest.mark.parametrize("setup,text", HOST_FORMS)
def test_no_host_command_is_unknown(setup: str, text: str) -> None:
    board = _setup(setup)
    board.send(text)
    board.advance(0.2)
    unknown = [e for e in board.board.errors if "unknown command" in e.reason]
    assert not unknown, unknown


MNEMONICS_HOSTS_SEND = str.split(
    "AX AY AZ AT AU AV AR AS AW AK AA AM AC DC VL VB MA MR MT ML MP MM MO GO GD GN GP TM JG "
    "JF ST SA SD KS KL FL WQ SI ID CA IC WT WTC SW WH WG HM HR HE HS HH HL HT KM KR LP LPE "
    "LO LH LL LT ?LS LM LN LF SL SF PS ?PS CL ?PM HN HF HV HD HG ES TN TF IS ER UU UF ET ECI "
    "ECB ECA HI EH RTL SME BC SVB SVN SVP KO KOD KP KI KD KA ?KA KK ?KP WY RP RE PP PE RV RC "
    "QA RA RI QI EA QL RQC RB BX AB? ?AB #WS #WC #UR ?UR CC VRV VRC BD BH BL BS IO AN AF PA "
    "SE PH PL LA PF PN SC SS PR CN VO VG VH VID VIO VA VV VP VE #BB #BN #BF EF RL RS IP EDI "
    "EDN BW IOK DBI AI AO VOA VC LS LE APP RDP RDF KU KV KF"
)
"""The evidence's and facts file's mnemonics (and the manual's, for the I/O and flash
ones). TL and TS are left out: the facts file found no trace of them anywhere."""


def test_every_mnemonic_hosts_send_is_in_the_table() -> None:
    missing = [m for m in MNEMONICS_HOSTS_SEND if m not in COMMANDS]
    assert not missing


def test_every_mnemonic_appears_in_a_host_form() -> None:
    text = " ".join(t.upper() for _, t in HOST_FORMS)
    absent = [m for m in ("SD", "JF", "GP", "TM", "WTC", "WQ", "PH", "PL", "ECI", "ECA", "ECB",
                          "RTL", "SME", "BC0", "#BB", "#BN", "#BF", "EDI", "EDN", "KOD", "BW",
                          "IOK", "IP", "RS", "WH", "WG", "EF", "DBI", "#WC", "RL", "KK2", "?AB",
                          "ET") if m not in text]
    assert not absent


# ---- set-up strings run without a command error ---------------------------------------
@pytest.mark.parametrize("text", [
    ";AX;PSE;ECI;ER10000,10000;RTL;LTL;LMH;CL1;SME;HV1000000;HD1;HG10000;BC0;"
    ";AY;PSE;ECI;ER10000,10000;RTL;LTL;LMH;CL1;SME;HV1000000;HD1;HG10000;BC0;"
    ";AT;SVB1;SVN;PSM;KO0;;AX;SME;AY;SME;AZ;SME;",
    "AX; VL5000; AC50000; KP20; KI1; KD45; CL1; HM0; MA10000; GO; ID;",
    "AX CL0; AX TF; AX LMH; AX PH; AX PL; AXHN; AXHF; AX HN; AX HF;",
    ";#BB100000;;#BB;;#BN;;#BF;",
    "EF; IO0,0; AX; DBI; LP0; SC; AY; DBI; LP0; SC;",
    "AX; PSE; ECA12,125000; AY; PSE; ECA9,250000;",
    "AX; PSE; ECA16,125000; AY; PSE; ECA16,125000; AZ; PSE; ECA24,500000; AT; PSE; "
    "ECA32,250000; AU; PSE; ECA32,250000;",
])
def test_host_set_up_strings_raise_no_command_error(text: str) -> None:
    board = MAXk()
    board.send(text)
    board.run_until_idle(timeout=5)
    assert not board.command_error, board.last_error


# ---- behaviour ------------------------------------------------------------------------
def test_sd_stops_with_deceleration_and_id_sets_done_at_rest() -> None:
    board = MAXk()
    board.send("AX AC100000; JG10000;")
    board.advance(0.5)
    board.send("AX SD ID")
    assert not board.done("X")
    board.advance(0.2)  # 10000/100000 = 0.1 s of ramp
    assert board.done("X") and board.velocity("X") == 0
    assert board.position("X") == 4500 + 500  # 0.05 s ramp up, 0.45 s slew, 500 down


def test_sd_in_aa_mode_stops_every_axis() -> None:
    board = MAXk("MAXk-2000")
    board.send("AA; JG1000,-1000;")
    board.advance(0.1)
    board.send("AA; SD; ID;")
    board.advance(0.1)
    assert board.done("X") and board.done("Y")
    assert board.query("AA RV") == "0,0"


def test_jf_keeps_the_fraction_of_a_step_per_second() -> None:
    board = MAXk()
    board.send("AX AC8000000; JF-00012.3456;")
    board.advance(10.0)
    assert board.position("X") in (-123, -124)  # 10 s at 12.3456 steps/s
    board.send("AX ST; JF000003.5000;")  # NMSU's reversal: ST first, then JF
    board.advance(10.0)
    assert board.velocity("X") == pytest.approx(3.5)


def test_gp_goes_to_a_position_without_go_and_holds_the_queue() -> None:
    board = MAXk()
    board.send("AX;AC100000;DC100000;VL2000;GP1000;ID;")
    assert not board.done("X")
    assert board.run_until_done("X", timeout=2)
    assert board.position("X") == 1000


def test_tm_runs_at_vl_for_the_given_update_cycles_in_the_sign_direction() -> None:
    board = MAXk()  # 8192 Hz: 8192 cycles are one second
    board.send("AX;AC100000;DC100000;VL2000;TM8192;ID;")
    assert board.run_until_done("X", timeout=3)
    assert board.position("X") == 2000
    board.send("AX CA; TM-4096; ID;")
    assert board.run_until_done("X", timeout=3)
    assert board.position("X") == 1000


def test_sysal_timed_start_waits_for_the_cycle_counter() -> None:
    board = MAXk()
    board.advance(0.1)
    now = int(board.query(";CC"))
    board.send(f";AX;AC100000;DC100000;VL20000;MA15000;wtc{now + 8192};GO;")
    assert not board.command_error, board.last_error
    board.advance(0.9)
    assert board.position("X") == 0  # the GO has not fired yet
    board.advance(0.2)
    assert board.position("X") > 0
    board.run_until_idle(timeout=3)
    assert board.position("X") == 15000


def test_wtc_in_the_past_does_not_wait() -> None:
    board = MAXk()
    board.advance(1.0)
    board.send("AX;MA100;wtc10;GO;ID;")
    board.advance(0.1)
    assert board.done("X") and board.position("X") == 100


def test_ph_pl_drive_the_aux_output() -> None:
    board = MAXk()
    board.send("AX PH")
    assert board.query("AX AB?") == "=h"
    board.send("AX PL")
    assert board.query("AX ?AB") == "=l"


def test_an_af_lists_in_aa_mode_switch_only_the_flagged_axes() -> None:
    board = MAXk("MAXk-6000")
    board.send("aa an,,,1,1,1;")
    assert board.query("AA AB?") == "=l,=l,=l,=h,=h,=h"
    board.send("aa af1,1,1,1,1,1;")
    assert board.query("AA AB?") == "=l,=l,=l,=l,=l,=l"
    board.send("at an; ay an;")
    assert board.query("AA AB?") == "=l,=h,=l,=h,=l,=l"
    board.send("AA AN")  # bare in AA: every axis
    assert board.query("AA AB?") == "=h,=h,=h,=h,=h,=h"


def test_wq_holds_the_parser_until_the_queue_is_empty() -> None:
    board = MAXk()
    board.send("AX VL10000; AC1000000; MA5000; GO; WQ; RP; ST;")
    assert board.send("") == []  # RP (and ST) wait behind WQ
    board.advance(0.3)  # the move (about 0.51 s) is still running: ST not yet acted on
    assert board.velocity("X") > 0
    assert board.run_until_idle(timeout=2)
    assert board.position("X") == 5000  # the held ST came after the move ended
    assert board.send("") == ["5000"]  # the held RP answered at the end of the move


def test_wq_after_fl_releases_at_once_so_st_uses_the_new_acceleration() -> None:
    board = MAXk()
    board.send("AX AC1000000; VL20000; JG20000;")
    board.advance(0.5)
    board.send("AX FL AC200000; WQ ST ID;")  # classic EPICS MAXv stop
    assert not board.command_error
    assert board.query("AX RC") == "200000"
    board.advance(0.09)
    assert not board.done("X")  # 20000/200000 = 0.1 s of ramp down
    board.advance(0.02)
    assert board.done("X")


def test_wq_on_a_session_delivers_the_held_reply_when_it_runs() -> None:
    board = MAXk()
    session = board.open_session()
    session.feed(b"AX VL10000; AC1000000; MA5000; GO; WQ; RP;\n")
    assert session.read() == b""
    board.run_until_idle(timeout=2)
    assert session.read() == b"5000\n\r"


def test_ip_sets_done_once_position_maintenance_brings_the_encoder_in() -> None:
    board = MAXk()
    board.send("AX PSE; VL1000; AC100000; HV200; HD2; HN; MA400; GD;")
    board.advance(0.1)
    board.miss_steps("X", 30)
    board.send("AX IP;")
    board.run_until_done("X", timeout=5)
    assert abs(int(board.query("AX RE")) - 400) <= 2
    assert board.position("X") == 400


def test_ip_without_maintenance_is_id_at_rest() -> None:
    board = MAXk()
    board.send("AX; CA; VL1000; AC100000; MA100; GD; IP;")
    assert not board.done("X")
    assert board.run_until_done("X", timeout=2)
    assert board.velocity("X") == 0 and board.position("X") == 100


def test_rs_resets_the_controller_and_addresses_x() -> None:
    board = MAXk()
    board.send("AY; LP1000; VL777; AX LP1000; JG100;")
    board.advance(0.1)
    board.send("ax lp1000 rs")
    board.advance(0.01)
    assert board.query("rp") == "0"  # TALON's proof that the reset worked
    assert board.query("AA RP").split(",")[:2] == ["0", "0"]
    assert board.velocity("X") == 0
    assert not board.command_error


def test_wh_wg_oscillates_until_stopped() -> None:
    board = MAXk()
    board.send("AX; IC; VL5000; AC1000000; WH; MA1000; GO; MA0; GO; WG;")
    board.advance(5.0)  # far more than one back-and-forth (about 0.4 s)
    seen = []
    for _ in range(100):  # the sixth second: still going back and forth
        board.advance(0.01)
        seen.append(board.position("X"))
    assert min(seen) <= 50 and max(seen) >= 950
    board.send("AX ST ID")
    assert board.run_until_done("X", timeout=2)
    board.advance(1.0)
    assert board.velocity("X") == 0 and board.board.is_idle()


def test_eca_checks_bits_and_clock() -> None:
    board = MAXk()
    board.send("AX; PSE; ECA12,125000;")
    assert not board.command_error
    assert board.board.axes[0].config.absolute_encoder == (12, 125000)
    for bad in ("ECA33,125000;", "ECA12,100000;"):
        board.send("IC; AX " + bad)
        assert board.command_error, bad
    board.send("IC; AX ECI;")
    assert board.board.axes[0].config.absolute_encoder is None


def test_bw_waits_for_an_input_to_read_low() -> None:
    board = MAXk()
    board.set_input(3, True)
    board.send("AX BW3; ID;")
    board.advance(0.1)
    assert not board.done("X")
    board.set_input(3, False)
    board.advance(0.01)
    assert board.done("X")


def test_kk2_probe_is_an_error_without_a_servo_loop_only() -> None:
    board = MAXk()
    board.send("AX KK2 ID")
    assert board.command_error
    board.send("IC; AY PSM; KK2 ID")
    assert not board.command_error


def test_sme_sets_the_motor_counter_from_the_encoder_on_an_encoder_stepper() -> None:
    board = MAXk()
    board.send(";AX;PSE;ECI;ER10000,10000;LP0;MR500;GO;")
    board.run_until_idle(timeout=2)
    board.send("AX LPE480;")
    board.send(";AX;SME;")
    assert board.query("AX RP") == "480"


def test_et_is_refused_as_not_modelled_never_ignored() -> None:
    board = MAXk()
    board.send("AX ET;")
    assert board.command_error and "not modelled" in board.last_error.reason


def test_parsing_of_host_forms() -> None:
    board = MAXk("MAXk-4000")
    board.send("AX JG1000;")
    board.advance(0.2)
    board.send("AX FLAC200000; WQ ST ID;")  # FL glued to AC
    assert board.query("AX RC") == "200000"
    board.run_until_idle(timeout=1)
    board.send("AX CA; vl1000 ma0 goid")  # TALON's glued GOID
    assert board.run_until_done("X", timeout=2) and board.position("X") == 0
    board.send("AA VL75000,50000; MA0100,-0200,,; GD; ID;")  # short list, zero padding
    assert board.run_until_idle(timeout=2)
    assert board.query("AA RP") == "100,-200,0,0"
    assert not board.command_error, board.last_error


def test_a_query_reply_comes_before_the_notification_of_a_later_failing_command() -> None:
    """TCP door: `RP; XX;` answers RP, then reports XX's command error, in that order."""
    board = MAXk()
    session = board.open_session()
    session.feed(b"AX RP; XX;\n")
    assert session.read() == b"0\n\r%000 01000000\n\r"


def test_jf_resent_while_running_steers_the_speed() -> None:
    """Tracking hosts (NMSU, TALON, GVO) resend JF at every update of their loop."""
    board = MAXk()
    board.send("AX AC100000; JF500.25;")
    board.advance(0.5)
    assert board.velocity("X") == pytest.approx(500.25)
    board.send("AX JF499.75;")
    board.advance(0.5)
    assert board.velocity("X") == pytest.approx(499.75)
    assert not board.command_error


def test_big_buffer_mode_is_recorded() -> None:
    board = MAXk()
    board.send(";#BB100000;")
    assert board.board.command_buffer == ("big", 100000)
    board.send(";#BN;")
    assert board.board.command_buffer == ("normal", 100000)
    board.send(";#BB;")
    assert board.board.command_buffer == ("big", 100000)
    board.send(";#BF;")
    assert not board.command_error

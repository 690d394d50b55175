"""The MM4005 command table: mnemonic -> handler, axis rule, operand, evidence.

Sources: "manual" is the MM4005 user's manual EDH0162En1040 (06/99), pages found as
mirrored text (3.3.1 syntax p.3.7, 3.41 DP, 3.75 MS, 3.126 TB, 3.132 TH, 5.7.1-5.7.4
command list p.5.10, 6.1.2 pulses = the seed); "MM4006 5.4" is the sibling manual's
trajectory tutorial; "EPICS" is /work/shared/reference/mm4005-epics-client.md together
with epics-modules/motor motorApp/NewportSrc/drvMM4000Asyn.c and
epics-motor/motorNewport newportApp/src/drvMM4000.cc; "Tcl" is a public Tcl GPIB driver
package 'mm4005' (command grouping, DH behaviour, French error texts).
"""

from __future__ import annotations

from typing import Final

from . import handlers_axis as ax
from . import handlers_flow as fl
from . import handlers_io as io
from . import handlers_manual as mn
from . import handlers_program as pg
from . import handlers_settings as st
from . import handlers_timed as tm
from . import handlers_trajectory as tr
from . import handlers_variables as vr
from . import manual_list as ml
from .spec import AxisRule, CommandSpec, Handler, Operand

_ONE = AxisRule.ALL_OR_ONE
_REQ = AxisRule.REQUIRED
_NO = AxisRule.NONE
_NUM = Operand.NUMBER
_NONE = Operand.NONE


def _spec(mnemonic: str, handler: Handler, axis: AxisRule, operand: Operand, *, query: bool,
          replies: bool, source: str, confidence: str, note: str = "",
          summary: str = "") -> CommandSpec:
    summary = summary or (handler.__doc__ or "").strip().splitlines()[0]
    return CommandSpec(mnemonic, handler, axis, operand, query, replies, summary, source,
                       confidence, note)


def _tell(mnemonic: str, handler: Handler, axis: AxisRule, source: str, confidence: str,
          note: str = "", operand: Operand = _NONE, summary: str = "") -> CommandSpec:
    return _spec(mnemonic, handler, axis, operand, query=False, replies=True, source=source,
                 confidence=confidence, note=note, summary=summary)


def _set(mnemonic: str, handler: Handler, axis: AxisRule, operand: Operand, source: str,
         confidence: str, note: str = "", query: bool = True, summary: str = "") -> CommandSpec:
    return _spec(mnemonic, handler, axis, operand, query=query, replies=False, source=source,
                 confidence=confidence, note=note, summary=summary)


_DRIVER_ENTRIES: Final[tuple[CommandSpec, ...]] = (
    # --- status, positions, errors (what the EPICS drivers poll) ---
    _tell("TP", ax.tell_position, _ONE, "manual 3.41 example '3TP5.32'; EPICS TP; poll", "C",
          "all axes '1TP0.0000,2TP0.0000' (token count = axis count); decimals are ours (D)"),
    _tell("TH", ax.tell_theoretical, _ONE, "manual 3.132 TH; EPICS model 1 readback", "C"),
    _tell("DP", ax.tell_desired, _ONE, "manual 3.41 DP", "C"),
    _tell("MS", ax.tell_status, _ONE, "manual 3.75 MS; EPICS offset axis*5+3", "C",
          "bit 6 always 1; direction bit starts positive ('D' idle, as observed) (D)"),
    _tell("TE", ax.tell_error, _NO, "EPICS 'TE;' -> 'TE@', reply[2] != '@' is a problem", "C",
          "reading clears the register (manual 3.126 note)"),
    _tell("TB", ax.tell_error_message, _NO, "manual 3.126 TB", "C",
          "'TB@ No error'; TBaa translates aa without clearing; unknown code text is the "
          "manual's, its reply layout ours (D)", operand=Operand.CHAR),
    _tell("VE", ax.tell_version, _NO, "EPICS 'VE;' -> 'VE MM4005 Version 2.42'", "I",
          "text from the machine; exact firmware wording not found (D)"),
    _tell("TU", ax.tell_resolution, _ONE, "EPICS '1TU' -> '1TU0.001'", "C",
          "shortest decimal form (I)"),
    _tell("TC", ax.tell_loop_type, _ONE, "EPICS '1TC' -> '1TC0' (atoi != 0: closed loop)", "C"),
    _tell("XH", ax.tell_home_preset, _ONE, "EPICS '1XH' -> '1XH0.0000'", "C"),
    _tell("TL", ax.tell_left_limit, _ONE, "EPICS '1TL' -> '1TL-100.0000'", "C"),
    _tell("TR", ax.tell_right_limit, _ONE, "EPICS '1TR' -> '1TR100.0000'", "C"),
    # --- settings and motion (sent by the EPICS drivers, no reply) ---
    _set("VA", ax.velocity, _REQ, _NUM, "EPICS '1VA1.00000'", "C",
         "at least 1e-6 units/s (D: denormal speeds never end a move)"),
    _set("AC", ax.acceleration, _REQ, _NUM, "EPICS '1AC5.00000'", "C",
         "at least 1e-6 units/s2 (D: as VA)"),
    _set("PA", ax.move_absolute, _REQ, _NUM, "EPICS '1PA2.50000;', jog = PA to TR/TL", "C",
         "refused with power off (D) or outside TL..TR (C, D)", query=False),
    _set("PR", ax.move_relative, _REQ, _NUM, "EPICS 'nPR' for relative moves", "C",
         "relative to DP (D)", query=False),
    _set("ST", ax.stop, _ONE, _NONE, "EPICS '1ST;' and model 1 'ST;' (all axes)", "C",
         query=False),
    _set("OR", ax.search_home, _ONE, Operand.MODE, "EPICS '1OR;'; Tcl OR0/OR1/OR2", "C",
         "mode 0..2 accepted; every mode searches the home switch, brakes and returns onto "
         "its first count (D)", query=False),
    _set("SH", ax.set_home, _REQ, _NUM, "EPICS set position '2SH5.00000;2DH;2SH0.00000'", "C"),
    _set("DH", ax.define_home, _REQ, _NONE, "EPICS set position", "C",
         "limits shift with the origin (I, Tcl log)", query=False),
    _set("SL", ax.left_limit, _REQ, _NUM, "EPICS '1SL-100.00000' at iocInit", "C",
         "must stay below TR (D)"),
    _set("SR", ax.right_limit, _REQ, _NUM, "EPICS '1SR100.00000' at iocInit", "C",
         "must stay above TL (D)"),
    _set("MO", ax.motor_on, _ONE, _NONE, "EPICS CNEN=1 '1MO' / model 1 '1MO;'", "C",
         query=False),
    _set("MF", ax.motor_off, _ONE, _NONE, "EPICS CNEN=0 '1MF'; manual 3.75 MS bit 1", "C",
         "sets the power-off bit: model 2 then polls MS until power is on again (its stall)",
         query=False),
    # --- trajectory setup (manual 5.7.1) ---
    _set("NT", tr.new_trajectory, _NO, _NONE, "manual 5.7.1 NT", "C",
         "keeps FA/AD/AX/AY/VV/VS (D)", query=False),
    _set("FA", tr.first_tangent, _NO, _NUM, "manual 5.7.1 FA; MM4006 5.4 entry angle", "C",
         "degrees, default 0 (D)"),
    _set("AD", tr.max_discontinuity, _NO, _NUM, "manual 5.7.1 AD; MM4006 5.4 range", "C",
         "0.001..10 degrees, default 0.001 (D)"),
    _set("AX", tr.assign_x, AxisRule.PHYSICAL, _NONE, "manual 5.7.1 'xxAX'", "C",
         "default axis 1; 'AX' alone reports '1AX' (D)"),
    _set("AY", tr.assign_y, AxisRule.PHYSICAL, _NONE, "manual 5.7.1 'xxAY'", "C",
         "default axis 2; 'AY' alone reports '2AY' (D)"),
    # --- elements (manual 5.7.2) ---
    _set("LX", tr.line_x, _NO, _NUM, "manual 5.7.2 LX = f(LX, tangent)", "C",
         "coordinates relative to the start point (D)", query=False),
    _set("LY", tr.line_y, _NO, _NUM, "manual 5.7.2 LY = f(LY, tangent)", "C", query=False),
    _set("MX", tr.line_end_x, _NO, _NUM, "manual 5.7.2 MX = f(MX, MY)", "C"),
    _set("MY", tr.line_end_y, _NO, _NUM, "manual 5.7.2 MY builds the line", "C",
         "direction checked against AD by ET (MM4006 5.4)", query=False),
    _set("CR", tr.arc_radius, _NO, _NUM, "manual 5.7.2 CR = f(CR, CA)", "C"),
    _set("CA", tr.arc_sweep, _NO, _NUM, "manual 5.7.2 CA builds the arc", "C",
         "positive sweep counter-clockwise (I)", query=False),
    _set("CX", tr.arc_end_x, _NO, _NUM, "manual 5.7.2 CX = f(CX, CY)", "C"),
    _set("CY", tr.arc_end_y, _NO, _NUM, "manual 5.7.2 CY builds the arc", "I",
         "the one arc tangent to the path ending at (CX, CY) (I)", query=False),
    _set("EL", tr.erase_last, _NO, _NONE, "manual 5.7.2 EL", "C", query=False),
    # --- reports (manual 5.7.3) ---
    _tell("AT", tr.tell_executing, _NO, "manual 5.7.3 AT", "C", "0 when idle (D)"),
    _tell("LT", tr.list_trajectory, AxisRule.ELEMENT, "manual 5.7.3 'xxLT'", "I",
          "one reply line per element; layout ours (D)"),
    _tell("XA", tr.tell_discontinuity, _NO, "manual 5.7.3 XA", "C"),
    _tell("XE", tr.tell_last_element, _NO, "manual 5.7.3 XE 'tell the current element'", "D",
          "read as the last defined element, LT layout (D)"),
    _tell("XT", tr.tell_element_count, _NO, "manual 5.7.3 XT", "C"),
    _tell("XU", tr.tell_acceleration, _NO, "manual 5.7.3 XU", "C"),
    _tell("XV", tr.tell_velocity, _NO, "manual 5.7.3 XV", "C"),
    # --- execution (manual 5.7.5 grouping per Tcl: ET VS VV WI WN) ---
    _set("VV", tr.vector_velocity, _NO, _NUM, "Tcl grouping; pairs with XV", "I",
         "default 1 unit/s, at least 1e-6 (D)"),
    _set("VS", tr.vector_acceleration, _NO, _NUM, "Tcl grouping; pairs with XU", "I",
         "default 10 units/s^2, at least 1e-6 (D)"),
    _set("ET", tr.execute_trajectory, _NO, _NONE, "manual 5.7.5 ET; seed 6.1.2 checks", "C",
         "also refuses power off/moving X or Y (D) and a path outside SL/SR (D)",
         query=False),
    # --- synchronized pulses (manual 5.7.4 and 6.1.2) ---
    _set("NB", tr.pulse_start, _NO, Operand.INTEGER, "seed 6.1.2 NB", "C"),
    _set("NE", tr.pulse_end, _NO, Operand.INTEGER, "seed 6.1.2 NE", "C"),
    _set("NI", tr.pulse_step, _NO, _NUM, "seed 6.1.2 NI", "C",
         "NI? reads the MPN after a substitution; pulses spaced CPTL/(NN-1), NI only "
         "derives NN when NN is unset (D)"),
    _set("NN", tr.pulse_count, _NO, Operand.INTEGER, "seed 6.1.2 NN", "C"),
    _set("NS", tr.pulse_arm, _NO, _NONE, "seed 6.1.2 NS", "C", "taken by the next ET (D)",
         query=False),
)

_SCAN = "EPICS MM4005_trajectoryScan.st (reference mm4005-trajectory-scan.md)"
_LIST = ml.SOURCE
_NOPAGE = "the MM4005 page was not found; "
_ESP = "sibling ESP300 manual p. 3-3 (program execution mode)"
_KIT = "public ESP301 driver (InstrumentKit define_program/run_program)"

_ENTRIES: Final[tuple[CommandSpec, ...]] = _DRIVER_ENTRIES + (
    # --- the time-based trajectory of the EPICS trajectory scan ---
    _set("NC", tm.new_timed, _NO, _NONE, f"{_SCAN} #3 'initialize new trajectory'", "C",
         "keeps UC and GC (D)", query=False),
    _set("DC", tm.take_part, _REQ, Operand.INTEGER, f"{_SCAN} #4 'nDC0|1'", "C",
         "1 takes part, 0 not", query=False),
    _set("UC", tm.accel_time, _NO, _NUM, f"{_SCAN} #5 'acceleration time'", "C",
         "0.001..100 s, default 0.5 s (D); used for the acceleration VC reports, |dv|/UC; "
         "positions are not smoothed (D)"),
    _set("DT", tm.element_time, AxisRule.ELEMENT, _NUM, f"{_SCAN} #6 'iDT' element time", "C",
         "i = an element defined or the next one (D); at least one servo cycle (D)",
         query=False),
    _set("DX", tm.displacement, _REQ, _NUM, f"{_SCAN} #7 'nDX' displacement in the element",
         "C", "applies to the element the last DT named (I)", query=False),
    _set("MB", tm.pulse_first, _NO, Operand.INTEGER, f"{_SCAN} #9 'MBs'", "C"),
    _set("ME", tm.pulse_last, _NO, Operand.INTEGER, f"{_SCAN} #9 'MEe'", "C"),
    _set("MN", tm.pulse_number, _NO, Operand.INTEGER, f"{_SCAN} #9 'MN(p+1)'", "C",
         "n - 1 pulses evenly spaced in time, the first at the start of MB, spacing "
         "(end of ME - start of MB)/(n - 1) (D from the scan's 'one fewer pulse')"),
    _set("VC", tm.verify_timed, _NO, _NONE, f"{_SCAN} #10 'verify trajectory'", "C",
         "checks K, L, H (VU), G (GC), N, P; TB tells (letters ours, D)", query=False),
    _tell("RC", tm.verify_report, _REQ, f"{_SCAN} #12 'nRC1..6'", "C",
          "1/2 element and value of the largest speed change, 3/4 velocity, 5/6 "
          "acceleration; integers for odd, 6 decimals for even (D)",
          operand=Operand.INTEGER),
    _set("GC", tm.speed_error_limit, _REQ, _NUM, f"{_SCAN} #1-2 'nGC?' / 'nGC<%f>'", "C",
         "maximum speed change between elements; default 0 = not checked (D)"),
    _set("LS", tm.load_sequence, _NO, _NONE, f"{_SCAN} #14 'LS,<s>EC'", "D",
         _NOPAGE + "accepted, no effect", query=False),
    _set("EC", mn.execute, AxisRule.ELEMENT, _NUM, f"{_SCAN} #14 '<s>EC<timescale>'",
         "C", "prefix 0 real, 1 simulation (the scan's SimMode); element times x the "
         "operand, 0.01..1000 (D); H if an element then beats VU. 1EC (D, page not "
         "found): 0EC's checks and letters (J D H R) without moving anything; XC, NQ, TQ "
         "keep the last real run", query=False),
    _tell("XC", tm.elements_done, _NO, f"{_SCAN} #16 'XC1' -> 'XCnnnn'", "C",
          "elements completed; an operand 0..2 is accepted and ignored (D)",
          operand=Operand.MODE),
    _tell("NQ", tm.trace_count, _NO, f"{_SCAN} #20 'NQ' -> 'NQnnnn'", "C",
          "pulses of the last run (the ring keeps the newest 20,000)"),
    _tell("TQ", tm.trace_point, AxisRule.ELEMENT, f"{_SCAN} #21 'iTQ'", "C",
          "'iTQ,1THa,1TPb,...' for every installed axis at pulse i"),
    _set("AB", tm.abort_motion, _NO, _NONE, f"{_SCAN} #22 'AB' on the Abort PV", "C",
         "every motion and trajectory stops at once, power stays on (D)", query=False),
    # --- servo gains (EPICS model 1 driver) and other settings ---
    _set("KP", st.setting, _REQ, _NUM, "EPICS model 1 'nKP'; manual 3.177 XP 'Rel. Commands: "
         "KP - Set proportional gain'", "C",
         "axis 1..4 required and no '?' as the KI and KD pages (I); read with XP; "
         "takes effect at UF; 0 to 1 as KD's page (I), above 1 is C; 1.0 stands for the "
         "shared servo's KP 100 (D, settings.FULL_SCALE); KP 0 (factory) = the exact "
         "profile-only axis (D)", query=False,
         summary="KP: proportional gain of the servo loop"),
    _set("KI", st.setting, _REQ, _NUM, "manual 3.64 KI 'xxKInn' (axis 1..4, nn missing: C); "
         "EPICS model 1 'nKI'", "C",
         "no '?' (read with XI); effect at UF; the manual's range 0 to 1 (C), above 1 "
         "is C; 1.0 stands for the shared servo's KI 10 (D, settings.FULL_SCALE)", query=False,
         summary="KI: integral gain of the servo loop"),
    _set("KD", st.setting, _REQ, _NUM, "manual 3.63 KD 'xxKDnn' (axis 1..4, nn missing: C); "
         "EPICS model 1 'nKD'", "C",
         "no '?' (read with XD); effect at UF; the manual's range 0 to 1 (C), above 1 "
         "is C; 1.0 stands for the shared servo's KD 1000 (D, settings.FULL_SCALE)", query=False,
         summary="KD: derivative gain of the servo loop"),
    _set("KS", st.setting, _REQ, _NUM, "manual 3.66 KS 'xxKSnn or xxKS?', 0 to 1", "C",
         "saturation of the integral factor, a fraction of the maximum output; effect at "
         "UF; 'nKS?' reads the value set (I: the page says 'actual')",
         summary="KS: integral saturation of the servo loop"),
    _set("UF", st.update_filter, _ONE, _NONE, "EPICS model 1 'nUF' after the gains; manual "
         "3.63 KD 'no effect until the UF (update filter) is received'", "C",
         "KP, KI, KD, KS set take effect; without an axis every axis (D)", query=False),
    _set("FE", st.following_error_limit, _REQ, _NUM, "manual 3.56 FE 'xxFEnn' (axis 1..4, "
         "nn missing: C)", "C",
         "2 x TU up to the travel TR - TL (the manual's 'maximum device travel', D), else C; "
         "no '?' (XF reads it); takes effect at the next UF; beyond it the motor turns off "
         "(the manual: every axis stops and every motor turns off; here the axis that "
         "lagged, D); default 1 unit (D)", query=False,
         summary="FE: maximum following error (motor off beyond it)"),
    _set("FF", st.master_slave_limit, _REQ, _NUM, "manual 3.57 FF 'xxFFnn or xxFF?'", "C",
         "2 x TU up to TR - TL, default 1 unit (D); stored and read back: master-slave "
         "(gearing) is not modelled, so it never trips",
         summary="FF: maximum master-slave following error"),
    _set("SS", mn.master_slave, _REQ, Operand.OPTIONAL_NUMBER,
         "manual 3.122 SS 'xxSSnp or xxSS?' (n master 1..4, missing 0 = master; p 0 "
         "theoretical, 1 real position)", "C",
         "master-slave is not modelled: 'xxSS?' reads 0 (every axis its own master), "
         "'xxSS'/'xxSS0' are accepted, slaving to another axis answers Q; n or p out of "
         "range C"),
    _set("GR", mn.reduction_ratio, _REQ, Operand.OPTIONAL_NUMBER,
         "manual 3.60 GR 'xxGRnn or xxGR?', 0.0001 to 10000, nn missing: 1.0", "C",
         "stored and read back ('2GR?' -> '2GR100'); no axis can be slaved here (SS), so "
         "it moves nothing", summary="GR: master-slave reduction ratio"),
    _tell("RB", mn.read_inputs, AxisRule.ELEMENT, "manual 3.103 RB 'xxRB', xx 0 to 8 "
          "(missing 0, out of range E); example '0RB' -> 'RB209'", "C",
          "the world's digital inputs 1..8 (`@world input 3 high`, the REPL's :world); "
          "the byte has bit 1 as its least significant bit; 'xxRB0|1' for one bit; the whole "
          "byte answers 'RBnn' for '0RB' and 'RB' alike (the manual's example, D)",
          summary="RB: read the GPIO input port or one of its bits"),
    _tell("XP", st.tell_gain, _REQ, "manual 3.177 XP 'xxXP' -> 'xxXPnn'", "C",
          "the proportional gain the loop uses (as of the last UF), shortest form (I)",
          summary="XP: read the proportional gain the servo loop uses (since the last UF)"),
    _tell("XI", st.tell_gain, _REQ, "manual 3.173 XI 'xxXI' -> 'xxXInn'", "C",
          "the integral gain the loop uses (as of the last UF)",
          summary="XI: read the integral gain the servo loop uses (since the last UF)"),
    _tell("XD", st.tell_gain, _REQ, "manual 3.169 XD 'xxXD' -> 'xxXDnn'", "C",
          "the derivative gain the loop uses (as of the last UF)",
          summary="XD: read the derivative gain the servo loop uses (since the last UF)"),
    _tell("XF", st.tell_following_limit, _REQ, "manual 3.171 XF 'xxXF' -> 'xxXFnn'", "C",
          "the maximum following error in force (FE as of the last UF)"),
    _tell("TF", st.tell_filter, _REQ, "manual 3.169-3.177 XD/XI/XP/XF 'Rel. Commands: TF - "
          "Read filter parameters'", "C",
          "its page was not found: the layout 'nTFKPa,KIb,KDc,KSd,FEe' (the values in the "
          "loop) is ours (D)"),
    _set("BA", st.backlash, _REQ, Operand.OPTIONAL_NUMBER,
         "manual 3.25 BA 'xxBAnn', axis 1..4 (missing: B), nn missing: 0", "C",
         "0 to the distance of 10000 encoder counts (10000 x TU), else C; 0 disables; read "
         "with XB (the manual's syntax has no '?'). Stored: the correction on reversals "
         "is not applied to motion (not modelled)", query=False),
    _tell("XB", st.tell_backlash, _ONE, "manual 3.25 BA 'Rel. Commands: XB - Read backlash "
          "compensation'", "C", "reply 'nXBvalue' like the other reads (I)"),
    _set("OH", st.setting, _ONE, _NUM, f"{_LIST}: special motion parameters; sibling ESP300 "
         "'OH set home search high speed'", "I",
         _NOPAGE + "stored; OR searches at VA (D)",
         summary="OH: home search high speed"),
    _set("OL", st.setting, _ONE, _NUM, f"{_LIST}: special motion parameters; sibling ESP300 "
         "'OL set home search low speed'", "I",
         _NOPAGE + "stored; OR searches at VA (D)",
         summary="OL: home search low speed"),
    _set("VU", st.setting, _ONE, _NUM, "sibling ESP300 'VU set maximum speed'; the maximum "
         "the time-based trajectory's VC checks", "D",
         "not in the 06/99 manual's list (later firmware, D); default 100 units/s (D); VC "
         "and DV1 read it",
         summary="VU: maximum speed of the axis"),
    _set("SN", st.setting, _ONE, Operand.INTEGER, f"{_LIST}: motor and stage set-up; sibling "
         "ESP300 3-133 'SN set axis displacement units'", "I",
         _NOPAGE + "codes 0..11 as the ESP300's (0 encoder count, 1 motor step, 2 mm, 3 um, "
         "4 in, 5 milli-in, 6 micro-in, 7 deg, 8 grad, 9 rad, 10 mrad, 11 urad), default 2 "
         "(mm, I); a label only, nothing is converted (as the ESP300 says); TN names it",
         summary="SN: displacement units code"),
    _set("SD", st.speed_reduction, _NO, _NUM, f"{_LIST}: motion parameters, 'SDnn' / 'SD?' "
         "-> 'SDnn', a reduced speed in percent", "I",
         _NOPAGE + "0 < nn <= 100, default 100 (D); stored and read back; the reduction is "
         "not applied to motion (not modelled)",
         summary="SD: reduced speed, percent"),
    _set("SU", st.encoder_resolution, _ONE, _NUM, "sibling ESP300 'SU set encoder "
         "resolution'", "D",
         "not in the 06/99 manual's list (D); reads TU; setting refused C (the resolution "
         "is fixed here, D)"),
    _set("MV", st.jog, _REQ, Operand.SIGN, f"{_LIST}: motion parameters, 'xxMVnn' move "
         "indefinitely; sibling ESP300 3-101 'MV move indefinitely', '3MV+'", "I",
         _NOPAGE + "moves at VA toward TR (+) or TL (-) (I); '+', '-' or a signed number "
         "('1MV+', '1MV-1'); 0 answers C (D)", query=False),
    _set("SY", st.setting, _REQ, Operand.INTEGER, f"{_LIST}: special motion parameters, "
         "'xxSYnn' synchronisation, 0 or 1", "I",
         _NOPAGE + "stored and read back ('1SY?' -> '1SY1'), default 0 (D); what it "
         "synchronises is not known: no effect (not modelled)",
         summary="SY: synchronisation flag of an axis (0 or 1)"),
    _tell("DV", st.tell_desired_velocity, _REQ, "manual 3.43 DV 'xxDVpp'", "C",
          "axis 1..4 required (B); pp missing or 0: the velocity VA programmed, pp >= 1: "
          "the maximum allowed velocity (VU here, I); a negative or fractional pp answers "
          "C (D); 4 decimals (D)", operand=Operand.OPTIONAL_NUMBER),
    _tell("DA", st.tell_desired_acceleration, _ONE, f"{_LIST}: motion parameters, beside DV",
          "I", "reads AC, like DV reads VA (I)"),
    _tell("DF", st.tell_following_error, _ONE, f"{_LIST}: motion parameters, 'xxDF' read "
          "following error", "I", "TH - TP (I)"),
    _tell("TN", st.tell_units, _ONE, f"{_LIST}: motor and stage set-up, 'xxTN' read units",
          "I", "the name of SN's code ('1TNmm' by default); the names are ours (D)"),
    _tell("TA", st.tell_axis_type, _ONE, f"{_LIST}: motor and stage set-up, 'xxTA' read the "
          "stage's name", "I", "no stage names are modelled: 'DC' (a DC servo stage, D)"),
    _tell("TS", st.tell_controller_status, _NO, "manual 3.139 TS 'Returns TSaa'", "C",
          "bits 0-3 axes 1-4 moving, 4 motor power off (any installed axis off, I), 5 "
          "default 0, 6 default 1, 7 IEEE SRQ (never set: RQ is not modelled); idle 'TS@' "
          "as a public MM4006 StreamDevice host expects"),
    _tell("TX", st.tell_controller_activity, _NO, "manual 3.142 TX 'Returns TXaa'", "C",
          "bit 0 program running (EX: 'TXK' while one runs), 1 command line executing and "
          "3 remote mode (always, as TX itself is answered: 'TXJ', the manual's example), "
          "2 manual jog (never), 4 trajectory executing (XY or time-based: 'TXZ'), 6 "
          "default 1"),
    _set("RQ", mn.not_modelled, _NO, _NONE, "manual 3.139 TS bit 7 'IEEE SRQ Interruption "
         "Status (Sent by RQ command)'", "C",
         "generates a GPIB service request: no GPIB door exists here, so RQ answers Q "
         "(not modelled, D)", query=False, summary="RQ: generate an IEEE service request"),
    _set("ZP", st.zero_position, _REQ, _NONE, f"{_LIST}: motion and position control, "
         "'xxZP' zero position (the host: 'sets the present position to 0')", "I",
         _NOPAGE + "the counter reads 0 where the axis stands; TL/TR stay (the host sets "
         "them again after ZP, unlike after DH); refused D while moving (D)",
         query=False, summary="ZP: the present position becomes 0"),
    # --- programming and flow control (ESP300 sibling manual p. 3-3, ESP301 driver) ---
    _set("EP", pg.enter_program, AxisRule.ELEMENT, _NONE, f"{_ESP} ('EP', the lines, 'QP'); "
         f"{_KIT} ('nXX', 'nEP', 'QP'); manual 3.175 XM (programs 1..127, 30720 bytes)", "I",
         _NOPAGE + "xx 1..127 (else F, as XM 3.175); the host's next lines are stored as entered, "
         "not evaluated, up to a line holding QP (what follows QP on it runs, D); the rest "
         "of the EP line is the first line (D); a program that exists is refused D (erase "
         "it first with XX, as the driver does, D); 30720 bytes of program memory (XM "
         "3.175, C), beyond it a line is refused D; refused D inside a program", query=False,
         summary="EP: enter program xx (its lines are stored up to QP)"),
    _set("QP", pg.quit_program, _NO, _NONE, f"{_ESP}; {_KIT}", "I",
         _NOPAGE + "ends program entry and stores the program in the non-volatile program "
         "memory (3.175; the program archive: it survives a power cycle; SM 'save "
         "program' and MP 'EEPROM to RAM', named on XM's page, were not found, D); "
         "outside an entry refused D (D)",
         query=False, summary="QP: quit program entry"),
    _set("EX", pg.execute_program, AxisRule.ELEMENT, _NONE, f"{_ESP} ('1EX' runs program "
         f"1); {_KIT} ('nEX')", "I",
         _NOPAGE + "runs beside the command lines, which stay answered (ESP300, I): its "
         "lines at once until a wait holds it, its replies to the host that started it "
         "(D); one program at a time (D, else D); xx 1..127 else F (3.175); no program xx: "
         "C (D); AB ends it (D); a "
         "refused command or malformed line ends it with its error (D)", query=False,
         summary="EX: execute program xx"),
    _set("XX", pg.erase_program, AxisRule.ELEMENT, _NONE, f"{_KIT} ('nXX' before 'nEP', "
         "error-checked: no error when none is stored)", "I",
         _NOPAGE + "xx 1..127 (else F, 3.175); the program running refused D (D)", query=False,
         summary="XX: erase program xx"),
    _tell("XM", pg.read_memory, AxisRule.ELEMENT, "manual 3.175 XM 'xxXM' -> 'xxXMnn' "
          "(xx 0 to 127, missing 0, out of range F; 30720 bytes; 'XM' -> 'XM29873', '1XM' -> "
          "'1XM15', '100XM' -> '100XM0')", "C",
          "xx missing or 0: the memory unused ('XMnn' for both, D); a program's length "
          "counts each line and its terminator (D)",
          summary="XM: read the program memory available, or a program's length"),
    _tell("TY", vr.read_variable, AxisRule.ELEMENT, "manual 3.145 TY 'xxTY' -> 'xxTYnn' (xx "
          "1 to 100 integers, 101 to 120 floats; missing or out of range O, a floating "
          "point xx A; 0 until YS sets it)", "C",
          "YS and the other setters were not found (Q): every variable reads 0; floats in "
          "their shortest form (D); '$Ypp' in place of a number (3.3.1) reads it when the "
          "command runs, '$Saa' there answers C (D)",
          summary="TY: read a variable"),
    _set("WS", fl.wait_motion_stop, _ONE, Operand.OPTIONAL_NUMBER, f"{_ESP} (program "
         "'1PA+30', '1WS', '2PR-10'); ESP-family hosts ('3MT+' then '3WS'; '1 WS 0' 'wait "
         "for motion stop')", "I",
         _NOPAGE + "the line (or program) holds until axis xx has stopped (missing or 0: "
         "every axis, D), on the tick its motion ends however it ends; the host's later "
         "lines wait behind it while other hosts are answered (a stop from them ends it); "
         "nn: a delay in ms after the stop, 0..3600000, whole (D)", query=False,
         summary="WS: wait for motion stop"),
)


# --- inputs and outputs, trace mode, display, special motion (issue 36) ---
_TQ_PAGE = ("manual 3.137 TQ 'Read global trace data': 'the global trace mode is enabled by "
            "GQ command and defined by SQ and GQ commands', samples 1 to 'the number of "
            "samples set by GQ'; Rel. Commands 'GQ - Set global trace mode', 'SQ - Set "
            "global sample rate'")
_TT_PAGE = "manual 3.140 TT (Rel. Commands and example):"
_SEARCHED = ("its page was searched for in the MM4005 manual's mirrored pages, the MM4006's "
             "and the ESP300's and not found: its syntax and reply are unknown, so it is not "
             "modelled and answers Q")


def _not_found(mnemonic: str, known: str = "") -> CommandSpec:
    """One of this group's commands whose page was found nowhere: Q, saying so."""
    group = ml.GROUP[mnemonic]
    return _spec(mnemonic, mn.not_modelled, AxisRule.ELEMENT, Operand.ANY, query=True,
                 replies=False, source=f"{_LIST}: {group}", confidence="I",
                 note=(known + "; " if known else "") + _SEARCHED,
                 summary=f"{mnemonic}: one of the {group} commands (page not found: Q)")


_IO_ENTRIES: Final[tuple[CommandSpec, ...]] = (
    _set("SB", io.output_port, _NO, Operand.INTEGER, "sibling ESP300 3-126 'SB set/get DIO "
         "port bits', 'SBnn or SB?' (the MM4005 page was not found)", "I",
         "drives the 8 GPIO outputs at once: bit 1 = 1 (least significant, as RB's byte, "
         "manual 3.103) ... bit 8 = 128; nn decimal 0..255 (the ESP300 writes hex, the "
         "MM4005's RB answers decimal: D), else C; 'SB?' -> 'SBnn' the outputs driven. "
         "The levels are the world's outputs (`:world`, the trace, the panel, `@expect "
         "output 3 high`); all low at power-up (D). The MM4005 also lists CB and SO, whose "
         "pages were not found: whether its SB sets only the bits of a mask is not known",
         summary="SB: set the GPIO output bits (the whole port byte)"),
    _tell("RA", io.read_analog, AxisRule.ELEMENT, "manual 3.103 RB 'Rel. Commands: RA - Read "
          "analog input'; manual 3.137 TQ: 'analog values of inputs 1, 2, 3 and 4', returned "
          "as '1RAnn, 2RAnn, 3RAnn, 4RAnn'", "I",
          "RA's own page was not found: 'xxRA' (xx 1..4) -> 'xxRAv' the world's analog input "
          "xx (`@world analog 2 1.5`) in volts, 4 decimals (D); without xx every input "
          "'1RAv,2RAv,3RAv,4RAv' (D); xx beyond 4 answers E (as RB)",
          summary="RA: read an analog input (volts)"),
    _set("GQ", io.global_trace, _NO, Operand.INTEGER, _TQ_PAGE, "I",
         "GQ's own page was not found: 'GQnn' (1..20000) starts an acquisition of nn "
         "samples into the trace buffer, the first on the tick GQ runs, then one every SQ "
         "servo cycles, each every axis's TH and TP (TQ reads sample i as 'iTQ,1THa,1TPb,...', "
         "NQ the count); 'GQ0' ends it early; 'GQ?' -> 'GQnn' (D). A trajectory run started "
         "meanwhile takes the buffer over and ends the acquisition (D)",
         summary="GQ: set the global trace mode (acquire nn samples)"),
    _set("SQ", io.sample_rate, _NO, Operand.INTEGER, _TQ_PAGE, "I",
         "SQ's own page was not found: 'SQnn' nn servo cycles (0.5 ms, manual 7.1.1) between "
         "two samples, 1..10000, default 1 (D); 'SQ?' -> 'SQnn'; refused D while an "
         "acquisition runs (D)",
         summary="SQ: set the global trace sample period (servo cycles)"),
    _set("TM", io.trace_mode, _REQ, Operand.INTEGER, f"{_TT_PAGE} '2TM500 | Set trace mode "
         "for axis #2 and 500 data points'", "I",
         "TM's own page was not found: 'xxTMnn' axis xx (1..axis count, else B), nn 1..20000 "
         "samples (C beyond, D), the first on the tick TM runs, then one every SP (D); a new "
         "TM starts the memory afresh; 'xxTM0' ends it early, keeping the samples (D); "
         "'xxTM?' -> 'xxTMnn' (0 for an axis not traced, D)",
         summary="TM: set the trace mode (axis xx, nn samples)"),
    _set("SP", io.trace_period, _NO, _NUM, f"{_TT_PAGE} 'SP0.002 | Set trace period to 2 "
         "ms'", "I",
         "SP's own page was not found: seconds, 0.0005 (one servo cycle) to 5 s, rounded to "
         "whole servo cycles, default 0.0005 (D); 'SP?' -> 'SPnn' (D); refused D while the "
         "trace mode acquires (D)",
         summary="SP: set the trace sample period (seconds)"),
    _tell("TT", io.read_trace, AxisRule.ELEMENT, "manual 3.140 TT 'Read trace data' 'xxTT' -> "
          "'xxTT, THnn, TPnn' (example '9TT, TH1.002, TP1.001'), xx 0 to the samples set by "
          "TM, missing 0: every sample, one a line; out of range C", "C",
          "written without the blanks of the manual's typesetting ('9TT,TH1.0020,TP1.0010', "
          "as TQ's replies, D), positions with TP's decimals (D); a sample within TM's count "
          "but not taken yet answers D (D)",
          summary="TT: read the trace mode's data"),
    _tell("XN", io.trace_count, _NO, f"{_TT_PAGE} 'XN - Read number of acquisitions'", "I",
          "XN's own page was not found: 'XNnn' the samples the trace mode has taken (D)",
          summary="XN: read the number of trace samples taken"),
    # found nowhere: Q, each saying so
    *(_not_found(name) for name in ("AM", "CB", "FT", "RO", "SO", "TG", "YO", "YP", "YR")),
    *(_not_found(name, "not named by the trace pages found (3.137 TQ, 3.140 TT)")
      for name in ("AQ", "XQ", "XS")),
    *(_not_found(name, "no page found defines the front panel display's text")
      for name in ("DS", "DY", "FB", "FC", "FD", "NP", "RD", "RE")),
    *(_not_found(name) for name in ("DM", "DO", "MH", "PB", "PE", "PI", "PS", "SE", "OA",
                                    "VB", "SC", "SF", "PW", "WI", "WN")),
)


_SEARCHED_WORDS: Final = ("WT WP WE WF WG WH WK WL WY UH UL DL JL RP IE KC OE YE YG YL YN YW WA "
                          "AS CS YA YB YC YD YF YK YM YQ YS YV YY LP EO AP CP MP SM XL")
SEARCHED_AGAIN: Final = frozenset(_SEARCHED_WORDS.split())
"""The flow-control, variable-setting and programming commands whose pages were looked
for a second time (2026-11-27) in the stored pages of the MM4005's and MM4006's manuals
and of the sibling ESP300's remote-mode chapter (whose WS example and program-execution
pages p. 3-2/3-3 were found), by name and in the pages' own layout (IMM PGM MIP, SYNTAX,
PARAMETERS...): none was found, so none has a syntax, a range or a reply to follow and
each stays Q rather than being guessed."""

_SEARCH_NOTE: Final = ("in the MM4005, MM4006 or ESP300 manual pages (searched again "
                       "2026-11-27)")


def _listed(mnemonic: str) -> CommandSpec:
    """A command of the manual's list the emulator does not carry out: answers Q."""
    group = ml.GROUP[mnemonic]
    searched = f" {_SEARCH_NOTE}" if mnemonic in SEARCHED_AGAIN else ""
    return _spec(mnemonic, mn.not_modelled, AxisRule.ELEMENT, Operand.ANY, query=True,
                 replies=False, source=f"{_LIST}: {group}", confidence="I",
                 note=f"one of the {group} commands; its page was not found{searched}: not "
                 "modelled, answers Q",
                 summary=f"{mnemonic}: one of the {group} commands (not modelled)")


_MODELLED: Final = {spec.mnemonic for spec in _ENTRIES + _IO_ENTRIES}
COMMANDS: Final[dict[str, CommandSpec]] = {
    spec.mnemonic: spec for spec in _ENTRIES + _IO_ENTRIES} | {
    name: _listed(name) for name in sorted(ml.GROUP) if name not in _MODELLED}

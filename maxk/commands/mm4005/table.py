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
from . import handlers_trajectory as tr
from .spec import AxisRule, CommandSpec, Handler, Operand

_ONE = AxisRule.ALL_OR_ONE
_REQ = AxisRule.REQUIRED
_NO = AxisRule.NONE
_NUM = Operand.NUMBER
_NONE = Operand.NONE


def _spec(mnemonic: str, handler: Handler, axis: AxisRule, operand: Operand, *, query: bool,
          replies: bool, source: str, confidence: str, note: str = "") -> CommandSpec:
    summary = (handler.__doc__ or "").strip().splitlines()[0]
    return CommandSpec(mnemonic, handler, axis, operand, query, replies, summary, source,
                       confidence, note)


def _tell(mnemonic: str, handler: Handler, axis: AxisRule, source: str, confidence: str,
          note: str = "", operand: Operand = _NONE) -> CommandSpec:
    return _spec(mnemonic, handler, axis, operand, query=False, replies=True, source=source,
                 confidence=confidence, note=note)


def _set(mnemonic: str, handler: Handler, axis: AxisRule, operand: Operand, source: str,
         confidence: str, note: str = "", query: bool = True) -> CommandSpec:
    return _spec(mnemonic, handler, axis, operand, query=query, replies=False, source=source,
                 confidence=confidence, note=note)


_ENTRIES: Final[tuple[CommandSpec, ...]] = (
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

COMMANDS: Final[dict[str, CommandSpec]] = {spec.mnemonic: spec for spec in _ENTRIES}

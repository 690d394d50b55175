"""The command table: one declarative entry per mnemonic.

The lexer, the interpreter, the REPL's help and completion and docs/commands.md all read
this table. Each entry says where its behaviour comes from and how sure we are:

- ``C`` certain: stated by the MAXk manual or seen literally in host code (evidence C);
- ``I`` inferred: deduced from how host code uses the command (evidence I);
- ``D`` decided: neither settles it; this is our choice, explained in ``notes``.

Long module: it is data, one entry per mnemonic (about 200), kept in one file so that
the single source of truth is one place to read and to review.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from enum import Enum
from typing import Any

from maxk.commands.tables import TableError, unique_table
from maxk.personalities.maxk.contouring import MAX_VECTOR_VELOCITY, OVERRIDE_MAX
from maxk.personalities.maxk.models import (
    MAX_ACCELERATION,
    MAX_VELOCITY,
    POSITION_MAX,
    POSITION_MIN,
    QUEUE_CAPACITY,
)


class Operand(Enum):
    NONE = "none"
    NUMBER = "#"  # signed decimal; one per axis (comma list) in AA/AM
    LETTER = "letter"  # one letter of `letters` (or '?' when query=True); lists in AA/AM
    PATTERN = "pattern"  # exactly four characters of `letters` (EH1111)
    HEX = "hex"  # hexadecimal digits (BD, BS); one operand, never a per-axis list
    VECTOR = "vector"  # vector-task commands: optional [n], a form letter or '=', a list


class Timing(Enum):
    MODE = "mode"  # changes the command mode at once
    IMMEDIATE = "immediate"  # acts the moment it is parsed
    QUEUED = "queued"  # goes into the addressed axis queue(s)
    VECTOR = "vector task"  # goes to the addressed vector task's contour (contouring)


class Start(Enum):
    """How a queued command starts motion on the axes it addresses."""

    NONE = "none"
    GO = "go"  # in AA mode every addressed axis starts on one tick (a start group)
    LINEAR_ABSOLUTE = "linear absolute"  # MT: one straight line, all axes arrive together
    LINEAR_RELATIVE = "linear relative"  # ML


SINGLE = "single"
AA = "AA"
AM = "AM"
ALL_MODES = frozenset({SINGLE, AA, AM})
LIST_MODES = frozenset({AA, AM})


@dataclass(frozen=True)
class CommandSpec:
    mnemonic: str
    group: str
    summary: str
    timing: Timing
    operand: Operand = Operand.NONE
    modes: frozenset[str] = ALL_MODES
    units: int = 0  # queue units per addressed axis
    reply: str = ""  # what a query answers; "" = no reply
    source: str = ""
    confidence: str = "C"
    notes: str = ""
    letters: str = ""  # LETTER operand choices
    query: bool = False  # accepts '?' in place of the operand (PS?, LT?, #UR?)
    value_range: tuple[float, float] | None = None
    integer: bool = True  # step quantities: decimals truncate toward zero
    operand_optional: bool = False
    per_axis: bool = True  # False: operands are positional (IO3,1), not one per axis
    arity: int = 1  # positional operands when per_axis is False
    form: str = ""  # the syntax shown in help and the reference, when the default won't do
    # How the command behaves, bound here rather than in lists of mnemonics elsewhere:
    user_units: bool = False  # operands in user units while UU is on (counts otherwise)
    start: Start = Start.NONE  # how a queued GO/MT/ML starts axes
    applied_at_stop: bool = False  # queued just before ST/SA, it acts first (evidence E4)
    assign_form: bool = False  # `VO=#`: '=' may stand for the form letter
    hex_operands: bool = False  # operands in hexadecimal (VIO)
    handler: Callable[..., Any] | None = field(default=None, compare=False, repr=False)
    # ^ what it does, bound once by the module that owns the behaviour (`bind`): an
    # immediate command's handler(ctx), a queued one's factory(value, ctx), a vector
    # command's handler(board, task, cmd); none for mode commands and MT/ML (by `start`)

    @property
    def syntax(self) -> str:
        if self.form:
            return self.form
        m = self.mnemonic
        if self.operand is Operand.NUMBER:
            form = ",".join(["#"] * self.arity) if not self.per_axis else "#"
            form = f"{m}[{form}]" if self.operand_optional else f"{m}{form}"
        elif self.operand is Operand.LETTER:
            form = f"{m}{{{'|'.join(self.letters)}}}"
        elif self.operand is Operand.PATTERN:
            form = f"{m}pppp"
        elif self.operand is Operand.HEX:
            form = f"{m}hhhh"
        else:
            form = m
        if self.query:
            form += f" / {m}?"
        return form


def _q(mnemonic: str, group: str, summary: str, *, units: int = 1, **kw) -> CommandSpec:
    return CommandSpec(mnemonic, group, summary, Timing.QUEUED, units=units, **kw)


def _i(mnemonic: str, group: str, summary: str, **kw) -> CommandSpec:
    return CommandSpec(mnemonic, group, summary, Timing.IMMEDIATE, **kw)


def _v(mnemonic: str, form: str, summary: str, *, arity: int = 1, **kw) -> CommandSpec:
    """A vector-task command (contouring): `[n]` picks task 1-8, none means task 1."""
    kw.setdefault("source", "evidence 2.8 (TRAJ)")
    kw.setdefault("confidence", "I")
    kw.setdefault("per_axis", False)
    return CommandSpec(mnemonic, "contour", summary, Timing.VECTOR, operand=Operand.VECTOR,
                       arity=arity, form=form, **kw)


_VEL = (0.0, float(MAX_VELOCITY))
_ACC = (1.0, float(MAX_ACCELERATION))
_POS = (float(POSITION_MIN), float(POSITION_MAX))
_SPAN = (float(POSITION_MIN) * 2, float(POSITION_MAX) * 2)

_SPECS: list[CommandSpec] = [
    # ---- axis and mode selection ------------------------------------------------------
    *[
        CommandSpec(
            f"A{letter}", "mode", f"Single-axis mode on axis {letter}: later commands address it.",
            Timing.MODE, source="evidence 2.1; manual Appendix C",
            notes="An axis letter the model does not have is a command error and leaves the "
            "mode unchanged.",
        )
        for letter in "XYZTUVRSWK"
    ],
    CommandSpec(
        "AA", "mode", "All-axes mode: one comma-separated operand per axis; GO starts every "
        "axis together.", Timing.MODE, source="evidence 2.1; manual Appendix C",
        notes="A queued GO in AA mode waits until every axis's queue reaches it, then starts "
        "all programmed axes on the same tick (decision D for the barrier mechanism).",
    ),
    CommandSpec(
        "AM", "mode", "Multitasking mode: comma lists like AA, but each axis runs its own queue.",
        Timing.MODE, source="evidence 2.1",
    ),
    # ---- motion parameters ------------------------------------------------------------
    _q("VL", "motion", "Peak (slew) velocity, steps/s.", units=2,
       integer=False, operand=Operand.NUMBER,
       value_range=(1.0, float(MAX_VELOCITY)), source="manual 2.14 (factory 200,000); evidence 2.2",
       notes="Range 1..4,176,000 (Appendix C): VL0 is refused. VL and VB are checked as a "
       "pair when a move uses them (GO, MA/MR GO, GP, TM, a home search), not when either "
       "is set (D, issue 40: the EPICS motor record sends `VL4000 VB400` after a move at "
       "VB5000, and its own check compares with the new VB; nothing in the manual makes "
       "the firmware refuse VL alone). A move with VB not below VL is a command error "
       "('VB5000 is not below VL4000') and does not start (evidence: 'OMS errors if "
       "VB = VL', I).", user_units=True),
    _q("VB", "motion", "Base (start/stop) velocity, steps/s.", units=2,
       integer=False, operand=Operand.NUMBER,
       value_range=_VEL, source="manual 2.14 (factory 0); evidence 2.2",
       notes="Must be below VL when a move uses the pair (see VL): set alone it is only "
       "range-checked (D, issue 40).", user_units=True),
    _q("AC", "motion", "Acceleration, steps/s^2; also sets the deceleration.", units=2,
       integer=False, operand=Operand.NUMBER, value_range=_ACC,
       source="manual 2.14 (factory 2,000,000); evidence 2.2",
       confidence="I", notes="AC sets both rates and DC afterwards overrides the deceleration "
       "(SySal sends AC then DC). Range 1..8,000,000: hosts clamp to 1 (DLL-H).",
       user_units=True, applied_at_stop=True),
    _q("DC", "motion", "Deceleration, steps/s^2.", units=2, integer=False, operand=Operand.NUMBER,
       value_range=_ACC, source="evidence 2.2 (SySal usage)", confidence="I",
    user_units=True, applied_at_stop=True),
    _q("LA", "profile", "Linear ramps: trapezoid, or triangle on short moves (factory).",
       source="evidence 2.7 (DLL SelectOmsLinearRamp)", confidence="I"),
    _q("PN", "profile", "Parabolic ramps: acceleration highest at low speed; PN# sets the "
       "curve's degree.", units=2,
       operand=Operand.NUMBER, operand_optional=True, value_range=(0.0, 8.0),
       source="evidence 2.7 (DLL SelectOmsParabolicRamp(n) sends PN#)", confidence="D",
       notes="The mnemonic is I (the DLL's parabolic selection); the operand's meaning is in "
       "no source (facts item 11) and is our decision (D): the degree n of the velocity "
       "curve 1 - (1 - u)^n over the ramp, so the acceleration starts at its peak AC and "
       "falls to 0 at the top speed; the ramp lasts n times as long as a linear one. PN0 "
       "gives the factory curve (n = 2, the square) and a bare PN keeps the degree last set "
       "(factory 0); PN1 is linear, up to PN8; a degree above 8 is a command error. "
       "Deceleration ramps are the mirror image in time."),
    _q("PF", "profile", "Parabolic ramps off: back to linear.", source="evidence 2.7",
       confidence="I"),
    _q("SC", "profile", "S-curve ramps: jerk-limited, acceleration peaks mid-ramp.",
       source="evidence 2.7 (DLL SelectOmsSCurveRamp)", confidence="I"),
    _q("SS", "profile", "S-curve jerk share of acceleration ramps, percent (the manual's "
       "'4 quadrant jerk': SS sets the two corners of speeding up).", units=2,
       operand=Operand.NUMBER, value_range=(0.0, 100.0),
       source="evidence 2.7 (DLL SelectOmsSCurveRamp(n) sends AXSS#); manual specifications "
       "('S-Curve with 4quadrant jerk parameters')", confidence="D",
       notes="The mnemonic is I (sent with the DLL's S-curve selection); the operand's meaning "
       "is in no source (facts item 11) and is our decision (D): the percentage of each "
       "S-curve acceleration ramp during which the acceleration changes (half rising at the "
       "start, half falling at the end), the rest at the constant peak AC. SS100, and SS0 "
       "(factory), give the full S (acceleration peaks mid-ramp); smaller values tend to the "
       "linear ramp (SS1). Above 100 is a command error. Acts on SC ramps only."),
    _q("PR", "profile", "S-curve jerk share of deceleration ramps, percent (the other two "
       "of the '4 quadrant jerk' corners).",
       units=2, operand=Operand.NUMBER, value_range=(0.0, 100.0),
       source="evidence 2.7 (DLL SelectOmsSCurveRamp(n) sends AXPR#)", confidence="D",
       notes="The mnemonic is I; its meaning is our decision (D), as SS: the percentage of "
       "each S-curve deceleration ramp (slowing down, stops, reversals) during which the "
       "deceleration changes. PR0 (factory) follows SS, so SS alone shapes both (the DLL's "
       "SelectOmsSCurveRamp(n) sends both, presumably with the same n). Above 100 is a "
       "command error. Acts on SC ramps only."),
    _q("CN", "profile", "Cosine ramps.", source="evidence 2.7 (DLL SelectOmsCosineRamp)",
       confidence="I"),
    # ---- moves ------------------------------------------------------------------------
    _q("MA", "motion", "Prepare a move to an absolute position; GO starts it.", units=2,

       integer=False, operand=Operand.NUMBER, value_range=_POS,
       source="evidence 2.2; manual Appendix C",
       notes="Positions are signed 32-bit; a target outside +/-2,147,483,647 is a command error.",
       user_units=True),
    _q("MR", "motion", "Prepare a relative move; GO starts it.", units=2,
       integer=False, operand=Operand.NUMBER,
       value_range=_SPAN, source="evidence 2.2",
       notes="Decimals truncate toward zero (MR-200.9 moves -200): classic EPICS sends "
       "n.9 for a move of n steps (decision D). A resulting target outside the 32-bit range is "
       "a command error when it executes.", user_units=True),
    _q("MT", "motion", "Linear move to absolute positions: the axes move on a straight line and "
       "arrive together; GO starts it.", units=2,
       integer=False, operand=Operand.NUMBER, modes=LIST_MODES,
       value_range=_POS, source="manual Appendix C (AM; ... MT1000,2000,3000; GO; ID;); "
       "evidence 2.2 (DLL AAMT/AMMT)",
       notes="AA/AM only: a command error in single-axis mode. One reference profile for the "
       "longest distance, scaled per axis: each axis stays within its own VL/AC/DC/VB and all "
       "end on the same tick, exactly on target; the ramp shape is the first axis's (D). In AM "
       "mode the move starts when every axis in it has reached its GO.",
       user_units=True, start=Start.LINEAR_ABSOLUTE),
    _q("ML", "motion", "Linear move by relative distances (see MT).", units=2,
       integer=False, operand=Operand.NUMBER, modes=LIST_MODES, value_range=_SPAN,
       source="evidence 2.2 (DLL AAML/AMML)", confidence="I", notes="As MT, relative.",
       user_units=True, start=Start.LINEAR_RELATIVE),
    _q("GO", "motion", "Start the prepared move(s): ramp up, slew, ramp down.", units=4,
       source="evidence 2.2; manual 6.2 (GO expands into start, ramp up, slew, ramp down)",
       notes="Costs 4 units (its expansion). The queue waits for the axis to be at rest, starts "
       "the move, and holds the next entry until the move ends. Without a prepared move GO does "
       "nothing (D).", start=Start.GO),
    _q("GD", "motion", "Go, as used by classic EPICS and the vendor DLL (MA#;GDID).", units=4,
       source="evidence 2.2", confidence="I",
       notes="The difference to GO is not recovered; modelled exactly as GO.", start=Start.GO),
    _q("GN", "motion", "Go, as used by the VIPER MAXv client.", units=4, source="evidence 2.2",
       confidence="I", notes="Modelled exactly as GO.", start=Start.GO),
    _q("JG", "motion", "Jog at a signed velocity until stopped (no GO needed).", units=2,

       integer=False, operand=Operand.NUMBER, value_range=(-float(MAX_VELOCITY),
       float(MAX_VELOCITY)),
       source="evidence 2.2, E4",
       notes="Ramps from the present velocity (through zero when reversing) and slews. The queue "
       "holds the next entry until the new speed is reached, so `JG0 ID` sets done at rest (D).",
       user_units=True),
    _q("MP", "motion", "Direction logic plus: MO steps forward.", source="evidence 2.2",
       confidence="I"),
    _q("MM", "motion", "Direction logic minus: MO steps backward.", source="evidence 2.2",
       confidence="I"),
    _q("MO", "motion", "Move one step in the MP/MM direction.", source="evidence 2.2 (DLL)",
       confidence="I", notes="Waits for rest, then steps once; the next entry runs a tick later."),
    _i("ST", "motion", "Stop with deceleration and flush the queue.",
       source="evidence 2.2, E4 (`AX AC200000; ST ID;`)", confidence="I",
       notes="Immediate: it acts on a running move. It flushes the queue, applying first any "
       "AC/DC still waiting there, so `AX AC200000; ST ID;` stops at 200000 (D). Entries "
       "queued after it wait until the axis is at rest: `ST ID` sets done when stopped. "
       "AA/AM: all axes."),
    _i("SA", "motion", "Stop all axes with deceleration, flushing every queue.",
       source="evidence 2.2, E1 (`AM SA;`)"),
    _i("KL", "motion", "Kill all motion at once, no deceleration; flush every queue.",
       source="evidence 2.2 (direct command 'kill all motion')", confidence="I"),
    _i("KS", "motion", "Kill selected axes at once and flush their queues (`KS1,,1`).",
       operand=Operand.NUMBER, operand_optional=True, value_range=(0.0, 1.0),
       source="evidence 2.2 (TRAJ comment)",
       notes="Single-axis mode: KS (or KS1) kills the addressed axis, KS0 nothing. AA/AM: a 1 "
       "in an axis's slot kills it; a bare KS is refused (D)."),
    _q("LP", "position", "Load position: motor and encoder counters.", units=2,
       integer=False, operand=Operand.NUMBER, value_range=_POS, source="evidence 2.3, E4",
    user_units=True),
    _q("LO", "position", "Load the motor (commanded) position only.", units=2,

       integer=False, operand=Operand.NUMBER, value_range=_POS, source="evidence 2.3, E3",
       confidence="I", user_units=True),
    _q("LPE", "position", "Load the encoder position only.", units=2,
       integer=False, operand=Operand.NUMBER,
       value_range=_POS, source="evidence 2.3, E4",
       notes="Open-loop axes read an ideal encoder that follows the motor; LPE offsets it, so "
       "RE then differs from RP by the loaded amount.", user_units=True),
    _q("WT", "queue", "Wait a number of update cycles before the next queued command.",
       units=2, operand=Operand.NUMBER, value_range=(0.0, 2_147_483_647.0),
       source="evidence 2.2, E8 (SySal); SySal OmsMAX.cpp (`WT%d` of wait-ms x the update "
       "cycles per ms it reads from ?UR)", confidence="I",
       notes="Update cycles (ticks at the present #UR rate), as the one MAXk host that sends "
       "WT computes its operand: WT8192 is one second at the factory 8192 Hz."),
    _q("ID", "queue", "Set the axis done flag when the queue reaches this entry.",
       source="evidence 2.2, 3.6; E3, E4",
       notes="Sets the done bit in QA/RA/RI/QI, the doorbell (bits 0-7, 25/26 for W/K) and "
       "raises a flag notification."),
    _i("CA", "queue", "Clear the done flag of the addressed axis (or all in AA/AM).",
       source="evidence 2.2 (drvMAXv: 'Clear done of addressed axis')", confidence="I",
       notes="Immediate (D): hosts send it ahead of a move so an old done is not seen."),
    _i("IC", "queue", "Interrupt clear: clears the command error and every done, overtravel "
       "and slip flag.", source="evidence 2.2 (first command at every init)", confidence="I"),
    _i("FL", "queue", "Flush the addressed axis queue(s); a running move continues.",
       source="evidence 2.2 (manual type C, MAN-CMD p.1-86)"),
    _q("LS", "queue", "Loop start: repeat the entries up to LE # times (loops nest).", units=2,
       operand=Operand.NUMBER, value_range=(1.0, 2_147_483_647.0), source="manual 6.2",
       notes="Entries inside a loop keep their queue units until the outermost loop ends (an "
       "LS never closed by LE keeps them until a flush)."),
    _q("LE", "queue", "Loop end: jump back to the latest LS until its count runs out.",
       source="manual 6.2", notes="Each jump back takes one update cycle (D), so no loop "
       "spins within a tick. An LE without an open LS does nothing (D)."),
    # ---- homing -----------------------------------------------------------------------
    _q("HM", "homing", "Home forward: search for home, load the counter with # (0) there.",
       units=2, operand=Operand.NUMBER, operand_optional=True, value_range=_POS,
       source="evidence 2.3, E4, E5; manual 4.3, 4.8, Appendix C (HM0)",
       notes="The search is documented in docs/homing.md: jog at VL toward home, load the "
       "counter and the encoder counter (D; on a PSO axis its ideal encoder, so RE stays "
       "equal to RP) on the update cycle home is seen, "
       "ramp to a stop at DC. Already on home: "
       "found at once. A limit stops it (overtravel) and home is not found. The queue holds "
       "the next entry until the axis is at rest."),
    _q("HR", "homing", "Home reverse: as HM, searching in the minus direction.", units=2,
       operand=Operand.NUMBER, operand_optional=True, value_range=_POS,
       source="evidence 2.3, E4, E5"),
    _q("KM", "homing", "Find home forward without resetting the position counter.", units=2,
       operand=Operand.NUMBER, operand_optional=True, value_range=_POS,
       source="evidence 2.3 (VIPER comment)", confidence="I",
       notes="An operand is accepted (the evidence shows one) but has no known meaning and is "
       "not used."),
    _q("KR", "homing", "Find home in reverse without resetting the position counter.",
       units=2, operand=Operand.NUMBER, operand_optional=True, value_range=_POS,
       source="evidence 2.3", confidence="I", notes="As KM."),
    _q("HS", "homing", "Home on the home switch alone (factory).", source="evidence 2.3 (DLL "
       "HomeOmsAxis*UseSwitch sends HSHM#); manual 4.8"),
    _q("HE", "homing", "Home on the encoder logic: Phase +A * Phase -B * Index * Home switch.",
       source="evidence 2.3 (DLL ...UseEncoder sends HEHM#); manual 4.8",
       notes="Each term is selected by the EH pattern; the quadrant is x4 count mod 4 = 0 "
       "(A high, B low)."),
    _q("HI", "homing", "Home Encoder mode on (HI, HI1) or off (HI0), the manual's 'HI' mode.",
       operand=Operand.NUMBER, operand_optional=True, value_range=(0.0, 1.0),
       source="manual 4.8 ('Home Encoder (HI) mode'); evidence 2.4 (MXA `HI1 EH1111`)",
       confidence="I", notes="Modelled as HE (HI, HI1) and HS (HI0)."),
    _q("HT", "homing", "Home switch true level: H active high, L active low (factory L).",
       operand=Operand.LETTER, letters="HL", query=True, reply="=l | =h",
       source="evidence 2.3 (VIPER HTH); manual 2.14 (Home Active 'Low')", confidence="I",
       notes="Stored and reported by HT?. Switches are taken to be wired to match the level, "
       "so it changes neither where home is nor what QA's H and the home word show (D)."),
    _q("HH", "homing", "Home switch active high (same as HTH).", source="evidence 2.3 (DLL "
       "DefineOmsHomeAsSwitchClosed)", confidence="I"),
    _q("HL", "homing", "Home switch active low (same as HTL).", source="evidence 2.3",
       confidence="I"),
    CommandSpec("EH", "homing", "Encoder home pattern: +A, -B, Index, Home (1 true, 0 false, "
                "X ignored).", Timing.QUEUED, units=2, operand=Operand.PATTERN, letters="01X",
                source="manual 4.8 (HT and EH create patterns); evidence 2.4 (MXA EH1111)",
                confidence="D", notes="Factory EH1111 is the manual's default logic. The "
                "digit meanings and X for 'ignore' are our decision."),
    # ---- general purpose I/O, aux and analog -------------------------------------------
    _q("BD", "io", "Bit direction: hex mask of the 16 I/O bits, 1 = output (factory ff00).",
       operand=Operand.HEX, per_axis=False, value_range=(0.0, 65535.0),
       source="evidence 2.6 (BD0001, BDff00; DLL BD%X); manual 4.4", confidence="I",
       notes="Lines per model (Table 6-2): 16 from six axes up, 8 on five or fewer, 6 on "
       "the MAXk-2000; bits for lines the model lacks are ignored (hosts send 16-bit words, "
       "D). Factory: the lower half inputs, the upper half outputs (16 lines: ff00; 8: "
       "00f0; 6: 0038; the manual says 8 and 8, not which; D). "
       "I/O commands are queued on the addressed axis in single-axis mode (so they switch in "
       "step with its moves) and act at once in AA/AM mode (D)."),
    _q("BH", "io", "Set output bit # high.", units=2, operand=Operand.NUMBER, per_axis=False,
       value_range=(0.0, 15.0), source="evidence 2.6 (TRAJ, VIPER, DLL BH#)",
       notes="A bit configured as an input is a command error; so is a line the model "
       "does not have (Table 6-2), as for BL, IO, SW and BW."),
    _q("BL", "io", "Set output bit # low.", units=2, operand=Operand.NUMBER, per_axis=False,
       value_range=(0.0, 15.0), source="evidence 2.6"),
    _q("BS", "io", "Set every output bit from a hex word (input bits are left alone).",
       units=2, operand=Operand.HEX, per_axis=False, value_range=(0.0, 65535.0),
       source="evidence 2.6 (DLL SetAllOmsIOBits BS%X)", confidence="I"),
    _q("IO", "io", "Configure bit # as an input (0) or an output (1): IO5,0.", units=3,
       operand=Operand.NUMBER, per_axis=False, arity=2, value_range=(0.0, 15.0),
       source="evidence 2.6 (TRAJ IO5,0)", notes="The second operand must be 0 or 1."),
    _i("BX", "io", "Report the 16 I/O bit levels as 4 hex digits.", reply="00ff",
       source="evidence 2.5, E9 (TRAJ reads 4 hex digits; DLL %x)"),
    _i("RB", "io", "Report the I/O bit directions as 4 hex digits (1 = output).",
       reply="ff00", source="evidence 2.5 (VME58 RB, DLL AXRB)", confidence="I"),
    _q("SW", "io", "Queue waits until input bit # reads high.", units=2,
       operand=Operand.NUMBER, value_range=(0.0, 15.0), source="evidence 2.2 (TRAJ start "
       "trigger `A<x>; SW<bit>;`); manual 4.4", confidence="I",
       notes="Per axis (a list in AA/AM). 'High' rather than 'active' is our reading (D)."),
    _q("AN", "aux", "Aux output of the axis on; in AA/AM a list flags the axes (AN,,,1,1).",
       operand=Operand.NUMBER, operand_optional=True, value_range=(0.0, 1.0),
       source="evidence 2.6 (DLL AXAN, AMAN); facts Table 2 (NMSU `aa an,,,1,1,1;`)",
       confidence="I", notes="Bare: the addressed axis (every axis in AA/AM). With a list, "
       "a 1 switches that axis, a 0 or an empty slot leaves it alone."),
    _q("AF", "aux", "Aux output of the axis off; in AA/AM a list flags the axes (AF1,1,1).",
       operand=Operand.NUMBER, operand_optional=True, value_range=(0.0, 1.0),
       source="evidence 2.6; facts Table 2 (NMSU `aa af1,1,1,1,1,1;`)", confidence="I",
       notes="As AN."),
    CommandSpec("PA", "aux", "Automatic aux output: 1 on (on while moving, off SE ms after), "
                "0 off.", Timing.QUEUED, units=1, operand=Operand.LETTER, letters="01",
                source="evidence 2.6 (DLL EnableOmsAxisAuxOutAutoMode AXPA1/AXPA0)",
                confidence="I", notes="The exact automatic behaviour is our decision (D): on "
                "when a motion starts, off SE# milliseconds after the axis comes to rest."),
    _q("SE", "aux", "Aux output settle time, milliseconds (automatic mode).", units=2,
       operand=Operand.NUMBER, value_range=(0.0, 65535.0),
       source="evidence 2.6 (DLL SetOmsAxisAuxOutSettleTime AXSE#)", confidence="I"),
    _i("AB?", "aux", "Query the aux output: =h on, =l off.", reply="=h | =l",
       source="evidence 2.6 (VIPER `A<x> AB?`)", confidence="I"),
    _i("AI", "analog", "Report analog input # (0-3) as a signed 16-bit count (+/-10 V).",
       operand=Operand.NUMBER, per_axis=False, value_range=(0.0, 3.0), reply="16384",
       source="manual 4.5.1 (names AI); no host evidence", confidence="D",
       notes="Inputs 0-3 from six axes up, 0-1 on five or fewer (Table 6-2): another "
       "channel is a command error, as for VOA. "
       "The reply format is our decision: the 16-bit two's-complement count, -32768 "
       "at -10 V, 1 count = 10/32768 V, clipping at 32767."),
    _q("AO", "analog", "Set the axis's DAC as a general purpose analog output (count).",
       units=2, operand=Operand.NUMBER, value_range=(-32768.0, 32767.0),
       source="manual 4.5.2 (names AO; a DAC per axis not used by a servo)", confidence="D",
       notes="Counts -32768..32767 for -10..+10 V. Refused on a servo axis (D)."),
    # ---- configuration ----------------------------------------------------------------
    _q("PS", "config", "Axis type: O open-loop stepper, E stepper with encoder, M servo.",
       operand=Operand.LETTER, letters="OEM", query=True, reply="=O | =E | =M",
       source="evidence 2.4, E1",
       notes="PS? answers immediately. The type changes when the axis is at rest; RP and RE "
       "carry on from where they were. PSM: the servo loop (open until CL1/HN), RP is the "
       "commanded position and RE the motor's encoder; PSE: a stepper with an encoder (EA, "
       "ER, slip detection, position maintenance)."),
    _i("?PS", "config", "Axis type query, firmware before 1.30.", reply="=O | =E | =M",
       source="evidence 2.4"),
    _q("LT", "limits", "Limit input true level: H active high, L active low (factory L).",
       operand=Operand.LETTER, letters="HL", query=True, reply="=l | =h",
       source="evidence 2.3, E1; manual 2.14"),
    _i("?LS", "limits", "Limit level query, firmware before 1.30.", reply="=l | =h",
       source="evidence 2.3"),
    _q("LH", "limits", "Limit switches active high (same as LTH).", source="evidence 2.3",
       confidence="I"),
    _q("LL", "limits", "Limit switches active low (same as LTL).", source="evidence 2.3",
       confidence="I"),
    _q("LM", "limits", "Limit mode: H stop at once (hard), S decelerate (soft), F off, N on.",
       operand=Operand.LETTER, letters="HSFN", query=True, reply="=h | =s | =f",
       source="evidence 2.3, E5; manual 4.2 and 2.14 (factory hard, enabled)", confidence="I",
       notes="LM? answers =f when limits are off, else =h or =s for the stop style; LMN turns "
       "limits on with the last style. The letters S and the LM? letters other than f are our "
       "decision (D). A limit trip in the hard style (factory) flushes the axis queue: "
       "the asyn driver allows for an ID that never comes after a limit stop (evidence "
       "3.6); in the soft style the rest of the queue runs after the stop, as TALON's PC39 "
       "homing string needs (facts Table 2; D for the MAXk)."),
    _q("SL", "limits", "Soft limits: decelerate to a stop when a limit trips (LMS's style).",
       source="manual 2.14 ('Over travel limit (soft limit or hard limit); Factory Default = "
       "Hard limit'); evidence 2.3 (DLL SetOmsSoftLimitsMode)", confidence="I",
       notes="Read as the manual's soft/hard limit choice, not software travel bounds: no "
       "command for bounds appears in the manual or the host code (docs/not-modelled.md). "
       "Unlike LMS it does not turn limit checking on (LN does)."),
    _q("SF", "limits", "Soft limits off: stop at once when a limit trips (factory, LMH's "
       "style).",
       source="manual 2.14; evidence 2.3", confidence="I"),
    _q("LN", "limits", "Limit (overtravel) detection on.", source="evidence 2.3",
       confidence="I"),
    _q("LF", "limits", "Limit (overtravel) detection off.", source="evidence 2.3",
       confidence="I"),
    CommandSpec("CL", "servo", "Closed loop on (1) or off (0); CL? reports per axis.",
                Timing.QUEUED, units=1, operand=Operand.LETTER, letters="01", query=True,
                reply="on | off", source="evidence 2.4, E4; manual 2.13", confidence="I",
                notes="Servo (PSM): CL1 runs the PID, CL0 opens the loop (the DAC puts out KO, "
                "as in the manual's balancing steps). A PSM axis starts open (D). CL1 also "
                "re-enables the PID after a following-error trip; `LP0;CL1;` zeroes the error "
                "first, as the manual does. On an encoder stepper (PSE) CL1/CL0 switch "
                "position maintenance, like HN/HF; on an open-loop stepper (PSO) they are "
                "accepted and do "
                "nothing (D): the manual's Appendix C sends CL1 to a factory (PSO) board, "
                "VIPER sends `AX CL0;` and the DLL `AXHN`/`AXHF` to every axis, and none "
                "expects an error. CL? answers off there. CL? answers on/off (EPICS compares "
                "the first two characters)."),
    _i("?PM", "servo", "Closed-loop query, firmware before 1.30.", reply="=on | =off",
       source="evidence 2.4", confidence="I"),
    _i("?KA", "servo", "PID present probe: a command error means the axis has no servo loop.",
       reply="2.5", source="evidence 2.4, E5",
       notes="On a servo axis it answers the KA gain as a plain decimal (the reply format is "
       "our decision, D: drivers flush it unread)."),
    _i("?KP", "servo", "PID present probe (PC68 form): the KP gain, or a command error.",
       reply="10", source="evidence 2.4, E7", confidence="I"),
    *[
        _q(m, "servo", summary, units=2, operand=Operand.NUMBER, integer=False,
           value_range=(-32767.0, 32767.0) if m == "KO" else (0.0, 32767.0),
           source=source, confidence=confidence, notes=notes)
        for m, summary, source, confidence, notes in (
            ("KP", "Proportional gain: DAC counts per count of position error.",
             "manual 2.13 (range 0..32767, factory 10); evidence 2.4, E4", "C",
             "DAC = KP*e + KD*(e - e_prev) + KI/1024*sum(e) + KV*v + KA*a + KF*sign(v) + KO, "
             "every tick; e in counts, v/a in counts per tick (and tick^2); the scaling is our "
             "decision (D), chosen so the factory gains hold the default motor."),
            ("KI", "Integral gain: acts on the sum of the errors / 1024.",
             "manual 2.13 (range 0..32767, factory 1.00)", "C",
             "The error sum is clamped so the integral term stays within 4*KU DAC counts; it "
             "only accumulates while KI > 0, and errors under 1/1000 count are not summed "
             "while static friction holds the motor (D)."),
            ("KD", "Derivative gain: acts on the change of error per tick (damping).",
             "manual 2.13 (range 0..32767, factory 160)", "C", ""),
            ("KU", "Integral limit: the integral term never exceeds 4*KU DAC counts.",
             "manual 2.13 ('KU limits the amount the KI term can contribute')", "I",
             "Factory 1000 (the manual lists no factory KU: our decision, D)."),
            ("KV", "Velocity feed-forward: DAC counts per count/tick of commanded velocity.",
             "manual 2.13 (range 0..32767, factory 0)", "C", ""),
            ("KA", "Acceleration feed-forward: DAC counts per count/tick^2 of commanded "
             "acceleration.", "manual 2.13 (factory 0); evidence 2.4 (VIPER KA2.0)", "C", ""),
            ("KF", "Friction feed-forward: DAC counts added in the direction of commanded "
             "motion.", "manual 2.13 (range 0..32767)", "C", ""),
            ("KO", "Offset: constant DAC output (3277 = 1 V), open loop or closed.",
             "manual 2.9, 2.13 (range -32767..32767, factory 0)", "C",
             "With the loop open (CL0) the DAC puts out KO alone."),
        )
    ],
    _q("SVB", "servo", "Servo output: SVB1 bipolar +/-10 V (factory), SVB0 unipolar 0..10 V.",
       units=2, operand=Operand.NUMBER, value_range=(0.0, 1.0),
       source="evidence 2.4 (VIPER `PSM SVB1`, SySal); manual 2.14 (factory bipolar)",
       confidence="I", notes="Unipolar puts the magnitude on the DAC and the sign on the "
       "direction output, so the motor sees the same command; it changes the reported DAC "
       "voltage only (D)."),
    _q("SVN", "servo", "Servo output polarity normal (factory).",
       source="evidence 2.4 (SySal `SVB1;SVN;PSM`)", confidence="D",
       notes="Read as the normal polarity of SVP+/SVP-; the evidence only shows it sent."),
    _q("SVP", "servo", "Servo output polarity: SVP- inverts the PID output (and KO), SVP+ "
       "normal.", operand=Operand.LETTER, letters="+-", source="manual 2.9 step 5",
       notes="Inverting the output of a motor that was wired right makes the loop run away "
       "until the following-error trip, as a real one does."),
    CommandSpec("ER", "encoder", "Encoder ratio: encoder counts, motor steps (ER4000,1000).",
                Timing.QUEUED, units=3, operand=Operand.NUMBER, per_axis=False, arity=2,
                modes=frozenset({SINGLE}), value_range=(1.0, 2_147_483_647.0),
                source="evidence 2.4 (README: encoder mode); EPICS devOmsCom.cc (ER enc,mot)",
                confidence="I",
                notes="On an encoder stepper (PSE) a ratio other than 1:1 is encoder mode: MA, "
                "MR, JG, VL, VB, AC, DC and HV take encoder counts, converted to the nearest "
                "motor step. RP, LP, LO and RV/RC stay in motor steps, RE/LPE in encoder "
                "counts (D: the reports are not settled by the evidence; EPICS's asyn driver "
                "reads RE and loads LO with RE/ratio, which fits). ER1,1 undoes it. "
                "Single-axis mode only (the DLL sends AXER#,#)."),
    _q("ES", "encoder", "Encoder slip tolerance, encoder counts (factory 0).", units=2,
       operand=Operand.NUMBER, value_range=(0.0, 2_147_483_647.0),
       source="evidence 2.4 (VIPER `ES# TN`); manual 2.14", confidence="I",
       notes="With TN, a disagreement of more than ES counts between the motor counter and "
       "the encoder (measured from where they last agreed: LP, LO, LPE, ER, PS, home) "
       "is a stall."),
    _q("TN", "encoder", "Stall (slip) detection on: a slip stops the axis at once, flushes "
       "its queue and sets the slip flag.", source="evidence 2.4 (VIPER)", confidence="I",
       notes="The stop (kill and flush, as a hard limit) is our decision (D); the flag is "
       "doorbell bit 16+i and EA's 'S'."),
    _q("TF", "encoder", "Stall (slip) detection off (factory).", source="evidence 2.4",
       confidence="I"),
    _q("IS", "encoder", "Slip detection on (the DLL's EnableOmsSlipDetection sends AXIS).",
       source="evidence 2.4 (DLL-BIN)", confidence="I", notes="Modelled as TN."),
    _q("HV", "encoder", "Position maintenance hold velocity (0: the axis's VL).", units=2,
       integer=False, operand=Operand.NUMBER, value_range=(0.0, float(MAX_VELOCITY)),
       source="evidence 2.4 (VIPER `HV# HD# HG# HN`); manual 2.14", confidence="I",
       user_units=True),
    _q("HD", "encoder", "Position maintenance deadband, encoder counts.", units=2,
       operand=Operand.NUMBER, value_range=(0.0, 32767.0),
       source="evidence 2.4; manual 2.14", confidence="I"),
    _q("HG", "encoder", "Position maintenance hold gain.", units=2, operand=Operand.NUMBER,
       value_range=(0.0, 32767.0), source="evidence 2.4; manual 2.14", confidence="I",
       notes="Stored (and archived by APP) only: a correction runs at HV, not at a speed "
       "scaled by HG, since no source says how the gain acts (docs/not-modelled.md)."),
    _q("UU", "units", "User units on: operands of moves, positions, velocities and "
       "accelerations are in user units (counts per unit = #), fixed point ##.#.", units=2,
       operand=Operand.NUMBER, integer=False, value_range=(1e-6, 1e9),
       source="evidence 1.3, 2.4 (MAN-CMD: fixed point ##.# with UU; classic EPICS sends "
       "`UU%f`, `UF`); manual 2.14 (archived, factory off)", confidence="I",
       notes="MA MR MT ML JG VL VB AC DC LP LO LPE HV take user units, multiplied by the "
       "factor and rounded to the nearest count (in encoder mode, encoder counts, then "
       "steps: EPICS's `ER e,m; UU e/m` keeps the host in motor steps). Reports stay in "
       "counts (D). Ranges are checked on the scaled value, when it executes."),
    _q("UF", "units", "User units off (factory): operands are counts again.",
       source="evidence 2.4; manual 2.14", confidence="I"),
    _i("APP", "flash", "Save the working parameters as the power-up defaults (the archive).",
       source="manual 2.13, 2.14", confidence="C",
       notes="Immediate (D): it saves what is in effect when it arrives; parameters still "
       "waiting in a busy queue are not included. Saves every axis's manual-2.14 list "
       "(docs/flash.md). A failed write is a command error and sets firmware flag bit 13."),
    _i("RDP", "flash", "Restore the saved power-up defaults into working memory.",
       source="manual 2.14", confidence="C",
       notes="A command error (nothing changes) when nothing was saved or the archive is "
       "corrupted. Sets firmware flag bit 16 (and clears 18)."),
    _i("RDF", "flash", "Restore the factory defaults into working memory.",
       source="manual 2.14", confidence="C",
       notes="The archive is left as it is (APP afterwards makes them the power-up set). "
       "Sets firmware flag bit 18 (and clears 16)."),
    _q("HN", "servo", "Hold on: position maintenance on an encoder stepper; closes a servo's "
       "loop (pre-1.30 form of CL1).", source="evidence 2.4, E4; manual 2.13", confidence="I",
       notes="Position maintenance: at rest, when the encoder is more than HD counts from "
       "where the motor counter says it should be, the axis steps back at HV; the correction "
       "leaves RP unchanged. It waits while the queue has work. On a PSO axis (no encoder) "
       "it is accepted and does nothing, as CL (D)."),
    _q("HF", "servo", "Hold off: position maintenance off; opens a servo's loop (CL0).",
       source="evidence 2.4, E4", confidence="I",
       notes="Accepted on a PSO axis, where there is nothing to switch (D, as CL)."),
    _i("#UR", "config", "Update rate in Hz: 1024, 2048, 4096 or 8192 (976.6..122.1 us).",
       operand=Operand.NUMBER, query=True, value_range=(1024.0, 8192.0), reply="#UR?: 8192",
       source="evidence 2.5 (TRAJ); manual 2.13", confidence="I",
       notes="Setting it resets the position counters (TRAJ reloads LP afterwards). Refused "
       "unless every axis is idle, with nothing queued (D); virtual time stays continuous."),
    _i("?UR", "config", "Update rate query (SySal form).", reply="8192",
       source="evidence 2.5, E8", confidence="I"),
    # ---- reports ----------------------------------------------------------------------
    _i("RP", "report", "Report motor (commanded) position.", reply="-123 | AA/AM: 1,2,...",
       source="evidence 2.5, E1, E8"),
    _i("RE", "report", "Report encoder position.", reply="-123 | AA/AM: list",
       source="evidence 2.5, E3",
       notes="Open-loop steppers read an ideal encoder: RE equals RP unless LPE offset it."),
    _i("PP", "report", "Report every axis's motor position.", reply="1,2,3,...",
       source="evidence 2.5, E1, E2"),
    _i("PE", "report", "Report every axis's encoder position.", reply="1,2,3,...",
       source="evidence 2.5, E2"),
    _i("RV", "report", "Report the present velocity (0 at rest).", reply="5000 | list",
       source="evidence 2.5, E2", confidence="I",
       notes="Signed: negative while moving in the minus direction (D). The PC39 answers "
       "the magnitude only (facts Table 2, TALON); no MAX host reads RV's sign (asyn only "
       "tests RV = 0), so we keep the sign, which carries more."),
    _i("RC", "report", "Report the programmed acceleration.", reply="2000000 | list",
       source="evidence 2.5 (DLL GetOmsAxisAcceleration)", confidence="I"),
    _i("QA", "report", "Query axis status without clearing: direction, done, limit, home.",
       reply="PNNN", source="evidence 3.4; manual type Q",
       notes="Four characters: P|M, D|N, L|N, H|N. QA leaves the done flag set."),
    _i("RA", "report", "Report axis status, then clear its done, overtravel and slip flags.",
       reply="PDNN", source="evidence 3.4", confidence="I",
       notes="EPICS sends RA after a move to clear done (I); RA clears the latched flags "
       "after reporting them."),
    _i("RI", "report", "Report every axis's status, then clear the done flags.",
       reply="MDNN,PNNN,...", source="evidence 3.4, E2",
       notes="asyn: 'read all axis status values and reset done-field'. Groups of 4 characters "
       "separated by commas, no trailing comma."),
    _i("QI", "report", "Query every axis's status without clearing.", reply="MDNN,PNNN,...",
       source="evidence 3.4, E9", confidence="I"),
    _i("RQC", "report", "Report free command-queue units (of 2559).",
       reply=f"{QUEUE_CAPACITY} | list", source="evidence 2.5; manual 6.2"),
    _i("EA", "report", "Encoder status: slip enable, hold enable, slipped, in deadband, home.",
       reply="DDNNN", source="evidence 3.4, E2, E5",
       notes="A command error on an axis without an encoder (the classic `EA ID` probe). In "
       "AA/AM lists such axes get an empty field. The fifth letter is H while an index mark "
       "is under the encoder. Letters for 'disabled' (D) and 'not' (N) are our decision."),
    _i("QL", "report", "Query limit inputs (raw levels) as hexadecimal.", reply="ffff",
       source="evidence 3.4, E2",
       notes="Bit i = minus limit, bit i+8 = plus limit for X..S; W/K use bits 16/17 and 24/25. "
       "Raw levels: an inactive active-low input reads 1."),
    _i("WY", "report", "Identify the controller.",
       reply="MAXk-8000, ver:1.33, S/N: 000001, FPGA:20", source="manual 2.6; evidence 3.5",
       notes="The manual's form with `ver:` in lower case and no space: asyn looks for the "
       "case-sensitive `ver:` followed by major.minor (and needs 1.30+, 1.33+ for #WS), "
       "SySal for `MAXk-`, classic drvMAXv reads the number after the first colon."),
    _i("#WS", "report", "Watchdog status: =0 while healthy.", reply="=0",
       source="evidence 2.5, E1, E2"),
    # ---- vector contouring (docs/contouring.md) --------------------------------------
    _v("VA", "VA[n]#", "Vector acceleration for the segments that follow, counts/s^2.",
       value_range=_ACC, source="manual Appendix C; evidence 2.8 (TRAJ `VA[n]#`)",
       notes="Each segment keeps the VA in effect when it was defined: its speed changes at "
       "VA, and on arcs it stays at or below sqrt(VA x radius), so the centripetal "
       "acceleration stays within VA too (D). Before any VA, the first contour axis's AC "
       "(D)."),
    _v("VV", "VV[n][#,]#", "Vector velocity: start and end, or end only, counts/s.", arity=2,
       value_range=(0.0, MAX_VECTOR_VELOCITY), source="manual Appendix C (VV1000,1000 ... "
       "VV1000,0); evidence 2.8 (`VV[n]#`, `VV[n]#,#`)",
       notes="A segment's speed rises from where it is toward its end velocity at VA (or "
       "stays at its start velocity and falls at VA to reach a lower end velocity exactly "
       "at its end); it never exceeds max(start, end) x override. The start velocity is "
       "taken at once only where the path starts from rest (as a stepper takes its base "
       "velocity); elsewhere the speed is continuous. `VV#` sets the end and lets the start "
       "follow on from the previous end. Before any VV: the first axis's VL (D)."),
    _v("VP", "VP[n][A|R]#,#,...", "Vector position: a straight segment to these "
       "coordinates (one slot per axis; A absolute, R relative).",
       value_range=_POS, letters="AR", per_axis=True,
       source="manual Appendix C (VP0,0); evidence 2.8 (`VP[n]A,p1,p2,...`)",
       notes="The first VP of a contour names its axes (the filled slots; the addressed axis "
       "in single-axis mode) and takes one queue unit (its anchor) on each: the contour "
       "starts when every one of those queues reaches it and the axes are at rest (and after "
       "VG if VH0 held it). Later VP/VC hold one unit per axis until the path passes them. "
       "An empty slot keeps that axis where the path is; naming an axis outside the contour "
       "is a command error. Without A/R: absolute (the MAXk form). The first segment runs "
       "from wherever the axes stand (D)."),
    _v("VC", "VC[n]#,#,#", "Circular arc: centre of the contour's first two axes, then the "
       "angle in degrees (negative clockwise).", arity=3, value_range=_POS,
       source="manual Appendix C (VC0,5000,-180; VC0,0,-360)", confidence="D",
       notes="The arc runs in the plane of the contour's first two axes (X before Y ...) from "
       "where the path is; positive angles turn from the first axis toward the second. "
       "|angle| up to 3600 (whole circles close exactly); the centre is absolute. A contour "
       "must be opened by a VP naming at least two axes first."),
    _v("VE", "VE[n]", "End of the contour: no more segments.", arity=0,
       source="manual Appendix C; evidence 2.8 (`VE[n]`)",
       notes="The path always plans to stop at the end of the segments it knows; before VE "
       "it waits there for more (a host may stream segments while it runs), after VE the "
       "contour is finished when it stops there, and the axes' queues go on."),
    _v("VG", "VG[n]", "Start (or resume) task n's contour.", arity=0,
       notes="Clears a VH hold: a contour held before its start begins, one stopped by VH1 "
       "goes on from where it stopped. A contour not held starts by itself (the manual's "
       "example has no VG)."),
    _v("VH", "VH[n]#", "Hold: VH0 the next contour waits for VG; VH1 stop the running "
       "contour on its path.", value_range=(0.0, 1.0),
       notes="VH1 ramps the path down at VA without leaving it; VG resumes (D for the "
       "resume)."),
    _v("VID", "VID[n]#", "Done flag when the task finishes: VID1 on, VID0 off.",
       value_range=(0.0, 1.0),
       notes="With VID1 a contour clears its axes' done flags when it starts and sets them "
       "when it finishes (not when stopped), so QI reads N while it runs (D)."),
    _v("VIO", "VIO[n]hhhh,hhhh,hhhh", "Outputs at each following segment start: on bits, "
       "off bits, mask (hex).", arity=3, value_range=(0.0, 65535.0),
       source="manual Appendix C (VIO0100,,0100 ... VIO0,,0100); evidence 2.8",
       notes="At the start of every segment defined after it, the mask's bits take the on "
       "bits. With an off word (TRAJ sends one) it is a pulse: one update cycle later they "
       "take the off bits (D for the width). Without the mask: the bits named. VIO0,0,0 "
       "stops it. Bit n is I/O line n (the manual's text calls the example's 0100 'I/O7'; "
       "the trajectory scan computes the mask as 1<<bit, so we take 0100 as line 8). Bits for "
       "lines the model lacks are ignored (line 8 needs six axes or more, Table 6-2).",
       hex_operands=True),
    _v("VO", "VO[n]=#", "Velocity override, percent of the programmed vector velocity "
       "(0-200).", value_range=(0.0, OVERRIDE_MAX), confidence="C",
       source="manual Appendix C; evidence 2.8 (`VO[n]=100`)",
       notes="Changes speed along the path at VA, never leaving it. 0 holds the path at rest "
       "(the contour is not finished). Also `VO#`. Replaces a VOA input.", assign_form=True),
    _v("VOA", "VOA#[,#]", "Velocity override from analog input # (0-3): 0 V is 100%, the "
       "span (volts, default 5) either side reaches 0% and 200%.", arity=2,
       value_range=(0.0, 10.0), source="manual 4.5.1, Appendix C (VOA0,5)", confidence="D",
       notes="The operands' meaning is not in the sources: we read VOA0,5 as input 0 with a "
       "5 V span, so an unconnected input (0 V) runs the program as written and -5..+5 V "
       "give 0..200%. Read every update cycle."),
    _v("VRV", "VRV[n]", "Report the task's present vector velocity.", arity=0,
       reply="1000", notes="0 when not moving."),
    _v("VRC", "VRC[n]", "Report the task's vector acceleration (the present segment's VA).",
       arity=0, reply="2000000"),
    _i("SI", "queue", "Clear the queues of the flagged axes (`AM; SI1,,1;`).",
       operand=Operand.NUMBER, operand_optional=True, value_range=(0.0, 1.0),
       source="evidence 2.2 (TRAJ: 'clear motor queue')", confidence="I",
       notes="As FL for each axis with a 1 in its slot (single-axis mode: the addressed axis); "
       "a running contour on them ramps down on its path."),
    _i("CC", "report", "Controller cycle counter (update ticks since power-up, 30 bits).",
       reply="123456", source="evidence 2.5, E8 (SySal)", confidence="I",
       notes="Plain decimal, wrapping at 2^30 (SySal checks 0..0x3FFFFFFF)."),
    # ---- what host programs send beyond the above (issue 17: evidence + facts file) ---
    _i("SD", "motion", "Stop with deceleration (the VIPER MAXv client's stop: `AX SD ID`, "
       "`AA; SD; ID;`).", source="evidence 2.2, E10 (VIPER); facts Table 1 (QViper)",
       confidence="I", notes="Nothing tells it apart from ST, so it is ST: decelerate, flush "
       "the queue (a pending AC/DC acts first), later entries wait for rest, so `SD ID` "
       "sets done when stopped (facts: 'an alias of ST would serve every host seen')."),
    _q("JF", "motion", "Jog at a velocity that may have a fraction of a step/s "
       "(`JF500.600000`, `JF-00012.3456`).", units=2, integer=False, operand=Operand.NUMBER,
       value_range=(-float(MAX_VELOCITY), float(MAX_VELOCITY)),
       source="evidence 2.2 (DLL MoveOmsAxisFractional `AXJF%f;`); facts Table 1, J1-J4 "
       "(NMSU, TALON, GVO)", confidence="I",
       notes="As JG with the fraction kept: ramps from the present velocity (through zero "
       "when reversing) and slews; re-sent while running it changes the speed (tracking "
       "hosts resend it every update). Same range as JG (J2). Steps/s, not user units (D)."),
    _q("GP", "motion", "Go to an absolute position at VL at once (no GO): SySal's profile "
       "segment `VL#;GP#`.", units=4, integer=False, operand=Operand.NUMBER, value_range=_POS,
       source="evidence 2.2, E8 (SySal `;VL<v>;GP<p>;WT<w>`); SySal OmsMAX.cpp "
       "(a segment with IsPosition)", confidence="D",
       notes="Read as MA# and GO in one: it waits for the axis to be at rest, starts the "
       "move and holds the queue until it ends, so a following WT is a pause at the point."),
    _q("TM", "motion", "Timed move: run at VL for |#| update cycles in the direction of #'s "
       "sign (SySal's velocity segment `VL#;TM#`).", units=4, operand=Operand.NUMBER,
       value_range=(-2_147_483_647.0, 2_147_483_647.0),
       source="evidence 2.2, E8; SySal OmsMAX.cpp (`VL|v|;TM±wait`, wait = ms x update "
       "cycles per ms)", confidence="D",
       notes="Modelled as a relative move of the distance VL covers in |#| update cycles "
       "(ramps at AC/DC added), started at once; the queue holds until it ends."),
    _q("WTC", "queue", "Wait until the controller cycle counter (CC) reaches # "
       "(SySal's timed start `wtc<t>;GO;`).", units=2, operand=Operand.NUMBER,
       value_range=(0.0, float(0x3FFF_FFFF)),
       source="evidence 2.2, E8 (SySal `wtc%d;` before GO); SySal OmsMAX.cpp (t = ms x CC "
       "cycles per ms + the CC offset it measured)", confidence="I",
       notes="Holds the queue until CC (30 bits, wrapping) reaches #; a time up to half the "
       "counter's range in the past does not wait (D). Lower case `wtc` as sent."),
    _q("PH", "aux", "Aux (enable) output of the axis high (VIPER `AX PH`).",
       source="evidence 2.6, E10 (VIPER); facts Table 1", confidence="I",
       notes="The same line as AN (QViper drives it with BH instead)."),
    _q("PL", "aux", "Aux (enable) output of the axis low (VIPER `AX PL`).",
       source="evidence 2.6, E10 (VIPER)", confidence="I", notes="The same line as AF."),
    _i("WQ", "queue", "Hold the command parser until the addressed axis queue is empty "
       "(classic EPICS MAXv stop `AX FL AC200000; WQ ST ID;`).",
       source="evidence 2.2 (DEV-COM); facts Table 1 (TALON `st wq jg`), note 'WQ in the "
       "emulator'", confidence="I",
       notes="Nothing after WQ on this host's stream is acted on (immediate commands "
       "included) until the queue(s) it addresses hold no work (AA/AM: every axis); other "
       "hosts' streams go on. Replies of held queries come when they run. After FL the "
       "queue is empty, so `FL AC#; WQ ST` stops at the new rate."),
    _q("ECI", "encoder", "Encoder interface incremental (quadrature, factory).",
       source="evidence 2.4, E8 (SySal sends it on every MAXk axis)", confidence="I",
       notes="Undoes ECA/ECB."),
    CommandSpec("ECA", "encoder", "SSI absolute encoder: data bits, clock Hz "
                "(`AX; PSE; ECA12,125000;`).", Timing.QUEUED, units=3, operand=Operand.NUMBER,
                per_axis=False, arity=2, modes=frozenset({SINGLE}),
                value_range=(1.0, 4_000_000.0), source="manual 4.9, 4.9.1; Table 3-1 "
                "(absolute positions at 0x3520)", confidence="C",
                notes="Bits 1-32 (12 standard on X and Y, up to 32 on request: we accept 32 "
                "on any axis, as the manual's second example needs, D); the clock must be "
                "one of 31250, 62500, 125000, 250000, 500000, 1000000, 2000000, 4000000 Hz, "
                "else a command error. The setting is stored; the absolute encoder itself "
                "is not modelled (docs/not-modelled.md)."),
    CommandSpec("ECB", "encoder", "Serial (BiSS-type) absolute encoder: data bits, clock Hz "
                "(MXA `ECB32,500000`).", Timing.QUEUED, units=3, operand=Operand.NUMBER,
                per_axis=False, arity=2, modes=frozenset({SINGLE}),
                value_range=(1.0, 4_000_000.0), source="evidence 2.4 (ASYN-MXA MXA.cmd)",
                confidence="I", notes="Checked and stored as ECA (BiSS rather than SSI is "
                "a guess from the name, facts Table 1)."),
    _q("EDI", "encoder", "Encoder direction inverted.", source="manual 2.9 step 5d-i",
       confidence="C", notes="Stored (factory EDN); the inversion of the count is not "
       "modelled (docs/not-modelled.md): the model's encoders always count with the motor."),
    _q("EDN", "encoder", "Encoder direction normal (factory).", source="manual 2.9 step 5d-i",
       confidence="C", notes="As EDI."),
    _q("KOD", "servo", "Second servo offset term (the manual: SVP- inverts 'KO and KOD').",
       units=2, operand=Operand.NUMBER, integer=False, value_range=(-32767.0, 32767.0),
       source="manual 2.9 step 5d-ii", confidence="D",
       notes="Only its existence is known: stored, not added to the DAC output."),
    _q("RTL", "config", "SySal's MAXk axis set-up sends it (`...ER#,#;RTL;LTL;...`).",
       source="evidence 2.4, E8 (SySal)", confidence="D",
       notes="Meaning unknown (facts: no text anywhere): accepted without effect, so the "
       "set-up string runs without a command error, as on the board SySal was written for."),
    _q("SME", "encoder", "Set the motor position counter from the encoder (SySal: in its "
       "set-up, every 1000 loops and after LP0).", source="evidence 2.4, E8 (SySal)",
       confidence="D",
       notes="Read as 'set motor to encoder': the motor counter takes the encoder reading "
       "(in motor steps through ER), so periodic re-sends keep RP on the stage. Only on an "
       "encoder stepper (PSE, as SySal's axes are): elsewhere it changes nothing."),
    _q("BC", "config", "Backlash compensation, steps (SySal's set-up sends BC0).", units=2,
       operand=Operand.NUMBER, value_range=(0.0, 32767.0),
       source="evidence 2.4, E8 (SySal `BC0`); manual specifications ('Backlash "
       "compensation')", confidence="D",
       notes="Read as the manual's backlash compensation: when a stepper reverses, the step "
       "output gives # extra steps in the new direction that the motor counter (RP) does "
       "not count. With BC equal to the stage's backlash (a world setting: `@world X "
       "backlash N`) the stage, and an encoder on it (RE), ends where RP says; without it "
       "the stage lags by the backlash after each reversal. The extra steps are given at "
       "once when the reversal starts; the board's direction memory starts positive (the "
       "first move down is a reversal, the first move up is not). Switches, index marks "
       "and position maintenance see the motor counter, not the stage. BC0 (off) is the "
       "factory value. Servo axes: stored, no effect."),
    _i("#BB", "config", "Big command buffer mode (vendor DLL OMS_SetCommandBuffer: `;#BB#;`, "
       "`;#BB;`).", operand=Operand.NUMBER, operand_optional=True, per_axis=False,
       value_range=(0.0, 2_147_483_647.0), source="evidence 2.9, §5 (DLL-BIN)",
       confidence="I", notes="Recorded (board.command_buffer); the parser takes text of any "
       "length in either mode, so it changes nothing else (D)."),
    _i("#BN", "config", "Normal command buffer mode (vendor DLL `;#BN;`).",
       source="evidence 2.9 (DLL-BIN)", confidence="I", notes="As #BB."),
    _i("#BF", "config", "Flush the big command buffer (vendor DLL OMS_FlushBigBuffer `;#BF`).",
       source="evidence 2.9 (DLL-BIN)", confidence="I",
       notes="Text is parsed as it arrives, so nothing is ever waiting in the buffer: "
       "nothing to drop (D)."),
    _q("BW", "io", "Queue waits until input bit # reads low (the counterpart of SW).",
       units=2, operand=Operand.NUMBER, value_range=(0.0, 15.0),
       source="manual 4.4 (names BW among the I/O commands)", confidence="D",
       notes="The manual names it only; 'bit wait' fits its company (SW waits for high), "
       "'bit write' would need a level operand that BH/BL already cover."),
    _q("IOK", "io", "Named by the manual among the I/O commands; meaning unknown.",
       operand=Operand.NUMBER, operand_optional=True, per_axis=False,
       value_range=(0.0, 65535.0), source="manual 4.4", confidence="D",
       notes="No source says what it does: accepted without effect (an operand too)."),
    _q("IP", "queue", "Set the done flag once the axis is in position: at rest and, with "
       "position maintenance on, its encoder inside the deadband.",
       source="facts Table 1 (NMSU `HN; MA<p>; GD; IP;`, `CA; HV#; HG#; HD#; IP;`)",
       confidence="I",
       notes="Without position maintenance it is ID after the axis has come to rest."),
    _i("RS", "config", "Reset the controller: as power-up (motion stops at once, counters 0 "
       "where the stages stand, archived parameters, AX addressed).",
       source="facts Table 1 (TALON, NMSU, GVO)", confidence="I",
       notes="The reset is complete within one update cycle (D; hosts wait 2-5 s). Text "
       "after RS in the same write runs on the reset board."),
    _q("WH", "queue", "While loop start: the entries up to WG repeat until a stop or flush "
       "(`WH; MA#; GO; MA#; GO; WG;`).", units=2,
       source="evidence 2.2 (VIPER VME58); facts Table 1 (QViper on a MAXv)", confidence="I",
       notes="Built on the LS/LE loop stack, with no count: ST, SD, SA, KL, KS, FL or SI "
       "end it. What else might end it is not known."),
    _q("WG", "queue", "While loop end: jump back to WH.", source="evidence 2.2 (VIPER)",
       confidence="I", notes="Each jump back takes one update cycle, as LE."),
    _q("EF", "config", "Echo off (older boards' first command at init).",
       source="evidence 2.10 (VME8, VME58, PC68 drivers); facts Table 1 (GVO)",
       confidence="I", notes="Ends the echo EN began, for the host that sent it; the "
       "bytes of the write that carries EF are still echoed (they arrived while echo "
       "was on). Power-up: echo off (D: the MAX hosts never send EF and read no echo)."),
    _q("EN", "config", "Echo on: the host's bytes come back before the replies they ask for.",
       source="issue 40 (the old EPICS 3.13 VME8 driver starts with EN and routes replies "
       "by their echo); evidence 2.10 (EF, its opposite)", confidence="I",
       notes="Per host stream (D: a second host on the TCP door never sees another's "
       "bytes). Each later write is echoed byte for byte, as received, ahead of the "
       "replies and notifications it causes (D: the old boards echoed as characters "
       "arrived, and a host reads its command back before the reply); the write that "
       "carries EN is not echoed (its bytes arrived while echo was off)."),
    _q("DBI", "config", "Sent once per axis by a PC68 host at init (GVO); meaning unknown.",
       source="facts Table 1 (GVO)", confidence="D", notes="Accepted without effect."),
    _i("#WC", "report", "Clear the watchdog counter (older drivers).",
       source="evidence 2.5 (HIST drvMAXv_trajectory)", confidence="I",
       notes="#WS always reads =0 here (no watchdog trips): nothing to clear."),
    _i("RL", "report", "Report the limit switch inputs (listed with QA, RA, EA as a reply "
       "command).", reply="ffff", source="evidence 3.2 (DRV-MAXV log: replies to RA, QA, "
       "EA, RL)", confidence="D",
       notes="Its reply format is not known: we answer as QL (raw levels, hexadecimal)."),
    _i("KK", "servo", "PID present probe of the VME58 (`AX KK2 ID`): a command error on an "
       "axis without a servo loop.", operand=Operand.NUMBER, operand_optional=True,
       per_axis=False, value_range=(0.0, 32767.0), source="evidence 2.4, E6 (DRV-58)",
       confidence="I", notes="On a servo axis it is accepted without effect (D)."),
    _i("?AB", "aux", "Aux output query, prefix form (as AB?).", reply="=h | =l",
       source="evidence 2.5 (`AB? / ?AB`)", confidence="I"),
    _q("ET", "encoder", "Encoder tracking (electronic gearing), named in a VIPER comment.",
       source="evidence 2.4 (VIPER comment); manual 4.7 (the feature)", confidence="I",
       notes="Not modelled: refused with a command error that says so (never ignored)."),
]

COMMANDS: dict[str, CommandSpec] = unique_table(_SPECS, lambda spec: spec.mnemonic,
                                                 "MAX command table")
"""Every mnemonic the board understands, keyed by its upper-case spelling."""


def bind(timing: Timing, handlers: Mapping[str, Callable[..., Any]]) -> None:
    """Bind behaviours on their table entries, once each (at import of the module that
    owns them): a mnemonic not in the table, of another timing, or bound twice is an
    error at import, not a surprise at run time."""
    for mnemonic, handler in handlers.items():
        spec = COMMANDS.get(mnemonic)
        if spec is None:
            raise TableError(f"{mnemonic}: a behaviour for a mnemonic not in the table")
        if spec.timing is not timing:
            raise TableError(f"{mnemonic}: bound as {timing.value}, listed as "
                             f"{spec.timing.value}")
        if spec.handler is not None:
            raise TableError(f"{mnemonic}: bound twice")
        object.__setattr__(spec, "handler", handler)  # (frozen: only here, only once)


def check_bound() -> None:
    """Every entry has its behaviour (called once every behaviour module is imported)."""
    loose = [m for m, spec in COMMANDS.items() if spec.handler is None
             and spec.timing is not Timing.MODE
             and spec.start not in (Start.LINEAR_ABSOLUTE, Start.LINEAR_RELATIVE)]
    if loose:
        raise TableError(f"table entries without a behaviour: {', '.join(loose)}")

GROUP_TITLES = {
    "mode": "Axis and mode selection",
    "motion": "Motion parameters and moves",
    "profile": "Velocity profiles (ramp selection)",
    "position": "Position counters",
    "queue": "Queue, flags and loops",
    "config": "Axis configuration",
    "limits": "Limit configuration",
    "homing": "Homing",
    "io": "General purpose I/O",
    "aux": "Auxiliary outputs",
    "analog": "Analog I/O",
    "report": "Reports and queries",
    "servo": "Servo loop (PSM axes) and position maintenance",
    "encoder": "Encoders on steppers (PSE axes)",
    "units": "User units",
    "flash": "Parameter flash (power-up defaults)",
    "contour": "Vector contouring (tasks 1-8)",
}


def lookup(mnemonic: str) -> CommandSpec | None:
    return COMMANDS.get(mnemonic.upper())


LINE_DISCIPLINE: tuple[tuple[str, str, str, str], ...] = (
    # (what, behaviour, source, confidence): the byte stream's rules beside the commands
    ("^X (0x18)", "Clears the command-error flag at once (also while WQ holds the stream); "
     "nothing else: the axis select, the queues and the done/overtravel/slip flags stay. "
     "It ends the command before it, as a separator would (`\\x18AX QA RP` runs AX, QA, RP).",
     "evidence 2.10 (VME8 driver: CMD_CLEAR, 'clears command errors only'); issue 40", "I"),
    ("other control characters (0x01-0x1F but TAB CR LF, and DEL)",
     "Each stands on its own: it ends the command before it and is never part of a mnemonic "
     "(`\\x04WY` runs WY); it does nothing else. ^D's meaning on the older boards was not "
     "found (no manual page reachable).", "issue 40 (a host sends ^D before WY)", "D"),
    ("end of a command", "A terminator (space, TAB, CR, LF, `;`, NUL, a control character), "
     "the next command (`MA1000GO`), or with `framing=pc68` the end of each write: that "
     "framing's hosts write whole commands with no terminator (`AX LP4000`). The MAXnet "
     "framing keeps waiting, since a TCP segment may end mid-number (`MA10`, then `00`).",
     "evidence 1.2 and 3.1 (PC68 driver: no terminator); issue 40", "D"),
    ("echo (EN/EF)", "Off at power-up. After EN each later write of that host comes back "
     "byte for byte before the replies it causes; other hosts of the board see none.",
     "evidence 2.10; issue 40 (the old VME8 driver starts with EN)", "I"),
    ("VL/VB pair", "Checked when a move uses it, not when either is set (see VL).",
     "issue 40 (the EPICS motor record sends VL before VB)", "D"),
)
"""What the generated reference says about the stream itself (docs/commands.md)."""

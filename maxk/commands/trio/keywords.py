"""The TrioBASIC keyword table: one declarative entry per keyword.

The parser, the interpreter's range checks, the fake machine's defaults and
docs/trio.md read this table. Each entry records where its behaviour comes from and how
sure we are (C certain, I inferred, D our decision, explained in ``note``). Sources:

- ``seed``: the MC405 PWM application note (shared/seeds/trio-mc405-pwm.txt);
- ``ref``: what atrio sends and needs (shared/reference/trio-command-line.md);
- ``tokentable``: the token table shipped in atrio (AbundantRobotics/atrio,
  ``atrio/tokentable``): each keyword's kind (axis/system parameter, command, function),
  argument counts and whether a parameter is writable;
- ``manual``: the Trio Motion Coordinator technical reference manual (MC2xx editions);
- ``public programs``: how public TrioBASIC programs for real controllers use a word;
- ``help``: the TrioBASIC help, one page per keyword (syntax, parameters, examples), as
  Motion Perfect ships it for the MC4xx/MC5xx controllers.

Long module: a declarative table, one entry per keyword with its source and notes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

from ...personalities.trio.memory import TABLE_SIZE, VR_COUNT
from ...personalities.trio.pwm import PWM_REGISTER_MAX
from .lexer import TrioError


class Kind(Enum):
    AXIS_PARAMETER = "axis parameter"
    SYSTEM_PARAMETER = "system parameter"
    COMMAND = "command"
    FUNCTION = "function"
    STATEMENT = "statement"
    CONSTANT = "constant"
    OPERATOR = "operator"
    MODIFIER = "modifier"


@dataclass(frozen=True)
class Keyword:
    name: str
    kind: Kind
    summary: str
    source: str
    confidence: str = "C"
    note: str = ""
    value_range: tuple[float, float] | None = None  # accepted values (parameters, constants)
    writable: bool = True  # parameters: False = read only
    default: float = 0.0  # parameters: power-up value; constants: the value
    args: tuple[int, int] = (0, 0)  # commands/functions: min, max arguments
    axis_modifier: bool = False  # accepts AXIS(n) after it
    string_arg: bool = False  # first argument is a program name in quotes

    def check(self, value: float) -> None:
        """Refuse a value outside the range (nothing is written)."""
        if not math.isfinite(value):
            raise TrioError("Parameter out of range")
        if self.value_range is not None:
            low, high = self.value_range
            if not low <= value <= high:
                raise TrioError("Parameter out of range")


SEED = "seed"
TOK = "tokentable"
REF = "ref"
MAN = "manual"
_BIG = 1e15
HELP = "help"


def _axis(name: str, summary: str, *, default: float = 0.0, writable: bool = True,
          value_range: tuple[float, float] | None = (-_BIG, _BIG), source: str = TOK,
          confidence: str = "C", note: str = "") -> Keyword:
    return Keyword(name, Kind.AXIS_PARAMETER, summary, source, confidence, note, value_range,
                   writable, default, axis_modifier=True)


def _system(name: str, summary: str, *, default: float = 0.0, writable: bool = True,
            value_range: tuple[float, float] | None = (-_BIG, _BIG), source: str = TOK,
            confidence: str = "C", note: str = "") -> Keyword:
    return Keyword(name, Kind.SYSTEM_PARAMETER, summary, source, confidence, note,
                   value_range, writable, default)


def _command(name: str, summary: str, args: tuple[int, int], *, axis: bool = False,
             source: str = TOK, confidence: str = "C", note: str = "",
             string_arg: bool = False) -> Keyword:
    return Keyword(name, Kind.COMMAND, summary, source, confidence, note, args=args,
                   axis_modifier=axis, string_arg=string_arg)


def _function(name: str, summary: str, args: tuple[int, int], *, source: str = TOK,
              confidence: str = "C", note: str = "", string_arg: bool = False) -> Keyword:
    return Keyword(name, Kind.FUNCTION, summary, source, confidence, note, args=args,
                   string_arg=string_arg)


def _statement(name: str, summary: str, *, source: str = TOK, confidence: str = "C",
               note: str = "") -> Keyword:
    return Keyword(name, Kind.STATEMENT, summary, source, confidence, note)


def _constant(name: str, value: float, *, source: str = TOK, note: str = "") -> Keyword:
    return Keyword(name, Kind.CONSTANT, f"Constant {value:g}.", source, "C", note,
                   default=value)


_REGISTER = (0.0, float(PWM_REGISTER_MAX))
_LIMIT_STOP = (" While it is on, AXISSTATUS bit {bit} is set. A motion reaching the switch is "
               "cancelled on that servo tick (found exactly) and ramps down at FASTDEC, or "
               "DECEL when FASTDEC is 0 (I); a move into the switch while it is on is "
               "cancelled as it starts (no step); moves away from it run (I). An input the "
               "world drives as a level acts when it changes (D).")

_ENTRIES: list[Keyword] = [
    # ---- axis parameters ------------------------------------------------------------
    _axis("ATYPE", "Axis type; 35 (pulse/direction + PWM) or 36 (servo + PWM) give a PWM "
          "output on the Z channel.", default=43, value_range=(0, 255), source=f"{SEED}; {TOK}",
          confidence="I", note="Power-up 43, the seed's 'recommended default' (I). Any "
          "0..255 is stored; only 35 and 36 give a PWM output (seed: 2.0229 supports 35). "
          "The encoder input types (76, 79, 86, 87, 88, 93, 104, 105: the help page) read "
          "the world's encoder mounted on the axis's input as MPOS (I)."),
    _axis("UNITS", "Counts per user unit: positions, speeds and gate positions are scaled "
          "by it.", default=1, value_range=(-_BIG, _BIG), source=f"{HELP}; {MAN}; {TOK}; "
          "public programs", confidence="I",
          note="0 is refused (D). A negative UNITS is taken (I: a calibration cell's "
          "encoder axes run with UNITS -1.5625 to flip their sign): positions read with "
          "the sign flipped, and while it is negative SPEED, ACCEL, DECEL, CREEP, FASTDEC "
          "and JOGSPEED above 0 are 'Parameter out of range' (I: that cell's notes; the "
          "controller keeps rates in counts). A move on such an axis is 'Parameter out "
          "of range' (D: the planner takes no negative rate). An axis of an encoder input "
          "type (ATYPE 76 ...) reads the world's encoder mounted on its input as MPOS "
          "(see docs/trio.md, Encoder axes)."),
    _axis("SPEED", "Programmed speed of moves, user units/s.", default=1000,
          value_range=(0, _BIG), source=f"{MAN}; {TOK}; TrioBASIC help VP_MODE",
          confidence="I", note="Power-up value 1000 is our decision (D). Written while "
          "moves run it acts at once on the base axis's plain (not SP) moves, the one "
          "running re-planned from where it is and those buffered run at it (C: VP_MODE "
          "page; buffered ones D; a single-axis move then ramps linearly, D: respeed.py)."),
    _axis("ACCEL", "Acceleration, user units/s^2.", default=1000, value_range=(0, _BIG),
          source=f"{MAN}; {TOK}", note="Power-up 1000 (D). Written while moves run: as "
          "SPEED (C: VP_MODE page)."),
    _axis("DECEL", "Deceleration, user units/s^2.", default=1000, value_range=(0, _BIG),
          source=f"{MAN}; {TOK}", note="Power-up 1000 (D). Written while moves run: as "
          "SPEED (C: VP_MODE page; a path's moves ramp down at ACCEL, D)."),
    _axis("MERGE", "Merge consecutive moves without stopping (ON/OFF).", default=0,
          value_range=(-1, 1), source=f"{SEED} examples 1-2; {TOK}", confidence="I",
          note="A move joins the one before it (one path, corners at full speed) when MERGE "
          "of its base axis is ON as it is loaded and both are on the same axes (I)."),
    _axis("FE_LIMIT", "Following error limit, user units.", default=2000,
          value_range=(0, _BIG), source=f"{SEED} example 3; {TOK}", confidence="I",
          note="Power-up 2000 (D). |FE| beyond it sets AXISSTATUS bit 8 (256), in ERRORMASK "
          "by default: a motion error (manual, C for steppers with verification), raised "
          "on the servo cycle it is first passed (the loop runs every cycle, D)."),
    _axis("DPOS", "Demand position, user units.", writable=False, source=f"{MAN}; {TOK}",
          note="The exact demand, fractions of a count included (D)."),
    _axis("MPOS", "Measured position, user units.", writable=False, source=f"{MAN}; {TOK}",
          confidence="I", note="A servo axis (see FE): the encoder of the world's motor "
          "(I); any other axis: equals DPOS (D)."),
    _axis("VP_SPEED", "Velocity profile speed: the path speed of the move this axis runs, "
          "user units/s.", writable=False, source=f"{SEED}; {TOK}",
          note="Read only (tokentable). PWM_CONTROL(2/8) links to it. Every axis of an "
          "interpolated group reads the group's path speed (I)."),
    _axis("IDLE", "TRUE (-1) when the axis has no move running or buffered.",
          writable=False, source=f"{MAN}; {TOK}", confidence="I",
          note="Reads -1/0 like the manual's TRUE/FALSE flags (I)."),
    _axis("PWM_CYCLE", "Clocks of 20 MHz in one PWM period (mark + space).", default=1000,
          value_range=(1, PWM_REGISTER_MAX), source=f"{SEED}; {TOK}",
          note="Maximum 65535 (seed). 0 is refused and the power-up 1000 (20 kHz) is ours "
          "(D). Axes 0-4 only."),
    _axis("PWM_MARK", "Clocks the output is on in each period; >= PWM_CYCLE: always on.",
          value_range=_REGISTER, source=f"{SEED}; {TOK}",
          note="Maximum 65535 (seed). In PWM_CONTROL modes 2 and 8 it reads the mark "
          "computed on the last servo cycle (I). Fractions truncate (D)."),
    _axis("PWM_ENCODER", "The 29-bit hardware position register the gating FIFO compares "
          "with.", writable=False, source=SEED, confidence="I",
          note="Read only; cleared by PWM_CONTROL(6), untouched by DEFPOS/OFFPOS (seed). "
          "Reads raw counts, unsigned 0..2^29-1 (D)."),
    # ---- system parameters -----------------------------------------------------------
    _system("WDOG", "Enable switch for the drives; PWM is generated only with WDOG=ON.",
            value_range=(-1, 1), source=f"{SEED}; {TOK}",
            note="A servo axis (ATYPE 36, 77) moves only with WDOG ON (see SERVO); a motion "
            "error sets it OFF (I). Pulse/direction axes run their demand whatever it is "
            "(I: the seed's example 1 loads its moves before WDOG=ON)."),
    _system("SERVO_PERIOD", "Servo cycle in microseconds (one tick of the emulator).",
            default=1000, value_range=(250, 2000), source=f"{MAN}; {TOK}", confidence="D",
            note="MC405 default 1000 us. 250, 500, 1000 or 2000 accepted; the new period "
            "applies from the next restart (EX), as on the controller (I)."),
    _system("VERSION", "System software version.", default=2.0299, writable=False,
            source=REF, confidence="D",
            note="2.0299: at least 2.0229 for PWM (seed) and 2.0297 (atrio's own test)."),
    _system("MPE", "Channel handshake mode; Motion Perfect sets it non-zero.", writable=False,
            source=f"{REF}; {TOK}", value_range=(0, 0), note="Must print 0 for atrio to "
            "connect (ref 3). Set with the command MPE(mode): only MPE(0) is accepted, the "
            "emulator has no Motion Perfect channel protocol (D)."),
    _system("SYSTEM_ERROR", "System error bit flags.", writable=False, source=REF,
            note="Always 0: no system errors are modelled."),
    _system("SYSTEM_LOAD_MAX", "Highest processor load seen, percent.", value_range=(0, 100),
            source=REF, confidence="D", note="Reads the value last written (atrio writes 0)."),
    _system("FLASH_STATUS", "0 when no flash write is pending.", writable=False, source=REF,
            confidence="I", note="Program stores finish at once, so always 0 (D)."),
    _system("CHECKSUM", "Checksum of all programs, after COMPILE_ALL.", writable=False,
            source=REF, confidence="D",
            note="CRC-16 (0x8005) over every program's EDPROG checksum, by name order."),
    _system("TSIZE", "Size of TABLE memory.", default=TABLE_SIZE, writable=False,
            source=TOK, confidence="D", note=f"{TABLE_SIZE} values (D)."),
    # ---- motion and axis commands ----------------------------------------------------------
    _command("MOVE", "Relative interpolated move on the BASE axes.", (1, 128), axis=True,
             source=f"{SEED}; {TOK}", note="A path at the base axis's SPEED and ACCEL taken "
             "when loaded, distances rounded to whole counts (D); 16 moves buffered per "
             "axis (D)."),
    _command("MOVEABS", "Absolute interpolated move on the BASE axes.", (1, 128), axis=True,
             source=f"{SEED}; {TOK}", note="As MOVE, to positions (DPOS, after DEFPOS)."),
    _command("DEFPOS", "Define the present positions of the BASE axes.", (1, 128),
             axis=True, source=f"{SEED}; {TOK}; {MAN}",
             note="Does not change PWM_ENCODER (seed)."),
    _command("ACC", "Set ACCEL and DECEL of the base axis.", (1, 1), axis=True,
             source=f"{SEED}; {TOK}"),
    _command("CANCEL", "Cancel the move running on the base axis.", (0, 1), axis=True,
             source=f"{TOK}; {MAN}", confidence="I", note="Ramps down (a path at its ACCEL, "
             "one axis at DECEL); buffered moves run after it; ends a CONNPATH/CAMBOX (I)."),
    _command("RAPIDSTOP", "Cancel the moves on every axis.", (0, 1), source=f"{TOK}; {MAN}",
             confidence="I", note="Drops every buffered move, ramps the running ones down."),
    _command("PWM_CONTROL", "PWM mode of the base axis: (0) off, (1) PWM_MARK, (2,...) "
             "speed link, (3,...) gate positions, (4) empty FIFO, (5) gating on, (6) clear "
             "PWM_ENCODER, (8,...) speed x profile.", (1, 6), axis=True,
             source=f"{SEED}; {TOK}", note="An axis function: AXIS() or BASE() picks the "
             "axis (seed). Refusals leave everything unchanged (personality DECISIONS)."),
    _command("CONNPATH", "Link an axis to the path distance of an interpolating group.",
             (1, 2), axis=True, source=f"{SEED}; {TOK}", confidence="I",
             note="First argument: the first axis of the driving group (seed example "
             "CONNPATH(0) AXIS(8) for BASE(0,1)); the optional second is a ratio, default 1 "
             "(D). The axis moves by ratio x the path distance (base user units) until "
             "CANCEL (D)."),
    _command("CAMBOX", "Follow a TABLE profile linked to another axis's movement: (start, "
             "end, multiplier, link distance, link axis[, link options[, link pos[, offset "
             "start]]]); CAMBOX(table start, axis count) loads several axes at once.",
             (2, 8), axis=True, source=f"{SEED}; {TOK}; {MAN}; help (CAMBOX page)",
             confidence="C",
             note="TABLE values offset by the first, times the multiplier (counts), "
             "interpolated linearly over the link distance; ends on the servo tick the link "
             "axis has travelled it (C). Link options (C: help page): 1/256 start on the "
             "link axis's MARK/MARKB at REG_POS exactly (one captured before counts, D); 2 "
             "at the absolute link position (already past: from where it is, D); 4 repeats "
             "both ways, each cycle from where the last ended, until REP_OPTION bit 1; 8 "
             "pattern mode (third argument the 7-value control block, stepped at each "
             "shape's end with the link moving forward; backward patterns not modelled, "
             "D); 128 starts offset start into the profile, the axis taken as there (no "
             "jump, D); 8192 DPOS (the model follows DPOS always, D); 32 follows only the "
             "link's forward travel, 16384 only forward travel past its highest point "
             "(taken in at every engine event, between which the link's motion is "
             "monotonic, D). 512 (R_MARK) and reserved bits: 'Parameter out of range' (D). "
             "Before a registration/absolute start the axis holds; a repeating CAMBOX "
             "does not run back past its start point (D). Multi-axis form: 8 TABLE values "
             "an axis, on the base axis and the axes after it (I), all checked first (C). "
             "A link axis that follows this axis is refused (D: no position)."),
    # ---- linked moves, MHELICAL, MOVEMODIFY and the move reports (links.py, moves.py) ----
    _command("MHELICAL", "MHELICAL(end1, end2, centre1, centre2, direction, distance3[, "
             "mode]): MOVECIRC's arc on the first two BASE axes while the third moves "
             "distance3 along it.", (6, 9), axis=True, source=f"{TOK}; {MAN}",
             confidence="I", note="One arc segment of the shared path planner whose third "
             "axis rises in proportion to the arc; the path speed is the circle's, at the "
             "base axis's SPEED and ACCEL (I); mode and the 8th/9th arguments other than 0 "
             "are refused (D). MTYPE 3."),
    _command("MOVEMODIFY", "MOVEMODIFY(position): the running move of the base axis now "
             "ends at this absolute position.", (1, 1), axis=True, source=f"{TOK}; {MAN}",
             confidence="I", note="Re-planned from where the axis is at the speed it has "
             "(SPEED/ACCEL of the axis now); if it cannot stop short of the new end it stops "
             "and comes back (I). On an idle axis an absolute move (I). Refused on a linked "
             "axis, an interpolated group or a merged move with more buffered behind it (D). "
             "Never waits. MTYPE 5."),
    _command("MOVELINK", "MOVELINK(distance, link dist, link acc, link dec, link axis[, "
             "options[, link pos]]): move distance while the link axis travels link dist, "
             "ramping over its first link acc and last link dec.", (5, 13), axis=True,
             source=f"{TOK}; {MAN}; help (MOVELINK page)", confidence="I",
             note="The axis's speed share of the link ramps with the link's travel, "
             "constant between (C); link acc + link dec above link dist are both shortened "
             "in proportion (C). It follows the link axis's DEMAND position (D: the "
             "manual's link is the measured one; bit 8192 asks for DPOS) and ends on the "
             "first servo tick the link has travelled link dist; the next MOVELINK "
             "buffered on the same link axis takes over at that exact link position (no "
             "drift: I). Options (C: help page): 1/256 start at the link axis's MARK/"
             "MARKB REG_POS; 2 at the absolute link position link pos (already past: from "
             "where it is, D); 4 repeats both ways until REP_OPTION bit 1; 16 curved "
             "ramps, bits 10..12 the curve: 0 sine, 1/2/3 power 9/7/5 polynomial speed "
             "(smoothstep polynomials, I), 4 linear; 32 forward travel only, 16384 forward "
             "past the highest point (as CAMBOX's). 512 (R_MARK), base_dist and reserved "
             "bits: 'Parameter out of range' (D). "
             "Buffered like a move (NTYPE 22). MTYPE 22."),
    _command("FLEXLINK", "FLEXLINK(base dist, excite dist, link dist, base in, base out, "
             "excite acc, excite dec, link axis[, options[, start pos]]): a constant-ratio "
             "base move plus a ramped excitation move, linked to another axis.", (8, 10),
             axis=True, source=f"{TOK}; help (FLEXLINK page)", confidence="I",
             note="The base moves base dist in proportion to the link's travel over link "
             "dist; the excitation moves excite dist between base in % and 100 - base out % "
             "of it, ramping over excite acc % and excite dec % of that window on the "
             "curve bits 10..12 give (0 sine by default, 1/2/3 power 9/7/5 polynomial "
             "speed, 4 linear: C, page). Options 1/256 (MARK/MARKB start), 2 (absolute "
             "start), 4 (repeat), 32/16384 (forward only), 8192 as MOVELINK's; 512 refused "
             "(D). "
             "Percentages outside 0..100 or pairs above 100: 'Parameter out of range' (D). "
             "Queued and ended as a MOVELINK, and reads MTYPE 22 (D: its own code is not "
             "in the pages found)."),
    _command("CONNECT", "CONNECT(ratio, link axis): the base axis follows ratio x the link "
             "axis's movement (electronic gearbox) until CANCEL or RAPIDSTOP.", (2, 2),
             axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="Ratio in counts per count, not user units (C: manual, Trio support). "
             "Follows the link axis's demand position (D). A second CONNECT on the same link "
             "axis changes the ratio at once from where both are; on another link axis it is "
             "ignored while the first runs (C: manual). Buffered behind moves and links like "
             "a move. CLUTCH_RATE is not modelled. MTYPE 21."),
    _command("ADDAX", "ADDAX(axis): add that axis's demand movements to the base axis's "
             "own; ADDAX(-1) ends it.", (1, 1), axis=True, source=f"{TOK}; {MAN}",
             confidence="I", note="Count for count from when it is given (I); after "
             "ADDAX(-1) the axis keeps what was added. Not buffered: it acts at once (I). "
             "A loop of ADDAX/links is 'Parameter out of range' (D). MOVEABS on the axis "
             "aims its own moves, without the live ADDAX part (D)."),
    _axis("MTYPE", "The type of move the axis runs: 0 idle, 1 MOVE, 2 MOVEABS, 3 MHELICAL, "
          "4 MOVECIRC, 5 MOVEMODIFY, 10 FORWARD, 11 REVERSE, 13 CAM, 14/15 FWD_JOG/REV_JOG, "
          "20 CAMBOX, 21 CONNECT, 22 MOVELINK, 23 CONNPATH.", writable=False,
          source=f"{TOK}; {MAN}", confidence="I",
          note="The codes as recalled from the manual's MTYPE table (the table's text was "
          "not found in the stored pages: I). DATUM's searches read 10/11 (D, not 12); a "
          "MOVE of exactly 2^50 counts reads as FORWARD/REVERSE (D)."),
    _axis("NTYPE", "The type of the next move held in the axis's buffer (MTYPE codes); 0 "
          "none.", writable=False, source=f"{TOK}; {MAN}", confidence="I",
          note="The move after the running one (merged moves, runs queued, linked moves); "
          "with none running, the first held (I)."),
    _axis("MOVES_BUFFERED", "Moves held in the axis's buffer behind the one running.",
          writable=False, source=f"{TOK}; {MAN}", confidence="I",
          note="Up to 16 moves held per axis, running included (D, docs/trio.md)."),
    _axis("REMAIN", "The distance left of the move running, user units.", writable=False,
          source=f"{TOK}; {MAN}", confidence="I", note="Unsigned; along the axis for its "
          "share of a path move, the axis's own distance left for a MOVELINK, 0 for links "
          "without an end and at rest (I)."),
    _axis("ENDMOVE", "The absolute end position of the move running, user units; written "
          "on an idle axis it steps the demand there.", source=f"{TOK}; {MAN}",
          confidence="I", note="Reads DPOS when there is no move. Written on an idle axis "
          "the demand steps to it (C: manual DPOS entry); on a running single-axis move it "
          "is MOVEMODIFY (D); otherwise 'Parameter out of range' (D)."),
    _axis("MSPEED", "The axis's speed over the last servo cycle, user units/s (signed).",
          writable=False, source=f"{TOK}; {MAN}", confidence="D",
          note="The demand's change over the servo cycle before now (D: the measured "
          "position is not modelled apart from the demand here)."),
    _axis("DEMAND_SPEED", "The speed of the axis's demand position, user units/s (signed).",
          writable=False, source=f"{TOK}; {MAN}", confidence="I",
          note="The demand's change over the servo cycle before now, per second (as "
          "MSPEED, which reads the same in this model: D)."),
    _axis("LINK_AXIS", "The axis a linked move follows (CONNECT, MOVELINK, CAMBOX link "
          "axis, CONNPATH base); -1 none.", writable=False, source=f"{TOK}; {MAN}",
          confidence="I", note="-1 for none is our reading of the manual (I)."),
    _axis("ADDAX_AXIS", "The axis ADDAX adds to this one; -1 none.", writable=False,
          source=f"{TOK}; {MAN}", confidence="I",
          note="-1 for none is our reading of the manual (I)."),
    _command("BASE", "Set the process's base axes; later axes follow in order.", (1, 128),
             source=f"{SEED}; {TOK}; {MAN}", confidence="I",
             note="BASE(4) makes the group 4,5,6,...,0,1,2,3 (manual)."),
    _command("TABLE", "TABLE(start, v1, v2, ...) writes a run of TABLE values; TABLE(i) "
             "reads one.", (1, 128), source=f"{SEED}; {TOK}"),
    _command("WA", "Wait this many milliseconds.", (1, 1), source=f"{SEED}; {TOK}",
             note="Rounded up to whole servo cycles; the process sleeps, the command line "
             "answers when it ends (D). More than 1e12 ms is 'Parameter out of range' (D)."),
    _command("ETHERCAT", "EtherCAT master functions ($87 reinit, $22 state, $21 ...).",
             (1, 20), source=REF, confidence="D",
             note="No EtherCAT network: $22 with VR index -1 prints 0 (no network), others "
             "are accepted and do nothing."),
    # ---- program handling ------------------------------------------------------------------
    _command("DIR", "List the programs.", (0, 1), source=REF,
             note="Header ending in dashes, one line per program, then OK (ref 5)."),
    _command("SELECT", "Select (and create) a program: SELECT \"N\"[,type] or SELECT N.",
             (1, 2), source=f"{REF}; {HELP}; public uploader", string_arg=True,
             confidence="I",
             note="Types 0 .BAS, 3 .TXT, 7 .PROJ, 9 .MCC, 12 .BAL. A missing program is "
             "created, a BASIC program (type 0) when no type is given (help page), even "
             "named MC_CONFIG. An existing program is selected whatever its type; a type "
             "given that differs is 'Program type mismatch' (page: the type of an existing "
             "program cannot change). The previously selected program is not compiled "
             "here (D: it compiles when run). The name may be unquoted "
             "(a vendor-style uploader sends SELECT MC_CONFIG; I), as for every command "
             "taking a program: a name that is no keyword, alone or before a comma."),
    _command("DEL", "Delete a program.", (0, 2), source=REF, string_arg=True),
    _command("LIST", "List a program's lines.", (0, 1), source=REF, string_arg=True),
    _command("NEW", "Clear the lines of a program.", (0, 1), source=TOK, string_arg=True,
             confidence="I", note="NEW \"N\" or the selected program (I from its name)."),
    _command("COMPILE", "Compile the selected program.", (0, 1), source=REF,
             note="Structure and syntax are checked here; errors are printed as "
             "%[Program NAME Line n] lines (D)."),
    _command("COMPILE_ALL", "Compile every program.", (0, 0), source=REF),
    _command("EDPROG", "EDPROG\"N\",10 prints the program's CRC-16.", (2, 5), source=REF,
             string_arg=True, note="Only function 10 (checksum) is modelled."),
    _command("RUNTYPE", "RUNTYPE\"N\",1,proc: run at power up; RUNTYPE\"N\",0,-1: manual.",
             (2, 3), source=REF, string_arg=True),
    _command("RUN", "Start a program: RUN \"N\"[,process].", (0, 2), source=TOK,
             string_arg=True, note="Compiles it first when edited (I)."),
    _command("STOP", "Stop one program.", (0, 2), source=TOK, string_arg=True),
    _command("HALT", "Stop every program.", (0, 0), source=f"{REF}; {TOK}",
             note="Moves already loaded continue (I)."),
    _command("PROCESS", "List the running processes.", (0, 1), source=REF, confidence="D",
             note="One 'Process p:Program NAME - Running' line per process: the form is "
             "ours (atrio only sends it)."),
    _command("AUTORUN", "Start every program set to run at power up.", (0, 0), source=REF,
             note="Prints '%[Process p:Program NAME] - Running' per program (atrio test)."),
    _command("EX", "Restart the controller.", (0, 1), source=REF,
             note="Echoes EX and CR LF, then nothing: the door closes the session and "
             "starts a new one (ref 5)."),
    # ---- functions ---------------------------------------------------------------------------
    *[_function(name, f"{name}(x).", (1, 1), source=f"{TOK}; {MAN}")
      for name in ("ABS", "INT", "FRAC", "SGN", "SQR", "SIN", "COS", "TAN", "ATAN", "EXP",
                   "LN")],
    _function("ATAN2", "ATAN2(y, x).", (2, 2)),
    _function("VR", "Global variable VR(i); assign with VR(i)=value.", (1, 1),
              source=f"{TOK}; {MAN}", note=f"VR(0..{VR_COUNT - 1}) (count I: public "
              "programs clear VR 0..65535)."),
    _function("IS_PROG", "TRUE (-1) when the program exists.", (1, 1), source=REF,
              string_arg=True, confidence="I", note="atrio tests it for truth; -1 is "
              "TrioBASIC's TRUE (I)."),
    _function("PROG_TYPE", "The program's type code, -1 when missing.", (1, 1), source=REF,
              string_arg=True),
    # ---- statements ---------------------------------------------------------------------------
    _statement("PRINT", "Print expressions and strings; ',' tabs, ';' joins, a final ';' "
               "keeps the line open. '?' is the same.", source=f"{REF}; {MAN}",
               note="Integer values print without decimals (ref 3), others with 4 (manual)."),
    _statement("IF", "IF cond THEN ... [ELSE ...] on one line, or a block to ENDIF."),
    _statement("THEN", "Part of IF."),
    _statement("ELSE", "Part of IF."),
    _statement("ENDIF", "Ends a block IF."),
    _statement("WHILE", "WHILE cond ... WEND.", note="One pass per servo cycle (D)."),
    _statement("WEND", "Ends WHILE."),
    _statement("REPEAT", "REPEAT ... UNTIL cond.", note="One pass per servo cycle (D)."),
    _statement("UNTIL", "Ends REPEAT."),
    _statement("FOR", "FOR v = a TO b [STEP s] ... NEXT v.", note="One pass per servo cycle "
               "(D)."),
    _statement("TO", "Part of FOR."),
    _statement("STEP", "Part of FOR."),
    _statement("NEXT", "Ends FOR."),
    _statement("WAIT", "WAIT IDLE (the base axis finished every move) or WAIT UNTIL cond.",
               source=f"{SEED}; {TOK}; {MAN}",
               note="WAIT UNTIL tests once per servo cycle (D). Allowed on the command "
               "line too, holding its prompt (D: the manual may restrict it to programs)."),
    # ---- drives, limits and I/O (personalities/trio/drive.py) ----------------------------
    *[_axis(name, f"The input wired to the axis's {what} (-1: none).", default=-1,
            value_range=(-1, 31), source=f"{HELP}; {TOK}; {MAN}", confidence="I",
            note="The input is active low (its help page, C): the function is on while "
            "IN(n) reads 0. IN(n) of that input reads the world's "
            f"{switch} switch of this axis at its position, wired normally closed: 1 away "
            "from it, 0 on it (D: as the pages' examples wire their sensors), unless the "
            "world drives input n itself (then its level); INVERT_IN inverts both what IN "
            "reads and the function." + stop)
      for name, what, switch, stop in (
          ("FWD_IN", "forward limit", "plus-limit", _LIMIT_STOP.format(bit=4)),
          ("REV_IN", "reverse limit", "minus-limit", _LIMIT_STOP.format(bit=5)),
          ("DATUM_IN", "datum (home) switch", "home", " DATUM(3..6) search for it."))],
    _axis("FS_LIMIT", "Forward software limit, user units.", default=200000000000,
          source=f"{TOK}; {MAN}", confidence="I", note="Power-up value (I). DPOS beyond it "
          "sets AXISSTATUS bit 9 (512). A motion reaching it (the first servo tick DPOS is at "
          "or beyond it) is cancelled there and ramps down to zero (manual: 'ramp down the "
          "speed to zero then cancel the move', C), at FASTDEC or DECEL as a hard limit; "
          "moves further forward are cancelled as they start (I)."),
    _axis("RS_LIMIT", "Reverse software limit, user units.", default=-200000000000,
          source=f"{TOK}; {MAN}", confidence="I", note="As FS_LIMIT: AXISSTATUS bit 10 "
          "(1024) while DPOS is below it (manual, C); it stops reverse motion the same way."),
    _axis("FASTDEC", "Deceleration at a limit, user units/s^2 (0: DECEL).", default=0,
          value_range=(0, _BIG), source=f"{TOK}; {MAN}", confidence="I",
          note="A single-axis move cancelled by a limit (hard or soft) ramps down at FASTDEC "
          "when it is not 0, else at DECEL (I); a path ramps along itself at its ACCEL (D)."),
    _axis("AXISSTATUS", "Axis status bits: 2 following error warning, 16 forward limit, 32 "
          "reverse limit, 64 datuming, 128 feed hold, 256 following error exceeded, 512 "
          "forward soft limit, 1024 reverse soft limit.", writable=False, source=f"{TOK}; {MAN}",
          confidence="I", note="Bits 4/5 from the FWD_IN/REV_IN inputs, 9/10 from DPOS "
          "against FS_LIMIT/RS_LIMIT (manual, C for 9/10), 6 while DATUM(1)/(2) searches, "
          "7 while FHOLD_IN's input is active (C: help AXISSTATUS), "
          "1/8 from FE against FE_RANGE/FE_LIMIT (8 also when the servo loop trips); the "
          "bits that put the axis into motion error stay set until DATUM(0). Bits 2/3 "
          "(remote drive) read 0: no remote drives (D)."),
    _axis("ERRORMASK", "AXISSTATUS bits that put the axis into motion error.", default=268,
          value_range=(0, 2 ** 24 - 1), source=f"{TOK}; {MAN}", confidence="I",
          note="Power-up 268 (256 following error exceeded, 8 and 4 remote drive errors: "
          "I). A bit newly set in AXISSTATUS AND ERRORMASK (looked at on every event: D) "
          "stops every axis at once, drops the buffered moves, sets WDOG OFF and the axis's "
          "MOTION_ERROR bit (I). Acting on newly set bits only is our decision (D): an axis "
          "left standing on a limit after DATUM(0) can move off it."),
    _system("MOTION_ERROR", "Axes in motion error: bit n set for axis n.", writable=False,
            source=f"{TOK}; {MAN}", confidence="I",
            note="Set by ERRORMASK (see it), cleared by DATUM(0) (I). A move on an axis in "
            "error is refused with 'Axis in error' (D: the text is ours)."),
    _system("ERROR_AXIS", "The first axis that went into motion error (-1: none).",
            default=-1, writable=False, source=f"{TOK}; {MAN}", confidence="I",
            note="-1 with no motion error (D); cleared by DATUM(0)."),
    _axis("FE", "Following error: DPOS - MPOS, user units.", writable=False,
          source=f"{TOK}; {MAN}", confidence="I",
          note="On a servo axis (ATYPE 36/77 with P_GAIN above 0) the shared servo loop "
          "drives the world's motor and FE is the demand less the encoder (I); on any "
          "other axis it is 0, the axis following its demand exactly (D)."),
    _axis("FE_RANGE", "Following error warning range, user units (0: off).",
          value_range=(0, _BIG), source=f"{TOK}; {MAN}", confidence="I",
          note="|FE| beyond it sets AXISSTATUS bit 1 (2) (I)."),
    *[_axis(name, f"Servo gain: {what}.", value_range=(0, _BIG), source=f"{TOK}; {MAN}",
            confidence="D", note=f"With ATYPE 36 or 77 and P_GAIN above 0 the axis runs the "
            f"shared servo loop (the MAXk's PID on the world's motor plant) as {term} (D: "
            "the MC405's own scaling is not published here). Power-up 0: the exact, "
            "profile-only axis (D).")
      for name, what, term in (
          ("P_GAIN", "proportional", "KP: DAC counts per count of error"),
          ("I_GAIN", "integral", "KI/1024: DAC counts per count summed each servo cycle"),
          ("D_GAIN", "derivative", "KD: DAC counts per count of change of the error"),
          ("VFF_GAIN", "velocity feed forward", "KV: DAC counts per count per servo "
           "cycle of demand speed"))],
    _axis("DRIVE_STATUS", "The status word of the axis's drive.", writable=False,
          source=f"{TOK}; {MAN}", confidence="D",
          note="The CiA 402 status word an EtherCAT drive reports (I), as far as the "
          "emulator knows it (D: the MC405's own axes have no drive word): 0x37 enabled "
          "(ready, switched on, operation enabled, voltage, quick stop) or 0x50 disabled "
          "(voltage, switch-on disabled); +8 fault while the axis is in motion error, "
          "+0x400 target reached while idle, +0x800 internal limit while an AXISSTATUS "
          "limit bit is set, +0x2000 following error with bit 8."),
    _axis("SERVO", "Position loop on (ON) or off for the axis.", value_range=(-1, 1),
          source=f"{TOK}; {MAN}", confidence="I", note="On a servo axis (ATYPE 36 or 77) "
          "the drive is enabled only with SERVO ON, WDOG ON and AXIS_ENABLE ON: a move is "
          "refused with 'Axis not enabled' (D: the text is ours) and one running stops at "
          "once when it goes off (D). Power-up OFF (I). Pulse/direction axes ignore it "
          "(manual: on a stepper it only gates the position verification, C)."),
    _axis("AXIS_ENABLE", "Enable of the axis's drive.", default=1, value_range=(-1, 1),
          source=f"{TOK}; {MAN}", confidence="I", note="Power-up ON (I). OFF disables the "
          "drive of any axis (as SERVO does a servo axis's)."),
    _axis("CREEP", "The slow speed of the second part of a DATUM search, and of the "
          "Z-mark searches DATUM(1)/(2), user units/s.", default=200,
          value_range=(0, _BIG), source=f"{TOK}; {MAN}", confidence="I",
          note="Power-up 200 (D)."),
    _command("DATUM", "DATUM(n): 0 clears motion errors; 1/2 search forward/reverse at CREEP "
             "for the encoder's Z mark, zero there; 3/5 search forward at SPEED for the "
             "DATUM_IN input, then back at CREEP until it goes off; 4/6 the same in "
             "reverse; the position there becomes 0.", (1, 1), axis=True,
             source=f"{TOK}; {MAN}", confidence="I",
             note="1/2: the Z mark is the world's index mark of the axis, found exactly to "
             "the servo tick; DPOS is 0 on the mark's first count met, then the axis ramps "
             "down at DECEL (D: it stops a ramp past the mark). 3..6 run on the planner "
             "watching the input every servo cycle; the zero is where the creep stopped "
             "after the input went off (D: not the exact edge); 5 and 6 do not look for the "
             "Z mark (D). 0 clears every axis's motion error (MOTION_ERROR, ERROR_AXIS, the "
             "bits AXISSTATUS held), WDOG stays OFF (I). The statement returns when the "
             "search ends (D: the controller returns at once and the axis moves on). "
             "Without a DATUM_IN, 3..6 are 'Parameter out of range' (D)."),
    _command("MOVECIRC", "MOVECIRC(end1, end2, centre1, centre2, direction): an arc on the "
             "first two BASE axes, end and centre relative to the start.", (5, 7), axis=True,
             source=f"{TOK}; {MAN}", confidence="I",
             note="On the shared path planner at the base axis's SPEED and ACCEL; direction "
             "1 clockwise, 0 anticlockwise (I); an end on the start is a whole circle; the "
             "6th and 7th arguments are refused unless 0 (D). A limit met ramps the path "
             "down along itself (see FWD_IN). MTYPE 4."),
    _command("FORWARD", "Move forward continuously at SPEED until CANCEL or RAPIDSTOP.",
             (0, 0), axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="A move of 2^50 counts on the shared planner, ended by CANCEL's ramp (D), "
             "or by the forward limit (FWD_IN, FS_LIMIT) at FASTDEC. MTYPE 10."),
    _command("REVERSE", "Move in reverse continuously at SPEED until CANCEL.", (0, 0),
             axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="As FORWARD, towards REV_IN and RS_LIMIT. MTYPE 11."),
    _function("IN", "IN(n): input n, 1 on / 0 off; IN(a, b): inputs a..b as a binary "
              "number; IN: inputs 0..31.", (0, 2), source=f"{TOK}; {MAN}", confidence="I",
              note="Reads the shared world's inputs (the world contract can drive them)."),
    _command("OP", "OP(n, ON|OFF) sets output n; OP(n) reads it as a function.", (1, 3),
             source=f"{TOK}; {MAN}", confidence="I",
             note="Outputs 0..31 kept by the machine, off at power up (D); OP(pattern) with "
             "one argument sets outputs 8..31 from bits (I)."),
    _function("READ_OP", "READ_OP(n): output n, 1/0; READ_OP(a, b): outputs a..b as a "
              "binary number.", (1, 2), source=f"{TOK}; {MAN}", confidence="I",
              note="Reads the outputs OP set (I)."),
    _function("AIN", "AIN(n): analog input n as a 12-bit signed count (-2048..2047 for "
              "-10..10 V).", (1, 1), source=f"{TOK}; {MAN}", confidence="D",
              note="The scaling is our decision (D); the volts come from the world."),
    _command("AOUT", "AOUT(n) = value: analog output n; AOUT(n) reads it back.", (1, 1),
             source=f"{TOK}; {MAN}", confidence="D",
             note="Kept by the language per controller; no analog world output (D)."),
    # ---- processes and errors ------------------------------------------------------------------
    _system("RUN_ERROR", "The code of the last runtime error of this process (PROC(n): of "
            "process n).", writable=False, confidence="D",
            note="Set when ON BASICERROR GOTO catches an error. The numbers are ours (D): "
            "1 Syntax error, 2 Parameter out of range, 3 Arithmetic error, 4 Divide by zero, "
            "5 Invalid axis number ... (interpreter.ERROR_CODES)."),
    _system("ERROR_LINE", "The program line of the last runtime error of this process.",
            writable=False, note="Lines of an INCLUDEd program report the INCLUDE's line (D)."),
    _system("TICKS", "The process's own clock: counts down one a servo cycle from the value "
            "last set.", confidence="I", note="Per process; one count per servo cycle (I)."),
    _system("PROC_STATUS", "PROC_STATUS PROC(n): 1 while process n runs a program, 0 "
            "stopped.", writable=False, confidence="I",
            note="Paused/stepping (2, 3) do not exist in the emulator (D)."),
    _system("PROCNUMBER", "The number of the process reading it.", writable=False),
    _system("PROC_LINE", "The line a process is on (PROC(n)).", writable=False),
    # ---- strings --------------------------------------------------------------------------
    _function("CHR", "CHR(n[, format]): the character of code n: format 0 (default) "
              "0..255, 1 a Unicode code point UTF-8 encoded.", (1, 2), source=f"{HELP}; {TOK}",
              note="Format 1 gives the code point's UTF-8 bytes, one string character "
              "each, so the wire carries UTF-8 (D)."),
    _function("HEX", "HEX(n): n in hexadecimal, upper case; negatives as 48-bit two's "
              "complement (D).", (1, 1), source=f"{HELP}; {TOK}"),
    _function("ASC", "ASC(s[, offset]): the code of the character at offset (from 0, "
              "default 0); 0 for an empty string or an offset outside it.", (1, 2),
              source=f"{HELP}; {TOK}"),
    _function("LEN", "LEN(s): characters in s.", (1, 1), source=f"{HELP}; {TOK}"),
    _function("LEFT", "LEFT(s, n): the first n characters.", (2, 2), source=f"{HELP}; {TOK}"),
    _function("RIGHT", "RIGHT(s, n): the last n characters.", (2, 2),
              source=f"{HELP}; {TOK}"),
    _function("MID", "MID(s, start[, n]): n characters (default the rest) from index start "
              "(from 0: the page's example takes MOTION at 5 of 'TRIO MOTION ...').", (2, 3),
              source=f"{HELP}; {TOK}", note="A negative start or length is 'Parameter out "
              "of range' (D)."),
    _function("UCASE", "UCASE(s): upper case.", (1, 1), source=f"{HELP}; {TOK}"),
    _function("LCASE", "LCASE(s): lower case.", (1, 1), source=f"{HELP}; {TOK}"),
    _function("STR", "STR(x[, precision[, width]]): x with precision decimals (default 5), "
              "right aligned in width characters (default 0: unlimited).", (1, 3),
              source=f"{HELP}; {TOK}", confidence="I",
              note="Rounded as Python's fixed-point format rounds (I); precision above 20 "
              "is 'Parameter out of range' (D)."),
    _function("VAL", "VAL(s): the number s spells (0 when it spells none).", (1, 1),
              source=f"{HELP}; {TOK}"),
    _function("INSTR", "INSTR([offset,] s, find[, wildcard]): the index (from 0) of the "
              "first find in s at or after offset, -1 if absent; wildcard (a one-character "
              "string or its code) in find matches any character.", (2, 4),
              source=f"{HELP}; {TOK}"),
    _function("VRSTRING", "VRSTRING(n): the characters held one a VR from VR(n) up to the "
              "first VR holding 0.", (1, 1), source=f"{HELP}; {TOK}", confidence="I",
              note="Only printable characters are kept (page); printable is codes 32..126 "
              "and 160..255 (I). At most 1024 characters (D)."),
    _statement("INCLUDE", "INCLUDE \"NAME\": compile another program's lines in here.",
               confidence="I", note="Resolved at COMPILE; nesting up to 8 (D)."),
    _statement("DEFCONST", "DEFCONST name value: a named constant, as CONSTANT \"name\", "
               "value.", source="public programs", confidence="I",
               note="Seen in Motion Perfect library templates; the emulator treats it as "
               "CONSTANT (I). An '=' or ',' between name and value is accepted (D)."),
    # ---- channels (files and terminals) ---------------------------------------------------
    _command("OPEN", "OPEN #n AS \"NAME\" FOR INPUT|OUTPUT|APPEND|FIFO_READ|FIFO_WRITE|"
             "READ_WRITE: a channel on a file.", (0, 0), confidence="I",
             source=f"{TOK}; public programs",
             note="FOR INPUT reads a program of the store (a .TXT file) as text, its lines "
             "ending CR LF (D: the store is the file system); a missing one is 'Program "
             "not found'; a channel already open is 'Channel already open' (D). Output "
             "modes accept and drop what is written (D)."),
    *(_command(mode, f"OPEN's {mode} channel mode (see OPEN).", (0, 0), confidence="I",
               source=f"{TOK}; public programs",
               note="Taken as a word of OPEN ... FOR; alone as a statement it is accepted "
               "with no effect (D).")
      for mode in ("FIFO_READ", "READ_WRITE", "APPEND")),
    _command("CLOSE", "CLOSE #n: close a channel.", (0, 0), confidence="I",
             source=f"{TOK}; public programs", note="Closing a channel not open does "
             "nothing (D)."),
    _command("GET", "GET [#n,] v: the code of the next character of channel n.", (0, 0),
             confidence="I", source=f"{TOK}; public programs",
             note="Waits until a character comes: an open file gives its next one; the "
             "terminal channels never receive one while a program runs (D), so GET on "
             "them waits (as on a controller nobody types to)."),
    _command("INPUT", "INPUT [#n,] v[, v]: numbers from a channel, comma or line "
             "separated.", (0, 0), confidence="I", source=f"{TOK}; public programs",
             note="As GET for where characters come from; at the end of a file a value "
             "reads 0 (D)."),
    _command("LINPUT", "LINPUT [#n,] v: one line of a channel as a string.", (0, 0),
             confidence="I", source=f"{TOK}; public programs", note="As INPUT."),
    _function("KEY", "KEY #n: TRUE when a character waits on channel n.", (0, 1),
              confidence="I", source=f"{TOK}; public programs",
              note="An open file with characters left reads TRUE; the terminal channels "
              "read FALSE (D: no typing reaches a running program)."),
    *[_function(name, f"{name}: {what} from the controller's clock.", (0, 0),
                confidence="D", source=TOK,
                note="The emulator's clock is virtual time since power up, which is 00:00:00 "
                "on Saturday 01/01/2000 (D).")
      for name, what in (("DATE$", "the date DD/MM/YYYY"), ("TIME$", "the time HH:MM:SS"),
                         ("DAY$", "the day of the week"))],
    _axis("OFFPOS", "OFFPOS = d: shift the axis's positions (DPOS and MPOS) by d; reads 0.",
          source=f"{TOK}; public programs", confidence="I",
          note="Applied at once as a DEFPOS to DPOS + d, and OFFPOS reads 0 again, so the "
          "common 'OFFPOS = d: WAIT UNTIL OFFPOS = 0' goes on (I: the controller applies it "
          "on the next servo cycle and clears it)."),
    _command("SET_BIT", "SET_BIT(b, vr): set bit b of VR(vr).", (2, 2), confidence="I",
             source=f"{TOK}; {MAN}", note="Bits 0..52 of the VR's integer part (D)."),
    _command("CLEAR_BIT", "CLEAR_BIT(b, vr): clear bit b of VR(vr).", (2, 2),
             confidence="I", source=f"{TOK}; {MAN}", note="As SET_BIT."),
    _function("READ_BIT", "READ_BIT(b, vr): bit b of VR(vr), 1 or 0.", (2, 2),
              confidence="I", source=f"{TOK}; {MAN}", note="As SET_BIT."),
    _command("TIME", "TIME reads the real time clock's seconds since midnight; TIME = "
             "hh:mm:ss sets it.", (0, 0), source=f"{HELP}; {TOK}", confidence="I",
             note="The clock is virtual time from 00:00:00 on Saturday 01/01/2000 at power "
             "up (D), set ahead or back by TIME = and DATE =; the three fields may be "
             "expressions (page example 3). Shared by every process (I)."),
    _command("DATE", "DATE reads the days since 01/01/2000 (0 that day), DATE(0|1|2) the "
             "day, month, year; DATE = dd:mm:yy (or yyyy) sets it.", (0, 1),
             source=f"{HELP}; {TOK}", confidence="I",
             note="As TIME for the clock; years 2000..2099 only (page); a day the month "
             "lacks is 'Parameter out of range' (D)."),
    _command("DAY", "DAY: the day of the week, 0..6, Sunday 0.", (0, 0),
             source=f"{HELP}; {TOK}", confidence="I", note="As TIME for the clock."),
    _function("RND", "RND: a pseudo-random unsigned 32-bit integer; RND(n) 0..n-1; "
              "RND(a, b) a..b-1.", (0, 2), source=f"{HELP}; {TOK}", confidence="I",
              note="Each process has its own generator, seeded with its number and the "
              "servo tick of its first draw (D: the page's 'varies with each execution', "
              "yet an emulator run repeats); limits must be whole with a < b (D)."),
    _function("RNDF", "RNDF: a pseudo-random number 0 <= x < 1; RNDF(n) 0..n; RNDF(a, b) "
              "a..b (upper limit excluded).", (0, 2), source=HELP, confidence="I",
              note="As RND."),
    _command("RANDOMIZE", "RANDOMIZE(seed): this process's RND/RNDF sequence starts again "
             "from seed; RANDOMIZE alone: from a fresh seed.", (0, 1), source=HELP,
             confidence="I", note="The same seed gives the same sequence (page); the "
             "generator is Python's (the values differ from a controller's: D)."),
    _system("INPUTS0", "IN(0)..IN(15) as one number.", writable=False,
            source=f"{HELP}; {TOK}", note="Read as IN reads each input."),
    _system("INPUTS1", "IN(16)..IN(31) as one number.", writable=False,
            source=f"{HELP}; {TOK}", note="As INPUTS0."),
    _command("SCOPE", "SCOPE(ON, period, table_start, table_stop, p0[, ... p7]) arms a "
             "capture of up to 8 parameters into TABLE; SCOPE(ON, period) changes the "
             "period; SCOPE(OFF) disables it.", (1, 13), source=f"{HELP}; {TOK}",
             confidence="I",
             note="Each parameter has its own block of (stop - start) / n values, filled "
             "one sample every period servo cycles from TRIGGER until full (page example "
             "1). The parameters are expressions read at each sample with the BASE of the "
             "process that set SCOPE (I). The FIFO form, SCOPE_DELAY and "
             "SCOPE_CYCLE_COUNT are not modelled (D)."),
    _command("TRIGGER", "TRIGGER[(auto)]: start the armed SCOPE; auto not 0: it starts "
             "again at the end of each scan.", (0, 1), source=f"{HELP}; {TOK}",
             confidence="I", note="The first sample is taken on TRIGGER's own servo "
             "cycle (D); after SCOPE(OFF) it starts nothing (page)."),
    _system("SCOPE_POS", "The TABLE index the SCOPE stores its next sample at.",
            writable=False, source=f"{HELP}; {TOK}", confidence="D",
            note="In the first parameter's block (D). The token table has it writable; "
            "writing is refused here (D)."),
    _command("FILE", "FILE \"function\" [parameters]: the SD card's files (DETECT, DIR, "
             "LOAD_PROGRAM ...); as a function TRUE when it succeeded.", (0, 0),
             source=f"{HELP}; {TOK}", confidence="D",
             note="The emulator has no SD card: FILE \"DETECT\" and every other function "
             "read FALSE (0), as a card that is not there fails them; as a statement it does "
             "nothing (D: the controller's terminal would report the error)."),
    _command("TIMER", "TIMER(slot, output, pattern, time[, option]): outputs on (option 0, "
             "default) or off (1) for time ms, then back.", (4, 5), source=f"{HELP}; {TOK}",
             confidence="I",
             note="Pattern 1: the output alone; another number: a bit array of outputs from "
             "output up (page). The end falls on the servo cycle time ms is rounded up to "
             "(D, as WA); a slot set again while it runs starts over (D). OP can change the "
             "outputs meanwhile; the end sets them anyway (D)."),
    _system("CONTROL", "The controller's ID: 405 for the MC405.", writable=False,
            source=f"{HELP}; {TOK}", note="Never locked (1000 would be added, page): D."),
    *[_function(name, f"{name}(x): the arc-{what} in radians.", (1, 1), source=HELP,
                note="Outside -1..1: 'Parameter out of range' (D).")
      for name, what in (("ACOS", "cosine, 0..PI"), ("ASIN", "sine, -PI/2..PI/2"))],
    *[_function(name, f"{name}(x): TRUE when x is {what}.", (1, 1), source=HELP,
                confidence="I", note="Every value the emulator holds is finite (its "
                "arithmetic refuses the rest), so it reads FALSE (I).")
      for name, what in (("IS_NAN", "not a number"), ("IS_INF", "infinite"))],
    *[_system(f"{kind}{n}", f"{kind}{n}: {what}({n}) as a parameter.", writable=kind == "AOUT",
              source=f"{HELP}; {TOK}", confidence="I", note="As the function reads it "
              "(page: for SCOPE, which stores parameters); AINBI reads the same counts as "
              "AIN (D: the world's inputs are signed volts)." if kind != "AOUT" else
              "AOUTn = v is AOUT(n) = v.")
      for kind, what in (("AIN", "AIN"), ("AINBI", "AIN"), ("AOUT", "AOUT"))
      for n in range(4)],
    *[_system(name, f"{name}: the number of {what} (the highest + 1).", writable=False,
              source=f"{HELP}; {TOK}", confidence="D",
              note="32: the I/O points the emulator's IN and OP address (D).")
      for name, what in (("NIN", "inputs"), ("NOP", "outputs"))],
    _command("INVERT_IN", "INVERT_IN(n, state) inverts input n in software (ON) or not "
             "(OFF); INVERT_IN(n) reads its state, ON (1) or OFF (0).", (1, 2),
             source=f"{HELP}; {TOK}", confidence="I",
             note="IN(n) reads the inverted level, and so do the functions the input drives "
             "(FWD_IN, REV_IN, DATUM_IN: active low, so an inverted input wired to a "
             "normally open sensor makes them active high, as the pages' examples do). "
             "The two-argument form as a function returns TRUE (page). Not saved: none is "
             "inverted at power up (D). An inverted limit input wired to a world switch is "
             "on everywhere but at the switch: a move into it is cancelled as it starts, "
             "and it is looked at on every event, not found to the tick (D)."),
    _command("FLAG", "FLAG(n, state) sets user flag n (0..23); FLAG(n) reads it.", (1, 2),
             confidence="I", source=f"{TOK}; {MAN}",
             note="Reads TRUE (-1) or FALSE; the flags start clear and are shared by every "
             "process (I)."),
    _command("FLAGS", "FLAGS(value) sets the 24 user flags as bits; FLAGS reads them.",
             (0, 1), confidence="I", source=f"{TOK}; {MAN}", note="As FLAG."),
    _command("PROFINET", "PROFINET(function, slot, ...): the PROFINET slave module's "
             "functions.", (1, 20), source="public programs", confidence="D",
             note="No PROFINET module: accepted, no effect; as a function it returns 0 (D)."),
    Keyword("NW_NODE_AXIS_MAP", Kind.SYSTEM_PARAMETER, "NW_NODE_AXIS_MAP(slot, node, n): the "
            "axis a network node's drive is mapped to.", "public programs", "D",
            "Not modelled: each (slot, node, n) keeps the value written, reads 0 before "
            "(D).", (-1, 1023)),
    Keyword("PROC", Kind.MODIFIER, "PROC(n) after a process parameter: process n's.", TOK,
            args=(1, 1)),
    # ---- registration (personalities/trio/registration.py) -------------------------------
    _command("REGIST", "REGIST(mode) AXIS(n): arm one capture of the axis's position on a "
             "registration edge.", (1, 7), axis=True, source=f"{TOK}; {MAN}",
             confidence="I", note="Modes (I: the MC2xx manual's table as recalled): 1/2 "
             "Z mark rising/falling, 3/4 R input rising/falling into MARK/REG_POS; 5..8 "
             "R (A) with the Z mark on MARKB/REG_POSB; 9 R rising (A) and falling (B). The "
             "Z mark is the world's index marks of the axis, found to the servo tick on "
             "the axis's own motion (on a linked axis by bisecting its demand up to the "
             "next motion event, D); REG_POS is the mark's exact count (the latch). The R "
             "input of axis n is world digital input n (D), latched on the tick it "
             "changes. + 256 / + 768: only edges inside / outside OPEN_WIN..CLOSE_WIN (I). The "
             "newer forms (20..) are refused (D)."),
    _command("CAM", "CAM(start, end, multiplier, distance): follow the TABLE profile in "
             "time, the whole of it taking distance / SPEED.", (4, 4), axis=True,
             source=f"{TOK}; {MAN}", confidence="I",
             note="TABLE values offset by the first, times the multiplier (counts), "
             "interpolated linearly in time: distance in the axis's user units at the "
             "SPEED it has when the CAM loads (I, the CAM page as recalled). Buffered like "
             "a move, never merged (D); ends on the profile's last value rounded to a "
             "whole count (D). MTYPE 13 (I)."),
    _command("MOVESP", "MOVESP(d1[, d2...]): MOVE at the base axis's FORCE_SPEED.", (1, 128),
             axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="As MOVE (buffered, merged with MERGE, MTYPE 1: D), its vector speed "
             "FORCE_SPEED, with STARTMOVE_SPEED and ENDMOVE_SPEED, taken when it loads "
             "(C); merged, the moves join at the speeds profiles_sp.py gives "
             "(ENDMOVE_SPEED, STARTMOVE_SPEED, else an SP move's FORCE_SPEED from its "
             "start: C, help pages FORCE_SPEED, ENDMOVE_SPEED, STARTMOVE_SPEED)."),
    _command("MOVEABSSP", "MOVEABSSP(p1[, p2...]): MOVEABS at the base axis's FORCE_SPEED.",
             (1, 128), axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="As MOVEABS (MTYPE 2: D), at FORCE_SPEED (as MOVESP)."),
    _axis("FORCE_SPEED", "The vector speed of MOVESP and MOVEABSSP, user units/s.",
          default=1000.0, value_range=(0, _BIG), source="TrioBASIC help FORCE_SPEED",
          confidence="C", note="Power-up 1000 (C: at UNITS 1; kept in user units, as "
          "SPEED, D). Read when an SP move loads: the move's own top speed, reached at its "
          "start (the move before ramps up to it at its end: C, the page's example 1); "
          "0 refuses them like a SPEED of 0 (D)."),
    _axis("STARTMOVE_SPEED", "The speed an SP move (MOVESP...) starts at; -1 not used.",
          default=-1.0, value_range=(-1, _BIG), source="TrioBASIC help STARTMOVE_SPEED",
          confidence="C", note="Loaded with the move; caps the seam speed into it (the "
          "move before slows to it at its end). Below 0: not used (D: any negative as -1). "
          "Taken with ENDMOVE_SPEED of the move before: the lower (D)."),
    _axis("ENDMOVE_SPEED", "The speed an SP move (MOVESP...) ends at; -1 not used.",
          default=-1.0, value_range=(-1, _BIG), source="TrioBASIC help ENDMOVE_SPEED",
          confidence="C", note="Loaded with the move; the move ramps at ACCEL within "
          "itself to reach it at its end, and the move after starts there; the last "
          "move buffered ends at rest (C). Below 0: not used (D)."),
    _axis("FHOLD_IN", "The feed-hold input: while it is active (low) the base axis's "
          "moves run at FHSPEED; -1 none.", default=-1, value_range=(-1, 1023),
          source="TrioBASIC help FHOLD_IN", confidence="C",
          note="Active low, read as IN(n) reads it (INVERT_IN applies, C). The moves of "
          "the BASE group based on the axis slow to FHSPEED and go back to their speed "
          "when it lets go, not cancelled (C); links go on (C). Re-planned on the shared "
          "path planner at the move's ACCEL (the page: ACCEL/DECEL/JERK, D), from the tick "
          "the input changes; moves merged after the one in progress run at FHSPEED too "
          "(re-planned at each move's start, D); a single-axis move held turns into a "
          "linear-ramped path (D) (feedhold.py)."),
    _axis("FHSPEED", "The speed moves run at while the feed-hold input is active, user "
          "units/s.", value_range=(0, _BIG), source="TrioBASIC help FHSPEED, FHOLD_IN",
          confidence="C", note="Power-up 0: a feed hold pauses the moves (C). Above a "
          "move's own speed: the move keeps its speed (D)."),
    _axis("CORNER_MODE", "Corner and radius speed control of SP moves (bits).",
          value_range=(0, 127), source="TrioBASIC help CORNER_MODE", confidence="C",
          note="Applied when an SP move loads (C; profiles_sp.py). Bit 1: the change of "
          "direction from END_DIR_LAST (CHANGE_DIR_LAST: first two axes, lines and arc "
          "tangents) lowers its STARTMOVE_SPEED by DECEL_ANGLE/STOP_ANGLE (C). Bit 3: an "
          "arc's FORCE_SPEED by radius / FULL_SP_RADIUS, or (bit 4) v^2/r within the "
          "centripetal acceleration at FULL_SP_RADIUS, or (bits 4, 5) within ACCEL (C; "
          "every arc of the shared planner is held within sqrt(ACCEL x radius) anyway, "
          "D). Bits 2 (the CORNER_STATE machine) and 6 (vector radius control: the page "
          "does not give its radius of two vectors) are stored, no effect (D)."),
    _axis("DECEL_ANGLE", "The change of direction (radians) beyond which CORNER_MODE "
          "slows a corner.", value_range=(0, _BIG), source="TrioBASIC help DECEL_ANGLE",
          confidence="C", note="Between DECEL_ANGLE and STOP_ANGLE the corner's speed "
          "falls linearly from FORCE_SPEED to 0 (D: the page's formula as printed reads "
          "the other way round, 0 at DECEL_ANGLE, against its own text); ignored when not "
          "below STOP_ANGLE (C)."),
    _axis("STOP_ANGLE", "The change of direction (radians) beyond which CORNER_MODE stops "
          "at the corner.", value_range=(0, _BIG), source="TrioBASIC help STOP_ANGLE",
          confidence="C", note="The move after the corner gets STARTMOVE_SPEED 0: the "
          "path comes to rest at the junction (C). 0: no stops (C)."),
    _axis("FULL_SP_RADIUS", "The smallest arc radius run at full speed under CORNER_MODE "
          "bit 3, user units.", value_range=(0, _BIG),
          source="TrioBASIC help FULL_SP_RADIUS", confidence="C", note="A tighter arc "
          "runs at FORCE_SPEED x radius / FULL_SP_RADIUS (C); 0: no slowing (D)."),
    _axis("START_DIR_LAST", "The start direction of the last SP move loaded (radians "
          "from the Y axis toward X).", writable=False,
          source="TrioBASIC help START_DIR_LAST", confidence="C", note="Of the first two "
          "BASE axes, -PI..PI; an arc's tangent (C). Set as the move loads (C)."),
    _axis("END_DIR_LAST", "The end direction of the last SP move loaded (radians from the "
          "Y axis toward X); written, the direction the next SP move's corner is taken "
          "from.", value_range=(-math.pi, math.pi), source="TrioBASIC help END_DIR_LAST",
          confidence="C", note="Power-up 0 (D). Plain moves leave it (C: write it after "
          "them)."),
    _axis("CHANGE_DIR_LAST", "The change of direction (0..PI) from END_DIR_LAST before "
          "the last SP move loaded to its start.", writable=False,
          source="TrioBASIC help CHANGE_DIR_LAST", confidence="C", note="The angle "
          "CORNER_MODE's DECEL_ANGLE and STOP_ANGLE compare (C); 2D (AXIS_MODE's 3D mode "
          "is not modelled, D)."),
    _axis("ENDMOVE_BUFFER", "The absolute end of every move buffered on the axis, user "
          "units.", writable=False, source="TrioBASIC help ENDMOVE_BUFFER",
          confidence="C", note="As DPOS reads (DEFPOS/OFFPOS applied, C); DPOS with none "
          "(D); the REP_DIST fold is not applied (D)."),
    _axis("VP_ACCEL", "The profiler's acceleration now, user units/s^2.", writable=False,
          source="TrioBASIC help VP_ACCEL", confidence="I", note="VP_SPEED's change over "
          "the servo cycle before now, per second: negative while slowing (D)."),
    _axis("VP_JERK", "The profiler's jerk now, user units/s^3.", writable=False,
          source="TrioBASIC help VP_JERK", confidence="I", note="VP_ACCEL's change over "
          "the servo cycle before now, per second (D)."),
    _axis("IN_POS", "TRUE when the axis has finished its moves and is in position.",
          writable=False, source="TrioBASIC help IN_POS", confidence="C",
          note="TRUE (-1) when no move runs or is buffered, |FE| < IN_POS_DIST and "
          "|MSPEED| < IN_POS_SPEED (C: strictly less, so with their power-up 0 it never "
          "is, as the page warns)."),
    _axis("IN_POS_DIST", "The following error within which IN_POS reads TRUE, user units.",
          value_range=(0, _BIG), source="TrioBASIC help IN_POS_DIST", confidence="C",
          note="Power-up 0 (C)."),
    _axis("IN_POS_SPEED", "The measured speed below which IN_POS reads TRUE, user "
          "units/s.", value_range=(0, _BIG), source="TrioBASIC help IN_POS_SPEED",
          confidence="C", note="Power-up 0 (C)."),
    _axis("VECTOR_BUFFERED", "The path length of the moves buffered on the group based "
          "on the axis, user units.", writable=False,
          source="TrioBASIC help VECTOR_BUFFERED", confidence="I", note="The running "
          "move's remainder included (D: the page's \"available for deceleration\"); "
          "links and CAMs are not vectors (0, D)."),
    _axis("MSPEEDF", "MSPEED through a low-pass filter (MSPEED_FILTER), user units/s.",
          writable=False, source="TrioBASIC help MSPEEDF, MSPEED_FILTER", confidence="I",
          note="Reads MSPEED: equal to it with MSPEED_FILTER at its power-up 1 (C); a "
          "filter below 1 is not applied (D: the filter runs every servo cycle over a "
          "history the event engine does not keep)."),
    _axis("MSPEED_FILTER", "MSPEEDF's filter coefficient, 0..1 (1: no filtering).",
          default=1.0, value_range=(0, 1), source="TrioBASIC help MSPEED_FILTER",
          confidence="C", note="Power-up 1 (C); values below 1 are stored, not applied "
          "(see MSPEEDF, D)."),
    _system("LIMIT_BUFFERED", "The most moves the controller buffers (1..BUFFERSIZE).",
            default=1, value_range=(1, 64), source="TrioBASIC help LIMIT_BUFFERED",
            confidence="D", note="Not modelled: the machine's buffer depth is fixed at "
            "16 moves per axis, the running one included (docs/trio.md), whatever it "
            "says; power-up 1 as the page, 1..64 (stored, D)."),
    _axis("MOVE_COUNT", "Counts the moves that became the running one (MTYPE); "
          "writable.", source="TrioBASIC help MOVE_COUNT", confidence="I",
          note="Each buffered move (MOVE..., SP moves, arcs, CAM) counts once on every "
          "axis of its group as it becomes the running move; zero-length moves and jogs "
          "do not (C). Links (CONNECT, MOVELINK, CAMBOX) and their automatic repeats are "
          "not counted (D: not modelled yet)."),
    _axis("VP_MODE", "The velocity profiler: 0 trapezoid (SRAMP blends), 5 and 6 jerk "
          "limited (JERK).", value_range=(0, 6), source="TrioBASIC help VP_MODE, JERK, "
          "SRAMP", confidence="C", note="Power-up 0 (C). Other values than 0, 5 and 6: "
          "Parameter out of range (D). Taken when a move loads. Modes 5 and 6 differ "
          "only in VP_OPTIONS and SP-move parameter binding, not modelled: one jerk "
          "profile (D); in 6 an SRAMP above 0 gives JERK = ACCEL/SRAMP (C: SRAMP page; "
          "SRAMP 0 leaves JERK in force, D). Jerk shapes single-axis moves; merged and "
          "interpolated paths keep linear ramps (D)."),
    _axis("JERK", "Jerk limit of moves in VP_MODE 5 and 6, user units/s^3.",
          value_range=(0, _BIG), source="TrioBASIC help JERK, VP_MODE", confidence="C",
          note="A single-axis move's acceleration rises at JERK to ACCEL, holds and falls "
          "at JERK (DECEL on the way down): a ramp to SPEED lasts SPEED/ACCEL + "
          "ACCEL/JERK, or 2 sqrt(SPEED/JERK) when ACCEL is not reached (C); a move too "
          "short to reach SPEED keeps the shares SPEED gives (D). 0: no jerk limit (D). "
          "Ignored in VP_MODE 0 (C)."),
    _axis("FWD_JOG", "The input that jogs the axis forward while it is low; -1 none.",
          default=-1, value_range=(-1, 1023), source=f"{TOK}; {MAN}", confidence="I",
          note="Active low (C: MC206 manual, JOGSPEED page); read as IN(n) reads it. The "
          "jog starts on the tick the input goes low with the axis idle (D: a jog does not "
          "interrupt a move) and ramps down at DECEL when it goes high; MTYPE 14 (I). "
          "Both jog inputs low: no jog (D). Power-up -1 (D)."),
    _axis("REV_JOG", "The input that jogs the axis in reverse while it is low; -1 none.",
          default=-1, value_range=(-1, 1023), source=f"{TOK}; {MAN}", confidence="I",
          note="As FWD_JOG; MTYPE 15 (I)."),
    _axis("FAST_JOG", "The input that, while low, makes a jog run at SPEED instead of "
          "JOGSPEED; -1 none.", default=-1, value_range=(-1, 1023),
          source=f"{TOK}; {MAN}", confidence="I", note="Read when the jog starts (D)."),
    _axis("JOGSPEED", "The slow jog speed, user units/s.", value_range=(0, _BIG),
          source=f"{TOK}; {MAN}", confidence="C", note="A jog at 0 does not start (D)."),
    _axis("SRAMP", "S-ramp time, ms: a single-axis move's acceleration rises to ACCEL "
          "(DECEL) over SRAMP, holds, and falls over SRAMP.", value_range=(0, 500),
          source="TrioBASIC help SRAMP", confidence="C",
          note="Range 0..500 ms (C). Taken when the move loads. VP_MODE 0: a "
          "ramp to SPEED then lasts SPEED/ACCEL + SRAMP (C: SRAMP page's example; the "
          "shared S-curve profile); VP_MODE 6: see VP_MODE (JERK = ACCEL/SRAMP); a move "
          "too short to reach SPEED keeps the shares SPEED gives (D). Interpolated and "
          "merged paths, CANCEL's ramp down and links stay linear (D)."),
    _axis("OPEN_WIN", "Where the registration window opens (user units).",
          source=f"{TOK}; {MAN}", confidence="I", note="REGIST modes + 256 take only "
          "edges between OPEN_WIN and CLOSE_WIN (as DPOS reads, REP_DIST folded), + 768 "
          "only edges outside (I); a rejected edge leaves the capture armed."),
    _axis("CLOSE_WIN", "Where the registration window closes (user units).",
          source=f"{TOK}; {MAN}", confidence="I", note="As OPEN_WIN."),
    _axis("MARK", "TRUE once the capture REGIST armed has happened.", writable=False,
          source=f"{TOK}; {MAN}", confidence="C", note="FALSE from REGIST until the "
          "edge; TRUE from the servo tick of the edge (registration.py)."),
    _axis("MARKB", "TRUE once the capture of REGIST's second channel has happened.",
          writable=False, source=f"{TOK}; {MAN}", confidence="I", note="As MARK, channel "
          "B (REGIST modes 5..9)."),
    _axis("REG_POS", "The position captured by the last registration (user units).",
          writable=False, source=f"{TOK}; {MAN}", confidence="C", note="The mark's exact "
          "position, DEFPOS applied, in the axis's UNITS."),
    _axis("REG_POSB", "The position captured by the second registration channel.",
          writable=False, source=f"{TOK}; {MAN}", confidence="I", note="As REG_POS."),
    _axis("REP_DIST", "The repeat distance: DPOS, MPOS and REG_POS read folded into "
          "-REP_DIST..REP_DIST (0..REP_DIST with REP_OPTION bit 0).", default=200000,
          value_range=(0, _BIG), source=f"{TOK}; {MAN}", confidence="I",
          note="Power-up 200000 (I, as recalled). The machine keeps the unfolded position "
          "(motion and links are never disturbed, D); MOVEABS and a CAMBOX's absolute "
          "start position are taken in the fold the axis reads now (D). 0 does not fold "
          "(D)."),
    _axis("REP_OPTION", "Repeat options: bit 1 set ends the repeating CAMBOX/MOVELINK at "
          "the end of its cycle, and clears.", value_range=(0, 255),
          source=f"{TOK}; help (CAMBOX, MOVELINK pages)", confidence="I",
          note="Bit 1 acts on the repeating links running on the axis or linked to it "
          "(D: the CAMBOX page's example sets it on the link axis) and reads 0 again (C). "
          "Bit 0 folds positions into 0..REP_DIST instead of -REP_DIST..REP_DIST (I)."),
    _command("MOVECIRCSP", "MOVECIRCSP(...): MOVECIRC at the base axis's FORCE_SPEED.",
             (5, 7), axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="As MOVECIRC, its path speed FORCE_SPEED (as MOVESP)."),
    _command("MHELICALSP", "MHELICALSP(...): MHELICAL at the base axis's FORCE_SPEED.",
             (6, 9), axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="As MHELICAL, its path speed FORCE_SPEED (as MOVESP)."),
    # ---- motion words stored but not acted on, each with why (issue 35) ----------------
    *[_axis(name, summary, confidence="D", note="Not modelled: " + why)
      for name, summary, why in (
          ("CORNER_STATE", "The corner state machine's handshake bits (CORNER_MODE bit 2).",
           "the state machine holding the move loader for a program's handshake is not "
           "modelled (stored, D)."),
          ("VP_POSITION", "Reserved.", "its page says only 'reserved keyword' (stored, D)."),
          ("SPEED_SIGN", "Reserved.", "its page says only 'reserved keyword' (stored, D)."),
          ("FORCE_RAMP", "A change of FORCE_SPEED over the length of an SP move.",
           "a speed ramp across a whole move is not among the path planner's pieces "
           "(stored, D)."),
          ("FORCE_DWELL", "A dwell (ms) at the end of the next SP move.",
           "a dwell inside a merged path is not in the shared path planner (stored, D)."),
          ("LOOKAHEAD_FACTOR", "A factor on the SP speeds in the move buffer.",
           "re-factoring the SP speeds already buffered is not modelled (stored, D)."),
          ("INTERP_FACTOR", "0 takes the axis out of the vector speed (a following axis).",
           "every BASE axis takes part in the vector speed (stored, D)."),
          ("FEED_OVERRIDE", "The feed-rate override of embedded speed profiles "
           "(MOVECONTOUR).", "MOVECONTOUR's embedded profiles are not modelled (stored, "
           "D)."),
          ("MOVE_PA", "A value carried with each move loaded (MOVE_PA_CONT acts on it).",
           "outputs and values switched as moves become active are not modelled "
           "(stored, D)."),
          ("MOVE_PB", "As MOVE_PA.", "see MOVE_PA (stored, D)."),
          ("MOVE_PA_CONT", "What MOVE_PA does when a move becomes active.",
           "see MOVE_PA (stored, D)."),
          ("MOVE_PB_CONT", "As MOVE_PA_CONT, for MOVE_PB.", "see MOVE_PA (stored, D)."),
          ("MOVE_PA_IDLE", "MOVE_PA's setting while the axis is idle.",
           "see MOVE_PA (stored, D)."),
          ("MOVE_PB_IDLE", "As MOVE_PA_IDLE, for MOVE_PB.", "see MOVE_PA (stored, D)."),
          ("RAISE_ANGLE", "Corner angle beyond which CORNER_STATE starts its sequence.",
           "the CORNER_STATE machine (CORNER_MODE bit 2), which holds the move loader "
           "for a program's handshake, is not modelled (stored, D)."),
          ("OV_GAIN", "Output velocity gain of the servo loop.",
           "the shared servo filter has no measured-velocity term (stored, D)."),
          ("AFF_GAIN", "Acceleration feed-forward of the servo loop.",
           "its scaling to the shared filter's acceleration term is not published "
           "(stored, D)."),
          ("DAC", "The servo's output (written: the open-loop output).",
           "open-loop output of a servo with SERVO OFF is not modelled; the closed loop's "
           "output is not read here (stored, D)."),
          ("DRIVE_FE_LIMIT", "Following-error limit inside a digital drive.",
           "no digital (EtherCAT) drive in the world: the controller's own FE_LIMIT acts "
           "(stored, D)."),
          ("AXIS_UNITS", "Units of an axis in the robot (kinematic) system.",
           "the robot system is not modelled (stored, D)."),
          ("FRAME", "The robot (kinematic) frame of the axes.",
           "the robot system's transforms (FRAME, MOVEL, MOVEJ, TOOL_OFFSET, USER_FRAME) "
           "are not modelled: the pages found do not give each frame's equations exactly "
           "enough to be exact to the tick (stored, D)."),
      )],
    *[_command(name, summary, arity, axis=axis, confidence="D", note="Not modelled: " + why)
      for name, summary, arity, axis, why in (
          ("B_SPLINE", "B_SPLINE(...): expand TABLE data into a B-spline curve.", (5, 9),
           False, "its spline's exact construction (knots, end conditions) was not found "
           "in the pages (accepted, no effect, D)."),
          ("MOVEL", "MOVEL: a straight move in the robot frame.", (0, 0), True,
           "the robot system is not modelled (see FRAME; accepted, no effect, D)."),
          ("MOVEJ", "MOVEJ: a joint move in the robot frame.", (0, 0), True,
           "the robot system is not modelled (see FRAME; accepted, no effect, D)."),
          ("FRAME_TRANS", "FRAME_TRANS(...): a robot frame's transform.", (4, 5), False,
           "the robot system is not modelled (see FRAME; accepted, returns 0, D)."),
          ("TOOL_OFFSET", "TOOL_OFFSET(...): the robot's tool offset.", (0, 8), True,
           "the robot system is not modelled (see FRAME; accepted, returns 0, D)."),
          ("USER_FRAME", "USER_FRAME(...): the robot's user frame.", (0, 8), True,
           "the robot system is not modelled (see FRAME; accepted, returns 0, D)."),
          ("R_MARK", "R_MARK(channel): the newer registration channels' mark.", (1, 1), True,
           "the newer REGIST(20..) channels are not modelled (REGIST modes 1..9 are: "
           "MARK, MARKB); reads 0 (D)."),
          ("DLINK", "DLINK(function, ...): set up a drive link (a Trio or fieldbus drive).",
           (2, 5), False, "no digital drive in the world; the axis's own ATYPE and gains "
           "drive it (accepted, returns 0, D)."),
      )],
    # ---- constants, operators, modifiers --------------------------------------------------------
    _constant("TRUE", -1.0),
    _constant("FALSE", 0.0),
    _constant("ON", 1.0, source=f"{SEED}; {TOK}", note="ON is 1 (OFF is 0)."),
    _constant("OFF", 0.0),
    _constant("PI", math.pi),
    *[Keyword(op, Kind.OPERATOR, f"{op} operator.", f"{TOK}; {MAN}", "C",
              "Bitwise on the integer parts; comparisons give TRUE (-1) or FALSE (0)."
              if op != "MOD" else "Remainder of the integer parts (I).")
      for op in ("AND", "OR", "XOR", "NOT", "MOD")],
    Keyword("AXIS", Kind.MODIFIER, "AXIS(n) after a parameter or command: axis n instead of "
            "the base axis.", f"{SEED}; {TOK}", args=(1, 1)),
]

# Statements the parser handles itself (structure, declarations, errors).
_STATEMENTS = {
    "GOTO": "GOTO label: go on at the line after `label:`.",
    "GOSUB": "GOSUB label: call the routine at `label:`; RETURN comes back.",
    "RETURN": "Return from a GOSUB.",
    "ELSEIF": "ELSEIF cond THEN: another branch of a block IF.",
    "CONSTANT": "CONSTANT \"name\", value: a named constant for every program.",
    "GLOBAL": "GLOBAL \"name\", vr: a name for VR(vr) in every program.",
    "DIM": "DIM name[(n)] AS INTEGER|FLOAT|BOOLEAN|STRING(n): a local variable or array.",
    "AS": "Part of DIM.", "FLOAT": "Part of DIM.", "INTEGER": "Part of DIM.",
    "BOOLEAN": "Part of DIM.", "STRING": "Part of DIM: STRING(n).",
    "SELECT_CASE": "SELECT_CASE expr ... CASE v[, v] ... CASE ELSE ... END_CASE.",
    "CASE": "Part of SELECT_CASE.", "END_CASE": "Ends SELECT_CASE.",
    "BASICERROR": "ON BASICERROR GOTO label: a runtime error jumps to label.",
    "FUNCTION": "FUNCTION name(p [AS type], ...) [AS type] ... ENDFUNC: a function of the "
                "program, called as name(...); RETURN value gives its value.",
    "ENDFUNC": "Ends a FUNCTION (its value is then 0).",
}
_STATEMENT_NOTE = ("Handled by the parser and the process runner; the form is from the "
                   "token table and public programs (I).")


_FIELDBUS = ("ETHERCAT", "ECAT_", "AUTO_ETHERCAT", "CAN", "CO_", "SERCOS", "RTEX", "DEVICENET",
             "ANYBUS", "MODBUS", "ETHERNET", "IP_", "HLM_", "HLS_", "NW_", "NODE_", "DRIVE_",
             "REMOTE", "GET_EIP", "SET_EIP", "PROTOCOL", "COMMS", "PLC_", "DLINK", "SLOT")
_FIRMWARE = ("FLASH", "EPROM", "FPGA_", "BOOT_LOADER", "LOADSYSTEM", "LOAD_PROJECT", "STICK_",
             "SD_", "ZIP_READ", "TEXT_FILE_LOADER", "BREAK_", "TRON", "TROFF", "STEPINTO",
             "STEPLINE", "DUMP", "CPU_", "FPU_", "SERIAL_NUMBER", "FEATURE_ENABLE", "LOCK",
             "UNLOCK", "IS_ENCRYPTION", "SET_ENCRYPTION", "VALIDATE_ENCRYPTION", "PROJECT_",
             "HMI_", "LCDSTR", "DISPLAY", "UNIT_", "PEEK", "POKE", "FREE", "SYSTEM_LOAD",
             "TRIOPCTEST", "PENDANT", "USER_PID", "CUSTOM_FUNC", "FUNCTION_LIST", "EXEC")


def _why_not(name: str) -> str:
    """Why a token-table word is only accepted: a fieldbus or network word, or one of
    firmware, files, memory and debugging, has no effect an emulated machine shows; any
    other word is simply not modelled yet."""
    if name.startswith(_FIELDBUS):
        return ("a fieldbus, network or drive-bus word: the emulator has no bus or remote "
                "drive, so nothing it shows depends on it (D)")
    if name.startswith(_FIRMWARE):
        return ("firmware, files, memory, debugging or display: no effect an emulated "
                "machine shows (D)")
    return "not modelled yet: the machine does not act on it (D)"


def _from_token_table() -> list[Keyword]:
    """Every token-table word without a hand-written entry: its kind and arity from the
    table, its effect "not modelled" (D) unless named above."""
    from .tokentable import TOKENS

    known = {k.name for k in _ENTRIES}
    out: list[Keyword] = []
    for row in TOKENS.split("\n"):
        fields = row.split()
        if not fields or fields[1] in known:
            continue
        tag, name = fields[0], fields[1]
        if name in _STATEMENTS:
            out.append(_statement(name, _STATEMENTS[name], note=_STATEMENT_NOTE, confidence="I"))
        elif tag == "V":
            scope, access = int(fields[2]), fields[3]
            note = ("Not modelled: stored and read back, no effect on the machine; "
                    if access == "w" else "Not modelled: reads 0; ") + _why_not(name) + "."
            make = _axis if scope == 1 else _system
            out.append(make(name, f"Token-table {'axis' if scope == 1 else 'system'} "
                            f"parameter.", writable=access == "w", confidence="D", note=note))
        elif tag == "C":
            kind, low, high, modifier = fields[2], int(fields[3]), int(fields[4]), fields[5]
            if kind == "f":
                out.append(_function(name, "Token-table function.", (low, high),
                                     confidence="D",
                                     note=f"Not modelled: returns 0; {_why_not(name)}."))
            elif kind == "o":
                out.append(Keyword(name, Kind.OPERATOR, "Operator.", TOK))
            else:
                out.append(_command(name, "Token-table command.", (low, high),
                                    axis=modifier == "1", confidence="D",
                                    note="Not modelled: accepted, no effect on the machine, "
                                    f"as a function it returns 0; {_why_not(name)}."))
        elif tag == "M":
            out.append(Keyword(name, Kind.MODIFIER, f"{name}(n) modifier.", TOK, "C",
                               "Not modelled: SLOT(n) and PORT(n) keep a parameter's "
                               "value per number; the emulator has no module slots or "
                               "ports to act on (D).",
                               args=(1, 1)))
        elif tag == "T":
            out.append(_constant(name, float(fields[2])))
    return out


def _index(entries: list[Keyword]) -> dict[str, Keyword]:
    """The table by name; a keyword listed twice is an error at import."""
    table: dict[str, Keyword] = {}
    for entry in entries:
        if entry.name in table:
            raise ValueError(f"TrioBASIC keyword {entry.name} is listed twice")
        table[entry.name] = entry
    return table


KEYWORDS: dict[str, Keyword] = _index(_ENTRIES + _from_token_table())


def lookup(name: str) -> Keyword | None:
    return KEYWORDS.get(name.upper())

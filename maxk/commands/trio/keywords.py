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


CHANNEL_PARAMETERS = frozenset({"R_MARK", "R_REGPOS", "R_REGISTSPEED"})
"""Read-only axis parameters of one channel: NAME(channel) [AXIS(n)] (registration.py)."""
BANKED_PARAMETERS = frozenset({"MOTION_ERROR"})
"""System parameters with an optional bank of 64 axes: NAME(bank), 0..15 (help page)."""
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
               "world drives as a level acts when it changes (D). An axis a link drives "
               "(CONNECT, CAMBOX, MOVELINK, FLEXLINK, CONNPATH) has its link cancelled at "
               "once on the tick its demand meets the switch (C: the page issues CANCEL, "
               "which ends a linked move at once; linked_limits.py); see AXIS_MODE bits 1, "
               "3, 17 for CONNECT and ADDAX.")

ROBOT_WHY = ("the robot (kinematic) system beyond FRAME 2, 5, 6 and 10 (personalities/trio/"
             "frames.py): the other frames' equations, USER_FRAME, TOOL_OFFSET and "
             "VOLUME_LIMIT, and the RPS robots' kinematic models (KINEMATIC_GROUP robot "
             "types) are not built")
_FRAMES = ("FRAME 2 (XY single belt), 5 (2x2 rotation matrix and its inverse from TABLE), 6 "
           "(polar programming of an XY machine) and 10 (XY programming of a polar machine, "
           "its whole turns counted every servo cycle) are modelled, the equations of the "
           "FRAME page, on raw positions (DPOS * UNITS world, AXIS_DPOS * AXIS_UNITS axis)")
_ENTRIES: list[Keyword] = [
    # ---- axis parameters ------------------------------------------------------------
    _axis("ATYPE", "Axis type: what the axis's hardware drives and reads (servo, "
          "pulse/direction, encoder output, encoder input ...).", default=43,
          value_range=(0, 255), source=f"{HELP} ATYPE; {SEED}; {TOK}", confidence="I",
          note="Power-up 43, the seed's 'recommended default' (I). A type the help page's "
          "tables do not list is 'Parameter out of range', the type kept (D). The servo "
          "types (44 the flexible axis's analogue servo, 36, 46, 47, 48, 60, 77, 92, 94, "
          "102, 103: the page) run the shared servo loop alike on the world's motor and "
          "encoder (I: the feedback device does not change the loop); the absolute ones "
          "(46, 47, 48, 92) read the encoder as absolute: MPOS its count from the world's "
          "origin with no DATUM, ENCODER its ENCODER_BITS data bits (D). The outputs (43, "
          "63, 78, 100 pulse/direction; 45, 64, 84, 101 quadrature) put the demand out "
          "exactly, which an encoder input mounted on the shaft reads (I; 78 and 84's "
          "VFF_GAIN not modelled: the page does not say what it does, D). The encoder "
          "input types (76, 79, 86, 87, 88, 93, 104, 105) read the world's encoder mounted "
          "on the axis's input as MPOS (I). 35 and 36 give a PWM output on the Z channel "
          "(seed). Fieldbus, SLM, FlexSlice and analogue-feedback types are stored and "
          "follow their demand (no such drive in the world, D). See axistypes.py."),
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
          "page; buffered ones D; a single-axis move then ramps linearly, D: respeed.py). "
          "A plain move loaded at SPEED 0 loads (MTYPE shows it) and waits held at speed "
          "0, WAIT IDLE not passing, and starts with its ACCEL ramp at the servo tick "
          "SPEED is written above 0, its MOVELINKs with it (C: CONNPATH page example 2, "
          "MOVE_PA_IDLE page example 2, SPEED reset from the command line; the tick D); "
          "MERGE joins it only to moves held so. Written 0 while "
          "moves run, they keep their speed (D). ACCEL or DECEL 0, a CAM or a jog at "
          "SPEED 0 stay 'Parameter out of range' (D)."),
    _axis("ACCEL", "Acceleration, user units/s^2.", default=1000, value_range=(0, _BIG),
          source=f"{MAN}; {TOK}", note="Power-up 1000 (D). Written while moves run: as "
          "SPEED (C: VP_MODE page)."),
    _axis("DECEL", "Deceleration, user units/s^2.", default=1000, value_range=(0, _BIG),
          source=f"{MAN}; {TOK}", note="Power-up 1000 (D). Written while moves run: as "
          "SPEED (C: VP_MODE page; a path's moves ramp down at ACCEL, D)."),
    _axis("MERGE", "Merge consecutive moves without stopping (ON/OFF).", default=0,
          value_range=(-1, 1), source=f"{SEED} examples 1-2; {TOK}", confidence="I",
          note="A move joins the one before it (one path, corners at full speed) when MERGE "
          "of its base axis is ON as it is loaded and both are on the same axes (I). With "
          "SRAMP or JERK (see VP_MODE) the speed changes within and at the ends of a "
          "merged chain are S-ramps: the acceleration rises at JERK (or over SRAMP) to "
          "ACCEL, holds, and falls to 0 again before the next change, so it is "
          "continuous across the moves; each change of speed happens within one move, as "
          "with linear ramps; the chain ramps down to rest at ACCEL (D, as linear). A move "
          "loaded while a speed change runs takes effect once that ramp has ended (D: the "
          "acceleration never jumps; loaded during the last ramp down, the path comes to "
          "rest first)."),
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
            note="A servo axis (ATYPE 44, 36, 77 ...) moves only with WDOG ON (see SERVO); a "
            "motion error sets it OFF, unless the axis in error is in a DISABLE_GROUP: then it "
            "stays ON (C: help WDOG, DISABLE_GROUP). Pulse/direction axes run their demand "
            "whatever it is (I: the seed's example 1 loads its moves before WDOG=ON)."),
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
    _command("THROW_ERROR", "THROW_ERROR(message): stop with an error of that text.", (1, 1),
             source="TrioBASIC help THROW_ERROR; help RUN_ERROR", confidence="C",
             string_arg=True,
             note="The process stops, its error line carrying the message, RUN_ERROR 268 "
             "(C); ON BASICERROR catches it as any error (I); a number for the message is "
             "'Type mismatch' (D)."),
    _system("MOTION_ERROR_COUNT", "How many axes are in motion error: the bits set in "
            "MOTION_ERROR.", writable=False, source="TrioBASIC help MOTION_ERROR_COUNT",
            confidence="C"),
    _statement("STATIC", "STATIC name AS type[(sizes)] [= value]: a FUNCTION's variable or "
               "array set up on its first call only, keeping its value between calls.",
               source="TrioBASIC help STATIC", confidence="C",
               note="One store per FUNCTION for the controller's run, shared by the processes "
               "that call it (I: a library's function is one; D), and by a recursive call "
               "and the call it is in (I: 'like Visual Basic STATIC'); editing the program "
               "starts it afresh (D). Outside a FUNCTION it acts as DIM (D: the page allows it in "
               "functions only)."),
    _system("AXISSIZE", "Number of axes (BASE and AXIS take 0..AXISSIZE-1).", default=16.0,
            writable=False, source="TrioBASIC help AXISSIZE", confidence="C",
            note="16: the MC405's axes here, 0-4 on the board and 5-15 virtual (D)."),
    _system("BUFFERSIZE", "The largest move buffer, the most LIMIT_BUFFERED takes.",
            default=64.0, writable=False, source="TrioBASIC help BUFFERSIZE",
            confidence="C", note="64: LIMIT_BUFFERED's range here (D)."),
    _system("VRSIZE", "Number of VR elements (VR(0..VRSIZE-1)).", default=VR_COUNT,
            writable=False, source="TrioBASIC help VRSIZE", confidence="C",
            note=f"{VR_COUNT}: this emulator's VR array (the page: it varies by controller)."),
    _system("IOSIZE", "Number of digital I/O channels, real and virtual (0..IOSIZE-1).",
            default=1024.0, writable=False, source="TrioBASIC help IOSIZE", confidence="C",
            note="1024: the I/O numbers IN, OP and READ_OP take here (D: the page says it "
            "varies by controller)."),
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
             source=f"{TOK}; {MAN}", confidence="I", note="Ramps down at FASTDEC when it "
             "is set and greater than DECEL (C: CANCEL and FASTDEC pages), else a linear "
             "path at its ACCEL, one axis or an S-curve path at DECEL; buffered moves run "
             "after it; ends a CONNPATH/CAMBOX (I). Modes (C: CANCEL page): 1 drops the "
             "moves and linked moves buffered on the axis (from every axis of their group), "
             "the running one ends as planned; 2 drops them and cancels the running one; 3 "
             "to 6 act as 0 (D: not modelled); others 'Parameter out of range'. Moves merged "
             "into the running path are part of it: mode 1 leaves them (D)."),
    _command("RAPIDSTOP", "Cancel the moves on every axis.", (0, 1), source=f"{TOK}; {MAN}",
             confidence="I", note="Ramps the running moves down, at FASTDEC where it "
             "applies, as CANCEL (C: RAPIDSTOP page). Modes (C): 0 "
             "(default) cancels the running moves and links only, the buffered ones then "
             "load; 1 drops every buffered move, the running ones end as planned; 2 both."),
    _command("PWM_CONTROL", "PWM mode of the base axis: (0) off, (1) PWM_MARK, (2,...) "
             "speed link, (3,...) gate positions, (4) empty FIFO, (5) gating on, (6) clear "
             "PWM_ENCODER, (8,...) speed x profile.", (1, 6), axis=True,
             source=f"{SEED}; {TOK}", note="An axis function: AXIS() or BASE() picks the "
             "axis (seed). Refusals leave everything unchanged (personality DECISIONS)."),
    _command("CONNPATH", "Link an axis to the path distance of an interpolating group.",
             (1, 2), axis=True, source=f"{HELP} CONNPATH; {SEED}; {TOK}", confidence="I",
             note="CONNPATH(ratio, driving_axis), the page's form (C): the axis moves by "
             "ratio x the path distance of the group whose first axis is driving_axis; "
             "one argument is the driving axis at ratio 1 (the seed's CONNPATH(0) AXIS(8) "
             "for BASE(0,1), I). Path distance in base user units, until CANCEL (D)."),
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
             "monotonic, D); 512 starts on the link axis's R_MARK(link pos) at R_REGPOS "
             "exactly (channels 0..7, C; registration.py). Reserved bits: 'Parameter out "
             "of range' (D). "
             "Before a registration/absolute start the axis holds; a repeating CAMBOX "
             "does not run back past its start point (D). Multi-axis form: 8 TABLE values "
             "an axis, on the base axis and the axes after it (I), all checked first (C). "
             "A link axis that follows this axis is refused (D: no position). The TABLE is "
             "read live (C: TABLE_POINTER page, new values for passed locations while it "
             "runs): a TABLE write moves the cycle the link is in to the new values at "
             "once (they are positions from the profile's start, C), the cycles done keep "
             "what they moved (D), a buffered CAMBOX takes the TABLE it starts on."),
    # ---- linked moves, MHELICAL, MOVEMODIFY and the move reports (links.py, moves.py) ----
    _command("MHELICAL", "MHELICAL(end1, end2, centre1, centre2, direction, distance3[, "
             "mode]): MOVECIRC's arc on the first two BASE axes while the third moves "
             "distance3 along it.", (6, 9), axis=True, source=f"{HELP} MHELICAL; {TOK}; {MAN}",
             confidence="I", note="One arc segment of the shared path planner whose third "
             "axis rises in proportion to the arc, at the base axis's SPEED, ACCEL and "
             "DECEL: along the helix in mode 0 (the default), along the circle in mode 1, "
             "the third axis following (C: the MHELICAL page; lengths in counts, the page "
             "asking equal UNITS, I; merged after another move the run keeps its DECEL, "
             "D). A mode other than 0 or 1, or an 8th/9th argument other than 0, is "
             "refused (D). MTYPE 3."),
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
             "past the highest point (as CAMBOX's); 512 starts at the link axis's "
             "R_MARK(link pos) R_REGPOS (C: page; one start event at once, D). base_dist "
             "and reserved bits: 'Parameter out of range' (D). "
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
             "start), 4 (repeat), 32/16384 (forward only), 8192 and 512 (R_MARK(start pos) "
             "start) as MOVELINK's. "
             "Percentages outside 0..100 or pairs above 100: 'Parameter out of range' (D). "
             "Queued and ended as a MOVELINK, and reads MTYPE 22 (D: its own code is not "
             "in the pages found)."),
    _command("CONNECT", "CONNECT(ratio, link axis[, mode]): the base axis follows ratio x "
             "the link axis's movement (electronic gearbox) until CANCEL or RAPIDSTOP.",
             (2, 3), axis=True, source=f"{TOK}; {MAN}; {HELP} (CONNECT page)",
             confidence="I",
             note="Ratio in counts per count, not user units (C: manual, Trio support). "
             "Mode 0 (MPOS, the default) or 1 (DPOS) of the link axis, the page's third "
             "argument (the token table gives two: the page wins, C); both follow the "
             "demand here (D, below); another mode: 'Parameter out of range' (D). "
             "Follows the link axis's demand position (D). A second CONNECT on the same link "
             "axis changes the ratio at once from where both are; on another link axis it is "
             "ignored while the first runs (C: manual). Buffered behind moves and links like "
             "a move. A new ratio on the same link axis ramps at CLUTCH_RATE (see it). MTYPE 21. "
             "A limit (FWD_IN, FS_LIMIT ...) met by the axis cancels it at once, unless "
             "AXIS_MODE bit 1 (see it; C: help CONNECT)."),
    _axis("MOVELINK_MODIFY", "An offset (user units) to the end of the running MOVELINK.",
          source=f"{TOK}; {HELP} (MOVELINK_MODIFY page)", confidence="C",
          note="The running MOVELINK ends at its end plus the offset (ENDMOVE with it) "
          "if it is not decelerating and there is room; applied, it reads 0, else it "
          "keeps the offset (C). A MOVELINK of no distance has its link distance changed "
          "(C). Decided (D, links_modify.py): the offset is added over the link travel "
          "from now to the decel start as a symmetric S (2z^2, then 1 - 2(1-z)^2), so "
          "position and ratio stay continuous; room is 4|offset|/stretch^2 at most the "
          "peak ratio over the decel distance; a kept offset is tried again when the "
          "next MOVELINK starts; repeating MOVELINKs, ones waiting for their start and "
          "FLEXLINK keep it."),
    _axis("CLUTCH_RATE", "The rate (ratio per second) a running CONNECT changes its ratio "
          "at.", source=f"{TOK}; {HELP} (CLUTCH_RATE, CONNECT pages)", confidence="C",
          default=1e6,
          note="A second CONNECT on the same link axis moves the ratio towards the new one "
          "by CLUTCH_RATE x the servo period each servo cycle (the k-th cycle after it at "
          "old + k x step, capped: D), the axis moving that cycle's ratio x the link's "
          "demand change (clutch.py); the default 1,000,000 takes any change under 1000 "
          "at once (C). A fresh CONNECT takes its ratio at once (C: the CONNECT page's "
          "example connects at 0 first to avoid the step). The rate is read every cycle "
          "(D); negative: 'Parameter out of range' (D)."),
    _command("ADDAX", "ADDAX(axis): add that axis's demand movements to the base axis's "
             "own; ADDAX(-1) ends it.", (1, 1), axis=True, source=f"{TOK}; {MAN}",
             confidence="I", note="Count for count from when it is given (I); after "
             "ADDAX(-1) the axis keeps what was added. Not buffered: it acts at once (I). "
             "A loop of ADDAX/links is 'Parameter out of range' (D). MOVEABS on the axis "
             "aims its own moves, without the live ADDAX part (D). A limit met by the sum "
             "cancels the axis's own move; the ADDAX part runs on unless AXIS_MODE bit 17 "
             "(see AXIS_MODE; C: help ADDAX)."),
    _axis("MTYPE", "The type of move the axis runs: 0 idle, 1 MOVE, 2 MOVEABS, 3 MHELICAL, "
          "4 MOVECIRC, 5 MOVEMODIFY, 10 FORWARD, 11 REVERSE, 13 CAM, 14/15 FWD_JOG/REV_JOG, "
          "20 CAMBOX, 21 CONNECT, 22 MOVELINK, 23 CONNPATH, 26 COMPENSATE_XY, 30 MOVETANG, "
          "31 MSPHERICAL, "
          "40 MSPHERICALSP.", writable=False,
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
    _command("BASE", "Set the process's base axes; later axes follow in order.", (0, 128),
             source=f"{SEED}; {TOK}; {MAN}; TrioBASIC help BASE", confidence="I",
             note="BASE(4) makes the group 4,5,6,...,0,1,2,3 (manual). BASE alone prints "
             "the whole array, (1, 5, 9, 10, ...) (C: its example 3)."),
    _command("TABLE", "TABLE(start, v1, v2, ...) writes a run of TABLE values; TABLE(i) "
             "reads one.", (1, 128), source=f"{SEED}; {TOK}; help (TABLE_POINTER page)",
             note="A running or buffered CAMBOX or CAM reads its values live: see CAMBOX, "
             "CAM (C: TABLE_POINTER page)."),
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
             "named MC_CONFIG (power up still runs it first: help 'MC_CONFIG Program', "
             "run if present). An existing program is selected whatever its type; a type "
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
    _command("EX", "Restart the controller.", (0, 1), source=f"{REF}; TrioBASIC help EX",
             note="Echoes EX and CR LF, then nothing: the door closes the session and "
             "starts a new one (ref 5). In a program (C: its page allows it) the program "
             "ends there and the controller restarts after that servo cycle, the command "
             "lines staying open (D). The VRs are kept (C: EX's page, they remain in "
             "memory), as are the FLASH parameters and the programs; axis parameters and "
             "motion start again (page); TABLE too (D), but for FLASHVR(-1)'s copy and, "
             "with FLASH_DATA = 1, its first 4096 values (FLASH_DATA's page)."),
    # ---- housekeeping, loop words and data functions (issue 35e) ----------------------------
    _command("COPY", "COPY \"program\" \"newprogram\": copy a program under a new name.",
             (2, 2), source=f"{HELP} COPY", string_arg=True, confidence="I",
             note="The names quoted or bare, a space or comma between. The copy has the "
             "original's type and lines; a new name already in use is 'Program already "
             "exists' and a copy that does not fit the store is not kept (D)."),
    _command("RENAME", "RENAME oldname newname: rename a program.", (2, 2),
             source=f"{HELP} RENAME", string_arg=True, confidence="I",
             note="Lines, type and RUNTYPE go with the name; a running program is 'Program "
             "is running', a name in use 'Program already exists' (D)."),
    _command("CLEAR", "CLEAR: every VR to 0, and the local variables of the process.",
             (0, 0), source=f"{HELP} CLEAR", confidence="I",
             note="TABLE is kept (the page names VRs and local variables only, I); "
             "strings become empty (D)."),
    _command("RESET", "RESET: the process's local named variables to 0.", (0, 0),
             source=f"{HELP} RESET",
             note="DIM'd arrays are zeroed too, strings made empty (D)."),
    _command("LIST_GLOBAL", "LIST_GLOBAL [offset[, length]]: print the GLOBAL and "
             "CONSTANT definitions.", (0, 2), source=f"{HELP} LIST_GLOBAL", confidence="I",
             note="Numbered in the order they were first defined (the page's example: "
             "offset 1 is the second one); the GLOBAL table then the CONSTANT table, names "
             "in a 33-character column, constants with 5 decimals (page); length -1 is "
             "all. Names as first typed (the page lists them lower-case as defined)."),
    _command("TABLEVALUES", "TABLEVALUES(first, last[, format]): TABLE values as one "
             "comma-separated line.", (2, 3), source=f"{HELP} TABLEVALUES",
             note="Four decimals; format 1 writes a run of n equal values as kn,value "
             "(page's example). More than 10000 values at once is out of range (D)."),
    _command("EXIT_LOOP", "EXIT_LOOP: leave the innermost WHILE, FOR or REPEAT loop.",
             (0, 0), source=f"{HELP} EXIT_LOOP",
             note="Outside a loop it is a 'Structure error' at COMPILE (D); on the command "
             "line it does nothing (D)."),
    _command("CONTINUE", "CONTINUE: go on with the next pass of the innermost loop.",
             (0, 0), source=f"{HELP} CONTINUE", confidence="I",
             note="Jumps to the loop's WEND, NEXT or UNTIL, which decides the next pass "
             "(UNTIL's condition is tested, D); outside a loop a 'Structure error' (D)."),
    _command("CRC16", "CRC16(mode, ...): set up (0) or compute (1 legacy, 2) a CRC of TABLE "
             "or VR bytes.", (2, 5), source=f"{HELP} CRC16", confidence="I",
             note="Mode 1 is the augmented CRC (the data followed by zero bytes flushes "
             "it); mode 2 the direct CRC, reverse_input running it least significant bit "
             "first (Modbus with the page's example 5, I) and reverse_output reversing the "
             "result (D). Each value is taken as its low 8 bits (D). Not set up: 0 (page)."),
    _function("STRTOD", "STRTOD(format, ...): read a number from VRs or a channel.", (3, 5),
              source=f"{HELP} STRTOD", confidence="I",
              note="VR source: one character a VR, the index of the first character not "
              "read goes to VR(vr_index). Channel source (an OPEN file channel's waiting "
              "characters): the length read and the terminating character's code are "
              "stored, the characters and the terminator are taken (I). Format 3 puts "
              "letter codes in VR(vr_index + 0..25) for A..Z (the page's A = +0, D where "
              "its M example says 13) and returns their bit mask. At most 64 characters "
              "(D)."),
    _function("IEEE_IN", "IEEE_IN(b0..b3[, b4..b7]): the float these IEEE 754 bytes "
              "encode.", (4, 8), source=f"{HELP} IEEE_IN",
              note="Byte 0 is the high byte (page). A byte outside 0..255 is out of range, "
              "a NaN or infinity an 'Arithmetic error' (D)."),
    _function("IEEE_OUT", "IEEE_OUT(value, n[, size]): byte n of value as an IEEE 754 "
              "float.", (2, 3), source=f"{HELP} IEEE_OUT",
              note="Size 32 (default) or 64; byte 0 is the high byte (page)."),
    _command("INTEGER_READ", "INTEGER_READ(source, low, high): the two 32-bit words of a "
             "value's 64-bit pattern.", (3, 3), source=f"{HELP} INTEGER_READ",
             confidence="I",
             note="low and high take a variable, VR(n) or TABLE(n). A parameter or an "
             "INTEGER variable is a 64-bit integer, every other value a 64-bit float (D). "
             "Each word 0..$FFFFFFFF (the page's example 1 swaps its MSW/LSW labels: its "
             "parameter list is followed)."),
    _command("INTEGER_WRITE", "INTEGER_WRITE(destination, low, high): write the 64-bit "
             "pattern high:low.", (3, 3), source=f"{HELP} INTEGER_WRITE", confidence="I",
             note="A word may be -2^31..$FFFFFFFF (its 32 bits, D); a float pattern that is "
             "NaN or infinite is 'Parameter out of range' (D)."),
    _system("NIO", "NIO: the number of I/O points (the highest + 1).", writable=False,
            source=f"{HELP} NIO", confidence="D",
            note="32, as NIN and NOP: the points IN and OP address (D; the page: read only, "
            "the larger of the input and output counts)."),
    *[_system(name, f"{name}: the number of analogue {what} channels.", writable=False,
              source=f"{HELP} {name}", confidence="D",
              note=f"8: the channels {word}(0..7) takes (D).")
      for name, what, word in (("N_ANA_IN", "input", "AIN"), ("N_ANA_OUT", "output",
                                                               "AOUT"))],
    _axis("LOADED", "TRUE when no move is held in the axis's buffer behind the one "
          "running (NTYPE 0), else FALSE.", writable=False, source=f"{HELP} LOADED",
          confidence="I", note="Read as NTYPE = 0: the page's 'all moves loaded into the "
          "MTYPE buffer' (I)."),
    _function("IS_OPEN", "IS_OPEN #n: TRUE (-1) while channel n is open, else FALSE.",
              (1, 1), source=f"{HELP} IS_OPEN", confidence="I",
              note="Open means an OPEN not yet closed; the terminal channels read FALSE "
              "(D: none is opened by OPEN here)."),
    _axis("DEMAND_EDGES", "The demand position DPOS in encoder edges (DPOS x UNITS).",
          writable=False, source=f"{HELP} DEMAND_EDGES", confidence="I",
          note="DPOS x UNITS, unrounded (D: the page does not say whether it rounds)."),
    _command("SEEK", "SEEK #n, from, position: where the next read of a file starts.",
             (3, 3), source=f"{HELP} SEEK", confidence="I",
             note="From 0: position characters from the start (0 is the first, D: the "
             "page's example counts one less); from 1: from where reading is. A file open "
             "FOR INPUT only ('Channel not open' else, D); outside the file 'Parameter out "
             "of range' (D)."),
    _command("CHANNEL_WRITE", "CHANNEL_WRITE(channel, buffer[, count]): write a string, "
             "VRs or an INTEGER array's bytes to a channel; returns the count.", (2, 3),
             source=f"{HELP} CHANNEL_WRITE", confidence="I",
             note="To a file open FOR OUTPUT, or a terminal channel (0..19: the "
             "command-line hosts, D); a file open for reading is 'Parameter out of "
             "range' (D). Each value's low 8 bits (D); at most 4096 (D)."),
    _command("CHANNEL_READ", "CHANNEL_READ(channel, buffer[, delimiters[, escape[, "
             "crc]]]): read a channel's characters into VRs or a STRING.", (2, 7),
             source=f"{HELP} CHANNEL_READ", confidence="I",
             note="Stops when full, empty or at a delimiter (taken, not stored, I). VR "
             "form: VR(base) why it stopped (0, k-th delimiter), the characters from "
             "VR(base + 1) and a 0, at most size - 2 (D), returns the count; STRING form: "
             "returns -k for the k-th delimiter, else 0. The escape character is not "
             "stored (D). crc: CRC16 mode 2 with CRC16(0, ...)'s set-up, 0 without (D). "
             "Terminal channels have nothing to read in a program (D). Files' names drop "
             "a RAM:/SD: prefix and a .TXT extension (D). The channel may be written #n; "
             "a STRING buffer's delimiters may be a string or a VR base and count (page)."),
    _system("OUTDEVICE", "OUTDEVICE = n: the channel PRINT with no #channel writes to, "
            "this process only.", value_range=(0, 255), source=f"{HELP} OUTDEVICE",
            confidence="I",
            note="A process's own (starts 0). A file open FOR OUTPUT on that channel takes "
            "the text; every other channel reaches the command-line hosts (D: one "
            "terminal). DIR and the like are not redirected (D)."),
    _system("INDEVICE", "INDEVICE = n: the channel GET, INPUT, LINPUT and KEY with no "
            "#channel read, this process only.", value_range=(0, 255),
            source=f"{HELP} INDEVICE", confidence="I",
            note="A process's own (starts 0): a file open FOR INPUT on it is read."),
    _system("SCOPE_CYCLE_COUNT", "How many SCOPE capture cycles have started.",
            writable=False, source=f"{HELP} SCOPE_CYCLE_COUNT", confidence="I",
            note="One more at each TRIGGER of an armed SCOPE and at each new scan of a "
            "repeating one (TRIGGER(1)); read only (D: the page gives no write)."),
    Keyword("PROGRAM_NAME", Kind.SYSTEM_PARAMETER, "The name of the program a process "
            "runs (a string); PROC(n) for another process.", f"{HELP} PROGRAM_NAME", "C",
            "On the command line, or for a process running nothing: an empty string (D).",
            None, False),
    # ---- functions ---------------------------------------------------------------------------
    *[_function(name, f"{name}(x).", (1, 1), source=f"{TOK}; {MAN}")
      for name in ("ABS", "INT", "FRAC", "SGN", "SQR", "SIN", "COS", "TAN", "ATAN", "EXP",
                   "LN")],
    _function("ATAN2", "ATAN2(y, x).", (2, 2)),
    _function("BITCOUNT", "BITCOUNT(x): how many bits are 1 in x taken as a 64-bit integer.",
              (1, 1), source="TrioBASIC help BITCOUNT", confidence="C",
              note="The fraction is dropped, a negative value is two's complement (-1: 64, "
              "the page's examples); outside the signed 64-bit range 'Parameter out of range' "
              "(D). Known gap: numbers here are 64-bit floats, so a value past 2^53 has lost "
              "its low bits before BITCOUNT sees it (the page's $1001200240048008 counts 7, "
              "not 8)."),
    _function("VR", "Global variable VR(i); assign with VR(i)=value.", (1, 1),
              source=f"{TOK}; {MAN}; TrioBASIC help VR", note=f"VR(0..{VR_COUNT - 1}) "
              "(count I: public programs clear VR 0..65535). VR(n) = \"text\" writes one "
              "character code a VR from n and a 0 after them, read back by VRSTRING(n) "
              "(C: VR's page, example 4). FOR VR(n) = a TO b ... NEXT VR(n) counts in "
              "the VR (C: example 2)."),
    _function("IS_PROG", "TRUE (-1) when the program exists.", (1, 1), source=REF,
              string_arg=True, confidence="I", note="atrio tests it for truth; -1 is "
              "TrioBASIC's TRUE (I)."),
    _function("IS_FILE", "TRUE (-1) when the file (a program of the store) exists.", (1, 1),
              source="TrioBASIC help IS_FILE", string_arg=True, confidence="C",
              note="The page: IS_FILE and IS_PROG do the same; `IS_FILE \"name\"` or with "
              "brackets."),
    _function("PROG_TYPE", "The program's type code, -1 when missing.", (1, 1), source=REF,
              string_arg=True),
    # ---- statements ---------------------------------------------------------------------------
    _statement("PRINT", "Print expressions and strings; ',' tabs, ';' joins, a final ';' "
               "keeps the line open. '?' is the same.", source=f"{REF}; {MAN}",
               note="A FLOAT prints with 4 decimals even when whole, any other value bare "
               "when whole (help INT example 2; atrio needs ?<integer> and ?MPE bare, ref "
               "3), else with 4: the types are in printformat.Real and docs/trio.md (I). "
               "Formats (TrioBASIC help PRINT, C): x[d] d decimals; x[w, d] in w characters, "
               "negative w left justified; x[\"%...\"] a C format string (%f %F %e %E, 4 "
               "decimals by default; %L, %W and %X 64-bit; %R %S strings; %C a character) "
               "with the text around it echoed."),
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
            value_range=(-1, top), source=f"{HELP}; {TOK}; {MAN}", confidence="I",
            note=f"-1 or 0..{top}: {span} (C). "
            "The input is active low (its help page, C): the function is on while "
            "IN(n) reads 0. IN(n) of that input reads the world's "
            f"{switch} switch of this axis at its position, wired normally closed: 1 away "
            "from it, 0 on it (D: as the pages' examples wire their sensors), unless the "
            "world drives input n itself (then its level); INVERT_IN inverts both what IN "
            "reads and the function." + stop)
      for name, what, switch, stop, top, span in (
          ("FWD_IN", "forward limit", "plus-limit", _LIMIT_STOP.format(bit=4), 63,
           "the page's range, built-in or expansion inputs"),
          ("REV_IN", "reverse limit", "minus-limit", _LIMIT_STOP.format(bit=5), 63,
           "the page's range, built-in or expansion inputs"),
          ("DATUM_IN", "datum (home) switch", "home", " DATUM(3..6) search for it.", 1023,
           "the page's 0..IO_Max, IO_Max taken as the last I/O number IN reads (IOSIZE - 1, "
           "I)"))],
    _axis("FS_LIMIT", "Forward software limit, user units.", default=200000000000,
          source=f"{TOK}; {MAN}", confidence="I", note="Power-up value (I). DPOS beyond it "
          "sets AXISSTATUS bit 9 (512). A motion reaching it (the first servo tick DPOS is at "
          "or beyond it) is cancelled there and ramps down to zero (manual: 'ramp down the "
          "speed to zero then cancel the move', C), at FASTDEC or DECEL as a hard limit; "
          "moves further forward are cancelled as they start (I). On an axis a link "
          "drives, the link is cancelled at once on the tick DPOS meets it (C: CANCEL page; "
          "DPOS compared, D; linked_limits.py), as at FWD_IN."),
    _axis("RS_LIMIT", "Reverse software limit, user units.", default=-200000000000,
          source=f"{TOK}; {MAN}", confidence="I", note="As FS_LIMIT: AXISSTATUS bit 10 "
          "(1024) while DPOS is below it (manual, C); it stops reverse motion the same way."),
    _axis("FASTDEC", "Deceleration at a limit, user units/s^2 (0: DECEL).", default=0,
          value_range=(0, _BIG), source=f"{TOK}; {MAN}", confidence="I",
          note="A move or path stopped by CANCEL, RAPIDSTOP or a limit (hard or soft) ramps "
          "down at FASTDEC when it is greater than DECEL (C: FASTDEC, CANCEL, RAPIDSTOP "
          "pages), else at DECEL (a linear path: its ACCEL, D); a jog released and a datum "
          "search stop at DECEL (D: their pages name DECEL only)."),
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
          "I). A bit of AXISSTATUS AND ERRORMASK on an axis not in error (ANDed every "
          "servo cycle: page; looked at on every event and the cycle after a clear, D) "
          "sets the axis's MOTION_ERROR bit (C) and stops every axis at once, drops the "
          "buffered moves, ends the links and sets WDOG OFF (I: help ERRORMASK, CANCEL); "
          "an axis of a DISABLE_GROUP stops its group only (see it); bits 9/10 act on the "
          "servo cycle DPOS first passes the limit (C: AXISSTATUS page, 'greater than'). "
          "DATUM(0)/(7) clears on its own cycle; an axis still standing on a limit whose "
          "bit ERRORMASK holds is in error again the next servo cycle (I: ERRORMASK's "
          "every cycle, DATUM's: only the flags are reset)."),
    _system("MOTION_ERROR", "Axes in motion error: bit n set for axis n.", writable=False,
            source=f"{HELP} MOTION_ERROR; {TOK}", confidence="I",
            note="Set by ERRORMASK (see it), cleared by DATUM(0), one axis's bit by DATUM(7) "
            "(C: help DATUM). MOTION_ERROR(bank), 0..15 (C): bank 0 holds the 16 axes, the "
            "others read 0 (C: 64 axes a bank); another bank: 'Parameter out of range' (D). A "
            "move on an axis in error is refused with 'Axis in error' (D: the text is ours)."),
    _system("ERROR_AXIS", "The axis that caused the motion error (0: none).",
            default=0, writable=False, source=f"{HELP} ERROR_AXIS; {TOK}", confidence="C",
            note="The axis that made MOTION_ERROR non-zero (C: help MOTION_ERROR's example "
            "1); 0 at power-up and after DATUM(0) (C), and after a DATUM(7) that leaves no "
            "axis in error (D); a DATUM(7) of another axis keeps it (D)."),
    _axis("FE", "Following error: DPOS - MPOS, user units.", writable=False,
          source=f"{TOK}; {MAN}", confidence="I",
          note="On a servo axis (ATYPE 44, 36, 77 ... with P_GAIN above 0) the shared loop "
          "drives the world's motor and FE is the demand less the encoder (I); on any "
          "other axis it is 0, the axis following its demand exactly (D)."),
    _axis("FE_RANGE", "Following error warning range, user units (0: off).",
          value_range=(0, _BIG), source=f"{TOK}; {MAN}", confidence="I",
          note="|FE| beyond it sets AXISSTATUS bit 1 (2) (I)."),
    *[_axis(name, f"Servo gain: {what}.", value_range=(0, _BIG), source=f"{TOK}; {MAN}",
            confidence="D", note=f"With a servo ATYPE (44, 36, 77 ...) and P_GAIN above 0 "
            f"the axis runs the shared servo loop (the MAXk's PID on the world's motor "
            f"plant) as {term} (D: "
            "the MC405's own scaling is not published here). Power-up 0: the exact, "
            "profile-only axis (D).")
      for name, what, term in (
          ("P_GAIN", "proportional", "KP: DAC counts per count of error"),
          ("I_GAIN", "integral", "KI/1024: DAC counts per count summed each servo cycle"),
          ("D_GAIN", "derivative", "KD: DAC counts per count of change of the error"),
          ("VFF_GAIN", "velocity feed forward", "KV: DAC counts per count per servo "
           "cycle of demand speed"))],
    # ---- the servo output: open loop, the other gains, its limit (issue 35) -------------
    _axis("DAC", "Open-loop output of a servo axis, DAC counts (12-bit: 2047 = 10 V).",
          source=f"{HELP} DAC, SERVO", confidence="C",
          note="With SERVO OFF, WDOG ON and AXIS_ENABLE ON a servo axis (ATYPE 44, 36, "
          "77 ...) puts it out, limited to +/-OUTLIMIT, and the world's motor runs under "
          "it (MPOS reads "
          "its encoder; DPOS reads MPOS and FE 0 while SERVO or WDOG is OFF, help DPOS, C; "
          "the demand takes MPOS when the loop closes, I); with WDOG or AXIS_ENABLE OFF "
          "the output is 0 (C). On the shared 16-bit output it is 16 x the value (D). The "
          "axis keeps its loop from then on, also with P_GAIN 0 (D). Reads back what was "
          "written (D)."),
    _axis("DAC_OUT", "The output of the axis's servo on the last servo cycle, DAC counts.",
          writable=False, source=f"{HELP} DAC_OUT", confidence="I",
          note="SERVO OFF: the DAC value within OUTLIMIT (0 with WDOG or AXIS_ENABLE OFF, "
          "C); SERVO ON: the closed loop's last output / 16 (the shared 16-bit output in "
          "12-bit counts, D), times DAC_SCALE's sign, the output of the servo cycle before "
          "the one read also where the loop ran in closed form (C). 0 on an axis without "
          "a loop (D)."),
    _axis("DAC_SCALE", "Multiplier of the closed loop's output (its sign: polarity).",
          default=1, value_range=(-16, 16), source=f"{HELP} DAC_SCALE", confidence="I",
          note="Power-up 1 (MC405, C). The gains act times |DAC_SCALE| (integer part) and "
          "a negative value inverts the closed loop's output (C); the open-loop DAC is "
          "not scaled (C). Range -16..16 (D)."),
    _axis("OUTLIMIT", "Limit of the DAC output, DAC counts.", default=2047,
          value_range=(0, 2047), source=f"{HELP} OUTLIMIT", confidence="I",
          note="Power-up 2047: the full +/-10 V of the MC405's 12-bit DAC (I). Limits the "
          "open-loop DAC (C); the closed loop saturates at the shared output's +/-10 V "
          "and is not limited further (D: a limit inside the shared filter is not "
          "modelled)."),
    *[_axis(name, f"The same parameter as {same}.", writable=same == "DAC",
            source=f"{HELP} {name}", confidence="C",
            note=f"Another name of {same}: reads and writes {same} itself.")
      for name, same in (("S_REF", "DAC"), ("T_REF", "DAC"), ("S_REF_OUT", "DAC_OUT"),
                         ("T_REF_OUT", "DAC_OUT"))],
    *[_axis(name, summary, source=f"{HELP} {name}", confidence="I", note=note)
      for name, summary, note in (
          ("D_ZONE_MIN", "DAC dead band: the output clamped to 0 at rest below it.",
           "Once the axis's motion is over and |following error| is below it, the closed "
           "loop's output is 0 (C) until the error passes D_ZONE_MAX or a motion starts "
           "(C), decided every servo cycle on the loop's own error. In user units of "
           "following error, as FE (x UNITS: counts, D). While it or an offset is set the "
           "shared loop is stepped cycle by cycle (the filter is no longer linear). 0 "
           "(power-up): no dead band."),
          ("D_ZONE_MAX", "DAC dead band: the loop acts again above it.",
           "See D_ZONE_MIN. Below D_ZONE_MIN it is taken as D_ZONE_MIN (D)."),
          ("POS_OFFSET", "Piezo DAC offset while the loop demands a positive output.",
           "Added to the closed loop's output on each servo cycle it is positive, after "
           "DAC_SCALE (C): in the MC405's DAC counts (x16 on the shared output, as DAC, D); "
           "DAC_OUT shows it; the open-loop DAC is not offset (D). Stepped cycle by cycle "
           "as D_ZONE_MIN."),
          ("NEG_OFFSET", "Piezo DAC offset while the loop demands a negative output.",
           "As POS_OFFSET on each cycle the output is negative (the page: a negative "
           "value; any value is taken, D)."),
      )],
    _axis("FE_LIMIT_MODE", "1: FE_LIMIT must be exceeded on two servo cycles in a row.",
          value_range=(0, 1), source=f"{HELP} FE_LIMIT_MODE", confidence="C",
          note="0 (power-up): AXISSTATUS bit 8 on the first cycle |FE| passes FE_LIMIT; 1: "
          "on the second of two cycles in a row, a single cycle beyond it is ignored (C). "
          "The cycle before is the servo loop's own last error (sub-count, D)."),
    _axis("OV_GAIN", "Output velocity gain: times the change of the measured position.",
          source=f"{HELP} OV_GAIN", confidence="C",
          note="Adds OV_GAIN x (MPOS change over the servo cycle, counts) to the output "
          "(C), exactly: the shared filter runs it as OV_GAIN added to the velocity "
          "feed-forward and taken from D_GAIN, since the measured change is the demand's "
          "change less the error's (I). Normally negative (damping). Scaling as the other "
          "gains (D)."),
    _axis("AFF_GAIN", "Acceleration feed-forward: times the change of demand speed.",
          source=f"{HELP} AFF_GAIN", confidence="I",
          note="Adds AFF_GAIN x (change of the demand speed over the servo cycle, counts "
          "per cycle per cycle) to the closed loop's output: the shared filter's "
          "acceleration feed-forward (scaling D, as the other gains)."),
    _axis("ENCODER", "Raw copy of the axis's feedback register, counts.", writable=False,
          source=f"{HELP} ENCODER", confidence="I",
          note="The count of the encoder the axis reads, with no DEFPOS, UNITS or "
          "ENCODER_RATIO (C): a servo axis's world motor encoder, an encoder input's "
          "mounted encoder (ATYPE 76 ...), else (no feedback: a stepper, a virtual axis) "
          "the demand counts, whole (D). A 32-bit register: wraps at +/-2^31 (D)."),
    _command("ENCODER_RATIO", "ENCODER_RATIO(mpos_count, input_count): MPOS counts per "
             "encoder count.", (0, 3), axis=True, source=f"{HELP} ENCODER_RATIO; {TOK}",
             confidence="I",
             note="On an encoder input (ATYPE 76 ...) MPOS and DPOS count mpos_count / "
             "input_count x the encoder's counts (C); MPOS keeps its value when the ratio "
             "changes (DEFPOS's offset takes the difference, D). Whole numbers up to "
             "16777215, input_count above 0, mpos_count not 0 (negative reverses the "
             "axis, C), else 'Parameter out of range'; no arguments: 1:1 (D); 1 or 3 "
             "arguments: 'Syntax error' (D). Power-up 1:1. On a servo axis MPOS counts the "
             "ratio x the motor encoder's edges and the loop closes on MPOS, its gains per "
             "MPOS count (C: 'affects all motion commands', the gains to adjust): the "
             "shared loop runs in MPOS counts; a change at rest keeps the motor, DPOS and "
             "MPOS (to half a count: DEFPOS's offset takes it up, D) and is refused with "
             "'Parameter out of range' while the axis moves (D)."),
    _axis("PP_STEP", "An integer multiplier on the encoder value: an encoder input's MPOS "
          "counts PP_STEP x ENCODER_RATIO x its encoder's counts (UNITS then divides).",
          default=1.0, source=f"{HELP} PP_STEP; {TOK}", confidence="I",
          note="A whole number in the page's recommended -1024..1023, not 0 (D), else "
          "'Parameter out of range'; MPOS keeps its value at the change, as for "
          "ENCODER_RATIO (D). Power-up 1 (C). On a servo axis it scales the loop's "
          "feedback as ENCODER_RATIO does (I: the page's note on servo gains)."),
    _axis("AXIS_MODE", "Feature bits of the axis (its page's table); bit 14 ignores the "
          "software limits, bit 8 compares DPOS with them.", source=f"{HELP} AXIS_MODE; {TOK}",
          confidence="I",
          note="Bit 14: FS_LIMIT/RS_LIMIT neither stop a move nor set AXISSTATUS bits 9/10 "
          "while it is set (C; axismode.py). Bit 8 set: the limits are compared with DPOS "
          "(exact to the tick, C); clear (power-up): with MPOS (C), which differs only on "
          "a servo axis: its loop's measured position is watched on every servo cycle of "
          "its own move, the move ramps down (FASTDEC/DECEL) from the cycle MPOS reaches "
          "the limit, and AXISSTATUS bits 9/10 read MPOS (I). Bit 1: a CONNECT meeting a "
          "limit is not cancelled, its ratio goes to 0 at CLUTCH_RATE while the limit is "
          "on and back to its ratio when it goes off (C: CONNECT page; back: D). Bit 3: a "
          "limit's cancel ends the axis's ADDAX (C: CANCEL page). Bit 17: an axis with "
          "ADDAX meeting a limit cancels its master's current move at FASTDEC/DECEL (C: "
          "ADDAX page; the direct master only, D); clear, the ADDAX part runs on (C). "
          "(linked_limits.py.) Stored, no effect (D): bits "
          "2 (CORNER_MODE's angles are 2D), 4 (the shared path planner always looks ahead), "
          "6 and 15 (the world has no analogue or dual feedback), 9 and 13 (the page gives "
          "no rule for what they change in the following error), 10 (no robot jog), 11 "
          "(a move's end is fixed when it is buffered), 12 (the page gives no rule for the "
          "shortest way) and 16 (an inverted motor is the world's wiring)."),
    _axis("POSI_SEQ_MODE", "The delay filter on DPOS: 0 off, 1 delay, 2 the mean of the "
          "newest and the delayed value.", value_range=(0, 2),
          source=f"{HELP} POSI_SEQ_MODE", confidence="I",
          note="1: the axis puts out its demand of POSI_SEQ_DELAY servo cycles ago, 2: the "
          "mean of that and the newest (C); not delayed until the buffer is full (C). The "
          "demand of every cycle is kept while it is on (bounded: the delay + 1 values, "
          "posiseq.py), so the output is exact to the tick. DPOS reads the output (C: "
          "'overwrite demand position'), as do MPOS of an axis without a servo loop, a "
          "stepper's world motor and a servo axis's loop (its command, I); moves and "
          "links plan from the undelayed demand, and a limit switch is found where the "
          "undelayed demand meets it (D). The buffer restarts when the mode or the delay "
          "is written (D). Power-up 0 (C)."),
    _axis("POSI_SEQ_DELAY", "The delay of POSI_SEQ_MODE's filter, servo cycles.",
          value_range=(0, 10000), source=f"{HELP} POSI_SEQ_DELAY", confidence="I",
          note="Whole servo cycles (a fraction is cut, D), 0..10000 (D: a bound on the "
          "buffer), else 'Parameter out of range'; 0 delays nothing. Power-up 0 (C)."),
    _axis("ENCODER_BITS", "Data bits of an SSI/EnDat absolute encoder.",
          value_range=(0, 65535), source=f"{HELP} ENCODER_BITS, ENCODER, ATYPE",
          confidence="I", note="On an absolute-feedback servo (ATYPE 46, 47, 48, 92) "
          "ENCODER reads the encoder's count in these data bits (modulo 2^bits): SSI and "
          "BiSS bits 0-5, EnDat bits 0-7 the total bits (C: the page's fields); Tamagawa "
          "(46) 17 bits whatever it holds (D). MPOS does not wrap (C: help ENCODER, "
          "'allowing for overflows'). 0 ('no data clocked out'): the register reads the "
          "whole count and the loop keeps the world's encoder (D). SSI bit 6 (binary/Gray) "
          "and bits 8-10 (status shift) change nothing the world's encoder shows; bit 7 "
          "(reverse) is not modelled (D). Stored on any other axis."),
    _function("ENCODER_READ", "ENCODER_READ(address): read a register of an EnDat absolute "
              "encoder.", (1, 2), source=f"{HELP} ENCODER_READ; {TOK}", confidence="I",
              note="The world has only incremental encoders, so no EnDat encoder is "
              "initialised: returns -1 (C) and sets ENCODER_CONTROL of the base axis to 1 "
              "(C). The address a whole number from 0, else 'Parameter out of range' (D)."),
    _function("ENCODER_WRITE", "ENCODER_WRITE(address, data): write a register of an EnDat "
              "absolute encoder.", (2, 2), source=f"{HELP} ENCODER_WRITE; {TOK}",
              confidence="I", note="No EnDat encoder in the world: returns FALSE (the write "
              "fails, C) and sets ENCODER_CONTROL of the base axis to 1 (C)."),
    *[_axis(name, summary, writable=writable, default=default, confidence="D",
            source=f"{HELP} {name}", note="Not modelled: " + why)
      for name, summary, writable, default, why in (
          ("DRIVE_FE_LIMIT", "Following-error limit on a remote drive's own FE.", True,
           20000.0, "it bounds DRIVE_FE, the error a fieldbus (EtherCAT) drive reports; the "
           "world has no remote drive, so DRIVE_FE is never reported (the controller's own "
           "FE_LIMIT acts). Power-up 20000 (C)."),
          ("ENCODER_CONTROL", "EnDat encoder mode: 0 position, 1 parameter read/write.", True,
           0.0, "no EnDat encoder in the world; ENCODER_READ and ENCODER_WRITE set it to 1 "
           "as the page says (stored)."),
          ("ENCODER_STATUS", "Status and alarm fields of a Tamagawa absolute encoder.", True,
           0.0, "absolute encoders only: reads 0, as the page gives for an encoder not "
           "initialised (stored)."),
          ("ENCODER_TURNS", "Multi-turn count of an EnDat/Tamagawa absolute encoder.", True,
           0.0, "absolute encoders only; the world's encoders are incremental (stored)."),
          ("ENCODER_ID", "Identification of a Tamagawa absolute encoder.", True, 0.0,
           "absolute encoders only; the world's encoders are incremental (stored)."),
          ("ENCODER_FILTER", "Filter on an encoder's feedback against jitter.", True, 1.0,
           "the world's encoders have no jitter, so the filter of a jitter-free count is "
           "not applied (stored; power-up 1: no filtering, C)."),
          ("PS_ENCODER", "Raw copy of the hardware position-switch encoder.", False, 0.0,
           "the hardware position switch (HW_PSWITCH) is not modelled: reads 0."),
          ("INVERT_STEP", "Rising (ON) or falling step edge active.", True, 0.0,
           "the world's stepper turns on whole steps, not on pulse edges; the only effect "
           "the manual gives (a step lost at a reversal when the setting does not match "
           "the drive, 'may') depends on the drive's active edge, which the world does "
           "not describe (stored)."),
          ("MICROSTEP", "Discontinued.", True, 0.0, "a reserved, discontinued word (help "
           "MICROSTEP): stored."),
          ("PLM_OFFSET", "SLM/PLM motor encoder offset.", True, 0.0,
           "SLM interface only; the MC405 has no SLM (see DLINK; stored)."),
          ("AXIS_ERROR_COUNT", "Communication errors counted on a digital axis.", True, 0.0,
           "the emulator has no digital axis bus to fail: stays as written (power-up 0)."),
      )],
    _system("SERVO_OFFSET", "Start of the servo work within the servo period.",
            source=f"{HELP} SERVO_OFFSET; {TOK}", confidence="D",
            note="Not modelled: firmware scheduling inside one servo period, which the "
            "emulator runs as one instant (stored)."),
    _system("MPE_MODE", "The command line's Motion Perfect protocol mode.", writable=False,
            source=f"{HELP} MPE_MODE; {TOK}", confidence="D",
            note="Not modelled: reads 0 (no protocol: direct mode), as every session the "
            "emulator serves is; the Motion Perfect protocols are not emulated."),
    _command("ADD_DAC", "ADD_DAC(axis): add another axis's loop output to this one's.",
             (1, 1), axis=True, source=f"{HELP} ADD_DAC; Omron TJ1-MC04 and TJ2-MC64 "
             f"programming manuals, ADD_DAC; {TOK}", confidence="I",
             note="The base axis's DAC (and DAC_OUT) is its own output (its loop's with "
             "SERVO ON, its DAC with SERVO OFF: the TJ manuals' figure and second "
             "example) plus the added axis's (C). The added axis (a servo ATYPE with "
             "gains: the page) runs "
             "the shared filter with its own gains on its demand (with ADDAX's part) less "
             "its MPOS, read from the encoder the world mounts on its input (`@world N "
             "shaft-encoder M RATIO`; none mounted: the base's motor count for count, D) "
             "times its ENCODER_RATIO, on the base loop's encoder sample every cycle (I); "
             "with its SERVO OFF its open-loop DAC is added instead (I), it drives no "
             "motor of its own (D), its "
             "FE is compared with FE_LIMIT on every cycle as a servo axis's (I). "
             "The base keeps its loop from then on, also with P_GAIN 0 (D). -1 ends it; "
             "the axis itself, one out of range or a chain is 'Parameter out of range' "
             "(D). See add_dac.py."),
    *[_command(name, summary, arity, axis=True, source=f"{HELP} {name}; {TOK}",
               confidence="D", note="Not modelled: " + why)
      for name, summary, arity, why in (
          ("HANDWHEEL_AXIS", "Reserved keyword.", (0, 2), "a reserved word without a help "
           "page (accepted, no effect)."),
          ("JOG_OPERATION", "Reserved keyword.", (1, 1), "reserved (help JOG_OPERATION: "
           "'Reserved Keyword'): accepted, no effect, returns 0."),
      )],
    # ---- a stepper's output stage (issue 35: stepratio.py, backlash.py) ------------------
    _command("STEP_RATIO", "STEP_RATIO(output_count, dpos_count): steps out per demand "
             "count.", (0, 3), axis=True, source=f"{HELP} STEP_RATIO; {TOK}", confidence="I",
             note="The axis's world motor turns demand counts x output_count / dpos_count "
             "steps: its limit switches (found to the tick) and the encoder the world mounts "
             "on its shaft see that (C); DPOS, UNITS and moves are unchanged (C). The world's "
             "steps are the step generator's counts: the page's divide by 16 is not applied "
             "(D). A change leaves the motor where it is (D). Whole counts 0..16777215, "
             "dpos_count above 0, else 'Parameter out of range'; a negative output_count "
             "reverses the step output (ENCODER_RATIO and AXESDIFF pages' STEP_RATIO(-1, 1), "
             "I); no arguments: 1:1, one or "
             "three: 'Syntax error' (D). Power-up 1:1. Not on a servo axis's loop (the "
             "shared loop runs in the motor encoder's counts) nor the Z mark searches (D)."),
    _command("COMPENSATE_XY", "COMPENSATE_XY(table, opt, x_axis, x_div, x_dist, x_offset, "
             "y_axis, y_div, y_dist, y_offset): a correction interpolated in a 2D TABLE "
             "grid from the X and Y axes' positions, superimposed on the axis.", (10, 10),
             axis=True, source=f"{HELP} COMPENSATE_XY, MTYPE; {TOK}", confidence="I",
             note="x_div x y_div values from table, X fastest, evenly spread over x_dist "
             "from x_offset (y likewise), interpolated linearly in both; outside the "
             "working area the nearest value inside it; the correction when given is "
             "taken off (no jump); MTYPE 26 until CANCEL; distances in the X/Y axes' "
             "units, TABLE values in the axis's (C). Decided (D, compensate.py): a linked "
             "move, buffered as CAMBOX; opt 0 (MPOS) and 1 (DPOS) both follow the X and Y "
             "axes' demand, as every link here (equal on virtual axes and steppers; a servo "
             "X or Y axis's following error is left out); the "
             "grid and UNITS are read when it is given; X or Y the axis itself: 'Invalid "
             "axis number', following it, a division count not whole from 1, a distance "
             "not above 0, a grid past TABLE or opt not 0/1: 'Parameter out of range'."),
    _command("BACKLASH", "BACKLASH(enable[, distance, speed, accel]): backlash compensation "
             "moves.", (1, 4), axis=True, source=f"{HELP} BACKLASH; {TOK}", confidence="I",
             note="After each reversal of the axis's own motion (a move, a path, a stop; "
             "the plan's direction changes, exact to the instant) a trapezoidal move at "
             "speed and accel (user units) takes the compensation to +distance going "
             "forward, 0 in reverse, superimposed on the output (C: page); a reversal "
             "during one starts the next from there, from rest (D). The first motion after "
             "ON counts when it goes forward (D: the page's example). MPOS of an axis "
             "without a servo loop reads DPOS + BACKLASH_DIST, a stepper's world motor (its "
             "switches, a shaft encoder) turns it, a servo axis's loop takes it in its "
             "command (MPOS moves by it, FE stays the loop's error, I; the loop is then "
             "stepped cycle by cycle) (C); DPOS never does. Values not given "
             "keep the last ones (power-up 0, D); speed or accel 0: at once (D); OFF takes "
             "it back to 0 at its speed (D); a negative speed or accel, or any value of "
             "2^53 counts or more, is 'Parameter out of range'. Left out (D): reversals "
             "of a linked axis (CONNECT, CAMBOX ...) "
             "and the compensation in the limit search."),
    _axis("BACKLASH_DIST", "The backlash compensation being applied, user units.",
          writable=False, source=f"{HELP} BACKLASH_DIST; {HELP} BACKLASH", confidence="I",
          note="BACKLASH's compensation at the servo tick it is read (exact: the "
          "compensation move is closed form). Read only (D: the page gives it as what "
          "is applied). 0 with no BACKLASH."),
    _command("DLINK", "DLINK(function, ...): the SLM digital drive interface (2, 3: is an "
             "SLM module / drive there; 4: assign an axis; 5, 8, 10: read; 6, 7: write; 9: "
             "slot and channel of an axis).", (2, 5), source=f"{HELP} DLINK; {TOK}",
             confidence="I",
             note="The MC405 has no SLM slot and the world no SLM module or drive, so each "
             "function answers as the page says when nothing answers: 2 and 3 return 0, 4 "
             "returns FALSE and leaves ATYPE (it would set 11), 6 and 7 return FALSE, 5, 8, "
             "9 and 10 return -1 (C from the page, I for the MC405). Each function's "
             "argument count is checked ('Syntax error' otherwise, D) and its axis (0..the "
             "last axis), slot and channel (whole, 0 up) ('Parameter out of range'); "
             "functions 0 and 1 are reserved: 'Parameter out of range' (D). The result is "
             "a FLOAT: PRINT gives 4 decimals (the page's examples: 1.0000, 463.0000)."),
    _axis("DRIVE_STATUS", "The status word of the axis's drive.", writable=False,
          source=f"{TOK}; {MAN}", confidence="D",
          note="The CiA 402 status word an EtherCAT drive reports (I), as far as the "
          "emulator knows it (D: the MC405's own axes have no drive word): 0x37 enabled "
          "(ready, switched on, operation enabled, voltage, quick stop) or 0x50 disabled "
          "(voltage, switch-on disabled); +8 fault while the axis is in motion error, "
          "+0x400 target reached while idle, +0x800 internal limit while an AXISSTATUS "
          "limit bit is set, +0x2000 following error with bit 8."),
    _axis("SERVO", "Position loop on (ON) or off for the axis.", value_range=(-1, 1),
          source=f"{TOK}; {MAN}", confidence="I", note="On a servo axis (ATYPE 44, 36, 77 ...) "
          "the drive is enabled only with SERVO ON, WDOG ON and AXIS_ENABLE ON: a move is "
          "refused with 'Axis not enabled' (D: the text is ours) and one running stops at "
          "once when it goes off (D). Power-up OFF (I). Pulse/direction axes ignore it "
          "(manual: on a stepper it only gates the position verification, C)."),
    _axis("AXIS_ENABLE", "Enable of the axis's drive.", default=1, value_range=(-1, 1),
          source=f"{HELP} AXIS_ENABLE; {TOK}", confidence="I", note="Power-up ON (C). OFF "
          "disables the drive of any axis (as SERVO does a servo axis's): a move is refused "
          "with 'Axis not enabled' and one running stops at once (D). A motion error on an "
          "axis of a DISABLE_GROUP sets it OFF on every axis of the group (C)."),
    _command("DISABLE_GROUP", "DISABLE_GROUP(a, b, ...): a motion error on one of these "
             "axes stops only them; DISABLE_GROUP(-1) removes every group.", (1, 128),
             source=f"{HELP} DISABLE_GROUP; {TOK}", confidence="C",
             note="On the error (ERRORMASK) every axis of the group gets AXIS_ENABLE and "
             "SERVO OFF and stops at once (runs, buffered moves, links; D: at once, as the "
             "controller-wide stop), WDOG stays ON and the other axes run on (C: help "
             "examples 1, 2; errors.py). An error on an axis in no group stops every axis "
             "and WDOG as without groups (D). An axis named again leaves its old group (D: "
             "one group an axis); an axis twice, out of range or not whole: 'Parameter out "
             "of range', nothing changed (D). DATUM(7) clears one axis's error (C)."),
    _command("INITIALISE", "Every axis parameter back to its power-up value.", (0, 0),
             source=f"{HELP} INITIALISE; {TOK}", confidence="I",
             note="Each parameter that differs is written as a program would write it "
             "(a running move takes a new SPEED, PP_STEP keeps MPOS, ATYPE makes or drops a "
             "servo loop: initialise.py, D); positions, moves, links, TABLE, VR and the "
             "system parameters stay (the page names axis parameters only, D), and so do "
             "ENDMOVE, MOVELINK_MODIFY and CORNER_STATE (orders to the motion, D)."),
    _axis("CREEP", "The slow speed of the second part of a DATUM search, and of the "
          "Z-mark searches DATUM(1)/(2), user units/s.", default=200,
          value_range=(0, _BIG), source=f"{TOK}; {MAN}", confidence="I",
          note="Power-up 200 (D)."),
    _command("DATUM", "DATUM(n): 0 clears motion errors (7 the axis's); 1/2 search "
             "forward/reverse at CREEP for the encoder's Z mark, zero there; 3/5 search "
             "forward at SPEED for the DATUM_IN input, then back at CREEP until it goes "
             "off; 4/6 the same in reverse; the position there becomes 0.", (1, 1), axis=True,
             source=f"{TOK}; {MAN}", confidence="I",
             note="1/2: the Z mark is the world's index mark of the axis, found exactly to "
             "the servo tick; DPOS is 0 on the mark's first count met, then the axis ramps "
             "down at DECEL (D: it stops a ramp past the mark). 3..6 run on the planner "
             "watching the input every servo cycle; the zero is where the creep stopped "
             "after the input went off (D: not the exact edge); 5 and 6 do not look for the "
             "Z mark (D). 0 clears every axis's motion error (MOTION_ERROR, ERROR_AXIS, the "
             "bits AXISSTATUS held), WDOG stays OFF (I); 7 the base axis's only (C: help "
             "DATUM, DISABLE_GROUP example 2). The statement returns when the "
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
             source=f"{TOK}; {MAN}; TrioBASIC help OP", confidence="C",
             note="Outputs kept by the machine, off at power up (D); OP(state): outputs "
             "8..31 from bits 8..31 of state, 0..7 being inputs only (C, its examples 2 and "
             "3); OP(start, end, state): outputs start..end from bits 0.. of state, at most "
             "32 (C; the limit is ours, D)."),
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
    _system("RUN_ERROR", "The number of the last runtime error of this process (PROC(n): of "
            "process n, also after the error stopped it; 31 after a normal stop, STOP or HALT).",
            writable=False, source="TrioBASIC help RUN_ERROR", confidence="C",
            note="Numbered as the page numbers the errors: each of our error texts has the "
            "page's number (9 Divide by zero, 19 Parameter out of range, 7 Stack overflow ...), "
            "with C/I/D per text in errorcodes.RUN_ERRORS; a text with none there is 62 (D). "
            "A process that never ran a program reads 0 (D)."),
    _system("ERROR_LINE", "The program line of the last runtime error of this process (PROC(n): "
            "of process n, also after the error stopped it).", writable=False,
            source="TrioBASIC help ERROR_LINE", confidence="C",
            note="Lines of an INCLUDEd program report the INCLUDE's line (D); a normal stop "
            "leaves it as it was (D)."),
    _system("TICKS", "The process's own clock: counts down one a servo cycle from the value "
            "last set.", confidence="I", note="Per process; one count per servo cycle (I)."),
    _system("PROC_STATUS", "PROC_STATUS PROC(n): 1 while process n runs a program, 8 "
            "while it sleeps in a waiting statement, 0 stopped, 3 paused by TRON/STEPLINE, "
            "2 running a stepped line.", writable=False,
            source=f"{HELP} PROC_STATUS; {TOK}", confidence="I",
            note="8 SLEEP while a statement waits: WA, WAIT IDLE (page, C), and WAIT UNTIL, "
            "WAIT LOADED, a move waiting for buffer room, DATUM's search, a PRINT to a full "
            "FIFO (I: the page's 'etc.'); a loop pass or a used time slice stays 1. 3 "
            "PAUSED while a traced process waits to be stepped, 2 STEPPING while it runs "
            "the stepped line (D: the page names both states, not which the trace words "
            "give). PAUSING, STOPPING and the operating system's SUSPEND states pass within "
            "one step here, so never read (D)."),
    # ---- the Ethernet port's settings, flash, program memory (network.py, flash.py) --------
    _command("ETHERNET", "ETHERNET(action, -1, function[, values]): read (printed) or write "
             "the Ethernet port's settings: 0 IP address, 2 subnet mask, 3 MAC (read only), "
             "4 command line port, 5 token port, 7 Modbus TCP mode, 8 gateway, 9 Modbus data "
             "source, 10 Modbus TCP port.", (3, 10), source=f"{HELP} ETHERNET; {TOK}",
             confidence="I",
             note="Addresses print as the page prints them (192.168.0.250, "
             "00:06:70:00:00:F9) and are IP_ADDRESS, IP_NETMASK, IP_GATEWAY and IP_MAC: "
             "either way of setting one is seen by the other (C). Power-up ports 23, 3240, "
             "502 and modes 0 (page). Values given write, also with action 0 (I: the page's "
             "gateway example). Slot other than -1, function 6 (MC464 only), a value out "
             "of range: 'Parameter out of range'; a MAC written: 'Parameter is read only' "
             "(D). The emulator's own socket does not move (D); functions 1, 11..25 are "
             "accepted with no effect: no Ethernet stack is emulated (D)."),
    *[_system(name, summary, default=default, value_range=(0, 2.0 ** 32 - 1),
              source=f"{HELP} {name}; {HELP} ETHERNET; {TOK}", confidence="I", note=note)
      for name, summary, default, note in (
          ("IP_ADDRESS", "The Ethernet port's IPv4 address, written dotted "
           "(IP_ADDRESS = 192.168.0.250).", 3232235770.0, "Power-up 192.168.0.250 (ETHERNET "
           "page); kept across EX and reset by CLEAR_PARAMS, a FLASH parameter (page); read "
           "as the number a*2^24 + b*2^16 + c*2^8 + d (D); ETHERNET(0, -1, 0) prints it "
           "dotted."),
          ("IP_NETMASK", "The Ethernet port's subnet mask, written dotted.", 4294967040.0,
           "Power-up 255.255.255.0 (ETHERNET page); FLASH as IP_ADDRESS; ETHERNET function "
           "2."),
          ("IP_GATEWAY", "The Ethernet port's default gateway, written dotted.", 0.0,
           "Power-up 0.0.0.0, no gateway (D: no page gives one); FLASH as IP_ADDRESS; "
           "ETHERNET function 8."),
      )],
    _system("IP_MAC", "The Ethernet port's MAC address as one 48-bit number.",
            default=27648852217.0, writable=False,
            source=f"{HELP} IP_MAC; {HELP} ETHERNET; {TOK}", confidence="D",
            note="Read only (page; the token table allows a write of older firmware). The "
            "value is the page's example, 00:06:70:00:00:F9 (D); ETHERNET(0, -1, 3) prints "
            "it so."),
    _command("CLEAR_PARAMS", "CLEAR_PARAMS: the FLASH parameters back to their power-up "
             "values.", (0, 1), source=f"{HELP} CLEAR_PARAMS; {TOK}", confidence="I",
             note="The FLASH parameters are SERVO_PERIOD, IP_ADDRESS, IP_NETMASK and "
             "IP_GATEWAY (their pages' type; personalities/trio/flash.py); the module and "
             "bus ones have nothing to act on (D). As the page says, SERVO_PERIOD takes "
             "effect at the next EX. Allowed in a program too (D: the page says command "
             "line only, not what a program gets)."),
    _command("FLASHTABLE", "FLASHTABLE(function, flashpage[, tablepage]): TABLE pages of "
             "16000 values to (1) and from (2) 32 flash pages; 3 TRUE if the flash page "
             "holds data, 4 erase it.", (2, 3), source=f"{HELP} FLASHTABLE; {TOK}",
             confidence="I",
             note="Also a function: TRUE (function 3: in use or not), as the page's examples "
             "(C). Flash outlives EX and TABLE does not (D: the emulator's power-up clears "
             "TABLE). tablepage 0..31, the pages TABLE's 512000 values fill (D); a flash "
             "page never written reads back zeros (D); a bad number: 'Parameter out of "
             "range'."),
    _system("FLASH_DATA", "1: TABLE's first 4096 values are the automatic flash backup "
            "and come back at each power-up (EX); 0 (power-up): the VRs are.",
            value_range=(0, 1), source=f"{HELP} FLASH_DATA; {HELP} EX; {TOK}",
            confidence="I",
            note="Page: MC4x, 0 VR memory, 1 TABLE memory, only the first 4096 elements. "
            "The VRs outlive EX either way (EX's page: they stay in memory). Its value at "
            "the EX decides (I: MC_CONFIG sets it at each power-up, the page's place for "
            "it); set from anywhere (D); a FLASHVR(-1) copy is put back after it (D)."),
    _command("FLASHVR", "FLASHVR(index): -1 keeps the whole TABLE in flash to replace TABLE "
             "at power-up, -2 stops that.", (1, 1), source=f"{HELP} FLASHVR; {TOK}",
             confidence="I",
             note="An index of a VR, and -100, do nothing (page: for the MC2xx/MC3xx; the "
             "MC4xx keeps its VRs itself) (D); the TABLE kept is the one at the call, put "
             "back at each power-up (EX) until -2 (page). As a function: TRUE (D)."),
    _function("FREE", "FREE: the program memory left, bytes.", (0, 0),
              source=f"{HELP} FREE; {TOK}", confidence="D",
              note="1048576 bytes (D: no page gives the MC405's) less what DIR lists for "
              "every program, its source and its compiled code; so it falls as programs "
              "are stored and compiled (page: compiled programs need nearly twice the "
              "memory). A FLOAT: PRINT FREE gives 4 decimals (page: 47104.0000)."),
    _command("SERVO_READ", "SERVO_READ(vr, p0[, ...p7]): up to 8 parameters read on the "
             "next servo cycle into VR(vr) onwards, not scaled by UNITS.", (2, 9), axis=True,
             source=f"{HELP} SERVO_READ; {TOK}", confidence="D",
             note="The statement waits for the next servo cycle and reads them all there "
             "(page, C). An axis parameter in user units (positions, distances, speeds, "
             "accelerations, jerks: servoread.SCALED, from each page's unit) is stored times "
             "its axis's UNITS; anything else as read (D: the page lists none). A parameter "
             "without AXIS(n) reads SERVO_READ's own AXIS(n), else BASE (D). VRs past the "
             "last: 'Parameter out of range', none written (D)."),
    *[_command(name, summary, args, source=f"{HELP} {name}; {TOK}", confidence="I",
               string_arg=True, note=note) for name, summary, args, note in (
        ("TRON", "TRON [\"prog\"]: pause the program (the SELECTed one; in a program, "
         "itself) before its next statement.", (0, 1),
         "Every pause prints '%[Process n:Line l] - Paused' and the text of that line "
         "(page's examples, I). A statement waiting (WA, WAIT IDLE) ends first (D). A "
         "program not running is started paused at its first statement (I: the page's "
         "example 2)."),
        ("TROFF", "TROFF [\"prog\"]: release a paused or stepping program: it runs on.",
         (0, 1), "Prints '%[Process n:Program NAME] - Released' (page's example; a hyphen "
         "where the page has a dash, D). RUN of a program under trace releases it the "
         "same way (D: one copy of a program runs here, and a debugger's Run goes on)."),
        ("STEPLINE", "STEPLINE [\"prog\"[, process]]: a paused program runs one line "
         "and pauses again, over a GOSUB routine.", (0, 2),
         "A program not running starts paused on the process given or the highest free one "
         "(page); one running untraced is paused before its next statement (D); alone in a "
         "program it pauses that program (page). A FUNCTION runs within its statement, so "
         "it is stepped over (D)."),
        ("STEPINTO", "STEPINTO [\"prog\"[, process]]: as STEPLINE, but a GOSUB routine's "
         "lines are stepped one by one.", (0, 2),
         "As STEPLINE; a FUNCTION call is stepped over, not into: it runs inside the "
         "statement that calls it (D)."),
        ("SETLINE", "SETLINE \"prog\", process, line[, base[, robot]]: move a program's "
         "pointer to a line; it stands paused there.", (3, 5),
         "A paused program is moved (its GOSUB returns dropped, D) and prints its Paused "
         "line; one not running is started paused there (process -1: the highest free), "
         "its BASE set unless base is -1 (page); a running one pauses there (D). A line "
         "with no statement is 'Parameter out of range' (D), a base that is no axis "
         "'Invalid axis number', nothing started (D); robot is accepted, no robot "
         "selection is modelled (D). The token table gives 2..3 arguments, the page 5: "
         "3..5 are taken (D)."),
        ("BREAK_ADD", "BREAK_ADD \"prog\" line: a breakpoint: the program pauses before "
         "that line, as TRON pauses it.", (2, 2),
         "A line with no code: the next line with code (page); none after it, or a line "
         "below 1: 'Parameter out of range' (page: 'an error'). It pauses each time it "
         "comes to the line from another line (D: a loop on one line does not stop "
         "itself); STEPLINE and TROFF go on from there. The comma the page leaves out is "
         "taken too (D). Kept by line number across edits (D)."),
        ("BREAK_DELETE", "BREAK_DELETE \"prog\" line: remove the breakpoint of that line.",
         (2, 2), "The line resolves as BREAK_ADD's (D); a line with none: nothing (D)."),
        ("BREAK_LIST", "BREAK_LIST [\"prog\"]: 'Program: NAME', then 'Line n: code' for "
         "each breakpoint.", (0, 1), "The page's example's form; lowest line first (D); "
         "no name: the SELECTed program (D)."),
        ("BREAK_RESET", "BREAK_RESET [\"prog\"]: remove every breakpoint of the program.",
         (0, 1), "No name: the SELECTed program (D)."),
    )],
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
    _function("LENB", "LENB(s): the bytes s takes in UTF-8.", (1, 1),
              source="TrioBASIC help LENB", confidence="I",
              note="Strings here hold characters; their UTF-8 length is the page's byte "
              "count (I)."),
    _function("ROUND", "ROUND(v[, places]): INT(v x 10^places + 0.5) / 10^places (- 0.5 "
              "below 0); negative places round the integer part.", (1, 2),
              source="TrioBASIC help ROUND", confidence="C",
              note="The page's formula and examples (C); the result is a FLOAT, so PRINT "
              "shows a whole one with 4 decimals (help INT example 2, C)."),
    _function("VECTOR_MAG", "VECTOR_MAG(c1[, c2 ... c6]): the magnitude of a vector of 1 to 6 "
              "components, the square root of the sum of their squares.", (1, 6),
              source="TrioBASIC help VECTOR_MAG", confidence="C",
              note="Its alternate name HYPOT is not in the MC405's token table (D: not "
              "added); an infinite or NaN component: Parameter out of range (D)."),
    _function("ULPDIFF", "ULPDIFF(a, b): how many doubles lie between a and b (units in "
              "the last place).", (2, 2), source="TrioBASIC help ULPDIFF", confidence="C"),
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
              "and 160..255 (I). At most 65535 characters, a string's limit here (D)."),
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
             "not found'; a channel already open is 'Channel already open' (D). FOR "
             "OUTPUT[(mode)] creates the file (a .TXT program) or clears it, FOR APPEND "
             "needs it and writes after its lines; PRINT #n writes each finished line to "
             "the store at once, CLOSE the rest (help page OPEN; every OUTPUT mode is the "
             "store, D). FOR FIFO_WRITE / FIFO_READ: a RAM circular buffer between two "
             "channels (see FIFO_WRITE; fifos.py). Channels 40 to 48 "
             "only (C: help page OPEN); any other is 'Parameter out of range'. AS "
             "\"STRING:name\": the process's STRING variable is the file (C: examples 8, "
             "9): OUTPUT empties it, PRINT #n adds to it, APPEND keeps it, INPUT reads it. "
             "As a value, OPEN gives the error's RUN_ERROR number or 0 (C); a TCP, DGRAM "
             "or TCPSERVER connection is FALSE: no program channel opens a socket (D)."),
    *(_command(mode, f"OPEN's {mode} channel mode (see OPEN).", (0, 0), confidence="I",
               source=f"{TOK}; public programs",
               note="Taken as a word of OPEN ... FOR; alone as a statement it is accepted "
               "with no effect (D).")
      for mode in ("READ_WRITE", "APPEND")),
    _command("FIFO_WRITE", "OPEN ... FOR FIFO_WRITE(size[, mode[, terminator]]): write a "
             "FIFO, a RAM circular buffer of size bytes (256 at least).", (0, 3),
             source=f"{HELP} OPEN; {HELP} FIFO_WRITE; {TOK}", confidence="I",
             note="An existing FIFO is cleared, its size kept (page). PRINT #n puts "
             "characters in; full: mode bit 1 overwrites the oldest (bit 0 too: whole oldest "
             "lines up to the terminator, 13 by default), else the PRINT waits until a "
             "reader makes room, a servo cycle at a time (page: blocking; the wait's pace "
             "D). The FIFO is not a program of the store: DIR does not list it (D); 'RAM:' "
             "names the same one (D). At most 1 MiB each and 2 MiB for all together: a "
             "new FIFO past that is 'Not enough memory' (D). Alone as a statement: no "
             "effect (D)."),
    _command("FIFO_READ", "OPEN ... FOR FIFO_READ[(mode[, terminator])]: read a FIFO; KEY #n "
             "counts its characters (mode 0) or lines (mode 1).", (0, 2),
             source=f"{HELP} OPEN; {HELP} FIFO_READ; {TOK}", confidence="I",
             note="GET #n takes the oldest character; a GET on an empty FIFO waits, looking "
             "again each servo cycle (D: the writer may be another process). A FIFO never "
             "opened for writing: 'Program not found' as INPUT of a missing file (D). Alone "
             "as a statement: no effect (D)."),
    _command("OUTPUT", "OPEN's OUTPUT[(mode)] channel mode: write a file (see OPEN).",
             (0, 1), source=f"{HELP} OUTPUT; {HELP} OPEN",
             note="Taken as a word of OPEN ... FOR; alone as a statement it is accepted "
             "with no effect (D)."),
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
    _command("SET_BIT", "SET_BIT(b, vr[, mode]): set bit b of VR(vr), or of TABLE(vr) "
             "with mode 1.", (2, 3), confidence="I", source=f"{TOK}; {MAN}; TrioBASIC help "
             "SET_BIT", note="Bits 0..52 of the value's integer part (the page); mode 0 VR, "
             "1 TABLE (C), another mode 'Parameter out of range' (D)."),
    _command("CLEAR_BIT", "CLEAR_BIT(b, vr[, mode]): clear bit b of VR(vr), or of "
             "TABLE(vr) with mode 1.", (2, 3), confidence="I",
             source=f"{TOK}; {MAN}; TrioBASIC help CLEAR_BIT", note="As SET_BIT."),
    _function("READ_BIT", "READ_BIT(b, vr[, mode]): bit b of VR(vr), or of TABLE(vr) with "
              "mode 1, 1 or 0.", (2, 3), confidence="I",
              source=f"{TOK}; {MAN}; TrioBASIC help READ_BIT", note="As SET_BIT."),
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
             note="Each parameter has its own block of (stop - start + 1) // n values: "
             "table_stop is the last index used (C: SCOPE_DELAY's examples, 10001..10800 "
             "holds 4 traces of 200 from 10001, 10201, ...; 10001..12000 1000 points on 2), "
             "filled one sample every period servo cycles from TRIGGER until full (page "
             "example 1); a stop past the TABLE, or before the start: 'Parameter out of "
             "range'. The parameters are expressions read at each sample with the BASE of the "
             "process that set SCOPE (I). SCOPE_DELAY delays or pre-triggers it (see "
             "there). The FIFO form is not modelled (D)."),
    _system("SCOPE_DELAY", "SCOPE's delay, ms: above 0 the capture starts that long after "
            "TRIGGER; below 0 up to that long of samples from before TRIGGER are stored "
            "first.", source=f"{HELP} SCOPE_DELAY; {HELP} SCOPE; {TOK}", confidence="I",
            note="Read at TRIGGER (SCOPE's example 4 sets it after SCOPE, C). Below 0, an "
            "armed scope samples every period while it is negative (D: needed for SCOPE's "
            "example 5), keeping at most block - 1, so the trigger's own sample is stored "
            "(D); fewer than asked: those taken (page). Milliseconds round up to whole "
            "servo cycles (D, as WA); an automatic TRIGGER's later scans have no "
            "pre-trigger (D)."),
    _system("SCOPE_TRIGGER_POS", "Where the last SCOPE trigger fell: the trigger's sample's "
            "place in each block, from 1.", writable=False,
            source=f"{HELP} SCOPE_TRIGGER_POS; {HELP} SCOPE_DELAY; {TOK}", confidence="I",
            note="The trigger's sample is TABLE(table_start - 1 + SCOPE_TRIGGER_POS) (I: the "
            "pages' example prints 10000 + SCOPE_TRIGGER_POS for a start of 10001, where "
            "the page's text says 'TABLE index'); 1 with no pre-trigger, 0 after a delayed "
            "start (D: the trigger came before the first sample), 0 at power-up (D)."),
    _command("TRIGGER", "TRIGGER[(auto)]: start the armed SCOPE; auto not 0: it starts "
             "again at the end of each scan.", (0, 1), source=f"{HELP}; {TOK}",
             confidence="I", note="The first sample is taken on TRIGGER's own servo "
             "cycle (D); after SCOPE(OFF) it starts nothing (page)."),
    _system("SCOPE_POS", "Where in each block the SCOPE stores its next sample: the "
            "samples stored since TRIGGER, the block's size once full.", writable=False,
            source=f"{HELP} SCOPE_POS; {HELP} SCOPE_DELAY; {TOK}", confidence="I",
            note="Counted from table_start, pre-trigger samples included (I: SCOPE_DELAY's "
            "examples wait for SCOPE_POS = 200 and = 1000, the points of each trace); 0 "
            "before a TRIGGER; a repeating scan (TRIGGER(1)) goes back to 0 as it "
            "restarts (D). The token table has it writable; writing is refused here (D)."),
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
    _command("REGIST", "REGIST(mode[, channel, source, edge, window[, quantity, table "
             "start]]) AXIS(n): arm a capture of the axis's position on a registration "
             "edge.", (1, 7), axis=True, source=f"{TOK}; {HELP} (REGIST page)",
             confidence="I", note="Modes as the page's tables (C): 0 cancels every "
             "channel; 1/2 Z mark rising/falling, 3/4 RA input rising/falling into MARK/"
             "REG_POS/REGIST_SPEED; 6..9 RA with the Z mark into MARKB/REG_POSB; 10..13 RA "
             "and RB; 14/15 Z, 16/17 RB into the B channel only; + 256 / + 768 only edges "
             "inside / outside OPEN_WIN..CLOSE_WIN. 20: channel 0/1 (A/B), source 0 RA, 1 "
             "Z, 2 RB, 4 any digital input (channel = its number, into MARK); windows 1/2 "
             "OPEN_WIN, 3/4 while the gate input (channel bits 16 up) is high/low; "
             "quantity captures to TABLE(table start ...) with MARK reading minus the "
             "count. 21: time-based channel 0..7 on input channel (source 256 + n: input "
             "n), read with R_MARK/R_REGPOS/R_REGISTSPEED(channel). RA/RB are the inputs "
             "REG_INPUTS names. The Z mark is the world's index marks of the axis, found to "
             "the servo tick on its motion (on a linked axis by bisecting its demand up to "
             "the next motion event, D); REG_POS the mark's exact count; an input edge is "
             "captured on the tick the world changes it (the world's inputs change on "
             "servo ticks: D). Arming one channel leaves the other armed (C for 20, D for "
             "1..17). 23/24 (pulse width): accepted, no effect, the world's edges are "
             "clean (D). Windows 5/6 (20, 21): inside/outside OPEN_WINB..CLOSE_WINB (C; "
             "those words are the help's, see OPEN_WINB). 5, 18, 19, 22 (Flexaxis), 32..71 "
             "(older time modes), windows above 6 and bad arguments: "
             "'Parameter out of range', nothing armed (D)."),
    _axis("R_MARK", "R_MARK(channel): TRUE once the time-based channel's capture (REGIST "
          "21) has happened.", writable=False, source=f"{TOK}; {HELP} (R_MARK page)",
          confidence="C", note="Per axis and channel 0..7 (as MARK: reset by REGIST, minus "
          "the count when capturing to TABLE). The token table lists it as a command; "
          "the page's form R_MARK(channel) [AXIS(n)] is a read-only axis parameter."),
    _axis("R_REGPOS", "R_REGPOS(channel): the position the time-based channel captured "
          "(user units).", writable=False, source=f"{TOK}; {HELP} (R_REGPOS page)",
          confidence="C", note="As REG_POS, per channel 0..7."),
    _axis("R_REGISTSPEED", "R_REGISTSPEED(channel): the axis's speed at the time-based "
          "channel's capture, user units per ms.", writable=False,
          source=f"{TOK}; {HELP} (R_REGISTSPEED page)", confidence="I",
          note="As REGIST_SPEED, per channel 0..7."),
    _axis("REGIST_SPEED", "The axis's speed at channel A's capture, user units per ms.",
          writable=False, source=f"{TOK}; {HELP} (REGIST_SPEED page)", confidence="I",
          note="The demand's change over the servo cycle before the capture's tick, "
          "signed (D: so REG_POS - REGIST_SPEED x delay compensates either way)."),
    _axis("REGIST_SPEEDB", "The axis's speed at channel B's capture, user units per ms.",
          writable=False, source=f"{TOK}; {HELP} (REGIST_SPEEDB page)", confidence="I",
          note="As REGIST_SPEED."),
    _axis("REGIST_CONTROL", "The registration control bits: channel A bits 0..3, B 4..7: "
          "input (1) or Z mark (0), enable (bit 2/6), falling edge (bit 3/7).",
          value_range=(0, 255), source=f"{TOK}; {HELP} (REGIST_CONTROL page)",
          confidence="I", note="Reads what is armed now (C: bits); written, a channel "
          "whose enable bit is 0 is disarmed, one enabled as it already is stays, "
          "otherwise it is armed as the bits say on its REG_INPUTS input or the Z mark "
          "(D). Bits 1 and 5 are not used (C)."),
    _axis("REG_INPUTS", "The registration inputs of the axis: bits 0..3 the first (RA), "
          "4..7 the second (RB).", value_range=(0, 255),
          source=f"{TOK}; {HELP} (REG_INPUTS page)", confidence="C",
          note="Power-up (MC405): axis n takes inputs n and n + 4 modulo 8 (C for axes "
          "0..4; the virtual axes likewise, D). Read when REGIST arms a channel."),
    _axis("REGIST_DELAY", "The delay (ms) time-based registration compensates.",
          source=f"{TOK}; {HELP} (REGIST_DELAY page)", confidence="D",
          note="Not modelled: stored; the emulator's inputs and positions carry no "
          "delay (an edge is captured at the exact position of its servo tick), so there "
          "is nothing to compensate (D)."),
    # ---- position switches (personalities/trio/pswitch.py) -------------------------------
    _command("PSWITCH", "PSWITCH(switch, enable[, axis, output, state, setpos, resetpos]), "
             "PSWITCH(switch, OFF[, hold]), PSWITCH(switch, mode, axis, output, state, "
             "table start, table end[, pulse time]): one of 64 software position switches.",
             (2, 8), axis=True, source=f"{TOK}; {HELP} (PSWITCH page)", confidence="I",
             note="The output is the OR of every switch on it and OP's setting (C). Cyclic "
             "(enable 1, 3 with setpos above resetpos, 5 on DPOS): the switch drives state "
             "while setpos <= position < resetpos (user units, REP_DIST folded as DPOS "
             "reads) and the opposite outside (C: example 3; the edge counts D); with bit 1 "
             "the window runs from setpos over the fold to resetpos (I). Sequence (mode bit "
             "3): TABLE start..end fire in turn as the axis reaches each in the direction "
             "of bit 5 (0 up, 1 down); the first drives state, each next toggles, or with "
             "bit 4 each gives a pulse of state for pulse time servo cycles (C); the "
             "sequence ends at the first value that does not go on in its direction (D: "
             "example 4 names 100 entries and fills 16); positions already passed fire at "
             "once, in order (D); before its first position it drives nothing (D). Every "
             "level follows the axis's whole demand counts (MPOS too, D) and changes on its "
             "exact servo tick, found on the motion. OFF: the output keeps its level (an "
             "output the switch held ON stays ON as if OP set it), hold 1 forces it OFF "
             "(C); PSWITCH(n, ON) alone enables the set-up again (D). Bad numbers, setpos "
             "above resetpos without bit 1, bit 6 (Z output) and an axis with a negative "
             "UNITS: 'Parameter out of range', nothing changed (D)."),
    _command("HW_PSWITCH", "HW_PSWITCH(mode[, direction, opstate, table start, table end]) "
             "AXIS(n): the axis's hardware position switch on output 8 + n.", (1, 5),
             axis=True, source=f"{TOK}; {HELP} (HW_PSWITCH page)", confidence="I",
             note="MC405: axes 0..4, output 8 + axis (C: note 1); other axes 'Invalid axis "
             "number' (D). Mode 1 loads TABLE start..end into the FIFO (512 positions: "
             "beyond, 'Parameter out of range', nothing loaded, C/D) behind what it holds; "
             "the first position drives opstate, each next toggles (C), compared with "
             "MPOS x UNITS (counts, DEFPOS applied; no x16 on the emulator's step axes, D) "
             "travelling direction (1 increasing, 0 decreasing) on the exact servo tick. "
             "Mode 0 disables it (the FIFO kept), 2 clears the FIFO (C). The output is "
             "ORed with OP's (D). A load ends at the first value not going on in its "
             "direction (D, as PSWITCH)."),
    _command("HW_TIMER", "HW_TIMER(mode, cycle time[, on time, reps], op mode, op sel, "
             "op state): drive a digital output from the hardware timer.", (1, 7),
             axis=True, source=f"{TOK}; {HELP} (HW_TIMER page)", confidence="I",
             note="Mode 1: the output at op state for cycle time us, then the opposite; "
             "mode 2: op state for on time us of each of reps cycles of cycle time us, the "
             "opposite between and after (C); times truncated to 10 us (C). Op mode 0: "
             "output op sel 8..15; 2: output 8 + op sel (0..4) (C). While it runs it owns "
             "the output; at its end the output stays at its last level as if OP had set "
             "it; HW_TIMER(0) stops it where it is (D). Op mode 1 (an axis's enable "
             "output: not in the emulated world) and bad values: 'Parameter out of range' "
             "(D). Outputs are read at servo ticks: a pulse shorter than a servo cycle "
             "shows on its first tick only (D)."),
    _system("HW_TIMER_DONE", "1 while the HW_TIMER runs, 0 when it is done.",
            writable=False, source=f"{TOK}; {HELP} (HW_TIMER_DONE page)", confidence="C",
            note="Turns 0 on the servo tick the timer's time is over (pswitch.py)."),
    _axis("FE_LATCH", "The following error that put the axis into motion error.",
          writable=False, source=f"{TOK}; {HELP} (FE_LATCH page)", confidence="I",
          note="The FE (user units) of the servo cycle |FE| passed FE_LIMIT and raised "
          "the motion error (the drive then goes off: C); 0 before, and again from SERVO "
          "= ON (C). Servo axes of the shared loop only (following.py)."),
    _system("PMOVE", "TRUE while a motion command of the process waits in its process "
            "move buffer.", writable=False, source=f"{TOK}; {HELP} (PMOVE page)",
            confidence="I", note="Per process (PROC(n) reads another's). TRUE while the "
            "process's motion command (MOVE, MOVEABS, the links, CAM, FORWARD ...) waits "
            "for room in the axes' move buffers, FALSE once it is loaded (C). The "
            "emulator hands a move to the axes in the servo cycle it is given, so the "
            "page's one-cycle transfer of a move that finds room is not seen (D)."),
    # ---- conveyor tracking and link words the pages do not give exactly enough ----------
    _command("SYNC", "SYNC(control, sync time[, sync position, sync axis, pos1[, pos2[, "
             "pos3]]]): synchronise the base axes with a point on a moving axis.", (2, 7),
             axis=True, source=f"{TOK}; {HELP} (SYNC, SYNC_CONTROL, SYNC_TIMER pages)",
             confidence="I",
             note="SYNC(1, time, pos, axis, pos1[, pos2[, pos3]]): over time servo cycles "
             "the first base axis comes to pos1 plus the sync axis's travel since pos, the "
             "next two to pos2/pos3, then follows (C); SYNC(10, ...) re-synchronises over "
             "its time, SYNC(4, time) stops; added to the axes' own moves, not buffered, "
             "not ended by CANCEL/RAPIDSTOP (C). Decided (D, sync.py): the share of the "
             "way is the cycloid z - sin(2 pi z)/2 pi of the time done; SYNC(4) fades the "
             "conveyor's pull as 1 - that, cycle by cycle, and the axes keep what they "
             "moved (MOVEABS sees it); a SYNC(1) while one stops ends the stop where it "
             "is; SYNC(10) mid-blend is refused; the conveyor's travel goes on the first "
             "axis (no USER_FRAME); it "
             "follows the sync axis's DPOS. SYNC(20) (USER_FRAMEB), a limit ending it, "
             "another control or a sync axis that follows the base axes: 'Parameter out "
             "of range'."),
    _axis("SYNC_CONTROL", "The SYNC state of the axis: 0 none, 2 synchronising, 3 "
          "synchronised, 4 stopping, 11 re-synchronising.", writable=False,
          source=f"{TOK}; {HELP} (SYNC_CONTROL page)", confidence="C",
          note="Every axis of the SYNC reads its state; 1 and 10 (starting) take no servo "
          "cycle here (D). Read only (its page; the token table has it writable: a write "
          "is refused, D)."),
    _axis("SYNC_TIMER", "The elapsed time of SYNC's synchronisation, ms.", writable=False,
          source=f"{TOK}; {HELP} (SYNC_TIMER page)", confidence="C",
          note="The ms of the (re)synchronisation so far, its whole time once complete "
          "(C); 0 while stopping and with no SYNC (D)."),
    _axis("SYNC_PAUSE", "The pause before SYNC's movement on this axis, ms.",
          source=f"{TOK}; {HELP} (SYNC_PAUSE page)", confidence="I",
          note="The axis's SYNC motion starts this long into the sync time (I: the page's "
          "words; its graph is not in the text); with SYNC_DWELL it must leave time to "
          "move: else the SYNC is 'Parameter out of range' (D). Read when SYNC is given."),
    _axis("SYNC_DWELL", "The dwell after SYNC's movement on this axis, ms.",
          source=f"{TOK}; {HELP} (SYNC_DWELL page)", confidence="I",
          note="The axis's SYNC motion is done this long before the sync time ends (I: the "
          "page's words); see SYNC_PAUSE."),
    *[_axis(name, summary, writable=writable, source=f"{TOK}; {HELP} ({name} page)",
            confidence="D", note="Not modelled: " + why)
      for name, summary, writable, why in (
          ("SYNC_WITHDRAW", "A withdraw distance SYNC adds on this axis.", True,
           "stored: its page calls it an additional motion of the distance, but not when "
           "in the sync time it runs (SYNC_PAUSE's profile graphs are pictures), its "
           "profile, or whether it comes back (its example sets -40 between conveyors and "
           "-65 to leave the last one) (D)."),
          ("SYNC_FLIGHT", "Reserved keyword (its page).", True,
           "stored: a reserved keyword, its page gives no effect (C)."),
          ("SYNC_DPOS", "Reserved keyword (its page).", True,
           "stored: a reserved keyword, its page gives no effect (C)."),
          ("SYNC_AXIS", "Reserved keyword (its page).", True,
           "stored: a reserved keyword, its page gives no effect (C)."),
          ("SYNC_TIME", "Reserved keyword (its page).", True,
           "stored: a reserved keyword, its page gives no effect (C)."),
      )],
    _command("CAMLINK", "CAMLINK(start, entries, mode, multiplier, link dist, link axis[, "
             "link opt[, link pos]]): Motion Perfect's off-line cam point calculation.",
             (5, 8), axis=True, source=f"{TOK}; {HELP} (CAMLINK page)", confidence="D",
             note="Not modelled: accepted, no effect, as a function it returns 0; the page "
             "leaves where the results go (start + entries + 1 inside the point blocks) and "
             "what relative X and the line segments' fixed speed mean open, so no exact "
             "TABLE result can be given (D)."),
    _command("CAM", "CAM(start, end, multiplier, distance): follow the TABLE profile in "
             "time, the whole of it taking distance / SPEED.", (4, 4), axis=True,
             source=f"{TOK}; {MAN}", confidence="I",
             note="TABLE values offset by the first, times the multiplier (counts), "
             "interpolated linearly in time: distance in the axis's user units at the "
             "SPEED it has when the CAM loads (I, the CAM page as recalled). Buffered like "
             "a move, never merged (D); ends on the profile's last value rounded to a "
             "whole count (D). MTYPE 13 (I). Its TABLE is read live as CAMBOX's (C: "
             "TABLE_POINTER page): a TABLE write re-shapes the running CAM over the same "
             "time (D), a buffered one takes the TABLE it starts on."),
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
          "linear-ramped path (D) (feedhold.py); with SRAMP/JERK the changes are S-ramps, "
          "the ramp running ending first (see SRAMP, D)."),
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
          "D). Bit 2: the CORNER_STATE handshake at corners beyond RAISE_ANGLE, on every "
          "move of a group of 2+ axes (C; corner_state.py). Bit 6 (vector radius control: "
          "the page does not give its radius of two vectors) is stored, no effect (D)."),
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
    _system("LIMIT_BUFFERED", "The most moves an axis buffers behind the one running "
            "(1..BUFFERSIZE).", default=15, value_range=(1, 64),
            source="TrioBASIC help LIMIT_BUFFERED", confidence="D",
            note="A move loaded while an axis of its group holds LIMIT_BUFFERED moves behind "
            "the running one waits for one to finish (C; the command line and the program "
            "wait). Power-up 15, not the page's 1 (D: the emulator's depth of 16 moves an "
            "axis, running included, that its programs and tests were written against). "
            "Lowering it below what is buffered drops nothing (D). 1..64 (D)."),
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
          "SRAMP 0 leaves JERK in force, D). Jerk (or SRAMP in mode 0) shapes "
          "single-axis moves and interpolated paths alike: a multi-axis MOVE, MOVEABS, "
          "MOVECIRC or MHELICAL that nothing merges into runs its vector speed exactly "
          "as a single-axis move of its path's length would (C: the page's 'jerk limited "
          "multi-axis interpolation'; MOVE page: the vector at the base's SPEED, ACCEL "
          "and DECEL), each axis at its share of the path on every servo "
          "tick; an arc's speed within sqrt(ACCEL x radius) as with linear ramps (D); "
          "merged moves: see MERGE; SPEED/ACCEL/DECEL written while it runs: an S-ramp "
          "to the new speed once the ramp running has ended (D); CANCEL and RAPIDSTOP: "
          "see SRAMP. Links (CONNECT, MOVELINK, CAMBOX) keep their own ramps: no page "
          "says a profile shapes them (D)."),
    _axis("JERK", "Jerk limit of moves in VP_MODE 5 and 6, user units/s^3.",
          value_range=(0, _BIG), source="TrioBASIC help JERK, VP_MODE", confidence="C",
          note="A single-axis move's acceleration rises at JERK to ACCEL, holds and falls "
          "at JERK (DECEL on the way down): a ramp to SPEED lasts SPEED/ACCEL + "
          "ACCEL/JERK, or 2 sqrt(SPEED/JERK) when ACCEL is not reached (C); a move too "
          "short to reach SPEED peaks at the highest speed whose jerk-limited ramps fit "
          "it, so its jerk stays JERK (I: JERK is the limit). 0: no jerk limit (D). "
          "Ignored in VP_MODE 0 (C). The same on interpolated and merged paths (see "
          "VP_MODE, MERGE); between merged moves each speed change rises at JERK to "
          "ACCEL, or to sqrt(change x JERK) when that is lower (D)."),
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
          "merged paths: the same S-ramps (see VP_MODE, MERGE); a speed change shorter "
          "than 2 x SRAMP rises over half of it (D, as a single-axis move's). CANCEL and "
          "RAPIDSTOP of an S-curve move S-ramp down at once from the speed it has, with "
          "the acceleration starting from 0 (D), at FASTDEC when it is greater than "
          "DECEL, else DECEL (C: CANCEL page); the move's own JERK (or SRAMP) shapes that "
          "ramp (D), or in VP_MODE 5/6 FASTJERK where it is higher (see FASTJERK). A CAM "
          "stops linearly (D)."),
    _axis("OPEN_WIN", "Where the registration window opens (user units).",
          source=f"{TOK}; {MAN}", confidence="I", note="REGIST modes + 256 take only "
          "edges between OPEN_WIN and CLOSE_WIN (as DPOS reads, REP_DIST folded), + 768 "
          "only edges outside (I); a rejected edge leaves the capture armed."),
    _axis("CLOSE_WIN", "Where the registration window closes (user units).",
          source=f"{TOK}; {MAN}", confidence="I", note="As OPEN_WIN."),
    _axis("MARK", "TRUE once the capture REGIST armed has happened.", writable=False,
          source=f"{TOK}; {MAN}; {HELP} (MARK page)", confidence="C", note="FALSE from "
          "REGIST until the edge; TRUE from the servo tick of the edge (registration.py); "
          "capturing to TABLE (REGIST 20/21 quantity), minus the count captured."),
    _axis("MARKB", "TRUE once the capture of REGIST's second channel has happened.",
          writable=False, source=f"{TOK}; {MAN}", confidence="I", note="As MARK, channel "
          "B (REGIST modes 6..17, 20 channel 1)."),
    _axis("REG_POS", "The position captured by the last registration (user units).",
          writable=False, source=f"{TOK}; {MAN}", confidence="C", note="The mark's exact "
          "position, DEFPOS applied, in the axis's UNITS."),
    _axis("REG_POSB", "The position captured by the second registration channel.",
          writable=False, source=f"{TOK}; {MAN}", confidence="I", note="As REG_POS."),
    _axis("FRAME_REP_DIST", "The fold of an axis in a FRAME: with REP_OPTION bit 3 its "
          "DPOS reads in -FRAME_REP_DIST..FRAME_REP_DIST (0..FRAME_REP_DIST with bit 0).",
          value_range=(0, _BIG), source=f"{HELP} FRAME_REP_DIST, REP_OPTION; {TOK}",
          confidence="C", note="With REP_OPTION bit 3, REP_DIST does not fold the axis; "
          "while its FRAME is on (not 0) FRAME_REP_DIST folds DPOS (and WORLD_DPOS), in "
          "UNITS; with the frame off nothing is folded; AXIS_DPOS and MPOS never are (C). "
          "As REP_DIST's fold, the machine keeps the unfolded position and MOVEABS acts in "
          "the fold read now; 0 (power-up, D) does not fold; no USER_FRAME is built "
          "(D, frames.py)."),
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
          "Bit 0 folds positions into 0..REP_DIST instead of -REP_DIST..REP_DIST (I). "
          "Bit 3: FRAME_REP_DIST folds DPOS instead of REP_DIST (C, see FRAME_REP_DIST)."),
    _command("MOVECIRCSP", "MOVECIRCSP(...): MOVECIRC at the base axis's FORCE_SPEED.",
             (5, 7), axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="As MOVECIRC, its path speed FORCE_SPEED (as MOVESP)."),
    _command("MHELICALSP", "MHELICALSP(...): MHELICAL at the base axis's FORCE_SPEED.",
             (6, 9), axis=True, source=f"{TOK}; {MAN}", confidence="I",
             note="As MHELICAL, its path speed FORCE_SPEED (as MOVESP)."),
    *[_axis(name, summary, value_range=(0, 2.0 ** 52), source="TrioBASIC help " + page,
            confidence="C", note=note)
      for name, summary, page, note in (
          ("MOVE_PA", "A value each move loaded carries, acted on when the move becomes "
           "active (MOVE_PA_CONT).", "MOVE_PA, MOVE_PA_CONT",
           "Copied into every move loaded, on each of its axes (C); acted on at the servo "
           "tick the move becomes active (its run starts, or the move before it ends) by "
           "the axis's MOVE_PA_CONT read then (D; move_pa.py)."),
          ("MOVE_PB", "As MOVE_PA: a second value each move carries (MOVE_PB_CONT).",
           "MOVE_PB, MOVE_PB_CONT", "As MOVE_PA (C; move_pa.py)."),
          ("MOVE_PA_IDLE", "What MOVE_PA_CONT acts on when the axis's last move ends.",
           "MOVE_PA_IDLE", "Acted on at the tick the axis's last buffered move ends "
           "(MTYPE 0), read then (C; D: not when set on an idle axis)."),
          ("MOVE_PB_IDLE", "As MOVE_PA_IDLE, for MOVE_PB.", "MOVE_PB_IDLE",
           "As MOVE_PA_IDLE (C)."),
      )],
    *[_axis(name, summary, value_range=(0, 6), source="TrioBASIC help " + page,
            confidence="C", note=note)
      for name, summary, page, note in (
          ("MOVE_PA_CONT", "What MOVE_PA / MOVE_PA_IDLE do when a move becomes active or "
           "the axis idle: 0 nothing, 1/3 one output, 4 an output pattern.", "MOVE_PA_CONT",
           "1 and 3: bits 0..11 the output, bit 12 its level; 4: bits 0..11 the first "
           "output, 12..19 how many, 20..51 the pattern (C). 3 acts as 1 (D: its VP_SPEED "
           "= 0 case is the idle one); 2: copied into AXIS_DEBUG_A (MOVE_PB: AXIS_DEBUG_B) "
           "(C); 5 and 6 (analogue outputs, none modelled): nothing (D); a fraction is "
           "cut (D)."),
          ("MOVE_PB_CONT", "As MOVE_PA_CONT, for MOVE_PB / MOVE_PB_IDLE.", "MOVE_PB_CONT",
           "As MOVE_PA_CONT (C)."),
      )],
    _axis("INTERP_FACTOR", "1: the axis takes part in the vector speed of MOVE and MOVEABS "
          "(and MOVESP, MOVEABSSP); 0: it follows, ending with the others.", default=1.0,
          value_range=(0, 1), source="TrioBASIC help INTERP_FACTOR", confidence="C",
          note="Power-up 1 (C: the page's example restores it). The vector SPEED, ACCEL, "
          "FORCE_SPEED, STARTMOVE_SPEED and ENDMOVE_SPEED hold along the interpolated axes' "
          "share of each straight move, VP_SPEED reads that speed (C); a move in which no "
          "such axis moves completes at once without moving (C). Arcs ignore it (C); "
          "MHELICAL's path speed is the circle's whatever the third axis's setting (D). "
          "Merged moves of different shares join at the lower of their path speeds (D: "
          "the planner has one path speed at a seam). Path distance (CONNPATH, DISTANCE) "
          "stays the whole path's (D)."),
    _axis("FORCE_DWELL", "A dwell (ms) at the end of each SP move loaded while it is set.",
          value_range=(0, _BIG), source="TrioBASIC help FORCE_DWELL", confidence="C",
          note="An SP move (MOVESP, MOVEABSSP, MOVECIRCSP, MHELICALSP, MSPHERICALSP) loaded "
          "with FORCE_DWELL above 0 ends at rest, nothing merges into it, and the next "
          "move starts that many ms later (C), rounded up to the servo cycle (D). Plain "
          "moves ignore it (C: SP moves). CANCEL drops a dwell waiting (D)."),
    _axis("CORNER_STATE", "The corner handshake of CORNER_MODE bit 2: 1 the held move is "
          "next, 3 the program lets it load at zero speed, 7 loaded, 0 the program lets it "
          "run.", value_range=(0, 7), source="TrioBASIC help CORNER_STATE",
          confidence="C", note="The move after a corner beyond RAISE_ANGLE is held out of "
          "the path (it ends at rest there); the system sets 1 when the moves before it "
          "are on their last, loads it at zero speed (MTYPE, TANG_DIRECTION read it) once "
          "they end after the program sets bit 1, and sets 7; the program's 0 ramps the "
          "path up (C; corner_state.py). A move from rest has no corner; one corner at a "
          "time per base axis; other writes are stored (D)."),
    _axis("RAISE_ANGLE", "The change of direction (radians) beyond which CORNER_MODE bit 2 "
          "holds the next move for the CORNER_STATE handshake.", value_range=(0, _BIG),
          source="TrioBASIC help RAISE_ANGLE", confidence="C", note="0 (power-up): no "
          "handshake (C). Measured as CHANGE_DIR_LAST, first two axes, from the end of "
          "the move loaded before (C), on every move, not only SP moves (C: the page's "
          "example uses MOVEABS)."),
    _axis("FORCE_RAMP", "The acceleration (user units/s^2, negative slowing) over the "
          "whole length of each SP move loaded while it is set: FORCE_SPEED to "
          "ENDMOVE_SPEED.", source="TrioBASIC help FORCE_RAMP", confidence="C",
          note="The move runs at the constant rate |FORCE_RAMP| (instead of ACCEL) with "
          "its top the higher of FORCE_SPEED and ENDMOVE_SPEED, so with the page's rate "
          "(end^2 - start^2) / (2 x distance) it ramps from the one to the other over its "
          "length (C); another rate is the path planner's best at that rate (D). 0: none "
          "(C). Plain moves ignore it (C)."),
    _axis("LOOKAHEAD_FACTOR", "A factor on the FORCE_SPEED, STARTMOVE_SPEED and "
          "ENDMOVE_SPEED of the SP moves in the buffer.", default=1.0,
          value_range=(0, _BIG), source="TrioBASIC help LOOKAHEAD_FACTOR", confidence="C",
          note="Power-up 1 (C: the page's example restores it). Taken by SP moves loaded "
          "and, when written, by every SP move of the base axis's group not yet done; the "
          "one running changes speed from where it is at its ACCEL (C; D: the rate). "
          "Below 0.001 it acts as 0.001 (D)."),
    # ---- motion words stored but not acted on, each with why (issue 35) ----------------
    *[_axis(name, summary, confidence="D", note="Not modelled: " + why)
      for name, summary, why in (
          ("VP_POSITION", "Reserved.", "its page says only 'reserved keyword' (stored, D)."),
          ("SPEED_SIGN", "Reserved.", "its page says only 'reserved keyword' (stored, D)."),
          ("FEED_OVERRIDE", "The feed-rate override of embedded speed profiles "
           "(MOVECONTOUR).", "it acts only on embedded speed profiles (MOVECONTOUR, "
           "MOVEABSSEQ's option bit 0), neither of which is modelled (stored, D)."),
      )],
    *[_command(name, summary, arity, axis=axis, confidence="D", note="Not modelled: " + why)
      for name, summary, arity, axis, why in (
          ("CUBIC_VPU", "CUBIC_VPU(...): a cubic path from TABLE data.", (5, 10), False,
           "no help page for it was found, so neither its arguments nor its effect are "
           "known (accepted, no effect, D)."),
          ("MOVEL", "MOVEL: a straight move in the robot frame.", (0, 0), True,
           "an RPS statement (MOVEL target [S:= T:= O:= ZT:= ...], GTA targets) on a robot "
           "chosen by ROBOT and KINEMATIC_GROUP: the robot types' kinematic models are not "
           "in the help pages, its profile is jerk-limited by WORLD_POS_MAX_JERK and "
           "blended by radius in ways the page names but does not give, and the RPS "
           "target syntax is not parsed (accepted bare, no effect, D)."),
          ("MOVEJ", "MOVEJ: a joint move in the robot frame.", (0, 0), True,
           "as MOVEL: an RPS statement on a robot whose kinematic model is not in the help "
           "pages (accepted bare, no effect, D)."),
          ("TOOL_OFFSET", "TOOL_OFFSET(...): the robot's tool offset.", (0, 8), True,
           "its TrioBASIC page was not found, only the RPS one (a named tool frame of an "
           "RPS robot, whose kinematic model is not in the pages); WORLD_DPOS takes none "
           "(accepted, returns 0, D)."),
          ("USER_FRAME", "USER_FRAME(...): the robot's user frame.", (0, 8), True,
           "its page does not settle the rotation: its examples turn a conveyor about Z "
           "with the fifth argument, which the syntax names x_rotation; and each move is "
           "loaded with the USER_FRAME selected then, the active one following MTYPE. "
           "Not built: DPOS stays the world (accepted, returns 0, D)."),
      )],
    # ---- robot frames (personalities/trio/frames.py) -------------------------------------
    _axis("FRAME", "The robot (kinematic) frame of the axes' frame group (0: none).",
          source=f"{TOK}; {HELP} FRAME", confidence="C",
          note=_FRAMES + " (C). With a frame on, DPOS (by UNITS) is the world position the "
          "moves plan and the motors follow the inverse transform every servo tick; "
          "enabling sets DPOS to the forward transform of AXIS_DPOS, FRAME = 0 sets DPOS "
          "to MPOS (C). FRAME on an axis of no FRAME_GROUP makes group 0 the lowest axes, "
          "table offset 0 (C). A change is refused with 'Parameter out of range' unless "
          "the group's axes are idle, and so is a frame whose equations the page does not "
          "give (1, 3, 13 ...) (D); a refused change leaves the old frame on. Frames 6 "
          "and 10 read their TABLE scale live, but a 0 or non-finite one written while "
          "on is not taken: the last one goes on (D: the page warns against the write). "
          "MPOS reads AXIS_DPOS, FE 0: a servo axis in a frame "
          "follows its motor demand exactly (D). The FWD_IN / REV_IN switches act on the "
          "motor (C): the tick a joint reaches one going towards it is found as for "
          "AXIS_FS_LIMIT and cancels the group's moves the same way (I)."),
    _axis("AXIS_UNITS", "Counts per unit of the axis (motor) positions while a FRAME is on: "
          "AXIS_DPOS and MPOS.", default=1.0, source=f"{TOK}; {HELP} AXIS_UNITS, FRAME",
          confidence="C", note="0 is refused with 'Parameter out of range' (D, as UNITS)."),
    _axis("AXIS_DPOS", "The axis (motor) demand at the output of the FRAME transform, in "
          "AXIS_UNITS; DPOS while FRAME is 0.", writable=False,
          source=f"{TOK}; {HELP} AXIS_DPOS", confidence="C",
          note="Exact at every servo tick (the inverse transform of the world demand)."),
    _axis("WORLD_DPOS", "The demand in the FRAME's coordinate system (between DPOS and "
          "AXIS_DPOS).", writable=False, source=f"{TOK}; {HELP} WORLD_DPOS",
          confidence="C", note="Equal to DPOS: no USER_FRAME or TOOL_OFFSET is modelled "
          "(see them) (I)."),
    *[_axis(name, f"The joint's {side} software limit in AXIS_UNITS, only with a FRAME on.",
            default=sign * 200000000000, source=f"{TOK}; {HELP} {name}", confidence="C",
            note=f"While AXIS_DPOS is {beyond} it AXISSTATUS bit {bit} is set (C). The tick a "
            "joint passes it going out (found exactly: the motor demand searched tick by "
            "tick, 1024 ticks at a time) every move of its FRAME_GROUP is cancelled: the "
            "running ones ramp down at the base's FASTDEC, or DECEL when it is 0 (a path "
            "along itself at its ACCEL), the buffered ones are dropped (I); moves back "
            "run (D). Off when beyond REP_DIST (C; -REP_DIST for the reverse one, I).")
      for name, side, sign, beyond, bit in (
          ("AXIS_FS_LIMIT", "forward", 1, "above", 16),
          ("AXIS_RS_LIMIT", "reverse", -1, "below", 17))],
    _axis("FRAME_SCALE", "The resolution of the high-accuracy frames (100 and up).",
          default=1000000000, source=f"{TOK}; {HELP} FRAME_SCALE", confidence="C",
          note="Power-up 1000000000 (C: page), so UNITS = FRAME_SCALE (its example) works; "
          "stored: no frame of 100 and up is built (D)."),
    _command("FRAME_TRANS", "FRAME_TRANS(frame, table_in, table_out, direction[, "
             "table_offset]): a frame's forward (1: AXIS_DPOS to DPOS) or inverse (0) "
             "transform of raw positions in TABLE, its parameters at table_offset.", (4, 5),
             source=f"{TOK}; {HELP} FRAME_TRANS", confidence="C",
             note="For the frames FRAME models (2, 5, 6, 10); another frame, a direction "
             "other than 0 or 1, or a result that is not a number is 'Parameter out of "
             "range', nothing written (D); frame 6's forward angle is atan2's, -pi..pi "
             "times the scale (D). As a function it returns 0 (D: the page gives none)."),
    _command("FRAME_GROUP", "FRAME_GROUP(group[, table_offset, axis0 ...]): the axes and "
             "TABLE offset of a FRAME; table_offset -1 deletes the group (its frame off); "
             "the group alone prints it.", (1, 128),
             source=f"{TOK}; {HELP} FRAME_GROUP", confidence="C",
             note="Groups 0-7, axes ascending (C); an axis in two groups, or a table_offset "
             "past the TABLE, is refused (D); "
             "redefining or deleting a group turns its frame off first (I). The printed "
             "line has the page's form, with the identity USER_FRAME, TOOL_OFFSET and "
             "VOLUME_LIMIT (none is modelled, D); a group not defined prints 'n [-1] :' (D). As "
             "a function it returns 0 (D)."),
    # ---- geometric moves (personalities/trio/geometry.py) ------------------------------------
    _command("MSPHERICAL", "MSPHERICAL(x, y, z, u, v, w, mode[, gtpi[, rotau[, rotav[, "
             "rotaw]]]]): an arc of a circle anywhere in the space of the first three BASE "
             "axes, at the base axis's SPEED: mode 0 end and a point on the way, 1 end and "
             "centre (the short way), 2 two points of a full circle, 3 a point and the "
             "centre of a full circle.", (6, 12), axis=True,
             source=f"{HELP} MSPHERICAL; {TOK}", confidence="I",
             note="One segment of the shared path planner (merges like MOVECIRC); MTYPE 31 "
             "(C: MTYPE page). Modes, gtpi (the other way round) and the linear rota axes "
             "from the page (C); every position relative to the start (I, as MOVECIRC); "
             "rota values are distances (I); points in line, the end off the circle by "
             "more than a count, or mode bits 8..12 (MOVETURN): Parameter out of range "
             "(D; the page: a RUN_ERROR for points in line); ends on whole counts (D)."),
    _command("MSPHERICALSP", "MSPHERICALSP(...): MSPHERICAL at the base axis's FORCE_SPEED.",
             (6, 12), axis=True, source=f"{HELP} MSPHERICALSP; {TOK}", confidence="I",
             note="As MSPHERICAL, its path speed FORCE_SPEED (as MOVESP); MTYPE 40 (C: MTYPE "
             "page). ENDMOVE_SPEED and STARTMOVE_SPEED are not applied (see them)."),
    _command("MOVETANG", "MOVETANG(position[, link_axis]) AXIS(n): move the axis at its "
             "SPEED/ACCEL/DECEL to `position` the short way round, REP_DIST being half a "
             "turn; called again while it moves, the end moves to the new position.",
             (1, 2), axis=True, source=f"{HELP} MOVETANG; {TOK}", confidence="I",
             note="The short way and the -REP_DIST..REP_DIST range from the page (C); a new "
             "MOVETANG while one runs re-plans its end from where the axis is at the speed "
             "it has, as MOVEMODIFY (I); MTYPE 30 while it moves (C), 0 after it (D: the page "
             "keeps 30, so WAIT IDLE would never end); while another move runs on the axis, "
             "or REP_DIST is not positive: Parameter out of range (D). The link_axis form "
             "(the end copied from TANG_DIRECTION each servo cycle) is refused: a target "
             "moved every cycle is not a closed-form motion of the shared machine (D)."),
    _axis("TABLE_POINTER", "The TABLE location the axis's CAMBOX or CAM is at, X.Y: the "
          "location of the interval it is in and the share of that interval done.",
          writable=False, source="TrioBASIC help TABLE_POINTER; tokentable", confidence="C",
          note="CAMBOX: from the link axis's DPOS at this tick (a repeating one starts again "
          "at its first location each cycle), its first location until its start comes (D); "
          "CAM: from the time into the profile (each interval an equal time). 0 with neither "
          "(D). The token table has it writable; writing is refused (D). A running CAMBOX "
          "or CAM reads its TABLE live, so the page's rewriting of passed locations acts "
          "on its next cycle (C)."),
    _axis("TANG_DIRECTION", "The direction of the interpolated path of the axis's group in "
          "radians, atan2(X, Y) of its first two axes: +Y 0, +X PI/2, -Y PI.",
          writable=False, source=f"{HELP} TANG_DIRECTION; {TOK}", confidence="I",
          note="The exact tangent of the path segment the group is on at this tick (C: the "
          "page's table); a single-axis move is X alone (D); at rest the direction of the "
          "last path the axis ended (D), 0 at power-up. The token table has it writable; "
          "writing is refused (D)."),
    _command("SPHERE_CENTRE", "SPHERE_CENTRE(mid, end, out): the centre (x, y, z), angle, "
             "radius and error flag of the arc from the start through the TABLE points mid "
             "and end (relative to the start), written to TABLE out..out+5.", (3, 3),
             axis=True, source=f"{HELP} SPHERE_CENTRE; {TOK}", confidence="I",
             note="The layout from the page (C); the angle in radians (D); points in line: "
             "the flag 1 and the rest 0 (D)."),
    _command("FILLET", "FILLET(in, out, option): option 0 the arc of a radius blending two "
             "3D lines (19 values), option 2 the unit vectors, mid vector and dot product of "
             "two 3D vectors (13 values).", (3, 3), source=f"{HELP} FILLET; {TOK}",
             confidence="I",
             note="Layouts from the page (C); option 2 gives the page's example output "
             "exactly; option 0's angle in radians and, when the radius does not fit, the "
             "largest whose ends fit both lines (D). Options 1 and 3 (2D arc pairs): "
             "Parameter out of range (D: not modelled)."),
    *[_command(name, f"{name}(table, axes, npoints, options, radius[, output[, "
               "transition]]): a sequence of TABLE points (" + what + ") loaded as "
               "MOVEABS moves with a fillet arc of `radius` at each corner: MOVECIRC on 2 "
               "axes, MSPHERICAL on 3.", (5, 7), axis=True, source=f"{HELP} {name}; {TOK}",
               confidence="I",
               note="The moves it loads and the radius reduced to fit from the page (C); "
               "the arcs are FILLET option 0's; a corner takes at most half of a side it "
               "shares with another corner (D); each move waits for room in the buffer as "
               "a MOVE does. Options other than 0, an output area, a transition angle, "
               "other than 2 or 3 axes: Parameter out of range (D: not modelled). "
               "MOVE_COUNT is not counted (D).")
      for name, what in (("MOVEABSSEQ", "absolute"),
                         ("MOVESEQ", "increments from the point before (I)"))],
    # ---- TABLE splines (personalities/trio/splines.py) ----------------------------------------
    _command("B_SPLINE", "B_SPLINE(1, in, points, out, expansion): a uniform cubic B-spline "
             "of TABLE points, (points + 1) * expansion values and the last point; "
             "B_SPLINE(2, 3, 3, 0, points, "
             "knots, expansion, in, out): a NURBS curve of XYZ points, points * expansion "
             "XYZ triples.", (5, 9), source=f"{HELP} B_SPLINE; {TOK}", confidence="I",
             note="Counts, argument order and the XYZ layout from the page (C); mode 1's "
             "closing point after the page's count (I: a real cell's program lays its "
             "outputs (points + 1) * expansion + 1 apart and cams over all); the knot "
             "vector read after the points (I: the page's example); mode 1's end points "
             "taken three times and mode 2's evenly spaced parameters, both ends included, "
             "are ours (D); weight_op other than 0, dimensions or curve type other than 3: "
             "Parameter out of range (D). Every value is computed before one TABLE write: "
             "an error writes nothing."),
    _command("C_SPLINE", "C_SPLINE(mode, in, points, dims, expansion, out[, tension, bias]): "
             "cubic Hermite (Catmull-Rom, modes 1/3; cardinal, modes 2/4) expansion of "
             "TABLE points, (points - 1) * expansion + 1 per dimension.", (6, 8),
             source=f"{HELP} C_SPLINE; {TOK}", confidence="I",
             note="Layout (3/4 interleaved, 1/2 a block per dimension), ranges (dims 2..8, "
             "expansion 2..100, tension and bias -1..1) from the page (C); the tangents are "
             "the usual tension/bias form (I); each end its own missing neighbour (D)."),
    _command("A_SPLINE", "A_SPLINE(in, points, out, expansion): Akima interpolation of "
             "TABLE values, points * expansion values.", (4, 4),
             source=f"{HELP} A_SPLINE; {TOK}", confidence="D",
             note="Akima's slopes with his extrapolated end slopes (I); the count from the "
             "page's example's CAMBOX (I); the values evenly spaced from the first point to "
             "the last (D); at least 3 points (D)."),
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
    Keyword("FMOD", Kind.OPERATOR, "a FMOD b: the floating point remainder of a / b, with "
            "a's sign, at MOD's precedence.", "TrioBASIC help FMOD", "C",
            "The page's examples: 2023.4 FMOD 356 = 243.4, -204.56 FMOD 60 = -24.56 (C); "
            "FMOD 0 is 'Divide by zero' as MOD (D)."),
    Keyword("AXIS", Kind.MODIFIER, "AXIS(n) after a parameter or command: axis n instead of "
            "the base axis.", f"{SEED}; {TOK}", args=(1, 1)),
]

# Statements the parser handles itself (structure, declarations, errors).
_STATEMENTS = {
    "GOTO": "GOTO label: go on at the line after `label:`.",
    "GOSUB": "GOSUB label: call the routine at `label:`; RETURN comes back.",
    "RETURN": "Return from a GOSUB.",
    "ELSEIF": "ELSEIF cond THEN: another branch of a block IF.",
    "CONSTANT": "CONSTANT \"name\", value: a named constant for every program; "
                "CONSTANT \"name\" clears that one, CONSTANT alone every one (help "
                "CONSTANT).",
    "GLOBAL": "GLOBAL \"name\", vr: a name for VR(vr) in every program; GLOBAL "
              "\"name\" clears that one, GLOBAL alone every one (help GLOBAL).",
    "DIM": "DIM name[(n)] AS INTEGER|FLOAT|BOOLEAN|STRING(n): a local variable or array; "
           "STRING with no (n) holds 64 characters (D: the CHR and HEX pages' examples "
           "declare one so, no page gives its length).",
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


_ROBOT = ("FRAME", "USER_FRAME", "WORLD_", "ROBOT_", "TCP_", "KINEMATIC_", "OBJECT_FRAME",
          "ATTACH_OBJECT_FRAME", "SYNC_TO_OBJECT_FRAME", "AXIS_DPOS", "AXIS_FS_LIMIT",
          "AXIS_RS_LIMIT", "VOLUME_LIMIT", "TOOL_OFFSET")
_OWN_WHY = {
    **{name: "a robot (kinematic) system word with no help page found (D)" for name in (
        "AXIS_ACCEL", "AXIS_DECEL", "AXIS_FASTDEC", "AXIS_JERK", "AXIS_JOGSPEED",
        "AXIS_MAX_SPEED", "AXIS_SPEED", "COLLISION_OBJECT", "DISABLE_ROBOT", "ROBOTSTATUS",
        "SYNC_TO_GTA", "TARGET", "TOOL_COLLISION")},
    "MOVEC": "no help page found: neither its arguments nor its effect are known (D)",
    "PATH_FLOW": "no help page found (D)",
    "CRANK_CAM": "its page: a reserved keyword, no function given (D)",
    "MOVEABSFR": "its page: under development, to be used only on Trio's instruction; it "
                 "gives no behaviour (D)",
    "MOVEPICK": "its page gives the arch (withdraw on Z, the XY move, the approach) in "
                "words and pictures: not the curve an overlap of 0..0.9 rounds a corner "
                "with, nor how 'the length of the shortest move' sets the acceleration; "
                "and the withdraw is from the start by its parameter, from each end by its "
                "example (D)",
    "PICKLINK": "MOVEPICK linked to another axis; see MOVEPICK (D)",
    "MOVETURN": "its page gives only each mode's arguments: not the path an exterior or "
                "interior change of direction makes (its radius or shape), mode 2's "
                "arguments, or what mode 3 does (a '?'); the examples are empty (D)",
    "MOVECONTOUR": "its page names, without giving them, the speed between embedded "
                   "speeds, the radius corner_acc slows by, the spline modes' curves and "
                   "the 15 values a point it writes to the output TABLE; 5-axis needs a "
                   "licence (D)",
    "VOLUME_LIMIT": "its page gives the cylinder-with-cone volume by a picture and a "
                    "table of sizes: which way Z runs from the top centre origin is not "
                    "given, nor what the cone angle is measured from (its axis or its "
                    "base: the example's 60 degrees over 150 narrow 1100 to 580 or to "
                    "927), nor whether the cone ends in a point or a flat base, so the "
                    "limit cannot be exact (D)",
    "USER_FRAMEB": "it names the USER_FRAME a SYNC(20) resynchronises to: neither "
                   "USER_FRAME (see it) nor SYNC(20) is built (D)",
    "USER_FRAME_TRANS": "it maps TABLE positions through USER_FRAMEs and TOOL_OFFSETs, "
                        "whose matrices are not settled (see USER_FRAME: its rotation "
                        "arguments; TOOL_OFFSET's TrioBASIC page is missing), and the "
                        "page does not say how many values it writes at table_out (D)",
}


_SERIAL = "the emulator has no serial port or multi-drop bus, only the telnet command line"
_MP = "a Motion Perfect transfer word whose binary reply format the pages do not give"
_MAP = "an I/O map of expansion modules, CAN or drive I/O, which the emulated MC405 has none of"
# Why the I/O, channel, program and system words left unmodelled have no effect to show
# (issue 35e; each from the word's TrioBASIC help page).
_SYSTEM_WHY = {
    "PRMBLK": _MP, "LOOKUP": _MP, "AXISVALUES": _MP, "EDPROG1": _MP,
    "VIEW": "it shows the compiled object code, which the emulator does not produce",
    "STORE": "it loads firmware (help page STORE)",
    "SETCOM": _SERIAL, "ADDRESS": _SERIAL, "READPACKET": _SERIAL,
    "IO_STATUS": "it reads a remote EtherCAT I/O device's status; there is no EtherCAT",
    "IO_STATUSMASK": "it masks a remote EtherCAT I/O device's status; there is no EtherCAT",
    "IOMAP": _MAP, "DRIVEIO_BASE": _MAP, "INTERNALIO_BASE": _MAP, "MODULEIO_BASE": _MAP,
    "MODULE_IO_MODE": _MAP, "AXIS_OFFSET": "it places a module slot's axes; the MC405's "
                                          "axes are fixed here",
    "VERIFY": "no function on the MC4xx (help page: kept for old programs' sake)",
    "POWER_UP": "no function on the MC4xx: programs always start from flash (help page)",
    "TABLE_PROTECT": "not available on the MC405 (help page TABLE_PROTECT)",
    "OUTPUT_PROGRAM_TYPE": "a RAM file of an explicit program type; FOR OUTPUT writes a "
                           "text file of the store",
    "SYSTEM_ERROR_MASK": "SYSTEM_ERROR is always 0 here (no fault it could mask)",
    "SCHEDULE_TYPE": "the emulator's process scheduling is fixed (one pass a servo cycle, "
                     "see tasks.py)",
    "COMPILE_MODE": "DIM is not enforced: programs compile as in the default mode 0",
    "LAST_AXIS": "every axis of the emulated MC405 is always processed, so no axis list is "
                 "kept: it reads what was written (power-up 0), not the highest axis used",
    "AXIS_ADDRESS": "a drive or feedback device's address: there is no drive network",
    "AXIS_DISPLAY": "no function on the MC4xx (help page)",
    "AXIS_DEBUG_A": "reserved for Trio's own analysis (help page)",
    "AXIS_DEBUG_B": "reserved for Trio's own analysis (help page)",
    "AXIS_DEBUG_C": "reserved for Trio's own analysis (help page)",
    "AXIS_DEBUG_D": "reserved for Trio's own analysis (help page)",
    "AXIS_A_OUTPUT": "a reserved keyword (help page)", "AXIS_B_OUTPUT": "a reserved keyword",
    "AXIS_D_OUTPUT": "a reserved keyword",
    "AXIS_Z_OUTPUT": "the Z pins' line driver as an output: no pins in the world",
    "POS_DELAY": "a digital drive network's delay on HW_PSWITCH: no drive network",
    "AXESDIFF": "it configures an ATYPE 85 monitoring axis, which is not modelled",
    "COORDINATOR_DATA": "special firmware features (help page: ask Trio)",
    "MPE_MODE": "the Motion Perfect channel protocol is not modelled (MPE is 0)",
    "GTA": "no help page found", "GTAMAP": "no help page found",
    "INT_BASE": "no help page found",
}

_NO_PAGE = "no help page found: neither its arguments nor its effect are known"
_CARD = "the SD card: the emulated MC405 has no card slot"
_KEYS = "project encryption keys: the emulator's projects are not encrypted"
_HMI = "the Trio HMI server and its clients: no HMI client connects to the emulator"
_MODULES = "the MC664's option modules (help page): the MC405 has none"
# Why the firmware, memory, debugging and display words have no effect to show (issue 35p;
# each from the word's TrioBASIC help page).
_FIRMWARE_WHY = {
    "BOOT_LOADER": "Motion Perfect's word to enter the boot loader (firmware loading)",
    "LOADSYSTEM": "it loads firmware (help page)",
    "LOAD_PROJECT": "Motion Perfect's project loading, whose protocol the page does not give",
    "FPGA_PROGRAM": "it selects the hardware's FPGA program: the emulator has no FPGA",
    "FPGA_VERSION": "the hardware's FPGA version: the emulator has no FPGA",
    "CPU_EXCEPTIONS": "the firmware's processor exception counts, no help text found",
    "FPU_EXCEPTIONS": "floating point exceptions of the firmware's processes, for Trio's own "
                      "debugging (help page): none arise here",
    "CPU_TEMP": "its page: not available on the MC405",
    "CPU_TEMP_MAX": "its page: not available on the MC405",
    "DUMP": "a memory image for the manufacturer's debugging (help page); the emulator has "
            "no firmware memory image",
    "PEEK": "a controller memory address: the pages give no memory map to read",
    "POKE": "a controller memory address: the pages give no memory map to write",
    "EPROM": "no function on the MC4xx: programs are always in flash (help page)",
    "EPROM_STATUS": "background flash programming: the store writes at once, so 0, 'not "
                    "active' (help page)",
    "FLASH_LOG": "the controller's log of firmware system events, which the emulator's "
                 "events are not",
    "FLASH_DUMP": "a flash memory dump, no help text found",
    "FEATURE_ENABLE": "feature enable codes unlock licensed features; every modelled "
                      "feature is there without one",
    "LOCK": "it hides programs behind a code (CONTROL + 1000); the page gives no reply for "
            "a refused command, so a locked emulator could not answer as the controller",
    "UNLOCK": "see LOCK",
    "SET_ENCRYPTION_KEY": _KEYS, "VALIDATE_ENCRYPTION_KEY": _KEYS,
    "IS_ENCRYPTION_KEY": _KEYS, "PROJECT_KEY": _KEYS,
    "PROJECT_KEY_REGISTRY": _NO_PAGE,
    "PROJECT_NAME": "the name Motion Perfect gives the project it loads; none is loaded here",
    "EXECUTE": "remote command execution of the PCMotion ActiveX, whose protocol the page "
               "does not give",
    "TEXT_FILE_LOADER": "the TrioPC ActiveX's file transfer, whose protocol the page does "
                        "not give",
    "TEXT_FILE_LOADER_PROC": "the TrioPC ActiveX's file transfer, whose protocol the page "
                             "does not give",
    "TEXT_FILE_LOADER_STATUS": _NO_PAGE,
    "TRIOPCTESTVARIAB": "Trio's own test of the TrioPC ActiveX (help page)",
    "STICK_READ": _CARD, "STICK_WRITE": _CARD, "STICK_READVR": _CARD,
    "STICK_WRITEVR": _CARD, "ZIP_READ": _CARD,
    "SD_READGTA": _NO_PAGE, "SD_WRITEGTA": _NO_PAGE, "EXEC": _NO_PAGE,
    "CUSTOM_FUNC": _NO_PAGE, "PENDANT_USER": _NO_PAGE,
    "HMI_CONNECTIONS": _HMI, "HMI_GET_PAGE": _HMI, "HMI_GET_STATUS": _HMI,
    "HMI_PROC": _HMI, "HMI_SERVER": _HMI, "HMI_SET_PAGE": _HMI,
    "DISPLAY": "it picks the I/O bank the controller's LEDs or display show: the emulator "
               "has no front panel display of its own",
    "LCDSTR": "the controller's display text: the emulator has no display",
    "UNIT_CLEAR": _MODULES, "UNIT_DISPLAY": _MODULES, "UNIT_ERROR": _MODULES,
    "UNIT_SW_VERSION": _MODULES,
    "SERIAL_NUMBER": "the unit's serial number: an emulated unit has none",
    "SYSTEM_LOAD": "the firmware's own share of the servo period (help page); the "
                   "emulator's work is not the firmware's, so it has no such share",
    "FUNCTION_LIST": "it lists the FUNCTIONs known, in a form the page does not give",
    "USER_PID": "its page gives the PID's inputs and outputs, not its equations (a "
                "function diagram of an IEC 61131-3 PID, a family with variants), so its "
                "output cannot be exact",
}


def _why_not(name: str) -> str:
    """Why a token-table word is only accepted: a fieldbus or network word, or one of
    firmware, files, memory and debugging, has no effect an emulated machine shows; the
    robot words, a few moves and the I/O and system words have their own reason; any other
    word is simply not modelled yet."""
    if name in _OWN_WHY:
        return _OWN_WHY[name]
    if name in _SYSTEM_WHY:
        return _SYSTEM_WHY[name] + " (D)"
    if name in _FIRMWARE_WHY:
        return _FIRMWARE_WHY[name] + " (D)"
    if name.startswith(_ROBOT):
        return ROBOT_WHY + " (D)"
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


def _from_help_pages(known: set[str]) -> list[Keyword]:
    """The help's fieldbus, set-up and diagnostic words the token table lacks
    (helpwords.py), each "Not modelled" with its reason; a word already known is skipped."""
    from .helpwords import HELP_WORDS

    out: list[Keyword] = []
    for row in HELP_WORDS.splitlines():
        tag, name, rest = row.split(" ", 2)
        if name in known:
            continue
        source = f"{HELP} {name}"
        if tag in ("S", "A"):
            access, why = rest.split(" ", 1)
            note = ("Not modelled: stored and read back, no effect on the machine"
                    if access == "w" else "Not modelled: reads 0") + \
                (", a value for each argument list" if tag == "A" else "") + f"; {why} (D)."
            out.append(_system(name, f"Help-page system {'array' if tag == 'A' else 'parameter'}"
                               ".", writable=access == "w", source=source, confidence="D",
                               note=note))
            continue
        low, high, why = rest.split(" ", 2)
        if tag == "F":
            out.append(_function(name, "Help-page function.", (int(low), int(high)),
                                 source=source, confidence="D",
                                 note=f"Not modelled: returns 0; {why} (D)."))
        else:
            out.append(_command(name, "Help-page command.", (int(low), int(high)),
                                source=source, confidence="D",
                                note=f"Not modelled: accepted, no effect; {why} (D)."))
    return out


def _from_newer_help(known: set[str]) -> list[Keyword]:
    """The help's words newer than the token table that act on motion, inputs or set-up
    (helpwords.NEWER_WORDS): modelled (a note starting "=") or "Not modelled" with why."""
    from .helpwords import NEWER_NOTE, NEWER_WORDS

    out: list[Keyword] = []
    for row in NEWER_WORDS.replace("\n    ", " ").splitlines():
        tag, name, rest = row.split(" ", 2)
        if name in known:
            continue
        source = f"TrioBASIC help {name}"
        if tag in ("P", "Y"):
            access, default, low, high, text = rest.split(" ", 4)
        else:
            low, high, text = rest.split(" ", 2)
        if text.startswith("="):
            note, confidence = f"{text[1:]} {NEWER_NOTE}", "C"
        elif tag in ("P", "Y"):
            note = ("Not modelled: stored and read back, no effect on the machine"
                    if access == "w" else f"Not modelled: reads {float(default):g}") + \
                f"; {text[1:]} (D). {NEWER_NOTE}"
            confidence = "D"
        else:
            note = (f"Not modelled: accepted, no effect, as a function it returns 0; "
                    f"{text[1:]} (D). {NEWER_NOTE}")
            confidence = "D"
        if tag in ("P", "Y"):
            make = _axis if tag == "P" else _system
            out.append(make(name, f"Help-page {'axis' if tag == 'P' else 'system'} "
                            "parameter.", default=float(default), writable=access == "w",
                            value_range=(float(low), float(high)), source=source,
                            confidence=confidence, note=note))
        else:
            out.append(_command(name, "Help-page command.", (int(low), int(high)),
                                axis=tag == "K", source=source, confidence=confidence,
                                note=note))
    return out


def _index(entries: list[Keyword]) -> dict[str, Keyword]:
    """The table by name; a keyword listed twice is an error at import."""
    table: dict[str, Keyword] = {}
    for entry in entries:
        if entry.name in table:
            raise ValueError(f"TrioBASIC keyword {entry.name} is listed twice")
        table[entry.name] = entry
    return table


_TABLED = _ENTRIES + _from_token_table()
_HELPED = _TABLED + _from_help_pages({k.name for k in _TABLED})
KEYWORDS: dict[str, Keyword] = _index(_HELPED + _from_newer_help({k.name for k in _HELPED}))


def lookup(name: str) -> Keyword | None:
    return KEYWORDS.get(name.upper())

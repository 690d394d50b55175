"""Evaluating TrioBASIC: expressions, and statements as resumable generators.

A statement runs as a generator that yields while the process must wait (WA, WAIT,
a full move buffer), so a program runs beside the command line: the scheduler resumes
each process once per servo cycle. Every argument of a statement is evaluated and
checked before the machine is asked to act, and the machine is asked once, so an error
leaves nothing half-applied.

Long module: expressions, statements, strings and I/O share one evaluator and its error
rules (every argument checked before the machine acts), kept in one place.
"""

from __future__ import annotations

import datetime
import math
import random
import struct
from collections.abc import Callable, Generator, Sequence
from dataclasses import dataclass, field
from functools import partial
from typing import Protocol

from ...personalities.trio.encoders import endat
from ...personalities.trio.frames import PARAMETERS as FRAME_TABLE
from ...personalities.trio.frames import SIZES as FRAME_SIZES
from ...personalities.trio.frames import transform as frame_transform
from ...personalities.trio.geometry import NAMES as GEOMETRIC
from ...personalities.trio.geometry import group_size
from ...personalities.trio.memory import VR_COUNT
from ...personalities.trio.sequences import NAMES as SEQUENCES
from ...personalities.trio.sequences import axes_of
from ...personalities.trio.slm import dlink
from .datawords import CrcSetup, value_of, words_of
from .errorcodes import RUN_ERRORS, run_error
from .fifos import FifoFiles
from .keywords import BANKED_PARAMETERS, CHANNEL_PARAMETERS, KEYWORDS, Keyword, Kind
from .lexer import Thrown, TrioError
from .machine import TrioMachine
from .motionwords import SET_MOTION_WORDS, set_motion
from .parser import (
    MAX_ARRAY,
    MAX_STRING,
    ArrayFill,
    Assign,
    Binary,
    Bit,
    Call,
    Channel,
    Command,
    Declare,
    Dim,
    Expr,
    Field,
    Format,
    IfLine,
    Num,
    Opened,
    Param,
    Perform,
    Print,
    Stmt,
    Str,
    Unary,
    Var,
    WaitIdle,
    WaitLoaded,
    WaitUntil,
)
from .printformat import ARITHMETIC, FLOAT_FUNCTIONS, FLOAT_OPERATORS, Real, c_format, real
from .servoread import servo_read

Value = float | str
Argument = Value | list[Value]  # a FUNCTION's argument: a value, or a DIM array by reference
# a STATIC name between calls: its value, or its array and shape, and its DIM type
Kept = tuple[Value | None, list[Value] | None, tuple[int, ...] | None, str | None]


MAX_WA_MS = 1e12  # WA in ms beyond about 30 years is refused (D): time has no such ticks


@dataclass(frozen=True, slots=True)
class Wake:
    """What a waiting statement waits for, so a scheduler can sleep until then: a servo
    tick (WA), or `tick` None for a change of the machine (WAIT IDLE, a full move buffer:
    they can only end when motion or another statement changes something). A bare
    ``yield None`` means "try again next servo cycle" (WAIT UNTIL, loop passes)."""

    tick: int | None = None


ON_CHANGE = Wake(None)


def due_after(wake: Wake | None, now: int) -> int | None:
    """The tick a statement that yielded `wake` at `now` runs again (None: on a change)."""
    if wake is None:
        return now + 1
    return wake.tick
Wait = Generator[Wake | None, None, None]


def format_number(value: float) -> str:
    """A FLOAT (printformat.Real) with 4 decimals; any other value without decimals
    when whole (atrio's handshake needs ?<integer> so), else with 4."""
    if value == int(value) and not isinstance(value, Real):
        return str(int(value))
    return f"{value:.4f}"


_UNSET = Real(0.0)  # a variable never assigned reads 0, a FLOAT (help DIM: the default type)
MAX_INDEXED = 4096  # values kept for parameters with arguments or SLOT/PORT (D: bounded)
FILE_CHANNELS = 20  # channels from 20 up are files: reading one not open is an error (D)
# The controller's one memory for its programs' DIMmed variables, arrays and strings, every
# process, FUNCTION call and command line together (D, issue 34: the real MC405 has a fixed
# memory; its size for variables is not published, this is far beyond what programs DIM).
# A DIM holds 8 bytes a number and n a STRING(n) element from the DIM on, a variable not
# DIMmed 8 bytes or its string's length; a DIM or an assignment that would pass the budget
# is "Not enough memory" (D: the text the store gives when its memory is full; no
# TrioBASIC error list was found to say otherwise) and nothing changes.
PROGRAM_MEMORY = 8 * 1024 * 1024
NUMBER_BYTES = 8

# RUN_ERROR codes: the RUN_ERROR help page's numbers for our error texts (errorcodes.py)
ERROR_CODES = {text: number for text, (number, _) in RUN_ERRORS.items()}


def error_code(message: str) -> float:
    return float(run_error(message))


@dataclass
class ProcessContext:
    """One process's own state: its BASE axes, its local variables, where it is."""

    process: int
    program: str = ""  # "" for the command line
    base: list[int] = field(default_factory=lambda: [0])
    variables: dict[str, Value] = field(default_factory=dict)
    line: int = 0
    loops: dict[int, tuple[float, float]] = field(default_factory=dict)  # FOR end, step
    arrays: dict[str, list[Value]] = field(default_factory=dict)  # DIM name(n)
    shapes: dict[str, tuple[int, ...]] = field(default_factory=dict)  # DIM name(n, m)
    types: dict[str, str] = field(default_factory=dict)  # DIM name AS type
    pc: int = 0  # the next step
    stack: list[int] = field(default_factory=list)  # GOSUB return steps
    cases: dict[int, Value] = field(default_factory=dict)  # SELECT_CASE values
    on_error: int | None = None  # ON BASICERROR GOTO handler step
    run_error: float = 0.0  # RUN_ERROR: the last error's code
    error_line: float = 0.0  # ERROR_LINE: the line it happened on
    ticks: tuple[float, int] = (0.0, 0)  # TICKS: the value set and the servo tick then
    stopped: bool = False  # STOP or HALT reached this process: it ends before its next step
    functions: Callable[[str, list[Argument]], Value] | None = None  # FUNCTIONs it calls
    memory: dict[str, int] = field(default_factory=dict)  # bytes each name holds
    held: int = 0  # their sum (PROGRAM_MEMORY)
    rng: random.Random | None = None  # RND/RNDF: this process's generator (RANDOMIZE)
    pmove: bool = False  # PMOVE: a motion command waits for room in the axes' buffers
    outdevice: int = 0  # OUTDEVICE: where PRINT with no #channel goes
    indevice: int = 0  # INDEVICE: where GET, INPUT, LINPUT and KEY with no #channel read
    status: int = 1  # PROC_STATUS while it runs a program: 1, or 2/3 under trace (tracing.py)


class SystemHook(Protocol):
    """Program handling and channel state, owned by the command-line runtime."""

    def system_command(self, keyword: Keyword, args: list[Value],
                       ctx: ProcessContext) -> Wait: ...

    def system_function(self, name: str, args: list[Value]) -> float: ...

    def system_parameter(self, name: str) -> float | None: ...

    def context_of(self, process: int) -> ProcessContext | None: ...

    def ended_context(self, process: int) -> ProcessContext | None:
        """The context of the program that last ran on a process now running none (its
        RUN_ERROR and ERROR_LINE stay readable with PROC(n), as on the controller)."""
        ...

    def memory_in_use(self, asking: ProcessContext) -> int:
        """Bytes the DIMs of every live context of the controller hold (PROGRAM_MEMORY)."""
        ...

    constants: dict[str, Value]
    globals: dict[str, int]
    spellings: dict[str, str]  # "C NAME" / "G NAME" -> the name as first typed
    analog_outputs: dict[int, float]
    indexed: dict[tuple[str, tuple[float, ...]], float]  # NODE_PROFILE(s, n), X SLOT(n)
    files: dict[int, list[int]]  # OPEN #n ... FOR INPUT: the characters still to read
    fifo_files: FifoFiles  # OPEN ... FOR FIFO_WRITE / FIFO_READ (fifos.py)
    sources: dict[int, list[int]]  # ... and every character of the file (SEEK)
    crc: CrcSetup | None  # CRC16(0, ...)'s set-up (CRC16, CHANNEL_READ's crc)
    clock_offset: float  # TIME = / DATE =: seconds the real time clock was set ahead by

    def file_text(self, name: str) -> str: ...

    def open_output(self, channel: int, name: str, append: bool) -> None: ...

    def channel_word(self, name: str, args: tuple[Expr, ...], ctx: ProcessContext,
                     interp: Interpreter) -> float: ...

    def write_file(self, channel: int, text: str) -> bool: ...

    def close_file(self, channel: int) -> None: ...

    def set_scope(self, args: list[float], params: list[Expr], ctx: ProcessContext) -> None: ...

    def trigger(self, repeat: bool) -> None: ...


def _int64(value: float) -> int:
    """A value taken as a 64-bit integer, its fraction dropped (BITCOUNT's page); outside
    the signed 64-bit range: 'Parameter out of range' (D)."""
    whole = math.trunc(value)
    if not -2 ** 63 <= whole < 2 ** 63:
        raise ValueError("Parameter out of range")
    return whole


_MATH: dict[str, Callable[[float], float]] = {
    "ABS": abs, "INT": lambda x: float(math.trunc(x)), "FRAC": lambda x: x - math.trunc(x),
    "SGN": lambda x: float((x > 0) - (x < 0)), "SQR": math.sqrt, "SIN": math.sin,
    "COS": math.cos, "TAN": math.tan, "ATAN": math.atan, "EXP": math.exp, "LN": math.log,
    "ACOS": math.acos, "ASIN": math.asin,  # outside -1..1: 'Parameter out of range' (D)
    "IS_NAN": lambda x: 0.0, "IS_INF": lambda x: 0.0,  # every value here is finite
    "BITCOUNT": lambda x: float(bin(_int64(x) & (2 ** 64 - 1)).count("1")),
}
_NETWORK = ("TCP:", "DGRAM:", "TCPSERVER:")  # OPEN's network connections (its page)
_EPOCH = datetime.datetime(2000, 1, 1)  # a Saturday
_DAYS = ("Sunday", "Monday", "Tuesday", "Wednesday", "Thursday", "Friday", "Saturday")
_CLOCK = frozenset({"TIME", "DATE", "DAY"})
_MACHINE_COMMANDS = frozenset({"MOVE", "MOVEABS", "DEFPOS", "ACC", "CANCEL", "RAPIDSTOP",
                               "PWM_CONTROL", "CONNPATH", "CAMBOX", "BASE", "TABLE", "WA",
                               "MPE", "FORWARD", "REVERSE", "OP", "DATUM", "MOVECIRC",
                               "MHELICAL", "MOVEMODIFY", "MOVELINK", "CONNECT", "ADDAX",
                               "REGIST", "MOVETEST", "FLEXLINK", "MOVESP", "MOVEABSSP", "CAM",
                               "MOVECIRCSP", "MHELICALSP", "PSWITCH", "HW_PSWITCH",
                               "HW_TIMER", "SYNC", "COMPENSATE_XY", "COMBINE_AXES",
                               *GEOMETRIC, *SEQUENCES})
_FRAME_WORDS = frozenset({"FRAME_TRANS", "FRAME_GROUP"})
_AXIS_HARDWARE = frozenset({"STEP_RATIO", "BACKLASH", "ADD_DAC",
                            "COMBINE_CONTROL"})  # set-ups of an axis
_RATES = frozenset({"SPEED", "ACCEL", "DECEL", "CREEP", "FASTDEC", "JOGSPEED"})
_BIT_COMMANDS = frozenset({"SET_BIT", "CLEAR_BIT", "READ_BIT", "FLAG", "FLAGS",
                           "INVERT_IN"})
IO_POINTS = 32  # digital inputs and outputs 0..31 (D, as the world contract's MC405 inputs)
IO_SPACE = 1024  # I/O numbers a program may name: 32 and up are expansion I/O (CAN, EtherCAT
# modules), off unless set (D: real cells use numbers above 100 for their alarms)
FOREVER_COUNTS = 2.0 ** 50  # FORWARD/REVERSE: a move this long, ended by CANCEL (D)


def _truth(value: bool) -> float:
    return -1.0 if value else 0.0


PROCESS_PARAMETERS = frozenset({"RUN_ERROR", "ERROR_LINE", "TICKS", "PROCNUMBER",
                                "PROC_LINE", "PROC_STATUS", "PMOVE", "OUTDEVICE",
                                "INDEVICE"})
_LOADING = frozenset({"MOVE", "MOVEABS", "MOVESP", "MOVEABSSP", "MOVECIRC", "MHELICAL",
                      "MOVECIRCSP", "MHELICALSP", "MOVELINK", "CONNECT", "FLEXLINK", "CAM",
                      "CAMBOX", "CONNPATH", "FORWARD", "REVERSE"})
"""Motion commands a process holds in its move buffer while the axes have no room."""


def _text(value: Value) -> str:
    return value if isinstance(value, str) else format_number(value)


def _checked(text: str) -> str:
    if len(text) > MAX_STRING:
        raise TrioError("String too long")
    return text


def _string_binary(op: str, left: Value, right: Value) -> Value:
    """Strings: + joins (a number joins as PRINT shows it), comparisons compare."""
    if op == "+":
        return _checked(_text(left) + _text(right))
    if not (isinstance(left, str) and isinstance(right, str)):
        raise TrioError("Type mismatch")
    comparisons = {"=": left == right, "<>": left != right, "<": left < right,
                   ">": left > right, "<=": left <= right, ">=": left >= right}
    if op not in comparisons:
        raise TrioError("Type mismatch")
    return _truth(comparisons[op])


def _int_arg(value: Value) -> int:
    if isinstance(value, str) or value != int(value) or abs(value) > MAX_STRING * 1e6:
        raise TrioError("Parameter out of range")
    return int(value)


def _str_arg(value: Value) -> str:
    if not isinstance(value, str):
        raise TrioError("Type mismatch")
    return value


def _chr(args: list[Value]) -> Value:
    """CHR(n[, format]): format 0 a character 0..255, 1 the UTF-8 bytes of code point n
    (each byte one character of the string, so the wire carries UTF-8: D)."""
    code = _int_arg(args[0])
    form = _int_arg(args[1]) if len(args) > 1 else 0
    if form == 0 and 0 <= code <= 255:
        return chr(code)
    if form == 1 and 0 <= code <= 0x10FFFF and not 0xD800 <= code <= 0xDFFF:
        return chr(code).encode("utf-8").decode("latin-1")
    raise TrioError("Parameter out of range")


def _hex(args: list[Value]) -> Value:
    """HEX(n): any whole n of 48 bits (D: the 48-bit two's complement it prints), so the
    32-bit words INTEGER_READ gives print as its page shows."""
    value = args[0]
    if isinstance(value, str) or value != int(value) or not -(1 << 47) <= value < (1 << 48):
        raise TrioError("Parameter out of range")
    number = int(value)
    return f"{number & 0xFFFFFFFFFFFF if number < 0 else number:X}"


def _asc(args: list[Value]) -> Value:
    """ASC(s[, offset]): the code of the character at offset (from 0); 0 when the
    string is empty or the offset is outside it (help page)."""
    text = _str_arg(args[0])
    offset = _int_arg(args[1]) if len(args) > 1 else 0
    return float(ord(text[offset])) if 0 <= offset < len(text) else 0.0


def _str(args: list[Value]) -> Value:
    """STR(v[, precision[, width]]): v with precision decimals (default 5), right
    aligned in width characters (0: as long as it takes) (help page)."""
    value = Interpreter.number_value(args[0])
    precision = _int_arg(args[1]) if len(args) > 1 else 5
    width = _int_arg(args[2]) if len(args) > 2 else 0
    if not 0 <= precision <= 20 or not 0 <= width <= MAX_STRING:
        raise TrioError("Parameter out of range")
    return _checked(f"{value:{width}.{precision}f}")


def _mid(args: list[Value]) -> Value:
    """MID(s, start[, length]): from index start (from 0, help page example)."""
    text, start = _str_arg(args[0]), _int_arg(args[1])
    count = _int_arg(args[2]) if len(args) > 2 else len(text)
    if start < 0 or count < 0:
        raise TrioError("Parameter out of range")
    return text[start:start + count]


def _val(args: list[Value]) -> Value:
    try:
        number = float(_str_arg(args[0]).strip() or "0")
    except ValueError:
        return 0.0
    if not math.isfinite(number):
        raise TrioError("Arithmetic error")
    return number


def _instr(args: list[Value]) -> Value:
    """INSTR([offset,] text, find[, wildcard]): the index (from 0) of the first find at
    or after offset, -1 when absent; wildcard, a one-character string or its code,
    matches any character in find (help page)."""
    offset = 0
    if not isinstance(args[0], str):
        offset, args = _int_arg(args[0]), args[1:]
    if len(args) not in (2, 3):
        raise TrioError("Syntax error")
    text, find = _str_arg(args[0]), _str_arg(args[1])
    wild: str | None = None
    if len(args) == 3:
        wild = args[2] if isinstance(args[2], str) else chr(_int_arg(args[2]) & 0x10FFFF)
        if len(wild) != 1:
            raise TrioError("Parameter out of range")
    if offset < 0:
        raise TrioError("Parameter out of range")
    if wild is None:
        return float(text.find(find, offset))
    for place in range(offset, len(text) - len(find) + 1):
        if all(f in (wild, c) for f, c in zip(find, text[place:place + len(find)], strict=True)):
            return float(place)
    return -1.0


def number_arg(value: Value) -> float:
    """A number argument; a string where a number belongs is a Type mismatch (every
    statement and function of the language checks it so)."""
    if isinstance(value, str):
        raise TrioError("Type mismatch")
    return value


def _round(args: list[Value]) -> Value:
    """ROUND(v[, p]): INT(v * 10^p +- 0.5) / 10^p, the sign's way (help ROUND)."""
    value = number_arg(args[0])
    places = _int_arg(args[1]) if len(args) > 1 else 0
    if not -308 <= places <= 308:
        raise TrioError("Parameter out of range")
    scale = 10.0 ** places
    half = 0.5 if value >= 0 else -0.5
    return math.trunc(value * scale + half) / scale


def _ulp_order(value: float) -> int:
    """A double's bits as an integer that counts the doubles in order."""
    bits = struct.unpack("<q", struct.pack("<d", value))[0]
    return bits if bits >= 0 else -(bits & 0x7FFFFFFFFFFFFFFF)


def _ulpdiff(args: list[Value]) -> Value:
    """ULPDIFF(a, b): how many doubles apart a and b are (help ULPDIFF)."""
    a, b = number_arg(args[0]), number_arg(args[1])
    return float(abs(_ulp_order(a) - _ulp_order(b)))


def _vector_mag(args: list[Value]) -> Value:
    """VECTOR_MAG(c1[, ... c6]): the square root of the sum of the squares (its page)."""
    magnitude = math.hypot(*(number_arg(a) for a in args))  # (no overflow on the way)
    if not math.isfinite(magnitude):
        raise TrioError("Parameter out of range")
    return magnitude


def _arity(low: int, high: int,
           function: Callable[[list[Value]], Value]) -> Callable[[list[Value]], Value]:
    def checked(args: list[Value]) -> Value:
        if not low <= len(args) <= high:
            raise TrioError("Syntax error")
        return function(args)
    return checked


_STRING_FUNCTIONS: dict[str, Callable[[list[Value]], Value]] = {
    "CHR": _arity(1, 2, _chr),
    "HEX": _arity(1, 1, _hex),
    "ASC": _arity(1, 2, _asc),
    "LEN": _arity(1, 1, lambda a: float(len(_str_arg(a[0])))),
    "LEFT": _arity(2, 2, lambda a: _str_arg(a[0])[:max(0, _int_arg(a[1]))]),
    "RIGHT": _arity(2, 2, lambda a: _str_arg(a[0])[len(_str_arg(a[0])) - max(
        0, _int_arg(a[1])):] if _int_arg(a[1]) > 0 else ""),
    "MID": _arity(2, 3, _mid),
    "UCASE": _arity(1, 1, lambda a: _str_arg(a[0]).upper()),
    "LCASE": _arity(1, 1, lambda a: _str_arg(a[0]).lower()),
    "STR": _arity(1, 3, _str),
    "VAL": _arity(1, 1, _val),
    "INSTR": _arity(2, 4, _instr),
    "LENB": _arity(1, 1, lambda a: float(len(_str_arg(a[0]).encode("utf-8")))),
    "ROUND": _arity(1, 2, _round),
    "ULPDIFF": _arity(2, 2, _ulpdiff),
    "VECTOR_MAG": _arity(1, 6, _vector_mag),
}


class Interpreter:
    def __init__(self, machine: TrioMachine, hook: SystemHook,
                 output: Callable[[str], None]) -> None:
        self.machine = machine
        self.hook = hook
        self.output = output
        # STATIC names of FUNCTIONs, kept between calls: (program steps, step) -> name ->
        # (scalar, array, shape, type); tasks.py fills and reads it
        self.statics: dict[tuple[int, int], dict[str, Kept]] = {}
        # channels opened AS "STRING:name": the process and the variable PRINT #n adds to
        self.strings: dict[int, tuple[ProcessContext, str]] = {}

    # ---- expressions ---------------------------------------------------------------------
    def evaluate(self, expr: Expr, ctx: ProcessContext) -> Value:
        if isinstance(expr, Num):
            return expr.value
        if isinstance(expr, Str):
            return expr.text
        if isinstance(expr, Var):
            return self.variable(expr.name, ctx)
        if isinstance(expr, Param):
            if expr.keyword.name == "PROGRAM_NAME":
                return self.program_name(expr, ctx)
            return self.read_parameter(expr, ctx)
        if isinstance(expr, Call):
            return self.call(expr, ctx)
        if isinstance(expr, Bit):
            return float((int(self.number(expr.operand, ctx)) >> self.bit_of(expr, ctx)) & 1)
        if isinstance(expr, Opened):
            return self.opened(expr.channel, ctx)
        if isinstance(expr, Field):
            return self.field(expr, ctx)
        if isinstance(expr, Unary):
            operand = self.number(expr.operand, ctx)
            if expr.op == "-":
                return real(-operand) if isinstance(operand, Real) else -operand
            return float(~int(operand))
        return self.binary(expr, ctx)

    def variable(self, name: str, ctx: ProcessContext) -> Value:
        """A name: the process's own variable, else a GLOBAL's VR, else a CONSTANT, else
        0 (an unassigned TrioBASIC variable reads 0)."""
        value = ctx.variables.get(name)
        if value is not None:
            return value
        if name in self.hook.globals:  # a VR: FLOAT (help VR: 64-bit floating point)
            return real(self.machine.vr_read(self.hook.globals[name]))
        return self.hook.constants.get(name, _UNSET)

    def number(self, expr: Expr, ctx: ProcessContext) -> float:
        return self.number_value(self.evaluate(expr, ctx))

    @staticmethod
    def number_value(value: Value) -> float:
        if isinstance(value, str):
            raise TrioError("Type mismatch")
        return value

    def integer(self, expr: Expr, ctx: ProcessContext) -> int:
        value = self.number(expr, ctx)
        if value != int(value):
            raise TrioError("Parameter out of range")
        return int(value)

    def binary(self, expr: Binary, ctx: ProcessContext) -> Value:
        left, right = self.evaluate(expr.left, ctx), self.evaluate(expr.right, ctx)
        op = expr.op
        if isinstance(left, str) or isinstance(right, str):
            return _string_binary(op, left, right)
        a, b = left, right
        try:
            result = self._apply(op, a, b)
        except (ZeroDivisionError, OverflowError, ValueError, TypeError):
            # (TypeError: a negative base to a fraction is complex, no real number)
            raise TrioError("Divide by zero" if op in ("/", "MOD", "FMOD") and b == 0
                            else "Arithmetic error") from None
        if isinstance(result, complex) or not math.isfinite(result):
            raise TrioError("Arithmetic error")
        if op in FLOAT_OPERATORS or op in ARITHMETIC and (isinstance(a, Real)
                                                         or isinstance(b, Real)):
            return real(result)  # a FLOAT operand makes a FLOAT (printformat.Real)
        return result

    @staticmethod
    def _apply(op: str, a: float, b: float) -> float:
        if op == "+":
            return a + b
        if op == "-":
            return a - b
        if op == "*":
            return a * b
        if op == "/":
            return a / b
        if op == "^":
            return float(a ** b)
        if op == "MOD":
            return math.fmod(int(a), int(b)) if int(b) else a / 0
        if op == "FMOD":  # the remainder keeps the dividend's sign (help FMOD: -204.56 -> -24.56)
            return math.fmod(a, b) if b else a / 0
        if op == "AND":
            return float(int(a) & int(b))
        if op == "OR":
            return float(int(a) | int(b))
        if op == "XOR":
            return float(int(a) ^ int(b))
        if op in ("<<", ">>"):
            if not 0 <= int(b) <= 63:
                raise ValueError("shift")
            value = int(a) << int(b) if op == "<<" else int(a) >> int(b)
            return float(value)
        comparisons = {"=": a == b, "<>": a != b, "<": a < b, ">": a > b, "<=": a <= b,
                       ">=": a >= b}
        return _truth(comparisons[op])

    def call(self, expr: Call, ctx: ProcessContext) -> Value:
        name = expr.name
        if name not in KEYWORDS:  # a DIM array's element, or a FUNCTION's value
            if name not in ctx.arrays and ctx.functions is not None:
                return ctx.functions(name, [self.argument(a, ctx) for a in expr.args])
            array, index = self._element(name, expr.args, ctx)
            return array[index]
        if name == "KEY":  # KEY #n: TRUE when a character waits on channel n
            channel = self._channel(expr.args, ctx) if expr.args else ctx.indevice
            counted = self.hook.fifo_files.key(channel)  # a FIFO: how many (fifos.py)
            return counted if counted is not None else _truth(bool(self.hook.files.get(channel)))
        if name in ("CHANNEL_READ", "CHANNEL_WRITE"):  # buffers go by reference
            return self.hook.channel_word(name, expr.args, ctx, self)
        if name == "IS_OPEN":  # IS_OPEN #n: TRUE while channel n is open (its page)
            if len(expr.args) != 1:
                raise TrioError("Syntax error")
            return _truth(self._channel(expr.args, ctx) in self.hook.files)
        if name in ("DATE$", "TIME$", "DAY$"):
            return self.clock_text(name)
        if name in _CLOCK:
            return self.clock_value(name, [self.number(a, ctx) for a in expr.args])
        if name in ("RND", "RNDF"):
            drawn = self.random_value(name, [self.number(a, ctx) for a in expr.args], ctx)
            return real(drawn) if name == "RNDF" else drawn
        if name in _BIT_COMMANDS:
            return self.bit_command(name, [self.number(a, ctx) for a in expr.args])
        if name in _STRING_FUNCTIONS:
            value = _STRING_FUNCTIONS[name]([self.evaluate(a, ctx) for a in expr.args])
            return real(value) if name in FLOAT_FUNCTIONS and isinstance(value, float) \
                else value
        if name == "VRSTRING":
            if len(expr.args) != 1:
                raise TrioError("Syntax error")
            return self.vr_string(self._index(self.number(expr.args[0], ctx)))
        if name == "BASE":
            if expr.args:
                raise TrioError("Syntax error")
            return float(ctx.base[0])
        args = [self.evaluate(a, ctx) for a in expr.args]
        if name in ("IS_PROG", "IS_FILE", "PROG_TYPE", "CRC16", "STRTOD", "IEEE_IN", "IEEE_OUT",
                    "FREE", "FLASHTABLE", "FLASHVR"):
            value = self.hook.system_function(name, args)
            return real(value) if name in FLOAT_FUNCTIONS else value  # FREE (printformat)
        if name in ("IN", "READ_OP", "AIN", "AOUT", "OP"):
            return self.io_function(name, [self.number_value(a) for a in args])
        numbers = [a for a in args if not isinstance(a, str)]
        if name in _FRAME_WORDS:
            if len(numbers) != len(args):
                raise TrioError("Type mismatch")
            return self.frame_word(name, [float(a) for a in numbers], ctx)
        if name == "DLINK":
            link = self.drive_link(args)  # FLOAT (printformat): its page prints 463.0000
            return real(link) if name in FLOAT_FUNCTIONS else link
        if name in SET_MOTION_WORDS:  # returns 0 (D)
            machine = self.machine
            self._act(lambda: set_motion(
                name, [self.number_value(a) for a in args], machine.axis_count,
                lambda a: machine.axis_parameter("UNITS", a), machine.set_axis_parameter))
            return 0.0
        if name in ("ENCODER_READ", "ENCODER_WRITE"):  # parameter mode: ENCODER_CONTROL 1
            value = self.drive_link(args, lambda a, _: endat(name, a))
            self._act(lambda: self.machine.set_axis_parameter("ENCODER_CONTROL",
                                                              ctx.base[0], 1.0))
            return value
        if name not in _MATH and name not in ("ATAN2", "TABLE", "VR"):
            return 0.0  # a token-table function not modelled: 0 (its table note)
        if len(numbers) != len(args):
            raise TrioError("Syntax error")
        try:
            if name in _MATH and len(numbers) == 1:
                if name in ("SQR", "LN") and numbers[0] < (0 if name == "SQR" else 1e-308) \
                        or name in ("ACOS", "ASIN") and abs(numbers[0]) > 1:
                    raise TrioError("Parameter out of range")
                result = _MATH[name](numbers[0])
            elif name == "ATAN2" and len(numbers) == 2:
                result = math.atan2(numbers[0], numbers[1])
            elif name == "TABLE" and len(numbers) == 1:
                result = self.machine.table_read(self._index(numbers[0]))
            elif name == "VR" and len(numbers) == 1:
                result = real(self.machine.vr_read(self._index(numbers[0])))
            elif name in KEYWORDS and name not in _MATH and name != "ATAN2":
                result = 0.0  # a token-table function not modelled: 0 (its table note)
            else:
                raise TrioError("Syntax error")
        except OverflowError:
            raise TrioError("Arithmetic error") from None
        except ValueError as exc:
            raise TrioError(_machine_text(exc)) from None
        if not math.isfinite(result):
            raise TrioError("Arithmetic error")
        if name in FLOAT_FUNCTIONS or name == "VR" or name == "ABS" and \
                isinstance(numbers[0], Real):
            return real(result)  # ABS keeps its argument's type (D)
        return float(result)

    def drive_link(self, args: list[Value],
                   answer: Callable[[list[float], int], float] = dlink) -> float:
        """DLINK(function, ...): the SLM drive interface (personalities/trio/slm.py); or
        another drive-side function with no hardware behind it (`answer`)."""
        if any(isinstance(a, str) for a in args):
            raise TrioError("Syntax error")
        try:
            return answer([float(a) for a in args], self.machine.axis_count)
        except ValueError as exc:
            raise TrioError(_machine_text(exc)) from None

    def frame_word(self, name: str, args: list[float], ctx: ProcessContext) -> float:
        """FRAME_TRANS(frame, table_in, table_out, direction[, table_offset]): a frame's
        forward (1) or inverse (0) transform of TABLE values (personalities/trio/
        frames.py); FRAME_GROUP(group[, table_offset, axes...]): define, delete or print
        a frame group. Both return 0 as functions (D: their pages give no value)."""
        if not all(math.isfinite(a) for a in args):
            raise TrioError("Parameter out of range")
        m = self.machine
        if name == "FRAME_GROUP":
            try:
                text = m.frame_group(args)
            except ValueError as exc:
                raise TrioError(_machine_text(exc)) from None
            if text and not self.hook.write_file(ctx.outdevice, text + "\r\n"):
                self.output(text + "\r\n")
            return 0.0
        if len(args) not in (4, 5):
            raise TrioError("Syntax error")
        frame, table_in, table_out, direction = args[:4]
        offset = args[4] if len(args) == 5 else 0.0
        if frame not in FRAME_SIZES or direction not in (0, 1):
            raise TrioError("Parameter out of range")
        size = FRAME_SIZES[int(frame)]
        first = [self._index(v) for v in (table_in, table_out, offset)]
        def act() -> None:
            values = [m.table_read(first[0] + k) for k in range(size)]
            table = [m.table_read(first[2] + k) for k in range(FRAME_TABLE[int(frame)])]
            m.table_write(first[1], frame_transform(int(frame), table, values,
                                                    direction == 1))
        self._act(act)
        return 0.0

    def vr_write_string(self, first: int, text: str) -> None:
        """VR(n) = "text": one character code a VR from VR(n) on and a 0 after them, so
        VRSTRING(n) reads the text back (TrioBASIC help VR, example 4); a text that would
        pass the last VR writes nothing (D)."""
        codes = [float(ord(c) & 0xFF) for c in text] + [0.0]
        if first + len(codes) > VR_COUNT:
            raise TrioError("Parameter out of range")
        def write() -> None:
            for k, code in enumerate(codes):
                self.machine.vr_write(first + k, code)
        self._act(write)

    def vr_string(self, first: int) -> str:
        """VRSTRING(n): one character a VR from VR(n) to the first VR holding 0; only
        printable characters are kept (help page: codes 32..126 and 160..255, I)."""
        out: list[str] = []
        for index in range(first, min(first + MAX_STRING, VR_COUNT)):
            code = int(self.machine.vr_read(index))
            if code == 0:
                break
            if 32 <= code <= 126 or 160 <= code <= 255:
                out.append(chr(code))
        return "".join(out)

    def argument(self, expr: Expr, ctx: ProcessContext) -> Argument:
        """A FUNCTION's argument: a DIM array named alone goes by reference (the
        function's ``AS INTEGER()`` parameter), anything else by value."""
        if isinstance(expr, Var) and expr.name in ctx.arrays:
            return ctx.arrays[expr.name]
        return self.evaluate(expr, ctx)

    def clock(self) -> datetime.datetime:
        """The real time clock: power up is 00:00:00 on Saturday 01/01/2000 (D: the
        emulator has no calendar of its own), then virtual time, plus what TIME = and
        DATE = set it ahead by."""
        seconds = self.machine.servo_tick() * self.machine.servo_period_us() / 1e6
        return _EPOCH + datetime.timedelta(seconds=math.floor(seconds + self.hook.clock_offset))

    def clock_text(self, name: str) -> str:
        """DATE$ (DD/MM/YYYY), TIME$ (HH:MM:SS), DAY$ from the real time clock."""
        now = self.clock()
        if name == "TIME$":
            return now.strftime("%H:%M:%S")
        if name == "DAY$":
            return _DAYS[(now.weekday() + 1) % 7]
        return now.strftime("%d/%m/%Y")

    def clock_value(self, name: str, args: list[float]) -> float:
        """TIME: seconds since midnight; DATE: days since 01/01/2000, DATE(0|1|2) the day,
        month, year; DAY: 0..6, Sunday 0 (their help pages)."""
        now = self.clock()
        if name == "TIME" and not args:
            return float(now.hour * 3600 + now.minute * 60 + now.second)
        if name == "DAY" and not args:
            return float((now.weekday() + 1) % 7)
        if name == "DATE" and not args:
            return float((now.date() - _EPOCH.date()).days)
        if name == "DATE" and len(args) == 1 and args[0] in (0, 1, 2):
            return float((now.day, now.month, now.year)[int(args[0])])
        raise TrioError("Parameter out of range" if args else "Syntax error")

    def set_clock(self, name: str, fields: list[float]) -> None:
        """TIME = hh:mm:ss / DATE = dd:mm:yy (yy 00..99 or 2000..2099): the clock is set
        ahead (or back) by the difference; nothing changes on a value out of range."""
        if not all(f == int(f) for f in fields):
            raise TrioError("Parameter out of range")
        a, b, c = (int(f) for f in fields)
        now = self.clock()
        try:
            if name == "TIME":
                wanted = now.replace(hour=a, minute=b, second=c)
            else:
                year = 2000 + c if 0 <= c <= 99 else c
                if not 2000 <= year <= 2099:
                    raise ValueError
                wanted = now.replace(year=year, month=b, day=a)
        except ValueError:
            raise TrioError("Parameter out of range") from None
        self.hook.clock_offset += (wanted - now).total_seconds()

    def random_value(self, name: str, args: list[float], ctx: ProcessContext) -> float:
        """RND: an unsigned 32-bit integer, RND(n) 0..n-1, RND(a, b) a..b-1; RNDF: 0 <= x
        < 1, RNDF(n) 0..n, RNDF(a, b) a..b (their help pages). Each process has its own
        generator (RANDOMIZE's page); its seed is the process number and the servo tick
        of its first draw (D: repeatable runs, yet each run of a program differs)."""
        if ctx.rng is None:
            ctx.rng = random.Random(ctx.process * 1_000_003 + self.machine.servo_tick())
        if len(args) > 2:
            raise TrioError("Syntax error")
        low, high = (0.0, args[0]) if len(args) == 1 else (args[0], args[1]) if args else \
            (0.0, 2.0 ** 32 if name == "RND" else 1.0)
        if name == "RNDF":
            if not low < high:
                raise TrioError("Parameter out of range")
            return low + ctx.rng.random() * (high - low)
        if low != int(low) or high != int(high) or not low < high:
            raise TrioError("Parameter out of range")
        return float(ctx.rng.randrange(int(low), int(high)))

    def _channel(self, args: Sequence[Expr], ctx: ProcessContext) -> int:
        number = self.number(args[0], ctx)
        if number != int(number) or not 0 <= number <= 255:
            raise TrioError("Parameter out of range")
        return int(number)

    def io_function(self, name: str, args: list[float]) -> float:
        m = self.machine
        if name in ("AIN", "AOUT"):
            if len(args) != 1:
                raise TrioError("Syntax error")
            channel = self._point(args[0], 8)
            if name == "AOUT":
                return self.hook.analog_outputs.get(channel, 0.0)
            return float(round(m.analog_input(channel) / 10.0 * 2047))
        read = m.debounced_input if name == "IN" else m.output  # (IN_DEBOUNCE)
        if not args:
            args = [0.0, IO_POINTS - 1.0]
        if len(args) == 1:
            return 1.0 if read(self._point(args[0], IO_SPACE)) else 0.0
        first, last = self._point(args[0], IO_SPACE), self._point(args[1], IO_SPACE)
        if not first <= last < first + IO_POINTS:
            raise TrioError("Parameter out of range")
        return float(sum(1 << k for k in range(last - first + 1) if read(first + k)))

    @staticmethod
    def _point(value: float, count: int) -> int:
        if value != int(value) or not 0 <= value < count:
            raise TrioError("Parameter out of range")
        return int(value)

    def _element(self, name: str, args: tuple[Expr, ...],
                 ctx: ProcessContext) -> tuple[list[Value], int]:
        """The array and flat index of ``name(i[, j ...])`` (row-major, from 0)."""
        array = ctx.arrays.get(name)
        shape = ctx.shapes.get(name, (len(array),) if array is not None else ())
        if array is None or len(args) != len(shape):
            raise TrioError("Variable not defined")
        flat = 0
        for arg, size in zip(args, shape, strict=True):
            index = self.number(arg, ctx)
            if index != int(index) or not 0 <= index < size:
                raise TrioError("Array index out of range")
            flat = flat * size + int(index)
        return array, flat

    @staticmethod
    def _index(value: float) -> int:
        if value != int(value) or value < 0:
            raise TrioError("Parameter out of range")
        return int(value)

    def axis_of(self, axis: Expr | None, ctx: ProcessContext) -> int:
        number = ctx.base[0] if axis is None else self.number(axis, ctx)
        if number != int(number) or not 0 <= number < self.machine.axis_count:
            raise TrioError("Invalid axis number")
        return int(number)

    def read_parameter(self, expr: Param, ctx: ProcessContext) -> float:
        keyword = expr.keyword
        if keyword.name in CHANNEL_PARAMETERS:  # R_MARK(channel) [AXIS(n)]
            if len(expr.index) != 1 or expr.slot is not None:
                raise TrioError("Syntax error")
            channel, axis = self.number(expr.index[0], ctx), self.axis_of(expr.axis, ctx)
            return self._machine(lambda: self.machine.channel_parameter(
                keyword.name, axis, channel))
        if keyword.name in BANKED_PARAMETERS and expr.index:  # MOTION_ERROR(bank)
            return self.motion_error_bank(expr, ctx)
        if keyword.name == "MOTION_ERROR_COUNT":  # the bits set in MOTION_ERROR (its page)
            errors = self.read_parameter(Param(KEYWORDS["MOTION_ERROR"], None), ctx)
            return _MATH["BITCOUNT"](errors)
        if expr.index or expr.slot is not None:
            return self.hook.indexed.get(self._indexed_key(expr, ctx), keyword.default)
        if keyword.name in PROCESS_PARAMETERS:
            if expr.process is not None:
                number = self.number(expr.process, ctx)
                if number != int(number) or not 0 <= number < 64:
                    raise TrioError("Parameter out of range")
                other = self.hook.context_of(int(number))
                if other is None and keyword.name in ("RUN_ERROR", "ERROR_LINE"):
                    other = self.hook.ended_context(int(number))  # why it stopped
                if other is None:
                    return 0.0  # a process that never ran a program: stopped, no error
                ctx = other
            return self.process_parameter(keyword.name, ctx)
        if keyword.kind is Kind.SYSTEM_PARAMETER:
            owned = self.hook.system_parameter(keyword.name)
            if owned is not None:
                return owned
            return self._machine(lambda: self.machine.system_parameter(keyword.name))
        axis = self.axis_of(expr.axis, ctx)
        if keyword.name == "IDLE":
            return _truth(self.machine.axis_idle(axis))
        if keyword.name == "DEMAND_EDGES":  # DPOS in encoder edges (its page)
            return self._machine(lambda: self.machine.axis_parameter("DPOS", axis)
                                 * self.machine.axis_parameter("UNITS", axis))
        if keyword.name == "LOADED":  # no move held behind the one running (its page)
            return _truth(self._machine(lambda: self.machine.axis_parameter("NTYPE", axis))
                          == 0)
        return self._machine(lambda: self.machine.axis_parameter(keyword.name, axis))

    def program_name(self, expr: Param, ctx: ProcessContext) -> str:
        """PROGRAM_NAME [PROC(n)]: the name of the program a process runs, "" for a
        process running none or the command line (help page PROGRAM_NAME; "" is D)."""
        if expr.process is not None:
            number = self.number(expr.process, ctx)
            if number != int(number) or not 0 <= number < 64:
                raise TrioError("Parameter out of range")
            other = self.hook.context_of(int(number))
            return other.program if other is not None else ""
        return ctx.program

    def _indexed_key(self, expr: Param, ctx: ProcessContext) -> tuple[str, tuple[float, ...]]:
        """Where a parameter with arguments or a SLOT/PORT modifier is stored (D: not
        modelled beyond keeping the value written)."""
        numbers = [self.number(e, ctx) for e in expr.index]
        if expr.slot is not None:
            numbers.append(self.number(expr.slot, ctx))
        if not all(math.isfinite(n) and abs(n) < 1e9 for n in numbers):
            raise TrioError("Parameter out of range")
        return expr.keyword.name, tuple(numbers)

    def process_parameter(self, name: str, ctx: ProcessContext) -> float:
        """The parameters each process has its own of."""
        if name == "RUN_ERROR":
            return ctx.run_error
        if name == "ERROR_LINE":
            return ctx.error_line
        if name == "TICKS":  # counts down one a servo cycle from the value last set (I)
            value, since = ctx.ticks
            return value - (self.machine.servo_tick() - since)
        if name == "PROCNUMBER":
            return float(ctx.process)
        if name in ("OUTDEVICE", "INDEVICE"):
            return float(ctx.outdevice if name == "OUTDEVICE" else ctx.indevice)
        if name == "PROC_LINE":
            return float(ctx.line)
        if name == "PMOVE":
            return _truth(ctx.pmove)
        return float(ctx.status) if ctx.program else 0.0  # PROC_STATUS (tracing.py)

    @staticmethod
    def _machine(action: Callable[[], float]) -> float:
        try:
            return float(action())
        except ValueError as exc:
            raise TrioError(_machine_text(exc)) from None

    # ---- statements ------------------------------------------------------------------------
    def execute(self, stmt: Stmt, ctx: ProcessContext) -> Wait:
        """Run one statement; yields while it must wait for the machine or the clock."""
        if isinstance(stmt, Print):
            channel = self.print(stmt, ctx)
            while self.hook.fifo_files.flush(channel):  # a full blocking FIFO (fifos.py)
                yield None
        elif isinstance(stmt, Assign):
            self.assign(stmt, ctx)
        elif isinstance(stmt, Command) and stmt.keyword.name in _LOADING:
            try:
                for wait in self.command(stmt, ctx):
                    ctx.pmove = True  # held in the process move buffer (PMOVE's page)
                    yield wait
            finally:
                ctx.pmove = False
        elif isinstance(stmt, Command):
            yield from self.command(stmt, ctx)
        elif isinstance(stmt, WaitIdle):
            axis = self.axis_of(stmt.axis, ctx)
            while not self.machine.axis_idle(axis):
                yield ON_CHANGE
        elif isinstance(stmt, WaitUntil):
            while self.number(stmt.condition, ctx) == 0:
                yield None
        elif isinstance(stmt, IfLine):
            branch = stmt.then if self.number(stmt.condition, ctx) != 0 else stmt.otherwise
            for inner in branch:
                yield from self.execute(inner, ctx)
        elif isinstance(stmt, Declare):
            self.declare(stmt, ctx)
        elif isinstance(stmt, Dim):
            self.dim(stmt, ctx)
        elif isinstance(stmt, Perform):
            self.evaluate(stmt.call, ctx)
        elif isinstance(stmt, ArrayFill):
            self.fill(stmt, ctx)
        elif isinstance(stmt, Channel):
            yield from self.channel(stmt, ctx)
        elif isinstance(stmt, WaitLoaded):
            axis = self.axis_of(stmt.axis, ctx)
            while not self.machine.can_load([axis]):
                yield ON_CHANGE
        else:
            raise TrioError("Structure error")  # a block statement outside a program

    def fill(self, stmt: ArrayFill, ctx: ProcessContext) -> None:
        """``name = a, b, c``: the first elements of the array, each value typed as the
        DIM says; every value is checked before one is stored."""
        array = ctx.arrays.get(stmt.name)
        if array is None:
            raise TrioError("Variable not defined")
        start, room = self._fill_start(stmt, array, ctx)
        if len(stmt.values) > room:
            raise TrioError("Array index out of range")
        values = [self._typed(stmt.name, self.evaluate(v, ctx), ctx) for v in stmt.values]
        array[start:start + len(values)] = values

    def _fill_start(self, stmt: ArrayFill, array: list[Value],
                    ctx: ProcessContext) -> tuple[int, int]:
        """Where ``name(i, ...) = v0, v1, ...`` starts and how many values fit: fewer
        indices than dimensions pick a row (its whole length), all of them an element,
        filled on to the end of its last dimension (D: the page shows rows only)."""
        if not stmt.index:
            return 0, len(array)
        shape = ctx.shapes.get(stmt.name, (len(array),))
        if len(stmt.index) > len(shape):
            raise TrioError("Variable not defined")
        flat = 0
        for arg, size in zip(stmt.index, shape, strict=False):
            index = self.number(arg, ctx)
            if index != int(index) or not 0 <= index < size:
                raise TrioError("Array index out of range")
            flat = flat * size + int(index)
        rest = shape[len(stmt.index):]
        if rest:
            room = math.prod(rest)
            return flat * room, room
        return flat, shape[-1] - flat % shape[-1]

    def open_string(self, number: int, name: str, mode: str, ctx: ProcessContext) -> None:
        """OPEN #n AS "STRING:name": a STRING variable of the process as the file (OPEN's
        examples 8 and 9). FOR OUTPUT empties it and PRINT #n adds to it, FOR APPEND adds
        after what it holds, FOR INPUT reads its characters (D: what a PRINT writes goes in
        whole, its CR LF too; past the DIM length, as any assignment: an error)."""
        if not ctx.types.get(name, "").startswith("STRING") or name in ctx.arrays:
            raise TrioError("Variable not defined")
        files = self.hook.files
        if mode in ("OUTPUT", "APPEND"):
            if mode == "OUTPUT":
                ctx.variables[name] = ""
            self.strings[number] = (ctx, name)
            files[number] = []
        elif mode == "INPUT":
            text = ctx.variables.get(name, "")
            assert isinstance(text, str)
            files[number] = [ord(c) for c in reversed(text)]
            self.hook.sources[number] = files[number][:]
        else:
            raise TrioError("Parameter out of range")

    def field(self, expr: Field, ctx: ProcessContext) -> float:
        """``name.dims``: how many dimensions the array has (0: not an array);
        ``name.dimsize(n)``: the size of dimension n, from 0 (the field operator's page;
        no brackets on a non-array, D: as DIMS gives 0 dimensions, 'Parameter out of
        range' for any n)."""
        if expr.name not in ctx.arrays and expr.name not in ctx.variables and \
                expr.name not in ctx.types:
            raise TrioError("Variable not defined")
        shape = ctx.shapes.get(expr.name, (len(ctx.arrays[expr.name]),)) \
            if expr.name in ctx.arrays else ()
        if expr.field == "DIMS":
            if expr.index is not None:
                raise TrioError("Syntax error")
            return float(len(shape))
        if expr.index is None:
            raise TrioError("Syntax error")
        n = self.number(expr.index, ctx)
        if n != int(n) or not 0 <= n < len(shape):
            raise TrioError("Parameter out of range")
        return float(shape[int(n)])

    def opened(self, stmt: Channel, ctx: ProcessContext) -> float:
        """OPEN as a value (its page): the number of the error the open met, 0 when it
        opened; a network connection (TCP, DGRAM, TCPSERVER) gives TRUE when made and FALSE
        when not, and none is ever made here: no program channel opens a socket (D)."""
        name = self.evaluate(stmt.name, ctx) if stmt.name is not None else ""
        if isinstance(name, str) and name.upper().startswith(_NETWORK):
            return 0.0
        try:
            for _ in self.channel(stmt, ctx):  # an OPEN never waits
                break
        except TrioError as exc:
            return error_code(exc.message)
        return 0.0

    def channel(self, stmt: Channel, ctx: ProcessContext) -> Wait:
        """OPEN/CLOSE/GET/INPUT/LINPUT on a channel (see docs/trio.md): a file opened FOR
        INPUT is read a character at a time; the terminal channels (none opened) never
        receive a character while a program runs, so GET/INPUT on them wait (D)."""
        files = self.hook.files
        number = ctx.indevice if stmt.channel is None else self._channel((stmt.channel,), ctx)
        if stmt.action == "OPEN":
            assert stmt.name is not None
            name = self.evaluate(stmt.name, ctx)
            if not isinstance(name, str):
                raise TrioError("Type mismatch")
            if not 40 <= number <= 48:  # OPEN's page: files and strings on 40 to 48 (C)
                raise TrioError("Parameter out of range")
            if number in files:
                raise TrioError("Channel already open")
            if name.upper().startswith("STRING:"):
                self.open_string(number, name[7:].strip().upper(), stmt.mode, ctx)
                return
            if stmt.mode in ("FIFO_READ", "FIFO_WRITE"):  # (fifos.py)
                files[number] = self.hook.fifo_files.open(
                    number, name, stmt.mode, [self.number(o, ctx) for o in stmt.options])
            elif stmt.mode in ("INPUT", "READ_WRITE"):
                text = self.hook.file_text(name)
                files[number] = [ord(c) for c in reversed(text)]
                self.hook.sources[number] = files[number][:]  # what SEEK goes back to
            elif stmt.mode in ("OUTPUT", "APPEND"):  # PRINT #n writes the file
                self.hook.open_output(number, name, stmt.mode == "APPEND")
                files[number] = []
            else:
                files[number] = []
            return
        if stmt.action == "CLOSE":
            self.strings.pop(number, None)
            files.pop(number, None)
            self.hook.fifo_files.close(number)
            self.hook.sources.pop(number, None)
            self.hook.close_file(number)
            return
        if number >= FILE_CHANNELS and number not in files:
            raise TrioError("Channel not open")
        while not files.get(number):
            if number in files and stmt.action != "GET":
                break  # the end of a file: INPUT reads what there is (D)
            yield None if self.hook.fifo_files.is_reader(number) else ON_CHANGE
        waiting = files.get(number, [])
        if stmt.action == "GET":
            self.store(stmt.targets[0], float(waiting.pop()), ctx)
            return
        for target in stmt.targets:
            chars = []
            while waiting and waiting[-1] not in (10, 13) and (
                    stmt.action == "LINPUT" or chr(waiting[-1]) != ","):
                chars.append(chr(waiting.pop()))
            if waiting and chr(waiting[-1]) in ",\r":
                waiting.pop()
            if waiting and waiting[-1] == 10:
                waiting.pop()
            text = "".join(chars)
            value: Value = text if stmt.action == "LINPUT" else _val([text])
            self.store(target, value, ctx)

    def store(self, target: Expr, value: Value, ctx: ProcessContext) -> None:
        """GET/INPUT storing into a variable, an array element or VR(i)."""
        assert isinstance(target, (Var, Call))
        self.assign(Assign(target, Str(value) if isinstance(value, str) else Num(value)),
                    ctx)

    def declare(self, stmt: Declare, ctx: ProcessContext) -> None:
        """CONSTANT "name", value and GLOBAL "name", vr: names every process sees;
        the name alone clears that one (a name not declared: nothing, D), the keyword
        alone clears every one (TrioBASIC help CONSTANT, GLOBAL)."""
        table: dict[str, Value] | dict[str, int] = \
            self.hook.globals if stmt.what == "GLOBAL" else self.hook.constants
        if not stmt.name:
            table.clear()
            return
        if stmt.value is None:
            table.pop(stmt.name, None)
            return
        value = self.evaluate(stmt.value, ctx)
        if stmt.what == "GLOBAL":
            index = self._index(self.number_value(value))
            self._machine(lambda: self.machine.vr_read(index))  # a VR that exists
            self.hook.globals[stmt.name] = index
        else:
            known = self.hook.constants.get(stmt.name)
            if known is not None and known != value:
                raise TrioError("Cannot assign to a constant")
            self.hook.constants[stmt.name] = value
        self.hook.spellings.setdefault(f"{stmt.what[0]} {stmt.name}", stmt.spelling)
        if len(self.hook.constants) + len(self.hook.globals) > 4096:  # (D) bounded
            raise TrioError("Parameter out of range")

    def dim(self, stmt: Dim, ctx: ProcessContext) -> None:
        """DIM: every name a scalar or an array of the dimensions given, holding the
        initial value (0, "" or the ``= value``)."""
        kind = stmt.type if stmt.type != "STRING" else f"STRING{stmt.length}"
        empty: Value = "" if stmt.type == "STRING" else Real(0.0) if stmt.type == "FLOAT" \
            else 0.0
        shape: tuple[int, ...] = ()
        for expr in stmt.sizes:
            size = self.number(expr, ctx)
            if size != int(size) or not 0 < size <= MAX_ARRAY:
                raise TrioError("Parameter out of range")
            shape += (int(size),)
        count = math.prod(shape) if shape else 0
        if count > MAX_ARRAY or sum(len(a) for a in ctx.arrays.values()) \
                + count * len(stmt.names) > 4 * MAX_ARRAY:
            raise TrioError("Parameter out of range")  # (D) a process's array memory
        cost = max(count, 1) * (stmt.length if stmt.type == "STRING" else NUMBER_BYTES)
        freed = sum(ctx.memory.get(name, 0) for name in stmt.names)  # a DIM again replaces
        if self.hook.memory_in_use(ctx) - freed + cost * len(stmt.names) > PROGRAM_MEMORY:
            raise TrioError("Not enough memory")
        ctx.held += cost * len(stmt.names) - freed
        for name in stmt.names:
            ctx.types[name] = kind
        if stmt.value is not None:
            empty = self._typed(stmt.names[0], self.evaluate(stmt.value, ctx), ctx)
        for name in stmt.names:
            ctx.memory[name] = cost
            if shape:
                ctx.arrays[name] = [empty] * count
                ctx.shapes[name] = shape
                ctx.variables.pop(name, None)
            else:
                ctx.variables[name] = empty
                ctx.arrays.pop(name, None)

    def print(self, stmt: Print, ctx: ProcessContext) -> int:
        """PRINT [#channel,] items: every channel reaches the command-line hosts (D: the
        emulator has one terminal; channel numbers are checked, 0..255). The channel."""
        channel = float(ctx.outdevice)  # OUTDEVICE when no #channel is given (its page)
        if stmt.channel is not None:
            channel = self.number(stmt.channel, ctx)
            if channel != int(channel) or not 0 <= channel <= 255:
                raise TrioError("Parameter out of range")
        parts = []
        for item, separator in stmt.items:
            if isinstance(item, Format) and item.spec is not None:
                parts.append(c_format(item.spec, self.evaluate(item.value, ctx)))
            elif isinstance(item, Format):
                number = self.number(item.value, ctx)
                field = f"{number:.{item.decimals}f}"
                parts.append(field.ljust(-item.width) if item.width < 0
                             else field.rjust(item.width))
            else:
                value = self.evaluate(item, ctx)
                parts.append(value if isinstance(value, str) else format_number(value))
            parts.append("\t" if separator == "," else "")
        text = "".join(parts) + ("\r\n" if stmt.newline else "")
        if int(channel) in self.strings:  # a STRING variable opened as a file
            owner, name = self.strings[int(channel)]
            held = owner.variables.get(name, "")
            assert isinstance(held, str)
            owner.variables[name] = self._typed(name, held + text, owner)
        elif not self.hook.write_file(int(channel), text):
            self.output(text)
        return int(channel)

    def _typed(self, name: str, value: Value, ctx: ProcessContext) -> Value:
        """A value as a variable of that name holds it: its DIM type, else FLOAT (help
        DIM: local variables are FLOAT by default)."""
        kind = ctx.types.get(name)
        if kind is None:
            return real(value) if isinstance(value, float) else value
        return self.as_type(kind, value)

    def as_type(self, kind: str, value: Value) -> Value:
        """`value` as a variable of type `kind` (DIM's types) holds it."""
        if kind.startswith("STRING"):
            if not isinstance(value, str):
                raise TrioError("Type mismatch")
            return value[:int(kind[6:])]
        number = self.number_value(value)
        if kind == "INTEGER":
            return float(math.trunc(number))
        if kind == "BOOLEAN":
            return _truth(number != 0)
        return real(number) if kind == "FLOAT" else number

    def motion_error_bank(self, expr: Param, ctx: ProcessContext) -> float:
        """MOTION_ERROR(bank): the axes 64 x bank.. in error (its page: banks 0..15 of 64
        axes); every axis here is in bank 0, so banks 1..15 read 0."""
        if len(expr.index) != 1 or expr.axis is not None or expr.slot is not None:
            raise TrioError("Syntax error")
        bank = self.number(expr.index[0], ctx)
        if bank != int(bank) or not 0 <= bank <= 15:
            raise TrioError("Parameter out of range")
        if bank:
            return 0.0
        return self.read_parameter(Param(expr.keyword, None, expr.process), ctx)

    def bit_of(self, expr: Bit, ctx: ProcessContext) -> int:
        """The bit a ``.n`` or ``.name`` selects: a whole 0..52 (as a written one)."""
        if isinstance(expr.bit, int):
            return expr.bit
        bit = self.number(expr.bit, ctx)
        if bit != int(bit) or not 0 <= bit <= 52:
            raise TrioError("Parameter out of range")
        return int(bit)

    def _hold(self, ctx: ProcessContext, name: str, cost: int) -> None:
        """A variable not DIMmed now holds `cost` bytes of the controller's memory."""
        old = ctx.memory.get(name, 0)
        if cost > old and self.hook.memory_in_use(ctx) - old + cost > PROGRAM_MEMORY:
            raise TrioError("Not enough memory")
        ctx.memory[name] = cost
        ctx.held += cost - old

    def assign(self, stmt: Assign, ctx: ProcessContext) -> None:
        target = stmt.target
        raw = self.evaluate(stmt.value, ctx)
        if isinstance(target, Bit):  # x.n = v: bit n of x's integer part set (v <> 0)
            mask = 1 << self.bit_of(target, ctx)
            word = int(self.number(target.operand, ctx))
            word = word | mask if self.number_value(raw) != 0 else word & ~mask
            assert isinstance(target.operand, (Var, Param, Call))
            self.assign(Assign(target.operand, Num(float(word))), ctx)
            return
        if isinstance(target, Var):
            name = target.name
            if name not in ctx.variables and name in self.hook.globals:
                number = self.number_value(raw)
                self._act(lambda: self.machine.vr_write(self.hook.globals[name], number))
            elif name not in ctx.variables and name in self.hook.constants:
                raise TrioError("Cannot assign to a constant")
            else:
                if len(ctx.variables) >= 4096 and name not in ctx.variables:
                    raise TrioError("Parameter out of range")  # (D) bounded
                value = self._typed(name, raw, ctx)
                if name not in ctx.types:  # a DIMmed name holds what its DIM took
                    self._hold(ctx, name, len(value) if isinstance(value, str)
                               else NUMBER_BYTES)
                ctx.variables[name] = value
            return
        if isinstance(target, Call) and target.name == "AOUT":
            channel = self._point(self.number(target.args[0], ctx), 8)
            value = self.number_value(raw)
            if not -2048 <= value <= 2047:
                raise TrioError("Parameter out of range")
            self.hook.analog_outputs[channel] = value
            return
        if isinstance(target, Call) and target.name in KEYWORDS and target.name != "VR":
            raise TrioError("Parameter is read only")
        if isinstance(target, Call) and target.name != "VR" and \
                0 < len(target.args) < len(ctx.shapes.get(target.name, ())):
            held: Expr = Str(raw) if isinstance(raw, str) else Num(raw)
            self.fill(ArrayFill(target.name, (held,), target.args), ctx)  # a row
            return
        if isinstance(target, Call) and target.name != "VR":
            array, index = self._element(target.name, target.args, ctx)
            array[index] = self._typed(target.name, raw, ctx)
            return
        if isinstance(target, Call) and isinstance(raw, str):  # VR(i) = "text" (VR's page)
            self.vr_write_string(self._index(self.number(target.args[0], ctx)), raw)
            return
        value = self.number_value(raw)
        if isinstance(target, Param) and target.keyword.name == "TICKS":
            ctx.ticks = (value, self.machine.servo_tick())
            return
        if isinstance(target, Param) and target.keyword.name in ("OUTDEVICE", "INDEVICE"):
            target.keyword.check(value)  # 0..255, whole (D)
            if value != int(value):
                raise TrioError("Parameter out of range")
            if target.keyword.name == "OUTDEVICE":
                ctx.outdevice = int(value)
            else:
                ctx.indevice = int(value)
            return
        if isinstance(target, Call):  # VR(i) = value
            index = self._index(self.number(target.args[0], ctx))
            self._act(lambda: self.machine.vr_write(index, value))
            return
        keyword = target.keyword
        if not keyword.writable:
            raise TrioError("Parameter is read only")
        if target.index or target.slot is not None:
            keyword.check(value)
            key = self._indexed_key(target, ctx)
            if key not in self.hook.indexed and len(self.hook.indexed) >= MAX_INDEXED:
                raise TrioError("Parameter out of range")  # (D) bounded
            self.hook.indexed[key] = value
            return
        if keyword.name in ("AOUT0", "AOUT1", "AOUT2", "AOUT3"):  # AOUT(n) = v (page)
            self.assign(Assign(Call("AOUT", (Num(float(keyword.name[-1])),)), Num(value)), ctx)
            return
        if keyword.kind is Kind.SYSTEM_PARAMETER:
            keyword.check(value)
            self._act(lambda: self.machine.set_system_parameter(keyword.name, value))
            return
        axis = self.axis_of(target.axis, ctx)
        keyword.check(value)
        if keyword.name == "UNITS" and value == 0 or keyword.name in _RATES and value > 0 \
                and self.machine.axis_parameter("UNITS", axis) < 0:
            raise TrioError("Parameter out of range")  # (see UNITS's table entry)
        if keyword.name == "OFFPOS":  # shifts the axis's positions, then reads 0 (I)
            dpos = self.machine.axis_parameter("DPOS", axis)
            self._act(lambda: self.machine.defpos([axis], [dpos + value]))
            return
        self._act(lambda: self.machine.set_axis_parameter(keyword.name, axis, value))

    def group(self, axis: Expr | None, ctx: ProcessContext, count: int) -> list[int]:
        """The axes a multi-axis command acts on: the base array, or AXIS(n) onwards."""
        if axis is None:
            # the default BASE array is the sequence 0, 1, 2, ... (TrioBASIC help, BASE),
            # held as [0] until a BASE command writes the whole array
            base = ctx.base if len(ctx.base) > 1 else \
                base_array(ctx.base, self.machine.axis_count)
        else:
            first = self.axis_of(axis, ctx)
            base = base_array([first], self.machine.axis_count)
        if count > len(base):
            raise TrioError("Invalid axis number")
        return base[:count]

    def command(self, stmt: Command, ctx: ProcessContext) -> Wait:
        name = stmt.keyword.name
        if name in ("TIME", "DATE") and len(stmt.args) == 3:
            self.set_clock(name, [self.number(a, ctx) for a in stmt.args])
            return
        if name == "SCOPE":  # the parameters are sampled later: kept, not evaluated
            head = [self.number(a, ctx) for a in stmt.args[:4]]
            self.hook.set_scope(head, list(stmt.args[4:]), ctx)
            return
        if name == "SERVO_READ":  # read on the next servo cycle, in counts (servoread.py)
            yield from servo_read(self.machine, stmt.args, stmt.axis,
                                  lambda e: self.number(e, ctx),
                                  lambda a: self.axis_of(a, ctx))
            return
        if name == "TRIGGER":
            self.hook.trigger(bool(stmt.args) and self.number(stmt.args[0], ctx) != 0)
            return
        if name == "RANDOMIZE":  # a seed given: a known sequence; none: a fresh one (D)
            seed = [self.number(a, ctx) for a in stmt.args]
            ctx.rng = random.Random(int(seed[0]) if seed else
                                    ctx.process * 1_000_003 + self.machine.servo_tick() + 1)
            return
        if name == "THROW_ERROR":  # the program stops with its own message (its page)
            text = self.evaluate(stmt.args[0], ctx)
            if not isinstance(text, str):
                raise TrioError("Type mismatch")
            raise Thrown(text)
        if name in _BIT_COMMANDS:
            self.bit_command(name, [self.number(a, ctx) for a in stmt.args])
            return
        if name in ("INTEGER_READ", "INTEGER_WRITE"):
            self.raw_bits(stmt, ctx)
            return
        if name in ("CHANNEL_READ", "CHANNEL_WRITE"):
            self.call(Call(name, stmt.args), ctx)
            return
        if name == "DLINK":
            self.drive_link([self.evaluate(a, ctx) for a in stmt.args])
            return
        if name in SET_MOTION_WORDS:  # the rates of a named axis (motionwords.py)
            self.call(Call(name, stmt.args), ctx)
            return
        if name in _FRAME_WORDS:
            self.frame_word(name, [self.number(a, ctx) for a in stmt.args], ctx)
            return
        if name == "ENCODER_RATIO":  # (no arguments: 1:1, D)
            ratio = [self.number(a, ctx) for a in stmt.args] or [1.0, 1.0]
            if len(ratio) != 2:
                raise TrioError("Syntax error")
            axis = self.axis_of(stmt.axis, ctx)
            self._act(lambda: self.machine.encoder_ratio(axis, ratio[0], ratio[1]))
            return
        if name in _AXIS_HARDWARE:  # STEP_RATIO, BACKLASH, COMBINE_CONTROL (never wait)
            hardware = [self.number(a, ctx) for a in stmt.args]
            axis = self.axis_of(stmt.axis, ctx)
            self._act(lambda: self.machine.axis_hardware(name, axis, hardware))
            return
        if name not in _MACHINE_COMMANDS:
            values = [self.evaluate(a, ctx) for a in stmt.args]
            yield from self.hook.system_command(stmt.keyword, values, ctx)
            return
        args = [self.number(a, ctx) for a in stmt.args]
        if not all(math.isfinite(a) for a in args):
            raise TrioError("Parameter out of range")
        m = self.machine
        if name in ("MOVE", "MOVEABS"):
            axes = self.group(stmt.axis, ctx, len(args))
            while not m.can_load(axes):
                yield ON_CHANGE
            move = m.move if name == "MOVE" else m.move_abs
            self._act(lambda: move(axes, args))
        elif name in ("MOVESP", "MOVEABSSP"):
            axes = self.group(stmt.axis, ctx, len(args))
            while not m.can_load(axes):
                yield ON_CHANGE
            self._act(lambda: m.move_sp(axes, args, name == "MOVEABSSP"))
        elif name in ("MOVECIRC", "MHELICAL"):
            axes = self.group(stmt.axis, ctx, 2 if name == "MOVECIRC" else 3)
            while not m.can_load(axes):
                yield ON_CHANGE
            self._act(lambda: (m.movecirc if name == "MOVECIRC" else m.mhelical)(axes, args))
        elif name in ("MOVECIRCSP", "MHELICALSP"):
            axes = self.group(stmt.axis, ctx, 2 if name == "MOVECIRCSP" else 3)
            while not m.can_load(axes):
                yield ON_CHANGE
            self._act(lambda: m.arc_sp(axes, args, name == "MHELICALSP"))
        elif name in SEQUENCES:  # MOVE(ABS)SEQ: its moves loaded one by one as room
            axes = self.group(stmt.axis, ctx, int(self._machine(lambda: axes_of(args))))
            sequence = self._machine_moves(lambda: m.sequence(name, axes, args))
            for move_kind, move_args in sequence:
                while not m.can_load(axes):
                    yield ON_CHANGE
                self._act(partial(self._load_one, axes, move_kind, move_args))
        elif name == "SYNC":  # not a buffered move: never waits (personality sync.py)
            axes = self.group(stmt.axis, ctx, max(1, len(args) - 4))
            self._act(lambda: m.sync(axes, args))
        elif name == "MOVETANG":  # retargets its running move: never waits (D)
            axes = [self.axis_of(stmt.axis, ctx)]
            self._act(lambda: m.geometric_move(name, axes, args))
        elif name in GEOMETRIC:  # MSPHERICAL(SP) (personality geometry.py)
            axes = self.group(stmt.axis, ctx, group_size(args))
            while not m.can_load(axes):
                yield ON_CHANGE
            self._act(lambda: m.geometric_move(name, axes, args))
        elif name == "DEFPOS":
            axes = self.group(stmt.axis, ctx, len(args))
            self._act(lambda: m.defpos(axes, args))
        elif name == "WA":
            if args[0] > MAX_WA_MS:  # (D) longer than any program waits: a value error
                raise TrioError("Parameter out of range")
            ticks = math.ceil(args[0] * 1000 / m.servo_period_us()) if args[0] > 0 else 0
            wake = m.servo_tick() + ticks
            while m.servo_tick() < wake:
                yield Wake(wake)
        elif name == "BASE" and not args:  # BASE alone prints the array (its example 3)
            axes = base_array(ctx.base, m.axis_count)  # (power-up [0]: 0, 1, 2, ...)
            self.output("(" + ", ".join(str(a) for a in axes) + ")\r\n")
        elif name == "BASE":
            ctx.base = base_array([self._axis_number(a) for a in args], m.axis_count)
        elif name == "TABLE":
            if len(args) < 2:
                raise TrioError("Syntax error")
            start = self._index(args[0])
            self._act(lambda: m.table_write(start, args[1:]))
        elif name == "MPE":
            from .keywords import KEYWORDS

            KEYWORDS["MPE"].check(args[0])
        elif name == "RAPIDSTOP":  # its modes (RAPIDSTOP page)
            self._act(lambda: m.rapidstop(args[0] if args else 0))
        elif name == "OP":
            self.op(args)
        else:
            axis = self.axis_of(stmt.axis, ctx)
            yield from self._axis_command(name, axis, args)

    def raw_bits(self, stmt: Command, ctx: ProcessContext) -> None:
        """INTEGER_READ(source, low, high) / INTEGER_WRITE(destination, low, high): a
        64-bit pattern as two 32-bit words (datawords.words_of, value_of)."""
        first, low, high = stmt.args
        whole = isinstance(first, Param) or isinstance(first, Var) \
            and ctx.types.get(first.name) == "INTEGER"
        if stmt.keyword.name == "INTEGER_READ":
            words = words_of(self.number(first, ctx), whole)
            for target, word in ((low, words[0]), (high, words[1])):
                self.put(target, word, ctx)
        else:
            self.put(first, value_of(self.number(low, ctx), self.number(high, ctx), whole),
                     ctx)

    def put(self, target: Expr, value: float, ctx: ProcessContext) -> None:
        """Store into what an argument names: a variable, VR(n), TABLE(n), an array
        element or a parameter; anything else (a number) cannot take a value."""
        if isinstance(target, Call) and target.name == "TABLE" and len(target.args) == 1:
            index = self._index(self.number(target.args[0], ctx))
            self._act(lambda: self.machine.table_write(index, [value]))
        elif isinstance(target, (Var, Call, Param)):
            self.assign(Assign(target, Num(value)), ctx)
        else:
            raise TrioError("Syntax error")

    def bit_command(self, name: str, args: list[float]) -> float:
        """SET_BIT(b, vr) / CLEAR_BIT(b, vr) / READ_BIT(b, vr): bit b (0..52) of VR(vr);
        FLAG(n[, state]) / FLAGS([value]): the 24 user flags (I: manual; every argument
        checked before anything changes)."""
        m = self.machine
        if name == "INVERT_IN":  # INVERT_IN(n) reads ON/OFF; INVERT_IN(n, state) sets
            if len(args) not in (1, 2):
                raise TrioError("Syntax error")
            point = self._point(args[0], IO_SPACE)
            if len(args) == 1:
                return 1.0 if m.input_inverted(point) else 0.0
            self._act(lambda: m.invert_input(point, args[1] != 0))
            return -1.0  # the two-argument form as a function: TRUE (help page)
        if name in ("SET_BIT", "CLEAR_BIT", "READ_BIT"):
            if len(args) not in (2, 3) or len(args) == 3 and args[2] not in (0.0, 1.0):
                raise TrioError("Syntax error" if len(args) not in (2, 3)
                                else "Parameter out of range")
            bit, index = self._point(args[0], 53), self._index(args[1])
            table = len(args) == 3 and args[2] == 1.0  # mode 1: a TABLE value (their pages)
            value = int(self._machine(lambda: m.table_read(index) if table
                                      else m.vr_read(index)))
            if name == "READ_BIT":
                return float((value >> bit) & 1)
            value = value | (1 << bit) if name == "SET_BIT" else value & ~(1 << bit)
            self._act(lambda: m.table_write(index, [float(value)]) if table
                      else m.vr_write(index, float(value)))
            return 0.0
        flags = int(self.hook.indexed.get(("FLAGS", ()), 0.0))
        if name == "FLAGS":
            if not args:
                return float(flags)
            if len(args) != 1 or args[0] != int(args[0]) or not 0 <= args[0] < 1 << 24:
                raise TrioError("Parameter out of range")
            self.hook.indexed[("FLAGS", ())] = args[0]
            return 0.0
        if not 1 <= len(args) <= 2:
            raise TrioError("Syntax error")
        flag = self._point(args[0], 24)
        if len(args) == 1:
            return _truth(bool(flags >> flag & 1))
        flags = flags | (1 << flag) if args[1] != 0 else flags & ~(1 << flag)
        self.hook.indexed[("FLAGS", ())] = float(flags)
        return 0.0

    @staticmethod
    def _machine_moves(action: Callable[[], list[tuple[str, list[float]]]]
                       ) -> list[tuple[str, list[float]]]:
        try:
            return action()
        except ValueError as exc:
            raise TrioError(_machine_text(exc)) from None

    def _load_one(self, axes: list[int], kind: str, values: list[float]) -> None:
        """One move of a MOVE(ABS)SEQ sequence."""
        m = self.machine
        if kind == "MOVEABS":
            m.move_abs(axes, values)
        elif kind == "MOVE":
            m.move(axes, values)
        elif kind == "MOVECIRC":
            m.movecirc(axes, values)
        else:
            m.geometric_move(kind, axes, values)

    def _axis_command(self, name: str, axis: int, args: list[float]) -> Wait:
        m = self.machine
        if name == "ACC":
            from .keywords import KEYWORDS

            KEYWORDS["ACCEL"].check(args[0])
            self._act(lambda: m.set_acc(axis, args[0]))
        elif name == "CANCEL":  # at FASTDEC where it applies, its modes (CANCEL page)
            self._act(lambda: m.cancel(axis, fast=True, mode=args[0] if args else 0))
        elif name == "PWM_CONTROL":
            self._act(lambda: m.pwm_control(axis, args))
        elif name in ("FORWARD", "REVERSE"):
            yield from self._forever(axis, 1 if name == "FORWARD" else -1)
        elif name == "DATUM":
            yield from self.datum(axis, args[0])
        elif name in ("MOVELINK", "CONNECT", "FLEXLINK"):  # queued behind links too
            while not m.can_link(axis):
                yield ON_CHANGE
            action = {"MOVELINK": m.movelink, "CONNECT": m.connect,
                      "FLEXLINK": m.flexlink}[name]
            self._act(lambda: action(axis, args))
        elif name == "MOVEMODIFY":  # acts on the running move: never waits (D)
            self._act(lambda: m.movemodify(axis, args))
        elif name == "ADDAX":
            self._act(lambda: m.addax(axis, args))
        elif name == "CAM":
            while not m.can_load([axis]):
                yield ON_CHANGE
            self._act(lambda: m.cam(axis, args))
        elif name == "MOVETEST":  # starts or ends a cycle: never waits (movetest.py)
            self._act(lambda: m.movetest(axis, args))
        elif name == "REGIST":  # arms a capture: never waits
            self._act(lambda: m.regist(axis, args))
        elif name in ("PSWITCH", "HW_PSWITCH", "HW_TIMER"):  # (pswitch.py): never wait
            self._act(lambda: m.position_switch(name, axis, args))
        elif name == "CAMBOX" and len(args) == 2:  # the multi-axis loading form
            axes = base_array([axis], m.axis_count)[:int(args[1])] \
                if args[1] == int(args[1]) and 1 <= args[1] <= m.axis_count else []
            if not axes:
                raise TrioError("Parameter out of range")
            while not m.can_load(axes):
                yield ON_CHANGE
            self._act(lambda: m.cambox_group(axes, args))
        elif name in ("CONNPATH", "CAMBOX"):
            if name == "CONNPATH" and len(args) == 2:  # the page's (ratio, driving_axis)
                args = [args[1], args[0]]  # as the machine takes it: (driving axis, ratio)
            while not m.can_load([axis]):
                yield ON_CHANGE
            action = m.connpath if name == "CONNPATH" else m.cambox
            self._act(lambda: action(axis, args))
        elif name in ("COMPENSATE_XY", "COMBINE_AXES"):  # linked moves (MTYPE 26):
            # personality compensate.py, combine.py
            while not m.can_load([axis]):
                yield ON_CHANGE
            self._act(lambda: m.axis_hardware(name, axis, args))

    def _forever(self, axis: int, direction: int) -> Wait:
        """FORWARD/REVERSE: a move long enough to end only by CANCEL."""
        m = self.machine
        while not m.can_load([axis]):
            yield ON_CHANGE
        units = m.axis_parameter("UNITS", axis)
        self._act(lambda: m.move([axis], [FOREVER_COUNTS / units * direction]))

    def _stop_and_settle(self, axis: int) -> Wait:
        self._act(lambda: self.machine.cancel(axis))
        while not self.machine.axis_idle(axis):
            yield ON_CHANGE

    def datum(self, axis: int, mode: float) -> Wait:
        """DATUM(n) on the shared world's switches (see the keyword's note)."""
        m = self.machine
        if mode in (0, 1, 2, 7):  # clear the motion errors; a Z-mark search, on the machine
            self._act(lambda: m.datum(axis, int(mode)))
            while mode in (1, 2) and not m.axis_idle(axis):  # (a clear never waits)
                yield ON_CHANGE
            return
        if mode not in (3, 4, 5, 6):
            raise TrioError("Parameter out of range")
        wired = m.axis_parameter("DATUM_IN", axis)
        if not 0 <= wired < IO_SPACE:
            raise TrioError("Parameter out of range")
        switch = int(wired)
        direction = 1 if mode in (3, 5) else -1
        on = m.input_function  # the datum input is active low (DATUM_IN's page)
        if not on(switch):
            yield from self._forever(axis, direction)
            while not on(switch):
                yield None  # the input is watched every servo cycle
            yield from self._stop_and_settle(axis)
        speed = m.axis_parameter("SPEED", axis)
        self._act(lambda: m.set_axis_parameter("SPEED", axis, m.axis_parameter("CREEP", axis)))
        try:
            yield from self._forever(axis, -direction)
            while not on(switch):
                yield None  # back into the switch, when the fast search ran past it
            while on(switch):
                yield None
            yield from self._stop_and_settle(axis)
        finally:
            m.set_axis_parameter("SPEED", axis, speed)
        self._act(lambda: m.defpos([axis], [0.0]))

    def op(self, args: list[float]) -> None:
        """OP(n, state) one output; OP(state) the first 32 outputs from the bits of state
        (bit k is output k; 0..7 are inputs only and are left alone); OP(start, end, state)
        outputs start..end from bits 0.. of state (TrioBASIC help OP, its four modes)."""
        m = self.machine
        if len(args) == 2:
            m.set_output(self._point(args[0], IO_SPACE), args[1] != 0)
            return
        if len(args) == 1:
            first, last, pattern = 8, IO_POINTS - 1, args[0]
            shift = 0
        elif len(args) == 3:
            first, last = self._point(args[0], IO_SPACE), self._point(args[1], IO_SPACE)
            if not first <= last < first + IO_POINTS:
                raise TrioError("Parameter out of range")
            pattern, shift = args[2], first
        else:
            raise TrioError("Syntax error")
        if pattern != int(pattern) or not 0 <= pattern < 2 ** IO_POINTS:
            raise TrioError("Parameter out of range")
        for k in range(first, last + 1):
            m.set_output(k, bool((int(pattern) >> (k - shift)) & 1))

    def _axis_number(self, value: float) -> int:
        if value != int(value) or not 0 <= value < self.machine.axis_count:
            raise TrioError("Invalid axis number")
        return int(value)

    @staticmethod
    def _act(action: Callable[[], None]) -> None:
        try:
            action()
        except ValueError as exc:
            raise TrioError(_machine_text(exc)) from None
        except OverflowError:
            raise TrioError("Arithmetic error") from None


def base_array(axes: Sequence[int], axis_count: int) -> list[int]:
    """BASE(a, b, ...): the named axes, then the rest in order after the last one."""
    if len(set(axes)) != len(axes):
        raise TrioError("Invalid axis number")
    rest = [(axes[-1] + k) % axis_count for k in range(1, axis_count + 1)]
    return list(axes) + [a for a in rest if a not in axes]


def _machine_text(exc: BaseException) -> str:
    text = str(exc)
    return text[:1].upper() + text[1:] if text else "Parameter out of range"

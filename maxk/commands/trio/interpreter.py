"""Evaluating TrioBASIC: expressions, and statements as resumable generators.

A statement runs as a generator that yields while the process must wait (WA, WAIT,
a full move buffer), so a program runs beside the command line: the scheduler resumes
each process once per servo cycle. Every argument of a statement is evaluated and
checked before the machine is asked to act, and the machine is asked once, so an error
leaves nothing half-applied.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Generator, Sequence
from dataclasses import dataclass, field
from typing import Protocol

from .keywords import KEYWORDS, Keyword, Kind
from .lexer import TrioError
from .machine import TrioMachine
from .parser import (
    Assign,
    Binary,
    Call,
    Command,
    Expr,
    IfLine,
    Num,
    Param,
    Print,
    Stmt,
    Str,
    Unary,
    Var,
    WaitIdle,
    WaitUntil,
)

Value = float | str


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
    """Integer values without decimals (atrio's handshake needs it), others with 4."""
    if value == int(value):
        return str(int(value))
    return f"{value:.4f}"


@dataclass
class ProcessContext:
    """One process's own state: its BASE axes, its local variables, where it is."""

    process: int
    program: str = ""  # "" for the command line
    base: list[int] = field(default_factory=lambda: [0])
    variables: dict[str, float] = field(default_factory=dict)
    line: int = 0
    loops: dict[int, tuple[float, float]] = field(default_factory=dict)  # FOR end, step


class SystemHook(Protocol):
    """Program handling and channel state, owned by the command-line runtime."""

    def system_command(self, keyword: Keyword, args: list[Value],
                       ctx: ProcessContext) -> Wait: ...

    def system_function(self, name: str, args: list[Value]) -> float: ...

    def system_parameter(self, name: str) -> float | None: ...


_MATH: dict[str, Callable[[float], float]] = {
    "ABS": abs, "INT": lambda x: float(math.trunc(x)), "FRAC": lambda x: x - math.trunc(x),
    "SGN": lambda x: float((x > 0) - (x < 0)), "SQR": math.sqrt, "SIN": math.sin,
    "COS": math.cos, "TAN": math.tan, "ATAN": math.atan, "EXP": math.exp, "LN": math.log,
}
_MACHINE_COMMANDS = frozenset({"MOVE", "MOVEABS", "DEFPOS", "ACC", "CANCEL", "RAPIDSTOP",
                               "PWM_CONTROL", "CONNPATH", "CAMBOX", "BASE", "TABLE", "WA",
                               "MPE"})


def _truth(value: bool) -> float:
    return -1.0 if value else 0.0


class Interpreter:
    def __init__(self, machine: TrioMachine, hook: SystemHook,
                 output: Callable[[str], None]) -> None:
        self.machine = machine
        self.hook = hook
        self.output = output

    # ---- expressions ---------------------------------------------------------------------
    def evaluate(self, expr: Expr, ctx: ProcessContext) -> Value:
        if isinstance(expr, Num):
            return expr.value
        if isinstance(expr, Str):
            return expr.text
        if isinstance(expr, Var):
            return ctx.variables.get(expr.name, 0.0)
        if isinstance(expr, Param):
            return self.read_parameter(expr, ctx)
        if isinstance(expr, Call):
            return self.call(expr, ctx)
        if isinstance(expr, Unary):
            operand = self.number(expr.operand, ctx)
            return -operand if expr.op == "-" else float(~int(operand))
        return self.binary(expr, ctx)

    def number(self, expr: Expr, ctx: ProcessContext) -> float:
        value = self.evaluate(expr, ctx)
        if isinstance(value, str):
            raise TrioError("Syntax error")
        return value

    def integer(self, expr: Expr, ctx: ProcessContext) -> int:
        value = self.number(expr, ctx)
        if value != int(value):
            raise TrioError("Parameter out of range")
        return int(value)

    def binary(self, expr: Binary, ctx: ProcessContext) -> float:
        a, b = self.number(expr.left, ctx), self.number(expr.right, ctx)
        op = expr.op
        try:
            result = self._apply(op, a, b)
        except (ZeroDivisionError, OverflowError, ValueError, TypeError):
            # (TypeError: a negative base to a fraction is complex, no real number)
            raise TrioError("Divide by zero" if op in ("/", "MOD") and b == 0
                            else "Arithmetic error") from None
        if isinstance(result, complex) or not math.isfinite(result):
            raise TrioError("Arithmetic error")
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
        if op == "AND":
            return float(int(a) & int(b))
        if op == "OR":
            return float(int(a) | int(b))
        if op == "XOR":
            return float(int(a) ^ int(b))
        comparisons = {"=": a == b, "<>": a != b, "<": a < b, ">": a > b, "<=": a <= b,
                       ">=": a >= b}
        return _truth(comparisons[op])

    def call(self, expr: Call, ctx: ProcessContext) -> float:
        name = expr.name
        if name == "BASE":
            if expr.args:
                raise TrioError("Syntax error")
            return float(ctx.base[0])
        args = [self.evaluate(a, ctx) for a in expr.args]
        if name in ("IS_PROG", "PROG_TYPE"):
            return self.hook.system_function(name, args)
        numbers = [a for a in args if not isinstance(a, str)]
        if len(numbers) != len(args):
            raise TrioError("Syntax error")
        try:
            if name in _MATH and len(numbers) == 1:
                if name in ("SQR", "LN") and numbers[0] < (0 if name == "SQR" else 1e-308):
                    raise TrioError("Parameter out of range")
                result = _MATH[name](numbers[0])
            elif name == "ATAN2" and len(numbers) == 2:
                result = math.atan2(numbers[0], numbers[1])
            elif name == "TABLE" and len(numbers) == 1:
                result = self.machine.table_read(self._index(numbers[0]))
            elif name == "VR" and len(numbers) == 1:
                result = self.machine.vr_read(self._index(numbers[0]))
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
        return float(result)

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
        if keyword.kind is Kind.SYSTEM_PARAMETER:
            owned = self.hook.system_parameter(keyword.name)
            if owned is not None:
                return owned
            return self._machine(lambda: self.machine.system_parameter(keyword.name))
        axis = self.axis_of(expr.axis, ctx)
        if keyword.name == "IDLE":
            return _truth(self.machine.axis_idle(axis))
        return self._machine(lambda: self.machine.axis_parameter(keyword.name, axis))

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
            self.print(stmt, ctx)
        elif isinstance(stmt, Assign):
            self.assign(stmt, ctx)
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
        else:
            raise TrioError("Structure error")  # a block statement outside a program

    def print(self, stmt: Print, ctx: ProcessContext) -> None:
        parts = []
        for expr, separator in stmt.items:
            value = self.evaluate(expr, ctx)
            parts.append(value if isinstance(value, str) else format_number(value))
            parts.append("\t" if separator == "," else "")
        self.output("".join(parts) + ("\r\n" if stmt.newline else ""))

    def assign(self, stmt: Assign, ctx: ProcessContext) -> None:
        value = self.number(stmt.value, ctx)
        target = stmt.target
        if isinstance(target, Var):
            ctx.variables[target.name] = value
            return
        if isinstance(target, Call):  # VR(i) = value
            index = self._index(self.number(target.args[0], ctx))
            self._act(lambda: self.machine.vr_write(index, value))
            return
        keyword = target.keyword
        if not keyword.writable:
            raise TrioError("Parameter is read only")
        if keyword.kind is Kind.SYSTEM_PARAMETER:
            keyword.check(value)
            self._act(lambda: self.machine.set_system_parameter(keyword.name, value))
            return
        axis = self.axis_of(target.axis, ctx)
        keyword.check(value)
        self._act(lambda: self.machine.set_axis_parameter(keyword.name, axis, value))

    def group(self, axis: Expr | None, ctx: ProcessContext, count: int) -> list[int]:
        """The axes a multi-axis command acts on: the base array, or AXIS(n) onwards."""
        if axis is None:
            base = ctx.base
        else:
            first = self.axis_of(axis, ctx)
            base = base_array([first], self.machine.axis_count)
        if count > len(base):
            raise TrioError("Invalid axis number")
        return base[:count]

    def command(self, stmt: Command, ctx: ProcessContext) -> Wait:
        name = stmt.keyword.name
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
        elif name == "RAPIDSTOP":
            self._act(m.rapidstop)
        else:
            axis = self.axis_of(stmt.axis, ctx)
            yield from self._axis_command(name, axis, args)

    def _axis_command(self, name: str, axis: int, args: list[float]) -> Wait:
        m = self.machine
        if name == "ACC":
            from .keywords import KEYWORDS

            KEYWORDS["ACCEL"].check(args[0])
            self._act(lambda: m.set_acc(axis, args[0]))
        elif name == "CANCEL":
            self._act(lambda: m.cancel(axis))
        elif name == "PWM_CONTROL":
            self._act(lambda: m.pwm_control(axis, args))
        elif name in ("CONNPATH", "CAMBOX"):
            while not m.can_load([axis]):
                yield ON_CHANGE
            action = m.connpath if name == "CONNPATH" else m.cambox
            self._act(lambda: action(axis, args))

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

"""TrioBASIC syntax: one line into statements, expressions into trees.

A line holds statements separated by ``:``. ``IF c THEN`` at the end of a line opens a
block IF (closed by ENDIF); with statements after THEN it is a one-line IF whose
statements run to the end of the line (ELSE splits them). Block statements (WHILE,
WEND, REPEAT, UNTIL, FOR, NEXT, block IF/ELSE/ENDIF) are markers here; the interpreter
links them into jumps when a program is compiled.

Precedence, loosest first (D where the manual is silent): OR XOR, AND, NOT,
comparisons, + -, * / MOD, unary minus, ^.

Long module: one recursive-descent parser for every statement form of the language.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import TypeVar

from .keywords import BANKED_PARAMETERS, CHANNEL_PARAMETERS, Keyword, Kind, lookup
from .lexer import Tok, Token, TrioError, tokenize
from .printformat import Real, check_spec, decimal_literal

# ---- expressions ---------------------------------------------------------------------


_CHANNEL_FIRST = frozenset({"CHANNEL_READ", "CHANNEL_WRITE"})  # (#n, ...) or (n, ...)


@dataclass(frozen=True)
class Num:
    value: float


@dataclass(frozen=True)
class Str:
    text: str


@dataclass(frozen=True)
class Var:
    name: str


@dataclass(frozen=True)
class Param:
    keyword: Keyword
    axis: Expr | None  # AXIS(n) modifier
    process: Expr | None = None  # PROC(n) modifier
    slot: Expr | None = None  # SLOT(n) or PORT(n) modifier (stored per number, D)
    index: tuple[Expr, ...] = ()  # NODE_PROFILE(slot, node): a parameter with arguments


@dataclass(frozen=True)
class Call:
    name: str
    args: tuple[Expr, ...]


@dataclass(frozen=True)
class Unary:
    op: str
    operand: Expr


@dataclass(frozen=True)
class Binary:
    op: str
    left: Expr
    right: Expr


@dataclass(frozen=True)
class Bit:
    """``value.n``: bit n of a value (``AXISSTATUS.2``), 1 or 0; ``value.name``: the bit
    numbered by a variable (``MOTION_ERROR.a`` on the MOTION_ERROR and AXISSTATUS pages)."""

    operand: Expr
    bit: int | Var


@dataclass(frozen=True)
class Opened:
    """``OPEN #n AS "name" FOR mode`` as a value: the error it met, 0 for none (OPEN's
    page: value = OPEN ...)."""

    channel: Channel


@dataclass(frozen=True)
class Field:
    """``name.dims`` / ``name.dimsize(n)``: an array's number of dimensions and the size of
    one (the field operator's page; the robot types' fields are not modelled)."""

    name: str
    field: str  # DIMS or DIMSIZE
    index: Expr | None = None


Expr = Num | Str | Var | Param | Call | Unary | Binary | Bit | Opened | Field

# ---- statements ----------------------------------------------------------------------


@dataclass(frozen=True)
class Format:
    """``x[w,d]`` in a PRINT: the value in a field of w characters (negative: left
    justified) with d decimals; ``x[d]``: d decimals; ``x["%..."]``: a C format string
    (printformat.py)."""

    value: Expr
    width: int
    decimals: int
    spec: str | None = None


@dataclass(frozen=True)
class Print:
    items: tuple[tuple[Expr | Format, str], ...]  # (item, separator after it: ',' ';' '')
    newline: bool
    channel: Expr | None = None  # PRINT #n, ...


@dataclass(frozen=True)
class Label:
    name: str


@dataclass(frozen=True)
class Goto:
    label: str


@dataclass(frozen=True)
class Gosub:
    label: str


@dataclass(frozen=True)
class Return:
    value: Expr | None = None


@dataclass(frozen=True)
class ElseIf:
    condition: Expr


@dataclass(frozen=True)
class SelectCase:
    value: Expr


@dataclass(frozen=True)
class Case:
    """CASE v[, v][, a TO b]; no choices: CASE ELSE."""

    choices: tuple[tuple[Expr, Expr | None], ...]


@dataclass(frozen=True)
class EndCase:
    pass


@dataclass(frozen=True)
class OnError:
    label: str | None  # None: ON BASICERROR with no handler (turns it off)


@dataclass(frozen=True)
class Declare:
    """CONSTANT "name", value / GLOBAL "name", vr."""

    what: str  # "CONSTANT" or "GLOBAL"
    name: str  # "": every one of them is cleared (CONSTANT / GLOBAL alone)
    value: Expr | None  # None: the name alone clears that one (the pages' examples)
    spelling: str = ""  # the name as typed (LIST_GLOBAL prints it so; the page's example)


@dataclass(frozen=True)
class FunctionDef:
    """FUNCTION name(p [AS type], ...) [AS type]: a function of this program."""

    name: str
    params: tuple[str, ...]
    types: tuple[str, ...] = ()  # each parameter's AS type ("" none: FLOAT, help DIM)
    returns: str = ""  # the function's AS type


@dataclass(frozen=True)
class EndFunc:
    pass


@dataclass(frozen=True)
class Perform:
    """A user FUNCTION called as a statement, its value dropped."""

    call: Call


@dataclass(frozen=True)
class Dim:
    """DIM a[, b ...][(n[, m])] [AS type[(n[, m])]] [= value]: each name the same."""

    names: tuple[str, ...]
    sizes: tuple[Expr, ...]  # array dimensions, () for scalars
    type: str  # INTEGER FLOAT BOOLEAN STRING
    length: int = 0  # STRING(n)
    value: Expr | None = None  # the initial value
    static: bool = False  # STATIC: in a FUNCTION, set up on its first call only


@dataclass(frozen=True)
class ArrayFill:
    """``name = v0, v1, ...``: the first elements of a DIM array; ``name(i) = v0, ...``
    the row i of a 2-dimensional array, or from element i on (Array Indexing's page)."""

    name: str
    values: tuple[Expr, ...]
    index: tuple[Expr, ...] = ()


@dataclass(frozen=True)
class OnJump:
    """ON expr GOTO|GOSUB l1, l2, ...: the n-th label (1-based); out of range goes on."""

    value: Expr
    labels: tuple[str, ...]
    gosub: bool


@dataclass(frozen=True)
class Channel:
    """OPEN #n AS "name" FOR mode / CLOSE #n / GET #n, v / INPUT #n, v [, v] /
    LINPUT #n, v: the channel statements."""

    action: str
    channel: Expr | None
    name: Expr | None = None
    mode: str = ""
    targets: tuple[Expr, ...] = ()
    options: tuple[Expr, ...] = ()  # OPEN ... FOR FIFO_WRITE(size, ...): its arguments


@dataclass(frozen=True)
class WaitLoaded:
    axis: Expr | None


_Target = TypeVar("_Target", "Var", "Param", "Call")


@dataclass(frozen=True)
class Assign:
    target: Var | Param | Call | Bit  # Call: VR(i) or a user array element; Bit: x.n
    value: Expr


@dataclass(frozen=True)
class Command:
    keyword: Keyword
    args: tuple[Expr, ...]
    axis: Expr | None


@dataclass(frozen=True)
class WaitIdle:
    axis: Expr | None


@dataclass(frozen=True)
class WaitUntil:
    condition: Expr


@dataclass(frozen=True)
class IfLine:
    condition: Expr
    then: tuple[Stmt, ...]
    otherwise: tuple[Stmt, ...]


@dataclass(frozen=True)
class IfBlock:
    condition: Expr


@dataclass(frozen=True)
class Else:
    pass


@dataclass(frozen=True)
class EndIf:
    pass


@dataclass(frozen=True)
class While:
    condition: Expr


@dataclass(frozen=True)
class Wend:
    pass


@dataclass(frozen=True)
class Repeat:
    pass


@dataclass(frozen=True)
class Until:
    condition: Expr


@dataclass(frozen=True)
class For:
    variable: str
    start: Expr
    end: Expr
    step: Expr | None
    vr: Expr | None = None  # FOR VR(n) = ...: the loop counts in VR(n) (help, VR example)


@dataclass(frozen=True)
class Next:
    variable: str | None


Stmt = (Print | Assign | Command | WaitIdle | WaitUntil | IfLine | IfBlock | Else | EndIf
        | While | Wend | Repeat | Until | For | Next | Label | Goto | Gosub | Return | ElseIf
        | SelectCase | Case | EndCase | OnError | Declare | Dim | FunctionDef | EndFunc
        | Perform | ArrayFill | OnJump | Channel | WaitLoaded)
BLOCK_STATEMENTS = (IfBlock, Else, EndIf, While, Wend, Repeat, Until, For, Next, Label,
                    Goto, Gosub, Return, ElseIf, SelectCase, Case, EndCase, OnError,
                    FunctionDef, EndFunc, OnJump)
JUMPS = (Goto, Gosub, Return, OnJump)  # block statements a one-line IF may hold
DIM_TYPES = ("INTEGER", "FLOAT", "BOOLEAN", "STRING")
CHANNEL_MODES = ("INPUT", "OUTPUT", "APPEND", "FIFO_READ", "FIFO_WRITE", "READ_WRITE")
MAX_ARRAY = 65536  # elements of one DIM array (D)

_EXPRESSION_COMMANDS = frozenset({"TABLE", "BASE"})  # commands that also read as functions
_CHANNEL_STATEMENTS = frozenset({"OPEN", "CLOSE", "GET", "INPUT", "LINPUT"})
_BARE_READS = frozenset({"OP", "FLAGS", "TIME", "DATE", "DAY"})  # commands read bare too
_PARAM_COMMANDS = frozenset({"MPE"})  # parameters set with NAME(value)


def parse_line(text: str) -> list[Stmt]:
    """All statements of one line (empty for a blank or comment line)."""
    return _Parser(tokenize(text), text).line()


def parse_expression(text: str) -> Expr:
    parser = _Parser(tokenize(text))
    expr = parser.expression()
    parser.expect_end()
    return expr


MAX_NESTING = 64  # brackets, unary operators and calls nested in one expression (D)
MAX_OPERATORS = 128  # binary operators in one line (D: evaluation recurses through them)


# DIM s AS STRING with no length: the help's CHR and HEX examples declare one so; no page
# gives its length, 64 characters is our decision (D).
DEFAULT_STRING_LENGTH = 64
MAX_STRING = 65535
"""The longest string a DIM may declare and a string value may be (D: the pages give no
limit; OPEN's page declares a STRING(10000) for a directory listing; bounded for memory)."""


class _Parser:
    def __init__(self, tokens: list[Token], source: str = "") -> None:
        self.tokens = tokens
        self.source = source  # the line as typed (a name's spelling: DEFCONST)
        self.pos = 0
        self.depth = 0
        self.operators = 0

    def binary(self, op: str, left: Expr, right: Expr) -> Binary:
        self.operators += 1
        if self.operators > MAX_OPERATORS:
            raise TrioError("Expression too complex")
        return Binary(op, left, right)

    def nest(self) -> None:
        """Count one level of nesting; a deeper expression is refused, never a crash."""
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise TrioError("Expression too complex")

    # ---- token helpers ---------------------------------------------------------------
    @property
    def tok(self) -> Token:
        return self.tokens[self.pos]

    def advance(self) -> Token:
        tok = self.tokens[self.pos]
        if tok.kind is not Tok.END:
            self.pos += 1
        return tok

    def at_op(self, *ops: str) -> bool:
        return self.tok.kind is Tok.OP and self.tok.text in ops

    def at_name(self, *names: str) -> bool:
        return self.tok.kind is Tok.NAME and self.tok.text in names

    def expect_op(self, op: str) -> None:
        if not self.at_op(op):
            raise TrioError("Syntax error")
        self.advance()

    def expect_end(self) -> None:
        if self.tok.kind is not Tok.END:
            raise TrioError("Syntax error")

    def at_statement_end(self) -> bool:
        return self.tok.kind is Tok.END or self.at_op(":") or self.at_name("ELSE")

    # ---- statements --------------------------------------------------------------------
    def line(self) -> list[Stmt]:
        statements: list[Stmt] = []
        while self.tok.kind is not Tok.END:
            if self.at_op(":"):
                self.advance()
                continue
            statement = self.statement()
            statements.append(statement)
            if isinstance(statement, IfLine):
                break  # a one-line IF takes the rest of the line
            if isinstance(statement, Else):
                continue  # ELSE of a block IF may have its first statement after it (I)
            if self.tok.kind is not Tok.END:
                self.expect_op(":")
        return statements

    def statements_until_else(self) -> tuple[Stmt, ...]:
        out: list[Stmt] = []
        while self.tok.kind is not Tok.END and not self.at_name("ELSE"):
            if self.at_op(":"):
                self.advance()
                continue
            statement = self.statement()
            if isinstance(statement, BLOCK_STATEMENTS) and not isinstance(statement, JUMPS):
                raise TrioError("Syntax error")
            out.append(statement)
            if not self.at_statement_end():
                raise TrioError("Syntax error")
        return tuple(out)

    def statement(self) -> Stmt:
        tok = self.tok
        if self.at_op("?"):
            self.advance()
            return self.print_rest()
        if tok.kind is not Tok.NAME:
            raise TrioError("Syntax error")
        name = tok.text
        keyword = lookup(name)
        if keyword is None:
            return self.user_statement(name)
        if name == "ON" and self.tokens[self.pos + 1].text == "BASICERROR":
            self.advance()
            self.advance()
            if self.tok.kind is Tok.END:
                return OnError(None)
            if not self.at_name("GOTO"):
                raise TrioError("Syntax error")
            self.advance()
            return OnError(self.label_name())
        if name == "ON" and self.tokens[self.pos + 1].kind is not Tok.END:
            self.advance()
            return self.on_jump()
        self.advance()
        if name in ("TIME", "DATE") and self.at_op("="):  # TIME = hh:mm:ss, DATE = dd:mm:yy
            self.advance()
            fields = [self.expression()]
            for _ in range(2):
                self.expect_op(":")
                fields.append(self.expression())
            return Command(keyword, tuple(fields), None)
        if keyword.kind is Kind.STATEMENT:
            return self.block_or_statement(name)
        if name in _CHANNEL_STATEMENTS:
            return self.channel_statement(name)
        if name == "FILE":  # FILE "function" [parameters] (FILE's page)
            return Command(keyword, self.file_args(), None)
        if keyword.kind is Kind.COMMAND:
            command = self.command(keyword)
            if self.at_op("=") and command.args:  # AOUT(n) = value
                self.advance()
                return Assign(Call(name, command.args), self.expression())
            return command
        if name in _PARAM_COMMANDS and self.at_op("("):
            return self.command(keyword)
        if keyword.kind in (Kind.AXIS_PARAMETER, Kind.SYSTEM_PARAMETER):
            target = self.bit_target(self.parameter(keyword))
            self.expect_op("=")
            return Assign(target, self.expression())
        if name == "VR":
            self.expect_op("(")
            index = self.expression()
            self.expect_op(")")
            vr = self.bit_target(Call("VR", (index,)))
            self.expect_op("=")
            return Assign(vr, self.expression())
        if keyword.kind is Kind.FUNCTION:  # a function called for its effect: POKE(...)
            return Perform(Call(name, self.call_args(keyword)))
        raise TrioError("Syntax error")

    def user_statement(self, name: str) -> Stmt:
        """A statement starting with a name that is no keyword: a label, an assignment to
        a variable or an array element, an array filled from a list, a FUNCTION called."""
        self.advance()
        if self.at_op(":") and self.pos == 1:  # `name:` starting a line: a label
            return Label(name)
        if self.at_op("("):  # an element of a DIM array, or a FUNCTION called
            args = self.user_args()
            element = self.bit_target(Call(name, args))
            if not self.at_op("="):
                if isinstance(element, Bit):
                    raise TrioError("Syntax error")
                return Perform(Call(name, args))
            self.advance()
            if not args:
                raise TrioError("Syntax error")
            value = self.expression()
            if not self.at_op(",") or isinstance(element, Bit) or name == "VR":
                return Assign(element, value)
            values = [value]
            while self.at_op(","):
                self.advance()
                values.append(self.expression())
            return ArrayFill(name, tuple(values), args)
        variable = self.bit_target(Var(name))
        self.expect_op("=")
        value = self.expression()
        if isinstance(variable, Bit):
            return Assign(variable, value)
        if not self.at_op(","):
            return Assign(Var(name), value)
        values = [value]
        while self.at_op(","):
            self.advance()
            values.append(self.expression())
        return ArrayFill(name, tuple(values))

    def on_jump(self) -> OnJump:
        """ON expr GOSUB|GOTO label, label, ..."""
        value = self.expression()
        if not self.at_name("GOTO", "GOSUB"):
            raise TrioError("Syntax error")
        gosub = self.advance().text == "GOSUB"
        labels = [self.label_name()]
        while self.at_op(","):
            self.advance()
            labels.append(self.label_name())
        return OnJump(value, tuple(labels), gosub)

    def parameter(self, keyword: Keyword) -> Param:
        """A parameter with its arguments (``NODE_PROFILE(s, n)``) and modifiers
        (``AXIS(n)``, ``PROC(n)``, ``SLOT(n)``, ``PORT(n)``) in any order."""
        index: tuple[Expr, ...] = ()
        if self.at_op("(") and (keyword.note.startswith("Not modelled")
                                or keyword.name in CHANNEL_PARAMETERS
                                or keyword.name in BANKED_PARAMETERS):
            # only a parameter the emulator keeps as written takes arguments (D): a
            # modelled one with brackets (DPOS(1)) stays a syntax error, never a silent 0
            index = self.user_args()
            if not index:
                raise TrioError("Syntax error")
        axis = process = slot = None
        while self.at_name("AXIS", "PROC", "SLOT", "PORT"):
            modifier = self.advance().text
            self.expect_op("(")
            value = self.expression()
            self.expect_op(")")
            if modifier == "AXIS" and keyword.axis_modifier and axis is None:
                axis = value
            elif modifier == "PROC" and process is None:
                process = value
            elif modifier in ("SLOT", "PORT") and slot is None and \
                    keyword.note.startswith("Not modelled"):
                slot = value
            else:
                raise TrioError("Syntax error")
        return Param(keyword, axis, process, slot, index)

    def channel_statement(self, name: str) -> Channel:
        """OPEN #n AS "name" FOR mode, CLOSE #n, GET #n, v, INPUT [#n,] v[, v],
        LINPUT #n, v."""
        channel = None
        if self.at_op("#"):
            self.advance()
            channel = self.expression()
        if name == "OPEN":
            if channel is None or not self.at_name("AS"):
                raise TrioError("Syntax error")
            self.advance()
            file_name = self.expression()
            if not self.at_name("FOR"):
                raise TrioError("Syntax error")
            self.advance()
            if not self.at_name(*CHANNEL_MODES):
                raise TrioError("Syntax error")
            mode = self.advance().text
            options: tuple[Expr, ...] = ()
            if self.at_op("("):  # OUTPUT(mode), FIFO_WRITE(size[, mode[, end]]): OPEN's
                options = self.user_args()  # page; kept for the FIFOs (fifos.py)
            return Channel("OPEN", channel, file_name, mode, options=options)
        if name == "CLOSE":
            return Channel("CLOSE", channel)
        if channel is not None:
            self.expect_op(",")
        targets = [self.target()]
        while name == "INPUT" and self.at_op(","):
            self.advance()
            targets.append(self.target())
        return Channel(name, channel, targets=tuple(targets))

    def target(self) -> Expr:
        """Where GET/INPUT store: a variable, an array element or VR(i)."""
        tok = self.advance()
        if tok.kind is not Tok.NAME:
            raise TrioError("Syntax error")
        if tok.text == "VR" or lookup(tok.text) is None and self.at_op("("):
            args = self.user_args()
            if len(args) != 1 and tok.text == "VR":
                raise TrioError("Syntax error")
            return Call(tok.text, args)
        if lookup(tok.text) is not None:
            raise TrioError("Syntax error")
        return Var(tok.text)

    def label_name(self) -> str:
        tok = self.advance()
        if tok.kind is not Tok.NAME or lookup(tok.text) is not None:
            raise TrioError("Syntax error")
        return tok.text

    def block_or_statement(self, name: str) -> Stmt:
        if name == "PRINT":
            return self.print_rest()
        if name == "GOTO":
            return Goto(self.label_name())
        if name == "GOSUB":
            return Gosub(self.label_name())
        if name == "RETURN":
            return Return(None if self.at_statement_end() else self.expression())
        if name == "ELSEIF":
            condition = self.expression()
            if not self.at_name("THEN"):
                raise TrioError("Syntax error")
            self.advance()
            self.expect_end()
            return ElseIf(condition)
        if name == "SELECT_CASE":
            return SelectCase(self.expression())
        if name == "CASE":
            return self.case()
        if name == "END_CASE":
            return EndCase()
        if name in ("CONSTANT", "GLOBAL") and self.at_statement_end():
            return Declare(name, "", None)  # clears every CONSTANT / GLOBAL (their pages)
        if name == "DEFCONST":  # DEFCONST name value: a CONSTANT (I, public programs)
            tok = self.advance()
            if tok.kind is not Tok.NAME or lookup(tok.text) is not None:
                raise TrioError("Syntax error")
            if self.at_op("=", ","):
                self.advance()
            typed = self.source[tok.column:tok.column + len(tok.text)] or tok.text
            return Declare("CONSTANT", tok.text, self.expression(), typed)
        if name in ("CONSTANT", "GLOBAL"):
            tok = self.advance()
            if tok.kind is not Tok.STRING or lookup(tok.text) is not None or not tok.text:
                raise TrioError("Syntax error")
            if self.at_statement_end():  # CONSTANT "name": clears that one (its page)
                return Declare(name, tok.text.upper(), None)
            self.expect_op(",")
            return Declare(name, tok.text.upper(), self.expression(), tok.text)
        if name == "DIM":
            return self.dim()
        if name == "STATIC":  # STATIC name AS type ...: a DIM kept between calls (its page)
            return replace(self.dim(), static=True)
        if name == "FUNCTION":
            return self.function()
        if name == "ENDFUNC":
            return EndFunc()
        if name == "IF":
            self.nest()
            condition = self.expression()
            if not self.at_name("THEN"):
                raise TrioError("Syntax error")
            self.advance()
            if self.tok.kind is Tok.END:
                return IfBlock(condition)
            then = self.statements_until_else()
            otherwise: tuple[Stmt, ...] = ()
            if self.at_name("ELSE"):
                self.advance()
                otherwise = self.statements_until_else()
                if self.tok.kind is not Tok.END:
                    raise TrioError("Syntax error")
            return IfLine(condition, then, otherwise)
        if name == "ELSE":
            return Else()
        if name == "ENDIF":
            return EndIf()
        if name == "WHILE":
            return While(self.expression())
        if name == "WEND":
            return Wend()
        if name == "REPEAT":
            return Repeat()
        if name == "UNTIL":
            return Until(self.expression())
        if name == "FOR":
            return self.for_statement()
        if name == "NEXT":
            if self.tok.kind is Tok.NAME and lookup(self.tok.text) is None:
                return Next(self.advance().text)
            if self.at_name("VR"):  # NEXT VR(n): ends the FOR VR(n) loop
                self.advance()
                self.expect_op("(")
                self.expression()
                self.expect_op(")")
                return Next("VR")
            return Next(None)
        if name == "WAIT":
            if self.at_name("IDLE"):
                self.advance()
                return WaitIdle(self.axis_modifier())
            if self.at_name("UNTIL"):
                self.advance()
                return WaitUntil(self.expression())
            if self.at_name("LOADED"):
                self.advance()
                return WaitLoaded(self.axis_modifier())
            if self.at_name("IN_POS"):  # WAIT IN_POS [AXIS(n)]: WAIT UNTIL IN_POS (WAIT's page)
                keyword = lookup(self.advance().text)
                assert keyword is not None
                return WaitUntil(self.parameter(keyword))
        raise TrioError("Syntax error")

    def case(self) -> Case:
        if self.at_name("ELSE"):
            self.advance()
            return Case(())
        choices: list[tuple[Expr, Expr | None]] = []
        while True:
            low = self.expression()
            high = None
            if self.at_name("TO"):
                self.advance()
                high = self.expression()
            choices.append((low, high))
            if not self.at_op(","):
                return Case(tuple(choices))
            self.advance()

    def user_args(self) -> tuple[Expr, ...]:
        self.expect_op("(")
        args: list[Expr] = []
        if not self.at_op(")"):
            args.append(self.expression())
            while self.at_op(","):
                self.advance()
                args.append(self.expression())
        self.expect_op(")")
        return tuple(args)

    def skip_type(self) -> str:
        """``AS type`` of a FUNCTION or its parameter; ``AS type()`` passes an array.
        The type's name ("" when none is written)."""
        kind = ""
        if self.at_name("AS"):
            self.advance()
            if not self.at_name(*DIM_TYPES):
                raise TrioError("Syntax error")
            kind = self.advance().text
            if self.at_op("("):
                self.advance()
                if not self.at_op(")"):
                    self.advance()
                self.expect_op(")")
        return kind

    def function(self) -> FunctionDef:
        name = self.label_name()
        params: list[str] = []
        types: list[str] = []
        if self.at_op("("):
            self.advance()
            while not self.at_op(")"):
                params.append(self.label_name())
                types.append(self.skip_type())
                if not self.at_op(","):
                    break
                self.advance()
            self.expect_op(")")
        returns = self.skip_type()
        if len(set(params)) != len(params):
            raise TrioError("Syntax error")
        return FunctionDef(name, tuple(params), tuple(types), returns)

    def dimensions(self) -> tuple[Expr, ...]:
        """``(n[, m ...])``: an array's dimensions."""
        sizes = self.user_args()
        if not sizes:
            raise TrioError("Syntax error")
        return sizes

    def dim(self) -> Dim:
        names: list[str] = []
        sizes: tuple[Expr, ...] = ()
        while True:
            tok = self.advance()
            if tok.kind is not Tok.NAME or lookup(tok.text) is not None or tok.text in names:
                raise TrioError("Syntax error")
            names.append(tok.text)
            if self.at_op("("):
                if sizes:
                    raise TrioError("Syntax error")
                sizes = self.dimensions()
            if not self.at_op(","):
                break
            self.advance()
        kind, length = "FLOAT", 0
        if self.at_name("AS"):
            self.advance()
            if not self.at_name(*DIM_TYPES):
                raise TrioError("Syntax error")
            kind = self.advance().text
            if kind == "STRING" and not self.at_op("("):
                length = DEFAULT_STRING_LENGTH  # DIM s AS STRING (the CHR and HEX pages)
            elif kind == "STRING":  # STRING(length), STRING(size, length), ... (DIM's page)
                self.expect_op("(")
                fields = [self.expression()]
                while self.at_op(","):
                    self.advance()
                    fields.append(self.expression())
                self.expect_op(")")
                number = fields[-1]
                if not isinstance(number, Num) or not 0 < number.value <= MAX_STRING \
                        or number.value != int(number.value) or len(fields) > 1 and sizes:
                    raise TrioError("Syntax error")
                length = int(number.value)
                sizes = sizes or tuple(fields[:-1])
            if self.at_op("("):  # DIM a AS INTEGER(8): the size after the type
                if sizes:
                    raise TrioError("Syntax error")
                sizes = self.dimensions()
        value = None
        if self.at_op("="):
            self.advance()
            value = self.expression()
        return Dim(tuple(names), sizes, kind, length, value)

    def for_statement(self) -> For:
        tok = self.advance()
        vr = None
        if tok.kind is Tok.NAME and tok.text == "VR" and self.at_op("("):
            self.advance()
            vr = self.expression()
            self.expect_op(")")
        elif tok.kind is not Tok.NAME or lookup(tok.text) is not None:
            raise TrioError("Syntax error")
        self.expect_op("=")
        start = self.expression()
        if not self.at_name("TO"):
            raise TrioError("Syntax error")
        self.advance()
        end = self.expression()
        step = None
        if self.at_name("STEP"):
            self.advance()
            step = self.expression()
        return For(tok.text, start, end, step, vr)

    def print_rest(self) -> Print:
        items: list[tuple[Expr | Format, str]] = []
        newline = True
        channel = None
        if self.at_op("#"):
            self.advance()
            channel = self.expression()
            if not self.at_op(","):
                return Print((), True, channel)
            self.advance()
        while not self.at_statement_end():
            expr: Expr | Format = self.expression()
            if self.at_op("["):
                self.advance()
                assert not isinstance(expr, Format)
                if self.tok.kind is Tok.STRING:  # x["%12.2f"]: a C format (PRINT's page)
                    spec = self.advance().text
                    check_spec(spec)
                    self.expect_op("]")
                    expr = Format(expr, 0, 0, spec)
                else:
                    sign = -1 if self.at_op("-") else 1
                    if sign < 0:
                        self.advance()
                    first = self.advance()
                    if first.kind is not Tok.NUMBER:
                        raise TrioError("Syntax error")
                    width, decimals = 0, int(first.value)  # x[d]: d decimals (PRINT's page)
                    if first.value != int(first.value):  # x[5.1]: as [5, 1] (D: the
                        whole, _, part = first.text.partition(".")  # REGIST page writes it)
                        if not whole.isdigit() or not part.isdigit() or self.at_op(","):
                            raise TrioError("Syntax error")
                        width, decimals = sign * int(whole), int(part)
                        sign = 1
                    if self.at_op(","):
                        self.advance()
                        tok = self.advance()
                        if tok.kind is not Tok.NUMBER:
                            raise TrioError("Syntax error")
                        width, decimals = sign * int(first.value), int(tok.value)
                    elif sign < 0 and width == 0:
                        raise TrioError("Syntax error")
                    self.expect_op("]")
                    if not -127 <= width <= 127 or not 0 <= decimals <= 15:
                        raise TrioError("Syntax error")
                    expr = Format(expr, width, decimals)
            separator = ""
            if self.at_op(",", ";"):
                separator = self.advance().text
            items.append((expr, separator))
            if not separator:
                break
        if items and items[-1][1]:
            newline = False  # a trailing ',' or ';' keeps the line open
        return Print(tuple(items), newline, channel)

    def command(self, keyword: Keyword) -> Command:
        args: list[Expr] = []
        if keyword.name in ("COPY", "RENAME"):
            return Command(keyword, self.two_program_names(), None)
        if keyword.name in ("BREAK_ADD", "BREAK_DELETE") and self.tok.kind is Tok.STRING:
            args.append(Str(self.advance().text))  # BREAK_ADD "prog" 8: the page's form,
            if self.at_op(","):  # no comma (a comma taken too, D)
                self.advance()
            if not self.at_statement_end():
                args.append(self.expression())
            return Command(keyword, tuple(args), None)
        if keyword.name == "SEEK" and self.at_op("#"):  # SEEK #n, from, position
            self.advance()
        if keyword.string_arg and self.bare_program_name():
            args.append(Str(self.advance().text))  # SELECT MC_CONFIG: a name unquoted
            while self.at_op(","):
                self.advance()
                args.append(self.expression())
        elif self.at_op("("):
            self.advance()
            if keyword.name in _CHANNEL_FIRST and self.at_op("#"):
                self.advance()
            if not self.at_op(")"):
                args.append(self.expression())
                while self.at_op(","):
                    self.advance()
                    args.append(self.expression())
            self.expect_op(")")
        elif not self.at_statement_end() and not self.at_name("AXIS"):
            args.append(self.expression())
            while self.at_op(","):
                self.advance()
                args.append(self.expression())
        axis = self.axis_modifier() if keyword.axis_modifier else None
        low, high = keyword.args if keyword.kind is Kind.COMMAND else (1, 1)
        if not low <= len(args) <= high:
            raise TrioError("Syntax error")
        return Command(keyword, tuple(args), axis)

    def file_args(self) -> tuple[Expr, ...]:
        """FILE's function name and its parameters, commas between them optional (the
        page writes both FILE "CRC16" "file" and FILE "FIND_NEXT", vr_index). The first
        parameter may also be a variable's expression with no comma (the STICK_WRITEVR
        page: FILE "TYPE" name + ".CSV"); a keyword there (THEN, AND ...) ends FILE."""
        if self.tok.kind is not Tok.STRING:
            raise TrioError("Syntax error")
        args: list[Expr] = [Str(self.advance().text)]
        if self.tok.kind is Tok.NAME and lookup(self.tok.text) is None:
            args.append(self.expression())
        while self.at_op(",") or self.tok.kind is Tok.STRING:
            if self.at_op(","):
                self.advance()
            args.append(self.expression())
        return tuple(args)

    def two_program_names(self) -> tuple[Expr, ...]:
        """COPY "a" "b" and RENAME a b: two program names, each quoted or bare, a space
        or a comma between (their help pages write both without a comma)."""
        names: list[Expr] = []
        while len(names) < 2 and self.tok.kind in (Tok.STRING, Tok.NAME):
            names.append(Str(self.advance().text))
            if len(names) == 1 and self.at_op(","):
                self.advance()
        if len(names) != 2:
            raise TrioError("Syntax error")
        return tuple(names)

    def bare_program_name(self) -> bool:
        """A program named without quotes, as a command line takes it (``SELECT
        MC_CONFIG``, a vendor uploader's form; I): a name that is no keyword, alone or
        before a comma. A variable holding a number is never a program, so nothing that
        parsed before changes meaning."""
        tok = self.tok
        if tok.kind is not Tok.NAME:
            return False
        after = self.tokens[self.pos + 1]
        return lookup(tok.text) is None and (
            after.kind is Tok.END or after.kind is Tok.OP and after.text in (",", ":"))

    def axis_modifier(self) -> Expr | None:
        if not self.at_name("AXIS"):
            return None
        self.advance()
        self.expect_op("(")
        axis = self.expression()
        self.expect_op(")")
        return axis

    # ---- expressions ---------------------------------------------------------------------
    def expression(self) -> Expr:
        self.nest()
        left = self.and_expr()
        while self.at_name("OR", "XOR"):
            op = self.advance().text
            left = self.binary(op, left, self.and_expr())
        self.depth -= 1
        return left

    def and_expr(self) -> Expr:
        left = self.not_expr()
        while self.at_name("AND"):
            self.advance()
            left = self.binary("AND", left, self.not_expr())
        return left

    def not_expr(self) -> Expr:
        if self.at_name("NOT"):
            self.advance()
            self.nest()
            operand = self.not_expr()
            self.depth -= 1
            return Unary("NOT", operand)
        return self.comparison()

    def comparison(self) -> Expr:
        left = self.shift()
        while self.at_op("=", "<>", "<", ">", "<=", ">="):
            op = self.advance().text
            left = self.binary(op, left, self.shift())
        return left

    def shift(self) -> Expr:
        """``<<`` and ``>>`` on the integer parts, between comparisons and + - (D: as C
        orders them; the programs seen always bracket them)."""
        left = self.additive()
        while self.at_op("<<", ">>"):
            op = self.advance().text
            left = self.binary(op, left, self.additive())
        return left

    def additive(self) -> Expr:
        left = self.term()
        while self.at_op("+", "-"):
            op = self.advance().text
            left = self.binary(op, left, self.term())
        return left

    def term(self) -> Expr:
        left = self.unary()
        while self.at_op("*", "/") or self.at_name("MOD", "FMOD"):
            op = self.advance().text
            left = self.binary(op, left, self.unary())
        return left

    def unary(self) -> Expr:
        if self.at_op("-", "+"):
            op = self.advance().text
            self.nest()
            operand = self.unary()
            self.depth -= 1
            return Unary("-", operand) if op == "-" else operand
        return self.power()

    def power(self) -> Expr:
        left = self.primary()
        while self.at_op("^"):
            self.advance()
            left = self.binary("^", left, self.unary_primary())
        return left

    def unary_primary(self) -> Expr:
        if self.at_op("-"):
            self.advance()
            return Unary("-", self.primary())
        return self.primary()

    def primary(self) -> Expr:
        literal = self.tok.kind is Tok.NUMBER
        expr = self.operand()
        if isinstance(expr, Var) and self.at_op(".") and \
                self.tokens[self.pos + 1].text in ("DIMS", "DIMSIZE"):
            self.advance()  # the field operator: name.dims, name.dimsize(n)
            field = self.advance().text
            index = None
            if self.at_op("("):
                self.advance()
                index = self.expression()
                self.expect_op(")")
            return Field(expr.name, field, index)
        bit = self.bit_number()
        if bit is not None and literal:  # 1.2.3: a mistyped number or address (D)
            raise TrioError("Syntax error")
        if bit is not None:  # value.n: bit n of a variable, element, bracket or parameter
            if isinstance(expr, Param) and expr.axis is None and \
                    expr.keyword.axis_modifier and self.at_name("AXIS"):
                expr = Param(expr.keyword, self.axis_modifier(), expr.process, expr.slot,
                             expr.index)  # x.n AXIS(a)
            return Bit(expr, bit)
        return expr

    def operand(self) -> Expr:
        tok = self.advance()
        if tok.kind is Tok.NUMBER:
            place = self.pos
            value = self.dotted_address(tok)
            if self.pos == place and decimal_literal(tok.text):
                return Num(Real(value))  # 2.0 is a FLOAT (printformat.Real)
            return Num(value)
        if tok.kind is Tok.STRING:
            return Str(tok.text)
        if tok.kind is Tok.OP and tok.text == "(":
            expr = self.expression()
            self.expect_op(")")
            return expr
        if tok.kind is not Tok.NAME:
            raise TrioError("Syntax error")
        keyword = lookup(tok.text)
        if keyword is None:
            if self.at_op("("):  # an element of a DIM array, or a FUNCTION's value
                return Call(tok.text, self.user_args())
            return Var(tok.text)
        if keyword.kind is Kind.CONSTANT:
            return Num(keyword.default)
        if keyword.kind in (Kind.AXIS_PARAMETER, Kind.SYSTEM_PARAMETER):
            return self.parameter(keyword)
        if tok.text in _BARE_READS and not self.at_op("("):  # OP alone: outputs 0..31
            return Call(tok.text, ())
        if tok.text == "FILE" and self.tok.kind is Tok.STRING:  # value = FILE "DETECT"
            return Call("FILE", self.file_args())
        if tok.text == "OPEN" and self.at_op("#"):  # value = OPEN #n AS ... FOR ...
            return Opened(self.channel_statement("OPEN"))
        if tok.text in ("KEY", "IS_OPEN") and self.at_op("#"):  # KEY #n, IS_OPEN #n
            self.advance()
            return Call(tok.text, (self.unary(),))
        if keyword.kind is Kind.FUNCTION or tok.text in _EXPRESSION_COMMANDS or (
                keyword.kind is Kind.COMMAND and self.at_op("(")):
            return Call(tok.text, self.call_args(keyword))
        raise TrioError("Syntax error")

    def dotted_address(self, tok: Token) -> float:
        """``192.168.0.250``: four dotted fields written together are one network
        address, the 32-bit number a*2^24 + b*2^16 + c*2^8 + d (D: the manual sets
        IP_ADDRESS this way; the number it stands for is ours). Anything else is the
        number itself."""
        first = tok.text.split(".")
        rest = self.tokens[self.pos:self.pos + 2]
        if len(first) != 2 or not all(f.isdigit() for f in first) or len(rest) < 2 or \
                not all(t.kind is Tok.NUMBER and t.text[:1] == "." and t.text[1:].isdigit()
                        for t in rest) or \
                rest[0].column != tok.column + len(tok.text) or \
                rest[1].column != rest[0].column + len(rest[0].text):
            return tok.value
        self.advance()
        self.advance()
        fields = [int(f) for f in first] + [int(t.text[1:]) for t in rest]
        if any(f > 255 for f in fields):
            raise TrioError("Parameter out of range")
        return float((fields[0] << 24) | (fields[1] << 16) | (fields[2] << 8) | fields[3])

    def bit_number(self) -> int | Var | None:
        """The ``.n`` or ``.name`` after a value (the bit operator), or None."""
        tok = self.tok
        if tok.kind is Tok.OP and tok.text == ".":
            self.advance()
            name = self.advance()
            if name.kind is not Tok.NAME or lookup(name.text) is not None:
                raise TrioError("Syntax error")
            return Var(name.text)
        if tok.kind is not Tok.NUMBER or tok.text[:1] != "." or not tok.text[1:].isdigit():
            return None
        self.advance()
        bit = int(tok.text[1:])
        if bit > 52:
            raise TrioError("Parameter out of range")
        return bit

    def bit_target(self, target: _Target) -> _Target | Bit:
        """``x.n`` on the left of ``=``: bit n of a variable, element, VR or parameter
        (``options.4 = ON``, ``CORNER_MODE.1 AXIS(2) = ON``)."""
        bit = self.bit_number()
        if bit is None:
            return target
        if isinstance(target, Param) and target.axis is None and \
                target.keyword.axis_modifier and self.at_name("AXIS"):
            return Bit(Param(target.keyword, self.axis_modifier(), target.process,
                             target.slot, target.index), bit)
        return Bit(target, bit)

    def call_args(self, keyword: Keyword) -> tuple[Expr, ...]:
        if keyword.string_arg and self.tok.kind is Tok.STRING:
            nxt = self.tokens[self.pos + 1]
            if nxt.kind is Tok.OP and nxt.text == "+":  # IS_PROG "SD:" + name (its page)
                return (self.additive(),)
            return (Str(self.advance().text),)
        if keyword.name in ("IS_FILE", "IS_PROG") and self.tok.kind is Tok.NAME:
            return (self.additive(),)  # IS_FILE name$: a string variable (IS_FILE's page)
        if not self.at_op("("):
            if keyword.name == "BASE" or keyword.args[0] == 0:
                return ()  # DATE$, KEY, BASE: a function of no arguments
            raise TrioError("Syntax error")
        self.advance()
        args: list[Expr] = []
        if keyword.name in _CHANNEL_FIRST and self.at_op("#"):
            self.advance()  # CHANNEL_WRITE(#25, ...): the channel may carry its #
        if not self.at_op(")"):
            args.append(self.expression())
            while self.at_op(","):
                self.advance()
                args.append(self.expression())
        self.expect_op(")")
        return tuple(args)

"""Issue 34: the MC405 has one memory for its programs' DIMmed variables, arrays and
strings (interpreter.PROGRAM_MEMORY, 8 MiB: a number 8 bytes, a STRING(n) element n),
shared by every process, FUNCTION call and command line; a DIM that would pass it is
"Not enough memory" and declares nothing. Run through the command line as atrio uploads
and runs programs (tests/trio_helpers.Rig)."""

from __future__ import annotations

import tracemalloc

from maxk.commands.trio.interpreter import ERROR_CODES, PROGRAM_MEMORY
from tests.trio_helpers import Rig

MIB = 1024 * 1024
ERROR = "Not enough memory"


def _ran(rig: Rig, name: str, text: str, cycles: int = 20) -> str:
    rig.load(name, text)
    rig.command(f'RUN "{name}"')
    return rig.cycles(cycles).decode()


def _in_use(rig: Rig) -> int:
    return rig.session.system.memory_in_use(rig.session.context)


def test_the_budget_is_8_mib() -> None:
    assert PROGRAM_MEMORY == 8 * MIB == 4096 * 1024 * 2


def test_the_issues_load_is_refused_at_its_dim_and_holds_nothing() -> None:
    """Three programs each asking for 4 x 65,536 STRING(1024) (256 MiB apiece)."""
    rig = Rig()
    for n in range(3):
        rig.load(f"HOG{n}", "DIM a, b, c, d(65536) AS STRING(1024)\nPRINT \"got it\"\n")
    for n in range(3):
        rig.command(f'RUN "HOG{n}"')
    out = rig.cycles(10).decode()
    assert out.count(f"Line 1] - {ERROR}") == 3 and "got it" not in out
    assert _in_use(rig) == 0
    # on the command line too, and nothing is declared by the refused DIM
    reply = rig.send("DIM big(65536) AS STRING(1024)").decode()
    assert f"%[COMMAND LINE] - {ERROR}" in reply
    assert "Variable not defined" in rig.send("?big(0)").decode()


def test_processes_share_the_budget_to_the_byte_and_free_it_when_they_end() -> None:
    rig = Rig()
    half = "DIM a(4096) AS STRING(1024)\n"  # 4 MiB: two of them are the whole budget
    assert _ran(rig, "A", half + "WA(1000)\n") == ""
    assert _ran(rig, "B", half + "WA(1000)\n") == ""
    assert _in_use(rig) == PROGRAM_MEMORY
    assert f"Line 1] - {ERROR}" in _ran(rig, "C", "DIM x AS INTEGER\nPRINT 1\n")
    assert f"%[COMMAND LINE] - {ERROR}" in rig.send("DIM y AS BOOLEAN").decode()
    rig.command('STOP "A"')  # A's 4 MiB come back
    assert _in_use(rig) == 4 * MIB
    assert _ran(rig, "C", half + "PRINT \"fits\"\n") == "fits\r\n"


def test_a_dim_again_replaces_and_a_function_call_frees_on_return() -> None:
    rig = Rig()
    out = _ran(rig, "P", """FOR k = 1 TO 5
  DIM a(6144) AS STRING(1024)
  PRINT grab()
NEXT k
PRINT "again"
FUNCTION grab()
  DIM t(1024) AS STRING(1024)
  RETURN LEN(t(0))
ENDFUNC""", 40)
    assert out == "0\r\n" * 5 + "again\r\n"  # 6 MiB + 1 MiB, five times over
    assert _in_use(rig) == 0  # the program ended


def test_recursion_runs_into_the_budget() -> None:
    out = _ran(Rig(), "P", """PRINT deep(1)
FUNCTION deep(n)
  DIM t(3072) AS STRING(1024)
  IF n = 3 THEN RETURN n
  RETURN deep(n + 1)
ENDFUNC""")
    assert out == f"%[Process 19:Program P Line 1] - {ERROR}\r\n"  # 3 x 3 MiB > 8 MiB


def test_on_basicerror_catches_it_with_its_own_code() -> None:
    out = _ran(Rig(), "P", """ON BASICERROR GOTO caught
DIM a(65536) AS STRING(1024)
PRINT "no"
caught:
PRINT RUN_ERROR; " "; ERROR_LINE""")
    assert out == f"{ERROR_CODES[ERROR]} 2\r\n"


def test_a_closed_command_line_gives_its_memory_back() -> None:
    rig = Rig()
    assert "%[COMMAND" not in rig.send("DIM held(6144) AS STRING(1024)").decode()
    assert _in_use(rig) == 6 * MIB
    assert f"Line 1] - {ERROR}" in _ran(rig, "P", "DIM a(4096) AS STRING(1024)\n")
    rig.session.close()
    assert rig.session.system.memory_in_use(rig.session.context) == 6 * MIB  # its own
    assert rig.session.system.command_lines == []


def test_programs_filling_the_budget_with_distinct_strings_stay_near_it() -> None:
    """The budget bounds what Python holds: two programs filling 4,000 elements each with
    distinct 1 KiB strings (7.8 MiB of the 8) keep the interpreter's traced memory under
    twice the budget."""
    fill = """DIM seed AS STRING(1024)
DIM a(4000) AS STRING(1024)
seed = "x"
FOR k = 1 TO 10
  seed = seed + seed
NEXT k
FOR i = 0 TO 3999
  a(i) = LEFT(seed, 1016) + STR(i, 0)
NEXT i
PRINT "filled "; LEN(a(3999))
WA(100000)"""
    rig = Rig()
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        rig.load("F1", fill)
        rig.load("F2", fill)
        rig.command('RUN "F1"')
        rig.command('RUN "F2"')
        out = rig.cycles(4100).decode()  # a FOR pass a servo cycle
        held, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert out == "filled 1020\r\nfilled 1020\r\n"
    assert _in_use(rig) == 2 * (4000 * 1024 + 1024)
    assert held - before > 8_000_000  # the strings are really there
    assert peak - before < 2 * PROGRAM_MEMORY


def test_variables_not_dimmed_hold_their_strings_length() -> None:
    rig = Rig()
    assert _ran(rig, "A", "DIM a(8191) AS STRING(1024)\nWA(1000)\n") == ""
    assert PROGRAM_MEMORY - _in_use(rig) == 1024  # one STRING(1024) element left
    assert "%[COMMAND" not in rig.send('s = "x"').decode()
    for _ in range(10):
        assert "%[COMMAND" not in rig.send("s = s + s").decode()
    assert rig.send("?LEN(s)").decode().split("\r\n")[1] == "1024"
    assert _in_use(rig) == PROGRAM_MEMORY  # to the byte
    assert f"%[COMMAND LINE] - {ERROR}" in rig.send("t = 1").decode()
    assert "t" not in rig.session.context.variables  # nothing changed
    assert "%[COMMAND" not in rig.send('s = ""').decode()  # gives its 1024 back
    assert "%[COMMAND" not in rig.send("t = 1").decode()
    assert _in_use(rig) == PROGRAM_MEMORY - 1024 + 8

"""TRON, TROFF, STEPLINE, STEPINTO and SETLINE: a program paused and stepped line by line,
from what their help pages' examples show (the Paused line with the text of the line
stepped to, the Released line, PROC_STATUS's paused and stepping states)."""

from __future__ import annotations

from maxk.controllers.trio import MC405
from tests.trio_helpers import Rig

# Lines 1 and 2 hold no statement: the first executable line is 3 (as the TRON page's
# example 2 pauses STARTUP at line 3).
_STARTUP = "' set up the table\n\nTABLE(0, 5)\nTABLE(10, 6)\nTABLE(20, 7)\nVR(3) = 99"


def _paused(line: int, text: str, process: int = 19) -> list[str]:
    return [f"%[Process {process}:Line {line}] - Paused", text]


def test_tron_on_the_selected_program_starts_it_paused_at_its_first_executable_line() -> None:
    trio = MC405()
    trio.load("STARTUP", _STARTUP)
    assert trio.send('SELECT "STARTUP"') == []
    assert trio.send("TRON") == []
    trio.advance(ticks=1)
    assert trio.send("?PROC_STATUS PROC(19)") == [*_paused(3, "TABLE(0, 5)"), "3"]
    trio.advance(ticks=500)  # paused: nothing runs however long it waits
    assert trio.send("?TABLE(0)") == ["0.0000"]
    assert trio.send("STEPLINE") == []
    trio.advance(ticks=1)
    assert trio.send("?TABLE(0), TABLE(10)") == [*_paused(4, "TABLE(10, 6)"),
                                                 "5.0000\t0.0000"]
    assert trio.send("?PROC_LINE PROC(19)") == ["4"]
    assert trio.send("STEPLINE") == []
    trio.advance(ticks=1)
    assert trio.send("?TABLE(10), TABLE(20)") == [*_paused(5, "TABLE(20, 7)"),
                                                  "6.0000\t0.0000"]
    assert trio.send("PROCESS") == ["Process 19:Program STARTUP - Paused"]
    assert trio.send("TROFF") == ["%[Process 19:Program STARTUP] - Released"]
    trio.advance(ticks=2)  # released: the rest runs at full speed and the program ends
    assert trio.send("?TABLE(20), VR(3), PROC_STATUS PROC(19)") == ["7.0000\t99.0000\t0"]


def test_tron_in_a_program_lets_another_program_step_it_through_its_moves() -> None:
    """The TRON page's example 1: the moves between TRON and TROFF run one STEPLINE at a
    time; after TROFF the rest run on their own."""
    moves = ("BASE(0, 1)\nSPEED = 100\nACCEL = 1000000\nDECEL = 1000000\nTRON\n"
             "MOVE(0, 10)\nMOVE(10, 0)\nTROFF\nMOVE(0, -10)\nMOVE(-10, 0)")
    trio = MC405()
    trio.load("SQUARE", moves)
    trio.load("STEPPER", 'FOR i = 1 TO 3\n  WA(200)\n  STEPLINE "SQUARE"\nNEXT i')
    assert trio.send('RUN "SQUARE", 3') == []
    trio.advance(ticks=5)  # lines 1..5 run, then it stands before MOVE(0, 10)
    assert trio.send("?PROC_STATUS PROC(3)") == [*_paused(6, "MOVE(0, 10)", 3), "3"]
    trio.advance(ticks=1000)
    assert trio.send("?DPOS AXIS(0), DPOS AXIS(1)") == ["0\t0"]  # no move while paused
    assert trio.send('RUN "STEPPER", 4') == []
    t0 = trio.tick
    trio.advance(ticks=150)  # before the first STEPLINE (WA(200)): still nothing
    assert trio.send("?DPOS AXIS(1)") == ["0"]
    trio.advance(ticks=t0 + 1200 - trio.tick)
    # MOVE(0, 10) at 100 units/s (0.1 s) stepped at about 200 ms, MOVE(10, 0) at about
    # 400 ms: both ended by 1.2 s; TROFF was stepped third (600 ms) and released it, so
    # the last two moves ran too and the square is closed
    out = trio.send("?DPOS AXIS(0), DPOS AXIS(1), PROC_STATUS PROC(3)")
    assert out[:4] == [*_paused(7, "MOVE(10, 0)", 3), *_paused(8, "TROFF", 3)]
    assert out[4:] == ["%[Process 3:Program SQUARE] - Released", "0\t0\t0"]


def test_each_step_moves_exactly_one_line_and_the_axis_waits_between() -> None:
    """Stepped at 300 ms, the MOVE(0, 10) line loads on the next servo cycle (D), while
    the next line waits paused."""
    trio = MC405()
    trio.load("P", "BASE(0, 1)\nSPEED = 100\nACCEL = 1000000\nDECEL = 1000000\nTRON\n"
              "MOVE(0, 10)\nMOVE(10, 0)")
    trio.send('RUN "P", 2')
    trio.advance(ticks=300)
    trio.send("?0")  # (the pause line)
    assert trio.send('STEPLINE "P"') == []
    trio.advance(ticks=51)
    # 100 units/s reached in 0.1 ms (ACCEL 1e6): 0.005 units short of full speed from
    # the start; 50 ms after the move loads (one cycle after STEPLINE): 5 - 0.005
    assert trio.send("?DPOS AXIS(0), DPOS AXIS(1)") == [*_paused(7, "MOVE(10, 0)", 2),
                                                        "0\t4.9950"]
    trio.advance(ticks=1000)  # MOVE(10, 0) never loads while it stands paused
    assert trio.send("?DPOS AXIS(0), DPOS AXIS(1)") == ["0\t10"]


_ROUTINE = "a = 1\nGOSUB sub\nb = 2\nSTOP\nsub:\nc = 3\nd = 4\nRETURN"


def _walk(word: str, steps: int) -> list[str]:
    trio = MC405()
    trio.load("R", _ROUTINE)
    seen = []
    for _ in range(steps):
        assert trio.send(f'{word} "R", 6') == []
        trio.advance(ticks=2)
        out = trio.send("?0")
        seen += [line.split("Line ")[1].split("]")[0] for line in out if "Paused" in line]
    return seen


def test_stepline_steps_over_a_gosub_routine() -> None:
    # the first STEPLINE starts R paused at line 1 (on process 6, as named)
    assert _walk("STEPLINE", 4) == ["1", "2", "3", "4"]


def test_stepinto_steps_into_the_routine_but_not_onto_its_label() -> None:
    assert _walk("STEPINTO", 7) == ["1", "2", "6", "7", "8", "3", "4"]


def test_tron_by_name_pauses_a_running_program_after_its_waiting_statement() -> None:
    """The TRON page's example 3: TRON "TEST" of a program that runs; its WA ends first,
    then it stands before the next statement (D)."""
    trio = MC405()
    trio.load("TEST", "n = 0\nWHILE TRUE\n  n = n + 1\n  VR(1) = n\n  WA(4)\nWEND")
    trio.send('RUN "TEST", 7')
    trio.advance(ticks=10)
    assert trio.send('TRON "TEST"') == []
    trio.advance(ticks=5)
    out = trio.send("?VR(1), PROC_STATUS PROC(7)")
    assert out[:2] == _paused(6, "WEND", 7)
    count = float(out[2].split("\t")[0])
    trio.advance(ticks=100)  # paused: the count stands still
    assert trio.send("?VR(1)") == [f"{count:.4f}"]
    assert trio.send('TROFF "TEST"') == ["%[Process 7:Program TEST] - Released"]
    trio.advance(ticks=40)  # released: one more each 4 ms WA again
    assert 9 <= float(trio.query("?VR(1)")) - count <= 11
    assert trio.query("?PROC_STATUS PROC(7)") == "8"  # running, asleep in its WA(4)


def test_stepline_alone_in_a_program_pauses_it_there() -> None:
    trio = MC405()
    trio.load("P", "VR(1) = 1\nSTEPLINE\nVR(1) = 2")
    trio.send('RUN "P", 0')
    trio.advance(ticks=3)
    assert trio.send("?VR(1), PROC_STATUS PROC(0)") == [*_paused(3, "VR(1) = 2", 0),
                                                        "1.0000\t3"]


def test_stepping_state_while_the_stepped_line_waits() -> None:
    trio = MC405()
    trio.load("P", "TRON\nWA(100)\nVR(2) = 5")
    trio.send('RUN "P", 1')
    trio.advance(ticks=2)
    trio.send("?0")
    trio.send('STEPLINE "P"')
    trio.advance(ticks=50)  # in the stepped line's WA(100)
    assert trio.query("?PROC_STATUS PROC(1)") == "2"
    trio.advance(ticks=60)
    assert trio.send("?PROC_STATUS PROC(1), VR(2)") == [*_paused(3, "VR(2) = 5", 1),
                                                        "3\t0.0000"]


def test_setline_starts_a_program_paused_at_the_line_with_its_base() -> None:
    trio = MC405()
    trio.load("PICK", "VR(1) = 1\nVR(2) = 2\nVR(3) = BASE\nVR(4) = 4")
    assert trio.send('SETLINE "PICK", -1, 3, 2, 0') == []
    trio.advance(ticks=1)
    assert trio.send("?VR(1), VR(2)") == [*_paused(3, "VR(3) = BASE"), "0.0000\t0.0000"]
    trio.send('STEPLINE "PICK"')
    trio.advance(ticks=1)
    assert trio.send("?VR(3), VR(4)") == [*_paused(4, "VR(4) = 4"), "2.0000\t0.0000"]
    # a paused program's pointer moved back to line 1: it says where it stands now
    assert trio.send('SETLINE "PICK", 19, 1') == _paused(1, "VR(1) = 1")
    trio.send('TROFF "PICK"')
    trio.advance(ticks=3)
    assert trio.query("?VR(1) + VR(2) + VR(4)") == "7.0000"


def test_bad_trace_words_change_nothing() -> None:
    trio = MC405()
    trio.load("P", "VR(1) = 1\n\nVR(2) = 2")
    assert trio.send('TRON "NOPE"') == ["! Program not found"]
    assert trio.send("STEPLINE 5") == ["! Syntax error"]
    assert trio.send('SETLINE "P", -1, 2') == ["! Parameter out of range"]  # no statement
    assert trio.send('SETLINE "P", -1, 2.5') == ["! Parameter out of range"]
    assert trio.send("PROCESS") == []  # nothing was started
    trio.send('RUN "P", 5')
    assert trio.send('STEPLINE "P", 6') == ["! Program is running"]


def test_halt_ends_a_paused_program() -> None:
    trio = MC405()
    trio.load("P", "TRON\nVR(1) = 1")
    trio.send('RUN "P", 5')
    trio.advance(ticks=2)
    assert trio.send("?PROC_STATUS PROC(5)") == [*_paused(2, "VR(1) = 1", 5), "3"]
    trio.send("HALT")
    assert trio.send("?PROC_STATUS PROC(5), VR(1)") == ["0\t0.0000"]
    assert trio.run_until_idle(1.0)


def test_the_rig_steps_on_its_servo_cycles_too() -> None:
    """The same pause on the command line's own servo cycles (no engine scheduler)."""
    rig = Rig()
    rig.load("STARTUP", _STARTUP)
    rig.command('SELECT "STARTUP"')
    rig.command("TRON")
    assert rig.cycles(3) == b"%[Process 19:Line 3] - Paused\r\nTABLE(0, 5)\r\n"
    rig.command("STEPLINE")
    assert rig.cycles(3) == b"%[Process 19:Line 4] - Paused\r\nTABLE(10, 6)\r\n"
    assert rig.machine.table_read(0) == 5.0


# ---- breakpoints: BREAK_ADD, BREAK_DELETE, BREAK_LIST, BREAK_RESET -----------------------

_LOOP = ("VR(1) = 0\n' count to three\nWHILE VR(1) < 3\n  VR(1) = VR(1) + 1\n\n"
         "  VR(2) = VR(1) * 10\nWEND\nVR(3) = 7")


def test_break_list_shows_each_breakpoint_and_empty_lines_move_to_the_next_code() -> None:
    """BREAK_ADD's page: a breakpoint on a line with no code goes to the next line with
    code (line 5 is empty: line 6; line 2 a comment: line 3); BREAK_LIST's page's form."""
    trio = MC405()
    trio.load("SIMPLETEST", _LOOP)
    assert trio.send('BREAK_ADD "simpletest" 5') == []
    assert trio.send('BREAK_ADD "simpletest", 2') == []
    assert trio.send('BREAK_LIST "simpletest"') == [
        "Program: SIMPLETEST", "Line 3: WHILE VR(1) < 3", "Line 6: VR(2) = VR(1) * 10"]
    assert trio.send('BREAK_ADD "simpletest" 9') == ["! Parameter out of range"]  # past it
    assert trio.send('BREAK_ADD "nothere" 1') == ["! Program not found"]
    assert trio.send('BREAK_DELETE "simpletest" 5') == []  # resolves to line 6 too
    assert trio.send('BREAK_LIST "simpletest"') == ["Program: SIMPLETEST",
                                                    "Line 3: WHILE VR(1) < 3"]
    assert trio.send('BREAK_RESET "simpletest"') == []
    assert trio.send('BREAK_LIST "simpletest"') == ["Program: SIMPLETEST"]


def test_a_running_program_pauses_at_its_breakpoint_each_pass() -> None:
    trio = MC405()
    trio.load("SIMPLETEST", _LOOP)
    trio.send('BREAK_ADD "simpletest" 6')
    trio.send('RUN "simpletest", 3')
    trio.advance(ticks=5)
    # first pass: VR(1) counted to 1, VR(2) not yet written
    assert trio.send("?VR(1), VR(2)") == [*_paused(6, "VR(2) = VR(1) * 10", 3),
                                          "1.0000\t0.0000"]
    assert trio.send('TROFF "simpletest"') == ["%[Process 3:Program SIMPLETEST] - Released"]
    trio.advance(ticks=5)  # released: on through WEND, the next pass stops there again
    assert trio.send("?VR(1), VR(2)") == [*_paused(6, "VR(2) = VR(1) * 10", 3),
                                          "2.0000\t10.0000"]
    trio.send('STEPLINE "simpletest"')  # one line from the breakpoint
    trio.advance(ticks=5)
    assert trio.send("?VR(2)") == [*_paused(7, "WEND", 3), "20.0000"]
    trio.send('BREAK_DELETE "simpletest" 6')
    trio.send('TROFF "simpletest"')
    trio.advance(ticks=20)  # no breakpoint left: it runs to its end
    assert trio.send("?VR(1), VR(2), VR(3), PROC_STATUS PROC(3)") == [
        "3.0000\t30.0000\t7.0000\t0"]


def test_a_breakpoint_added_while_the_program_runs_stops_it() -> None:
    trio = MC405()
    trio.load("P", "WHILE TRUE\n  VR(1) = VR(1) + 1\n  WA(10)\nWEND")
    trio.send('RUN "P", 2')
    trio.advance(ticks=50)
    assert trio.send('BREAK_ADD "P" 2') == []
    trio.advance(ticks=20)
    out = trio.send("?VR(1)")
    assert out[:2] == _paused(2, "VR(1) = VR(1) + 1", 2)
    trio.advance(ticks=100)
    assert trio.send("?VR(1)") == out[2:]  # it stands


def test_run_of_a_paused_program_releases_it() -> None:
    trio = MC405()
    trio.load("P", "TRON\nVR(1) = 1\nVR(2) = 2")
    trio.send('RUN "P", 4')
    trio.advance(ticks=2)
    assert trio.send("?PROC_STATUS PROC(4)") == [*_paused(2, "VR(1) = 1", 4), "3"]
    assert trio.send('RUN "P"') == ["%[Process 4:Program P] - Released"]
    trio.advance(ticks=2)
    assert trio.send("?VR(1) + VR(2), PROC_STATUS PROC(4)") == ["3.0000\t0"]
    trio.send('RUN "P", 4')  # not under trace: a fresh run, paused again by its TRON
    trio.advance(ticks=2)
    assert trio.send("?PROC_STATUS PROC(4)") == [*_paused(2, "VR(1) = 1", 4), "3"]

"""Review 5b: hostile input on the merged debug, system, error and language words of the
MC405 (issue 35), each a reproducer of a defect found by attacking them."""

from __future__ import annotations

from maxk.controllers.trio import MC405

POWER_UP_ADDRESS = str((192 << 24) | (168 << 16) | (0 << 8) | 250)


def test_a_three_field_address_is_a_syntax_error_not_zero() -> None:
    """``IP_ADDRESS = 1.2.3`` (a mistyped address) was taken as bit 3 of 1.2, i.e. 0, and
    silently set the address to 0.0.0.0."""
    trio = MC405()
    assert trio.query("?IP_ADDRESS") == POWER_UP_ADDRESS
    assert trio.send("IP_ADDRESS = 1.2.3") == ["! Syntax error"]
    assert trio.send("IP_ADDRESS = 10.1.2.3.4") == ["! Syntax error"]
    assert trio.query("?IP_ADDRESS") == POWER_UP_ADDRESS  # nothing applied
    assert trio.send("IP_ADDRESS = 10.1.2.3") == []
    assert trio.query("?IP_ADDRESS") == str((10 << 24) | (1 << 16) | (2 << 8) | 3)


def test_a_bit_of_a_variable_still_reads() -> None:
    trio = MC405()
    trio.send("a = 6")
    assert trio.query("?a.1") == "1"
    assert trio.query("?a.0") == "0"
    assert trio.query("?(a).2") == "1"


def test_ethernet_refuses_a_function_the_page_does_not_list() -> None:
    """ETHERNET's function table is 0-15 and 21-25; 999 (or 17, or -4) was accepted and
    did nothing."""
    trio = MC405()
    for function in (999, 17, 26, -4):
        assert trio.send(f"ETHERNET(0, -1, {function})") == ["! Parameter out of range"]
        assert trio.send(f"ETHERNET(1, -1, {function}, 1)") == ["! Parameter out of range"]
    assert trio.send("ETHERNET(0, -1, 4)") == ["23"]  # a listed one still answers
    assert trio.send("ETHERNET(2, -1, 25)") == []  # restart services: accepted


def _fifo_text(trio: MC405, channel: int = 41) -> str:
    text = []
    for _ in range(4096):  # (bounded: more than any FIFO here holds)
        if trio.query(f"?KEY #{channel}") == "0":
            break
        trio.send(f"GET #{channel}, c")
        text.append(chr(int(float(trio.query("?c")))))
    return "".join(text)


def test_one_print_longer_than_a_non_blocking_fifo_keeps_its_newest_characters() -> None:
    """A PRINT now goes into an overwriting FIFO in one insertion (a character at a time
    took 10 s of CPU for 380 KB into a 1 MiB FIFO, quadratic); what stays is as before:
    300 characters and CR LF into 256 keep the last 256."""
    trio = MC405()
    trio.send('OPEN #42 AS "ring" FOR FIFO_WRITE(256, 2)')
    text = "".join(chr(65 + k % 26) for k in range(300))
    trio.send(f'PRINT #42, "{text}"')
    trio.send('OPEN #41 AS "ring" FOR FIFO_READ')
    assert _fifo_text(trio) == (text + "\r\n")[-256:]


def test_line_mode_drops_lines_of_the_print_going_in_when_no_old_line_is_left() -> None:
    """Mode 3, LF the terminator: one 102-character line in, then 300 'b' and CR LF in one
    PRINT. At 256 the old line goes (154 left); 102 more 'b' fill it again with no
    terminator in it, so the next one empties it; the last 44 'b' and CR LF stay."""
    trio = MC405()
    trio.send('OPEN #42 AS "lines" FOR FIFO_WRITE(256, 3, 10)')
    trio.send(f'PRINT #42, "{"a" * 100}"')
    trio.send(f'PRINT #42, "{"b" * 300}"')
    trio.send('OPEN #41 AS "lines" FOR FIFO_READ')
    assert _fifo_text(trio) == "b" * 44 + "\r\n"


def test_fifos_under_ever_new_names_stop_at_the_memory_budget() -> None:
    """A FIFO lives on after its channel closes, so a loop opening 1 MiB FIFOs under new
    names took the host's memory without end (each full one is megabytes). All FIFOs
    together hold at most 2 MiB: the third 1 MiB one is refused and not made."""
    trio = MC405()
    trio.load("MANY", "\n".join([
        "FOR i = 0 TO 9",
        '  OPEN #42 AS "f" + STR(i, 0) FOR FIFO_WRITE(1048576, 2)',
        "  CLOSE #42",
        "  VR(20) = i + 1",
        "NEXT i",
    ]))
    trio.send('RUN "MANY"')
    trio.advance(1.0)
    out = trio.send("?VR(20)")
    assert out == ["%[Process 19:Program MANY Line 2] - Not enough memory", "2.0000"]
    assert trio.send('OPEN #41 AS "f2" FOR FIFO_READ') == ["! Program not found"]
    assert trio.send('OPEN #41 AS "f1" FOR FIFO_READ') == []  # the two made are kept
    assert trio.send('OPEN #42 AS "f0" FOR FIFO_WRITE(256)') == []  # reopened: no more


def test_a_static_is_one_storage_for_a_recursive_function() -> None:
    """STATIC is 'like Visual Basic STATIC' (its page): one variable for every call. A
    call inside a call started from the value saved by the last finished call (0), so a
    depth counter read 1 after six nested calls; it reads 6, and a later call goes on
    from it."""
    trio = MC405()
    trio.load("DEEP", "\n".join([
        "VR(2) = depth(5)",
        "VR(3) = depth(0)",
        "STOP",
        "FUNCTION depth(k AS INTEGER) AS INTEGER",
        "  STATIC calls AS INTEGER",
        "  calls = calls + 1",
        "  IF k > 0 THEN",
        "    VR(10 + k) = depth(k - 1)",
        "    calls = calls + 100",
        "  ENDIF",
        "  RETURN calls",
        "ENDFUNC",
    ]))
    trio.send('RUN "DEEP"')
    trio.advance(1.0)
    # six calls count 1..6; the innermost returns 6; each of the five outer ones adds
    # 100 after its inner call returned: 106, 206, ... 506
    assert trio.query("?VR(10)") == "0.0000"  # (k = 0 stores nothing)
    assert [trio.query(f"?VR({10 + k})") for k in range(1, 6)] == [
        f"{6 + 100 * (k - 1)}.0000" for k in range(1, 6)]
    assert trio.query("?VR(2)") == "506.0000"
    assert trio.query("?VR(3)") == "507.0000"


def test_setline_refuses_a_base_that_is_no_axis_and_starts_nothing() -> None:
    """SETLINE "P", -1, 1, 99 started P with BASE 99: its MOVE raised an IndexError out of
    the servo cycle (the server logged it and went on; the program vanished without a
    controller error), and -5 made Python's negative index act on axis 11."""
    for base in (99, 16, -5):
        trio = MC405()
        trio.load("P", "MOVE(10)\nVR(1) = 1\n")
        assert trio.send(f'SETLINE "P", -1, 1, {base}') == ["! Invalid axis number"]
        assert trio.query("?PROC_STATUS PROC(19)") == "0"  # nothing started
        trio.advance(1.0)
        assert trio.query("?DPOS AXIS(11)") == "0"
    trio = MC405()
    trio.load("P", "MOVE(10)\nVR(1) = 1\n")
    assert trio.send('SETLINE "P", -1, 1, 0, 0, 7') == ["! Syntax error"]
    assert trio.send('SETLINE "P", -1, 1, 3') == []
    trio.advance(0.01)
    assert trio.send("?PROC_STATUS PROC(19)") == ["%[Process 19:Line 1] - Paused",
                                                  "MOVE(10)", "3"]  # 3: paused
    assert trio.send('TROFF "P"') == ["%[Process 19:Program P] - Released"]
    trio.advance(1.0)  # BASE 3: the move on axis 3, whose 10 counts end well within 1 s
    assert (trio.query("?DPOS AXIS(3)"), trio.query("?DPOS AXIS(0)")) == ("10", "0")
    assert trio.query("?VR(1)") == "1.0000"

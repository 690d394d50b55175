"""FIFO files: OPEN ... FOR FIFO_WRITE(size[, mode[, terminator]]) and FOR
FIFO_READ[(mode[, terminator])], a RAM circular buffer between two channels (TrioBASIC help
OPEN, FIFO_WRITE: its example passes a file through a 512-byte FIFO)."""

from __future__ import annotations

from maxk.controllers.trio import MC405


def _read_all(trio: MC405, channel: int = 41) -> str:
    trio.send("s = 0")
    text = []
    while trio.query(f"?KEY #{channel}") != "0":
        trio.send(f"GET #{channel}, c")
        text.append(chr(int(float(trio.query("?c")))))
    return "".join(text)


def test_characters_come_out_oldest_first_and_key_counts_them() -> None:
    trio = MC405()
    assert trio.send('OPEN #42 AS "gcodefifo" FOR FIFO_WRITE(512)') == []
    assert trio.send('PRINT #42, "G01 X10";') == []
    assert trio.send('OPEN #41 AS "gcodefifo" FOR FIFO_READ') == []
    assert trio.query("?KEY #41") == "7"  # mode 0: the characters in it
    assert trio.send('PRINT #42, " Y5"') == []  # with CR LF
    assert trio.query("?KEY #41") == str(7 + 3 + 2)
    assert _read_all(trio) == "G01 X10 Y5\r\n"


def test_line_mode_key_counts_the_terminators() -> None:
    trio = MC405()
    trio.send('OPEN #42 AS "lines" FOR FIFO_WRITE(256)')
    trio.send('OPEN #41 AS "lines" FOR FIFO_READ(1)')
    trio.send('PRINT #42, "first"')
    trio.send('PRINT #42, "second"')
    trio.send('PRINT #42, "third";')  # no line end yet
    assert trio.query("?KEY #41") == "2"
    for _ in range(len("first\r\n")):
        trio.send("GET #41, c")
    assert trio.query("?KEY #41") == "1"  # a terminator taken out: one line less


def test_a_non_blocking_fifo_keeps_the_newest_characters() -> None:
    """Mode bit 1: a full FIFO overwrites; 300 characters into 256 keep the last 256."""
    trio = MC405()
    trio.send('OPEN #42 AS "ring" FOR FIFO_WRITE(256, 2)')
    alphabet = "".join(chr(65 + k % 26) for k in range(300))
    for start in range(0, 300, 60):
        assert trio.send(f'PRINT #42, "{alphabet[start:start + 60]}";') == []
    trio.send('OPEN #41 AS "ring" FOR FIFO_READ')
    assert trio.query("?KEY #41") == "256"
    assert _read_all(trio) == alphabet[-256:]


def test_non_blocking_line_mode_drops_whole_oldest_lines() -> None:
    """Mode 3: a line that overflows clears the oldest line up to its terminator (here
    LF, 10, the end of PRINT's CR LF)."""
    trio = MC405()
    trio.send('OPEN #42 AS "log" FOR FIFO_WRITE(256, 3, 10)')
    lines = [f"{k:02d}" + "." * 60 for k in range(5)]  # 64 characters with CR LF each
    for line in lines:
        trio.send(f'PRINT #42, "{line}"')
    # 320 characters into 256: line 0 went whole (64), so exactly lines 1..4 remain
    trio.send('OPEN #41 AS "log" FOR FIFO_READ')
    assert _read_all(trio) == "".join(line + "\r\n" for line in lines[1:])


def test_the_size_is_at_least_256_and_reopening_clears_it() -> None:
    trio = MC405()
    trio.send('OPEN #42 AS "small" FOR FIFO_WRITE(10, 2)')
    trio.send(f'PRINT #42, "{"x" * 200}";')
    trio.send('OPEN #41 AS "small" FOR FIFO_READ')
    assert trio.query("?KEY #41") == "200"  # 10 asked for: 256 made (page)
    trio.send("CLOSE #42")
    assert trio.send('OPEN #42 AS "small" FOR FIFO_WRITE(10)') == []
    assert trio.query("?KEY #41") == "0"  # its contents cleared


def test_a_full_blocking_fifo_holds_the_print_until_a_reader_makes_room() -> None:
    """The page's example's shape: one process writes 300 characters through a 256-byte
    FIFO; the PRINT waits until the reader has taken 44 of them."""
    trio = MC405()
    trio.load("W", 'OPEN #42 AS "pipe" FOR FIFO_WRITE(256)\nVR(1) = 1\n'
              's = ""\nFOR i = 0 TO 299\n  s = s + CHR(65 + i MOD 26)\nNEXT i\n'
              'PRINT #42, s;\nVR(1) = 2\nCLOSE #42')
    trio.load("R", 'WAIT UNTIL VR(1) = 1\nOPEN #41 AS "pipe" FOR FIFO_READ\n'
              "WA(1000)\nVR(2) = KEY #41\nn = 0\nWHILE n < 300\n  GET #41, c\n"
              "  VR(10 + n) = c\n  n = n + 1\nWEND")
    trio.send('RUN "W", 1')
    trio.send('RUN "R", 2')
    trio.advance(ticks=900)
    assert trio.query("?VR(1)") == "1.0000"  # the PRINT is waiting
    assert trio.query("?PROC_STATUS PROC(1)") == "8"  # running, asleep in the PRINT
    trio.advance(ticks=1000)
    assert trio.query("?VR(2)") == "256.0000"  # full when the reader looked
    assert trio.query("?VR(1)") == "2.0000"  # room made: the PRINT finished
    read = "".join(chr(int(trio.machine.vr_read(10 + k))) for k in range(300))
    assert read == "".join(chr(65 + k % 26) for k in range(300))


def test_bad_fifo_opens_are_refused() -> None:
    trio = MC405()
    assert trio.send('OPEN #41 AS "nothing" FOR FIFO_READ') == ["! Program not found"]
    assert trio.send('OPEN #42 AS "f" FOR FIFO_WRITE(256, 4)') == ["! Parameter out of range"]
    assert trio.send('OPEN #42 AS "f" FOR FIFO_WRITE(1.5)') == ["! Parameter out of range"]
    assert trio.send('OPEN #41 AS "nothing" FOR FIFO_READ') == ["! Program not found"]

"""PROC_STATUS as its help page lists the states: 0 stopped, 1 running, 8 SLEEP while a
statement waits (the page: WA, WAIT IDLE and the like); 2 and 3 under trace are in
test_trio_debugwords.py. The page's example: RUN a program on process 12, wait for it to
start (<> 0), then to finish (= 0)."""

from __future__ import annotations

from maxk.controllers.trio import MC405


def _status(trio: MC405, process: int) -> str:
    return trio.query(f"?PROC_STATUS PROC({process})")


def test_wa_sleeps_and_the_end_stops() -> None:
    trio = MC405()
    trio.load("NAP", "WA(50)\nVR(1) = 1")
    assert _status(trio, 4) == "0"  # nothing on it
    trio.send('RUN "NAP", 4')
    trio.advance(ticks=10)
    assert _status(trio, 4) == "8"
    trio.advance(ticks=60)
    assert trio.query("?VR(1)") == "1.0000" and _status(trio, 4) == "0"


def test_a_busy_loop_runs_and_a_wait_until_sleeps() -> None:
    trio = MC405()
    trio.load("SPIN", "WHILE VR(2) = 0\n  VR(3) = VR(3) + 1\nWEND\nWAIT UNTIL VR(4) = 1\n"
              "VR(5) = 1\nWHILE TRUE\nWEND")
    trio.send('RUN "SPIN", 6')
    trio.advance(ticks=5)
    assert _status(trio, 6) == "1"  # working every cycle, never waiting
    trio.send("VR(2) = 1")
    trio.advance(ticks=5)
    assert _status(trio, 6) == "8"  # in WAIT UNTIL
    trio.send("VR(4) = 1")
    trio.advance(ticks=5)
    assert trio.query("?VR(5)") == "1.0000" and _status(trio, 6) == "1"


def test_wait_idle_sleeps_while_the_axis_moves() -> None:
    """MOVE(100) at SPEED 1000 and ACCEL/DECEL 100000: 10 ms ramps up and down and 90 ms at
    speed, 110 ms in all; 50 ms in, the program is asleep in WAIT IDLE."""
    trio = MC405()
    trio.load("M", "SPEED = 1000\nACCEL = 100000\nDECEL = 100000\nMOVE(100)\nWAIT IDLE\n"
              "WHILE TRUE\nWEND")
    trio.send('RUN "M", 2')
    trio.advance(ticks=50)
    assert _status(trio, 2) == "8"
    trio.advance(ticks=100)
    assert float(trio.query("?DPOS")) == 100 and _status(trio, 2) == "1"


def test_the_pages_example_waits_for_the_start_and_the_end_of_another() -> None:
    trio = MC405()
    trio.load("WORK", "WA(30)\nVR(10) = VR(10) + 1")
    trio.load("MAIN", 'RUN "WORK", 12\nWAIT UNTIL PROC_STATUS PROC(12) <> 0\nVR(11) = TICKS\n'
              "WAIT UNTIL PROC_STATUS PROC(12) = 0\nVR(12) = TICKS\nVR(13) = VR(10)")
    trio.send('RUN "MAIN", 3')
    trio.advance(ticks=100)
    assert trio.query("?VR(13)") == "1.0000"  # it saw WORK end, after its one pass
    waited = trio.machine.vr_read(11) - trio.machine.vr_read(12)  # TICKS counts down
    assert 30 <= waited <= 32  # WORK's WA(30), give or take the cycles around it

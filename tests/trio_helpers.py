"""Shared pieces of the Trio tests: a fake machine with its command line, atrio's parse of
a reply (reference trio-command-line.md section 2, applied to the bytes), and the seed's
three examples as they would be typed into the controller."""

from __future__ import annotations

import re
from pathlib import Path

from maxk.commands.trio import FakeTrioMachine, TrioCommandLine
from maxk.controllers.trio import MC405


class AtrioError(Exception):
    pass


class Rig:
    """A FakeTrioMachine and a TrioCommandLine on it, clocked together."""

    def __init__(self, programs: Path | None = None, axis_count: int = 16) -> None:
        self.machine = FakeTrioMachine(axis_count)
        self.session = TrioCommandLine(self.machine, programs)

    def send(self, text: str) -> bytes:
        """Send one command as atrio does (text + CR LF) and return every byte sent back."""
        self.session.feed(text.encode("latin-1") + b"\r\n")
        return self.session.read()

    def cycles(self, count: int) -> bytes:
        """Run servo cycles: the machine's, then the processes' and the command line's."""
        for _ in range(count):
            self.machine.cycle()
            self.session.servo_cycle()
        return self.session.read()

    def command(self, cmd: str) -> bytes:
        """atrio's Trio.command: the reply must parse, with no %[COMMAND error line."""
        return parse_reply(cmd, self.send(cmd))

    def load(self, name: str, text: str, program_type: int = 0) -> None:
        """atrio's write_program: SELECT, one !NAME,nR line each, COMPILE."""
        self.command(f'SELECT "{name}",{program_type}')
        for n, line in enumerate(text.splitlines()):
            self.command(f"!{name},{n}R{line}")
        self.command("COMPILE")


_REPLY = (rb"(.*?)%s\r\n(.*)>>\nControl char : ((?-s:.*))\r\n>>")


def parse_reply(cmd: str, data: bytes) -> bytes:
    """The exact regular expressions atrio applies to a command's reply."""
    c = cmd.encode("ascii")
    match = re.search(_REPLY % re.escape(c), data, re.MULTILINE | re.DOTALL)
    if match is None:
        raise AtrioError(f"Cannot parse answer to {c!r}: {data!r}")
    error = re.match(rb".*%(\[COMMAND[^\n]+)\r", match.group(2), re.MULTILINE | re.DOTALL)
    if error:
        raise AtrioError(f"Command Error {error.group(1)!r}")
    if match.group(3) != b"0x10000000A":
        raise AtrioError(f"bad return code: {match.group(3)!r}")
    return re.sub(rb"\r\n$", b"", match.group(2))


# The seed's examples as typed into a controller. The text extraction dropped the
# underscores (PWM CONTROL -> PWM_CONTROL ...), ran example 1 onto one line and wrapped two
# comments of example 2 onto lines of their own: restored here, nothing else changed.
EXAMPLE_1 = """BASE(0,1)
SPEED=5000
ACC (50000)
MERGE=ON
MOVE (10000,0)
MOVE (0, -10000)
MOVE (-10000,0)
MOVE (0,10000)
' This program sets the PWM output to a minimum of 50 and maximum of 500. At a speed of 2000 the PWM output will be 250:
BASE(4)
WDOG=OFF
WA(10)
ATYPE=35
WDOG=ON
PWM_CYCLE=1000' sets 20khz PWM
link=0' link to axes 0 and 1
mult=0.1' if speed=2000: pwm=2000*0.1=200
PWM_CONTROL(2,mult,50,500,link)
"""  # noqa: E501

EXAMPLE_2 = """start=1000
TABLE(start,0,0,0,0,1000,1000,1000,0,0)
CONNPATH(0) AXIS(8)
BASE(4)
WDOG=OFF
WA(10)
ATYPE=35
WDOG=ON
PWM_CYCLE=1000' sets 20khz PWM
link=0'                 link to axes 0 and 1
mult=1/10000'                   if speed=5000: pwm=5000*(1/10000) * DPOS = 500
PWM_CONTROL(8,mult,50,500,link,9)
' Note how the CAMBOX links to a length of the box outline path of 40000:
TABLE (1000,0,0,0,0,1000,1000,1000,0,0)
BASE (0,1)
SPEED=10000
ACC (50000)
MERGE=ON
WHILE TRUE
    CAMBOX(1000,1008,1,40000,8) AXIS(9)
    MOVE (10000,0)
    MOVE (0, -10000)
    MOVE (-10000,0)
    MOVE (0,10000)
    WAIT IDLE
    WA(10)
    DEFPOS(0) AXIS(8)
WEND
"""

EXAMPLE_3 = """WDOG=OFF
BASE(0)
PWM_CONTROL(0)
ATYPE=35 ' atype for stepper output with PWM
FE_LIMIT=500000000 ' dpos and mpos may not match
PWM_CYCLE=1000 ' 20Khz PWM output
PWM_MARK=0 ' switch off for now
UNITS=16 '
PWM_CONTROL(1)
DEFPOS(0)
PWM_CONTROL(6)
TABLE (1000, 110, 115, 195, 220)
TABLE (2000, 220, 195, 115, 110)
PWM_CONTROL(4)
PWM_CONTROL(5)' switch on gating function
PWM_MARK=400
WDOG=ON
REPEAT
    PWM_CONTROL(3,1,ON,1000,1003) ' load positions to gate
    MOVEABS (300)
    WAIT IDLE
    PWM_CONTROL(3,0,ON,2000,2003) ' same pattern in reverse
    MOVEABS(0)
    WAIT IDLE
UNTIL FALSE
"""


def mc405(*lines: str) -> MC405:
    """An MC405 after `lines` typed at its command line, each answered with nothing."""
    trio = MC405()
    for line in lines:
        assert trio.send(line) == [], line
    return trio


def at(trio: MC405, tick: int) -> None:
    """Run the MC405's virtual time on to servo tick `tick`."""
    trio.advance(ticks=tick - trio.machine.tick)

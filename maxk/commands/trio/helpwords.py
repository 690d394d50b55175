"""Keywords of the TrioBASIC help that atrio's token table predates, for fieldbus, set-up
and diagnostics: known by name, stored or read as 0, each with why it has no effect here.

Without an entry such a word was no keyword at all, so ``AIN_CONFIG(5) = 3`` or
``MS_BUS(0, 1)`` stopped a program with "Variable not defined" and ``IP_BIND_ADDRESS = 0``
silently made a local variable of a controller parameter. The words that act on motion,
inputs or program flow (ACCEL_FACTOR, SPEED_FACTOR, FORCE_ACCEL, MOVEADD, IN_FILTER ...)
are not listed here: they need modelling, not a "Not modelled" line.

Row forms (keywords.py builds the entries; a word with a hand-written entry is skipped):

- ``S NAME w|r why``: a system parameter, writable or read only; ``A`` the same taking
  arguments (``NODE_AXIS_MAP(slot, node, i) = v``), each argument list keeping its value;
- ``F NAME min max why``: a function (returns 0); ``C NAME min max why``: a command.
"""

from __future__ import annotations

_BUS = "a fieldbus word: the emulator has no bus, slices or remote drives"
_FLASH = "an MC_CONFIG set-up of the controller's flash or boot, which the emulator has not"

HELP_WORDS = f"""\
S AUTOLOCK_SECONDS w the project lock's timer: the emulator has no project locking
S AUTO_PROFINET w {_BUS}
S BATTERY_LOW r the clock battery's state: there is no battery (reads 0, not low)
S DEBUG_LOG_MODE w {_FLASH}
S FLASH_TABLE_FIRST w {_FLASH}: TABLE is kept in memory only
S FLASH_TABLE_LAST w {_FLASH}: TABLE is kept in memory only
S FLASH_VR_FIRST w {_FLASH}: VRs are kept in memory only
S FLASH_VR_LAST w {_FLASH}: VRs are kept in memory only
S IP_BIND_ADDRESS w the local address of a program's network channels, which open no socket
S PCMCAT_PROC w the process of the PC-MCAT API program: there is no PC-MCAT connection
S PLOT_CALC w a reserved keyword (its page)
S SYSTEM_LOAD_AVG r the firmware's load: the emulator's servo cycle is one instant
S SYSTEM_WARNING r firmware warnings: the emulator reports none
S VP_MODE_PLC w {_FLASH}
A AIN_CONFIG w the analogue input's electrical mode: the world's inputs have one range
A AOUT_CONFIG w the analogue output's electrical mode: the world's outputs have one range
A DV_CONTROLWORD w {_BUS}
A DV_OUT w {_BUS}
A DV_IN r {_BUS}
A DV_STATUSWORD r {_BUS}
A MS_BUS_CONFIG w {_BUS}
A NODE_AXIS_MAP w {_BUS}
A NW_NODE_PROFILE w {_BUS}
F CHANNEL_TRANSACT 1 16 a network channel's transaction: program channels open no socket
F DEBUG_LOG 0 2 the firmware's event log: the emulator logs no firmware events
F MS_BUS 1 16 {_BUS}
F MS_BUS_IO 1 16 {_BUS}
F REGISTER_KEYWORD 4 4 the open architecture's own keywords are not emulated
F REGISTER_MOVE 5 5 the open architecture's own moves are not emulated
C AXISLIST 0 0 the list of active axes: every axis here is always present (prints nothing)
C DV_MAP 0 0 {_BUS} (prints nothing)
C TOKENTABLE 0 0 the token list a host downloads: its numbered tags are not in the pages
"""

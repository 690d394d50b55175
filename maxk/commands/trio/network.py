"""ETHERNET, the IP_ parameters, CLEAR_PARAMS, FLASHTABLE, FLASHVR and FREE (their
TrioBASIC help pages).

ETHERNET(action, slot, function[, values]) reads (action 0: printed as the page prints
it) or writes (action 1) the Ethernet port's settings. The addresses are the system
parameters IP_ADDRESS (function 0), IP_NETMASK (2) and IP_GATEWAY (8), so both ways of
setting them agree; IP_MAC (3) is read only. The ports (4 command line, 5 token channel,
10 Modbus TCP) and the Modbus TCP data type (7) and source (9) are kept and read back.
Nothing of it moves the emulator's own listening socket: a new address "applies after
EX(1)" on the controller, and the emulator's door is the host's (D). The other functions
(ARP cache, MIB, endpoints, connection state, restart) are accepted and do nothing: the
emulator has no Ethernet stack (D); a function number the page's table does not list
(16-20, 26 on, negative) is 'Parameter out of range' (D).

CLEAR_PARAMS resets the FLASH parameters (personalities/trio/flash.py) to their power-up
values; like the controller's, the new SERVO_PERIOD takes effect at the next EX.

FLASHTABLE(function, flashpage[, tablepage]) copies TABLE pages of 16000 values to and
from 32 flash pages (1 write, 2 read back, 3 in use?, 4 erase; its page), and
FLASHVR(-1) keeps the whole TABLE to replace TABLE at power-up (-2 stops that; its page).
Flash outlives EX, TABLE does not. A flash page never written reads back as zeros (D).

FREE is the program memory left: a capacity less what DIR lists for every program (its
source and compiled code), so it falls as programs are stored and compiled (page: the
program's lines, and "a little under twice the memory" to run it). The capacity is ours
(D: no page gives the MC405's).
"""

from __future__ import annotations

from collections.abc import Callable

from ...personalities.trio.flash import FLASH_PARAMETERS, dotted, mac_text
from ...personalities.trio.memory import TABLE_SIZE, VR_COUNT
from .interpreter import Value, number_arg
from .keywords import KEYWORDS
from .lexer import TrioError
from .machine import TrioMachine
from .programs import ProgramStore

FLASH_PAGES = 32  # FLASHTABLE's flash pages (page)
FLASH_PAGE_SIZE = 16000  # TABLE values a page (page)
PROGRAM_CAPACITY = 1_048_576  # FREE with no program stored (D)
_ADDRESSES = {0: "IP_ADDRESS", 2: "IP_NETMASK", 8: "IP_GATEWAY"}
_NUMBERS = {4: (23.0, 65535.0), 5: (3240.0, 65535.0), 10: (502.0, 65535.0),
            7: (0.0, 2.0), 9: (0.0, 1.0)}  # function: (power-up value, highest), pages
_MAC = 3
_FUNCTIONS = frozenset(range(16)) | frozenset(range(21, 26))  # the page's function table
_MC464_ONLY = 6  # PRP firmware version: "MC464 read only"


class NetworkWords:
    """ETHERNET, CLEAR_PARAMS and FREE; the attributes are the runtime's own (system.py)."""

    machine: TrioMachine
    programs: ProgramStore
    output: Callable[[str], None]
    ethernet_values: dict[int, float]
    flash_pages: dict[int, list[float]]  # FLASHTABLE: flash page -> its 16000 values
    flash_table: list[float] | None  # FLASHVR(-1): TABLE as it was, restored at power-up

    def cmd_ethernet(self, args: list[Value]) -> None:
        numbers = [number_arg(a) for a in args]
        if len(numbers) < 3 or any(n != int(n) for n in numbers):
            raise TrioError("Parameter out of range")
        action, slot, function = (int(n) for n in numbers[:3])
        values = numbers[3:]
        if action not in (0, 1, 2) or slot != -1 or function == _MC464_ONLY or \
                function not in _FUNCTIONS:
            raise TrioError("Parameter out of range")  # (the MC405 has one port: -1, D)
        # (the page's gateway example writes with action 0: values given write, I)
        writing = bool(values)
        if function in _ADDRESSES:
            name = _ADDRESSES[function]
            if not writing:
                self.output(dotted(self.machine.system_parameter(name)) + "\r\n")
                return
            if len(values) != 4 or not all(0 <= v <= 255 for v in values):
                raise TrioError("Parameter out of range")
            octets = [int(v) for v in values]
            self.machine.set_system_parameter(
                name, float(octets[0] << 24 | octets[1] << 16 | octets[2] << 8 | octets[3]))
        elif function == _MAC:
            if writing:
                raise TrioError("Parameter is read only")
            self.output(mac_text(self.machine.system_parameter("IP_MAC")) + "\r\n")
        elif function in _NUMBERS:
            default, highest = _NUMBERS[function]
            if not writing:
                self.output(f"{int(self.ethernet_values.get(function, default))}\r\n")
                return
            if len(values) != 1 or not 0 <= values[0] <= highest:
                raise TrioError("Parameter out of range")
            self.ethernet_values[function] = values[0]

    def cmd_clear_params(self, args: list[Value]) -> None:
        for name in sorted(FLASH_PARAMETERS):
            self.machine.set_system_parameter(name, KEYWORDS[name].default)

    def free_memory(self) -> float:
        used = sum(self.programs.source_size(name) + self.programs.info[name].code_size
                   for name in self.programs.names())
        return float(max(0, PROGRAM_CAPACITY - used))

    def flashtable(self, args: list[Value]) -> float:
        """FLASHTABLE(function, flashpage[, tablepage]): TRUE, or for function 3 whether
        the flash page holds data; bad numbers are 'Parameter out of range'."""
        numbers = [number_arg(a) for a in args]
        if not 2 <= len(numbers) <= 3 or any(n != int(n) for n in numbers):
            raise TrioError("Parameter out of range")
        function, page = int(numbers[0]), int(numbers[1])
        table_page = int(numbers[2]) if len(numbers) > 2 else 0
        last_page = TABLE_SIZE // FLASH_PAGE_SIZE - 1
        if function not in (1, 2, 3, 4) or not 0 <= page < FLASH_PAGES or \
                not 0 <= table_page <= last_page or (function in (1, 2) and len(numbers) < 3):
            raise TrioError("Parameter out of range")
        start = table_page * FLASH_PAGE_SIZE
        if function == 1:
            self.flash_pages[page] = [self.machine.table_read(start + k)
                                      for k in range(FLASH_PAGE_SIZE)]
        elif function == 2:
            self.machine.table_write(start, self.flash_pages.get(page,
                                                                 [0.0] * FLASH_PAGE_SIZE))
        elif function == 3:
            return -1.0 if page in self.flash_pages else 0.0
        else:
            self.flash_pages.pop(page, None)
        return -1.0

    def flashvr(self, args: list[Value]) -> float:
        """FLASHVR(index): -1 keeps TABLE for power-up, -2 forgets it; an index 0 and up
        (a VR) and -100 have nothing to do: the MC4xx keeps VRs itself (page) (D: TRUE)."""
        if len(args) != 1:
            raise TrioError("Syntax error")
        index = number_arg(args[0])
        if index != int(index) or not (index in (-1, -2, -100) or 0 <= index < VR_COUNT):
            raise TrioError("Parameter out of range")
        if index == -1:
            self.flash_table = [self.machine.table_read(k) for k in range(TABLE_SIZE)]
        elif index == -2:
            self.flash_table = None
        return -1.0

    def cmd_flashtable(self, args: list[Value]) -> None:
        self.flashtable(args)

    def cmd_flashvr(self, args: list[Value]) -> None:
        self.flashvr(args)

    def power_up_table(self) -> None:
        """Power-up (EX): TABLE from FLASHVR(-1)'s copy, if one is kept."""
        if self.flash_table is not None:
            self.machine.table_write(0, self.flash_table)

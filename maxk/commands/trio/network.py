"""ETHERNET, the IP_ parameters, CLEAR_PARAMS and FREE (their TrioBASIC help pages).

ETHERNET(action, slot, function[, values]) reads (action 0: printed as the page prints
it) or writes (action 1) the Ethernet port's settings. The addresses are the system
parameters IP_ADDRESS (function 0), IP_NETMASK (2) and IP_GATEWAY (8), so both ways of
setting them agree; IP_MAC (3) is read only. The ports (4 command line, 5 token channel,
10 Modbus TCP) and the Modbus TCP data type (7) and source (9) are kept and read back.
Nothing of it moves the emulator's own listening socket: a new address "applies after
EX(1)" on the controller, and the emulator's door is the host's (D). The other functions
(ARP cache, MIB, endpoints, connection state, restart) are accepted and do nothing: the
emulator has no Ethernet stack (D).

CLEAR_PARAMS resets the FLASH parameters (personalities/trio/flash.py) to their power-up
values; like the controller's, the new SERVO_PERIOD takes effect at the next EX.

FREE is the program memory left: a capacity less what DIR lists for every program (its
source and compiled code), so it falls as programs are stored and compiled (page: the
program's lines, and "a little under twice the memory" to run it). The capacity is ours
(D: no page gives the MC405's).
"""

from __future__ import annotations

from collections.abc import Callable

from ...personalities.trio.flash import FLASH_PARAMETERS, dotted, mac_text
from .interpreter import Value, number_arg
from .keywords import KEYWORDS
from .lexer import TrioError
from .machine import TrioMachine
from .programs import ProgramStore

PROGRAM_CAPACITY = 1_048_576  # FREE with no program stored (D)
_ADDRESSES = {0: "IP_ADDRESS", 2: "IP_NETMASK", 8: "IP_GATEWAY"}
_NUMBERS = {4: (23.0, 65535.0), 5: (3240.0, 65535.0), 10: (502.0, 65535.0),
            7: (0.0, 2.0), 9: (0.0, 1.0)}  # function: (power-up value, highest), pages
_MAC = 3
_MC464_ONLY = 6  # PRP firmware version: "MC464 read only"


class NetworkWords:
    """ETHERNET, CLEAR_PARAMS and FREE; the attributes are the runtime's own (system.py)."""

    machine: TrioMachine
    programs: ProgramStore
    output: Callable[[str], None]
    ethernet_values: dict[int, float]

    def cmd_ethernet(self, args: list[Value]) -> None:
        numbers = [number_arg(a) for a in args]
        if len(numbers) < 3 or any(n != int(n) for n in numbers):
            raise TrioError("Parameter out of range")
        action, slot, function = (int(n) for n in numbers[:3])
        values = numbers[3:]
        if action not in (0, 1, 2) or slot != -1 or function == _MC464_ONLY:
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

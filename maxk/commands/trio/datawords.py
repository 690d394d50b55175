"""TrioBASIC words that turn data into other data: CRC16, IEEE_IN/IEEE_OUT, STRTOD's
number reading and TABLEVALUES' listing.

Kept apart from the program and process handling (system.py): these are pure
computations on bytes, numbers and text, with the controller's own rules taken from their
help pages (recorded on each keyword's table entry).
"""

from __future__ import annotations

import math
import re
import struct
from dataclasses import dataclass

from .lexer import TrioError


@dataclass
class CrcSetup:
    """CRC16(0, poly[, reverse_input[, reverse_output[, bits]]]): what later CRC16(1|2, ...)
    calls compute with (help page CRC16)."""

    poly: int
    reverse_input: bool = False
    reverse_output: bool = False
    bits: int = 16


def _reflect(value: int, width: int) -> int:
    return int(format(value, f"0{width}b")[::-1], 2)


def crc_legacy(setup: CrcSetup, data: list[int], initial: int) -> int:
    """Mode 1: the shift register fed bit by bit, the polynomial applied as a bit falls out
    of the top (the "augmented" CRC, which needs the data followed by bits/8 zero bytes to
    flush the result: help page CRC16). The optional parameters do not apply (page)."""
    mask = (1 << setup.bits) - 1
    top = 1 << (setup.bits - 1)
    register = initial & mask
    for byte in data:
        for k in range(7, -1, -1):
            carry = register & top
            register = ((register << 1) | (byte >> k) & 1) & mask
            if carry:
                register ^= setup.poly & mask
    return register


def crc_direct(setup: CrcSetup, data: list[int], initial: int) -> int:
    """Mode 2: the CRC with no flush, more data may follow by passing the result back as
    `initial`. reverse_input runs the register least significant bit first (the
    reflected algorithm, so its register is already the reflected CRC: Modbus's, the page's
    example 5 with reverse_output FALSE, I); reverse_output then reverses the bits of the
    result (D)."""
    width = setup.bits
    mask = (1 << width) - 1
    register = initial & mask
    if setup.reverse_input:
        poly = _reflect(setup.poly & mask, width)
        for byte in data:
            register ^= byte
            for _ in range(8):
                register = (register >> 1) ^ poly if register & 1 else register >> 1
    else:
        top = 1 << (width - 1)
        for byte in data:
            for k in range(7, -1, -1):
                bit = (byte >> k) & 1
                feedback = bool(register & top) != bool(bit)
                register = (register << 1) & mask
                if feedback:
                    register ^= setup.poly & mask
    return _reflect(register, width) if setup.reverse_output else register


def crc_setup(args: list[float]) -> CrcSetup:
    """CRC16(0, ...)'s arguments, checked: poly 0..$FFFF (wider for bits > 16), bits 8..32."""
    if not 1 <= len(args) <= 4:
        raise TrioError("Syntax error")
    bits = int(args[3]) if len(args) > 3 else 16
    if len(args) > 3 and (args[3] != bits or not 8 <= bits <= 32):
        raise TrioError("Parameter out of range")
    poly = args[0]
    if poly != int(poly) or not 0 <= poly < (1 << bits):
        raise TrioError("Parameter out of range")
    return CrcSetup(int(poly), len(args) > 1 and args[1] != 0,
                    len(args) > 2 and args[2] != 0, bits)


def ieee_in(args: list[float]) -> float:
    """IEEE_IN(b0..b3) or (b0..b7): the float these bytes encode, byte 0 the high byte
    (help page IEEE_IN). A byte outside 0..255 is out of range (D)."""
    if len(args) not in (4, 8):
        raise TrioError("Syntax error")
    if not all(b == int(b) and 0 <= b <= 255 for b in args):
        raise TrioError("Parameter out of range")
    raw = bytes(int(b) for b in args)
    value = struct.unpack(">f" if len(raw) == 4 else ">d", raw)[0]
    if not math.isfinite(value):
        raise TrioError("Arithmetic error")  # a NaN or infinity has no TrioBASIC value (D)
    return float(value)


def ieee_out(args: list[float]) -> float:
    """IEEE_OUT(value, n[, size]): byte n (0 the high byte) of value as a 32 or 64 bit
    IEEE 754 float (help page IEEE_OUT). A value too large for 32 bits is out of range (D)."""
    if len(args) not in (2, 3):
        raise TrioError("Syntax error")
    size = args[2] if len(args) == 3 else 32
    if size not in (32, 64):
        raise TrioError("Parameter out of range")
    count = int(size) // 8
    n = args[1]
    if n != int(n) or not 0 <= n < count:
        raise TrioError("Parameter out of range")
    try:
        raw = struct.pack(">f" if count == 4 else ">d", args[0])
    except OverflowError:
        raise TrioError("Parameter out of range") from None
    return float(raw[int(n)])


_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


def read_number(text: str, number_format: int) -> tuple[float, int]:
    """STRTOD's conversion of the start of `text`: the value and how many characters it
    took (0: no number; the value is then 0). Format 1 (integer) gives 0 for a number that
    is not whole; 0 and 2 give the number as read (help page STRTOD; the "best resolution"
    of 2 is the emulator's float in both cases, D)."""
    match = _NUMBER.match(text)
    if match is None:
        return 0.0, 0
    exponent = match.group(2)
    if exponent is not None and not re.fullmatch(r"[eE][+-]?\d+", exponent):
        exponent = None
    value = float(match.group(0))
    if not math.isfinite(value):
        raise TrioError("Arithmetic error")
    if number_format == 1 and value != int(value):
        value = 0.0
    return value, match.end()


def letter_codes(text: str) -> tuple[dict[int, float], int]:
    """STRTOD format 3 (LETTER+VALUE, a G-code line): each letter's value by its place
    from A = 0 to Z = 25, and the characters read. Reading stops at the first character
    that neither starts a letter code nor is a space (D: the page's list of the
    conversion's ends is its format 0 rule, a character that is not part of a number)."""
    values: dict[int, float] = {}
    at = 0
    while at < len(text):
        char = text[at]
        if char == " ":
            at += 1
            continue
        if not ("A" <= char.upper() <= "Z"):
            break
        value, used = read_number(text[at + 1:], 0)
        if used == 0:
            break
        values[ord(char.upper()) - ord("A")] = value
        at += 1 + used
    return values, at


def table_values(values: list[float], compressed: bool) -> str:
    """TABLEVALUES' line: each value with four decimals, commas between; compressed, a run
    of n > 1 equal values is "kn," before the value (help page TABLEVALUES' example)."""
    out: list[str] = []
    k = 0
    while k < len(values):
        run = 1
        while compressed and k + run < len(values) and values[k + run] == values[k]:
            run += 1
        if run > 1:
            out.append(f"k{run}")
        out.append(f"{values[k]:.4f}")
        k += run
    return ",".join(out)


def words_of(value: float, whole: bool) -> tuple[float, float]:
    """INTEGER_READ: the low and high 32-bit words of the value's 64-bit pattern, each
    0..$FFFFFFFF. A parameter or an INTEGER variable holds a 64-bit integer, anything else
    (VR, TABLE, a plain variable) a 64-bit float (help page INTEGER_READ: the bit pattern,
    not a cast; which values are integers here is our decision, D)."""
    if whole:
        if not -(1 << 63) <= value < (1 << 63):
            raise TrioError("Parameter out of range")
        pattern = int(value) & 0xFFFF_FFFF_FFFF_FFFF
    else:
        pattern = struct.unpack(">Q", struct.pack(">d", value))[0]
    return float(pattern & 0xFFFF_FFFF), float(pattern >> 32)


def value_of(low: float, high: float, whole: bool) -> float:
    """INTEGER_WRITE: the value whose 64-bit pattern is high:low (each word -2^31 ..
    $FFFFFFFF, taken as its 32 bits, D). A float pattern that is no number (NaN,
    infinity) has no TrioBASIC value: 'Parameter out of range' (D)."""
    for word in (low, high):
        if word != int(word) or not -(1 << 31) <= word <= 0xFFFF_FFFF:
            raise TrioError("Parameter out of range")
    pattern = (int(high) & 0xFFFF_FFFF) << 32 | int(low) & 0xFFFF_FFFF
    if whole:
        return float(pattern - (1 << 64) if pattern >> 63 else pattern)
    value = struct.unpack(">d", struct.pack(">Q", pattern))[0]
    if not math.isfinite(value):
        raise TrioError("Parameter out of range")
    return float(value)

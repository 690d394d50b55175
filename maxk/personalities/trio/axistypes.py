"""The MC405's axis types (ATYPE) as the emulator wires them (TrioBASIC help ATYPE).

The help page's table is the list of types a program may set; which of them the axis's
hardware takes is "controller and module dependent" (its footnote). What each type does
here:

- **Servo types** (`SERVO_ATYPES`): an analogue (or PWM) output driven by the position
  loop, with the position fed back by an encoder. Every one runs the shared servo loop
  exactly as 36 and 77 always did (`following.py`): the world's motor of the axis and
  its encoder, DAC, FE, FE_LIMIT, MOTION_ERROR, the drive enable (WDOG, SERVO,
  AXIS_ENABLE). 44 is the flexible axis's standard analogue servo ("44 for analogue
  servo": the page); 102 is the same on a high-density connector, 60 and 103 read their
  feedback as pulse and direction, 94 puts the loop's output out as PWM, 36 as PWM with
  the Z channel's PWM output (pwm.py). The feedback device does not change the loop: the
  world's motor has one encoder, which each of them reads (D). An encoder the world
  mounts on a servo axis's input (`World.encoders`) is read by it only as an ADD_DAC
  added axis (add_dac.py: a measuring wheel on another axis's motor); otherwise its loop
  closes on its own motor (D).
- **Absolute-feedback servos** (`ABSOLUTE_SERVO_ATYPES`: 46 Tamagawa, 47 EnDat, 48 SSI,
  92 BiSS): the same loop; the world's encoder reads as an absolute one: MPOS is the
  encoder's count from the world's origin, with no DATUM needed (help MPOS: an absolute
  encoder's MPOS is not reset at power up). The world's motors stand at its origin when
  the controller powers up or restarts (EX), so at power up an absolute axis reads 0 as
  an incremental one does; what differs is ENCODER, the raw register, which holds only
  the data bits ENCODER_BITS clocks out (help ENCODER, ENCODER_BITS): the count modulo
  2^bits, MPOS being computed from it allowing for overflows (`absolute_register`; D:
  the world's origin as the encoder's zero).
- **Output types** (43, 63, 78, 100 pulse and direction; 45, 64, 84, 101 quadrature
  encoder output; 35 with PWM): the axis's demand is put out as steps or as A/B
  quadrature, which the world's motor follows exactly, so an encoder input (76 ...)
  mounted on the axis's shaft reads that demand (`World.encoders`). 78 and 84 ("with
  VFF_GAIN") are taken as their plain forms: the page does not say what the gain does
  to an output (D).
- **Encoder inputs** (76, 79, 86, 87, 88, 93, 104, 105): `machine.ENCODER_ATYPES`.
- **Others** (virtual 0; CANopen, RTEX, Sercos, EtherCAT, SLM, FlexSlice, analogue
  feedback 30/31, monitoring 85, SSI slave 75): stored as given; they have no axis
  hardware or drive in the world, so the axis follows its demand as a virtual one (D).
- A number the page does not list is 'Parameter out of range', the axis's type kept (D:
  the page's list is the set of types the firmware knows).
"""

from __future__ import annotations

from typing import Final

SERVO_ATYPES: Final = frozenset({36, 44, 46, 47, 48, 60, 77, 92, 94, 102, 103})
"""Axis types whose drive is a servo amplifier run by the position loop (help ATYPE)."""

ABSOLUTE_SERVO_ATYPES: Final = frozenset({46, 47, 48, 92})
"""Servo types whose feedback is an absolute encoder (Tamagawa, EnDat, SSI, BiSS)."""

OUTPUT_ATYPES: Final = frozenset({35, 43, 45, 63, 64, 78, 84, 100, 101})
"""Pulse/direction and quadrature-encoder outputs: the axis's demand, put out."""

KNOWN_ATYPES: Final = frozenset({
    0, 18, 19, 26, 27, 30, 31, 35, 36, 37, 43, 44, 45, 46, 47, 48, 50, 51, 52, 53, 54, 55,
    56, 57, 58, 59, 60, 61, 62, 63, 64, 65, 66, 67, 68, 69, 70, 71, 75, 76, 77, 78, 79, 84,
    85, 86, 87, 88, 92, 93, 94, 100, 101, 102, 103, 104, 105})
"""Every type the ATYPE help page's tables list."""

TAMAGAWA_BITS: Final = 17
"""Data bits of a Tamagawa encoder's single-turn position (D: the page gives none)."""


def check(value: float) -> int:
    """An ATYPE being set: a whole number the page lists, else 'Parameter out of range'."""
    if value != int(value) or int(value) not in KNOWN_ATYPES:
        raise ValueError("Parameter out of range")
    return int(value)


def data_bits(atype: int, encoder_bits: float) -> int | None:
    """The bits an absolute servo's register holds (None: not an absolute servo, or no
    limit): SSI and BiSS bits 0-5 of ENCODER_BITS, EnDat bits 0-7 (help ENCODER_BITS),
    Tamagawa `TAMAGAWA_BITS`. With ENCODER_BITS 0 ('no data is clocked out': the page)
    the world's encoder still feeds the loop and the register is the whole count, as an
    incremental one's (D: the world has no encoder that could stop answering)."""
    if atype not in ABSOLUTE_SERVO_ATYPES:
        return None
    if atype == 46:
        return TAMAGAWA_BITS
    bits = int(encoder_bits) & (0xFF if atype == 47 else 0x3F)
    return bits or None


def absolute_register(atype: int, encoder_bits: float, counts: int) -> int | None:
    """ENCODER of an absolute servo: the encoder's count in its data bits (None: not an
    absolute servo, the caller's register applies)."""
    bits = data_bits(atype, encoder_bits)
    if bits is None:
        return None
    return counts % (1 << min(bits, 32))


__all__ = ["ABSOLUTE_SERVO_ATYPES", "KNOWN_ATYPES", "OUTPUT_ATYPES", "SERVO_ATYPES",
           "absolute_register", "check", "data_bits"]

"""The PoKeys command table: (command byte, sub-command) -> handler, with where each
behaviour comes from and how sure we are:

- ``C`` certain: the seeds or the reference (PoKeysLib as run or read) state it;
- ``I`` inferred: deduced from how the library uses the command;
- ``D`` decided: neither settles it; our choice, explained in ``note``.

A request whose (command, sub) is not here gets no reply (silence), as does any request
a handler refuses: the host's retry logic copes with silence, never with a wrong reply.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

from ...personalities.pokeys.device import PoKeysDevice
from . import device_commands as dev
from . import pev1_commands as v1
from . import pev2_commands as v2
from .packet import Reply, Request

Handler = Callable[[PoKeysDevice, Request], Reply | None]

ANY: Final = -1  # the entry takes every value of [2]
PEV1: Final = 0x80
PEV2: Final = 0x85
MULTIPART: Final = 0xB0


@dataclass(frozen=True)
class CommandEntry:
    command: int
    sub: int  # value of [2], or ANY
    name: str  # PoKeysLib's function name
    handler: Handler
    source: str
    confidence: str = "C"
    note: str = ""


def _e(command: int, sub: int, name: str, handler: Handler, source: str,
       confidence: str = "C", note: str = "") -> CommandEntry:
    return CommandEntry(command, sub, name, handler, source, confidence, note)


ENTRIES: Final[list[CommandEntry]] = [
    # ---- connect sequence ----------------------------------------------------------------
    _e(0x00, ANY, "PK_DeviceDataGet (serial, firmware)", dev.read_serial_firmware,
       "reference 4", "C", "PoKeys57: 'PKEx' layout; PoKeys56E: old layout, serial [2..3]."),
    _e(0x03, ANY, "PK_DeviceDataGet (user ID, lock)", dev.read_user_id, "reference 4", "C",
       "User ID 0, unlocked (D)."),
    _e(0x04, ANY, "PK_DeviceDataGet (build date, old ID)", dev.read_build_date,
       "reference 4", "C", "Parts 0, 1, 2 give 4 + 4 + 3 date characters; part > 2 silent (D)."),
    _e(0x06, ANY, "PK_DeviceDataGet / PK_DeviceNameSet", dev.device_name, "reference 4", "C",
       "Short name [8..17] equals the long name's first 10 bytes, so the long one is used."),
    _e(0xE0, ANY, "PK_DeviceDataGet (network) / PK_NetworkConfigurationSet",
       dev.network_config, "reference 4", "C",
       "Set ([2]=10) is stored; the door keeps listening where it listens (D)."),
    _e(0x8F, ANY, "PK_DeviceDataGet (activated options)", dev.activated_options,
       "reference 4, 10", "I", "Bit 0 = pulse engine; activation codes not modelled (D)."),
    # ---- pulse engine v2 -----------------------------------------------------------------
    _e(PEV2, 0x00, "PK_PEv2_StatusGet", v2.status_get, "reference 6, 7", "C",
       "[63] = [3] + 0x5A; [61]/[62] error and misc inputs always 0 (D). Position "
       "counters are 32-bit and wrap past 2^31 pulses (D: the motion keeps every pulse)."),
    _e(PEV2, 0x08, "PK_PEv2_Status2Get", v2.status2_get, "reference 6", "I",
       "Raw pin levels of the dedicated limit-/limit+/home inputs (D: levels, not activation)."),
    _e(PEV2, 0x01, "PK_PEv2_PulseEngineSetup", v2.setup, "reference 6", "C",
       "Enabled axes = how many axes (0..n-1) take part and travel in a fill (seed v2); "
       "more than 8 is refused (D). Buffer size [11] is stored; the depth stays 128 (D)."),
    _e(PEV2, 0x02, "PK_PEv2_PulseEngineStateSet", v2.state_set, "reference 6", "C",
       "Only STOPPED, RUNNING and JOGGING can be set (D); setting the present state keeps "
       "motions, any other change stops internal motions at once (D). O = per-axis limit "
       "override (I)."),
    _e(PEV2, 0x03, "PK_PEv2_PositionSet", v2.position_set, "reference 6", "C",
       "A moving axis keeps moving: its counter and target shift (D)."),
    _e(PEV2, 0x04, "PK_PEv2_ExternalOutputsGet/Set", v2.external_outputs, "reference 6", "I",
       "Stored and read back; no outputs are modelled."),
    _e(PEV2, 0x05, "PK_PEv2_PulseEngineReboot", v2.reboot, "reference 6", "D",
       "Stopped, buffer empty, counters 0, configuration kept; the reply is sent."),
    _e(PEV2, 0x06, "PK_PEv2_AdditionalParametersGet/Set", v2.additional_params,
       "reference 6", "I", "E-stop pin [8] stored and read back."),
    _e(PEV2, 0x10, "PK_PEv2_AxisConfigurationGet", v2.axis_config_get, "reference 6", "C",
       "Axis >= 8 is silent (the library refuses it locally). Bytes [8..52] come back as set."),
    _e(PEV2, 0x11, "PK_PEv2_AxisConfigurationSet", v2.axis_config_set, "reference 6", "C",
       "Max speed pulses/ms, acceleration pulses/ms^2 (reference 8); speeds above 125 "
       "pulses/ms are capped (D)."),
    _e(PEV2, 0x20, "PK_PEv2_PulseEngineMove", v2.move, "reference 6, 8", "C",
       "RUNNING, internal-planner axes only: position, or speed in pulses/s (reference 8, I). "
       "A new position while moving carries on from the present speed if the axis can "
       "still stop there, else stops and comes back (D)."),
    _e(PEV2, 0x25, "PK_PEv2_PulseEngineMovePV", v2.move_pv, "reference 6", "I",
       "[3] = axis mask (I); velocity u16/65535 scales the max speed; 0 = axis left alone (D)."),
    _e(PEV2, 0x21, "PK_PEv2_HomingStart", v2.homing_start, "reference 6, 9; seed v2", "C",
       "Homing speed [13] % of max (0 -> 10 %, D), return [14] % of homing (0 -> 50 %, the "
       "seed's 'half', D); constant speeds without ramps (D). Counter set to the axis's home "
       "offset (0 = the seed's reset) (D)."),
    _e(PEV2, 0x22, "PK_PEv2_HomingFinish", v2.homing_finish, "reference 6, 9", "C",
       "Engine goes to state [3]; a state that cannot be set is silent (D)."),
    _e(PEV2, 0x23, "PK_PEv2_ProbingStart", v2.probing_start, "reference 6; seed v2", "C",
       "Speed f32 = fraction of max speed (library comment), constant (D); the probe "
       "triggers when its level equals polarity [45] (D); reaching the max position without "
       "a trigger is PROBE_ERROR (I). Hybrid probing ([4]=1) is not modelled: silent."),
    _e(PEV2, 0x24, "PK_PEv2_ProbingFinish(Simple)", v2.probing_finish, "reference 6", "C",
       "Status [40]: 0 none, 1 probed, 2 max position reached (D); back to the state before "
       "probing (D)."),
    _e(PEV2, 0xF0, "PK_PEv2_BufferClear", v2.buffer_clear, "reference 6", "C",
       "Clears the slot buffer only: internal controllers use their own (seed v2)."),
    _e(PEV2, 0xFF, "PK_PEv2_BufferFill", v2.buffer_fill_8, "reference 6, 8", "C",
       "Accepted = min(N, free slots), [2]; N*AX > 56 or AX outside 1..8 is silent (D). "
       "Pulses above 125 per slot are clipped when the slot runs (D)."),
    _e(PEV2, 0xFE, "PK_PEv2_BufferFill_16", v2.buffer_fill_16, "reference 6, 8", "C",
       "u16 little-endian, bit 15 direction."),
    _e(MULTIPART, ANY, "PK_PEv2_BufferFillLarge[_16]", v2.buffer_fill_large,
       "reference 8", "C",
       "8 frames, one reply with the last frame's ID; a bad or missing frame silences the "
       "whole group (D)."),
    # ---- pulse engine v1 -----------------------------------------------------------------
    _e(PEV1, 0x00, "PK_PEStatusGet", v1.status, "reference 10", "C",
       "Position counters are 32-bit and wrap past 2^31 pulses (D)."),
    _e(PEV1, 0x01, "PK_PECurrentPositionSet", v1.set_position, "reference 10", "C",
       "Sets all three counters; a moving axis stops (D)."),
    _e(PEV1, 0x02, "PK_PEStateSet", v1.set_state, "reference 10; seed v1", "C",
       "STOPPED, INTERNAL, BUFFER, JOGGING; others silent (D). Leaving INTERNAL/JOGGING "
       "leaves up to 10 slots of the move in the buffer (seed's 10 ms rule, I); entering "
       "them clears the buffer, which the internal controller then owns (D)."),
    _e(PEV1, 0x03, "PK_PEMPGJogConfigurationGet/Set", v1.mpg_config, "reference 10", "C",
       "Stored and read back; v1 MPG jogging is not modelled."),
    _e(PEV1, 0x05, "PK_PEMove", v1.move, "reference 10; seed v1", "C",
       "INTERNAL: positions; JOGGING: speeds in pulses/s (I). [3] = axes whose value is a "
       "speed in INTERNAL (D: the library sends 0)."),
    _e(PEV1, 0x06, "PK_PEStatusSet (enable, charge pump)", v1.enable, "reference 10", "C",
       "Nonzero enables all three axes (D); power-up value 1 (D)."),
    _e(PEV1, 0x10, "PK_PEParametersGet", v1.parameters, "reference 10", "C"),
    _e(PEV1, 0x11, "PK_PEParametersSet", v1.parameters, "reference 10; seed v1", "C",
       "Homing [44] and return [45] speeds in % of max speed, power-up 10 and 1 (seed v1, D "
       "for the byte meaning); speeds above 25 pulses/ms capped (D)."),
    _e(PEV1, 0x12, "PK_PEAxisConfigurationGet", v1.axis_config, "reference 10", "C"),
    _e(PEV1, 0x13, "PK_PEAxisConfigurationSet", v1.axis_config, "reference 10", "C",
       "Bytes are per-axis bit masks (I)."),
    _e(PEV1, 0x14, "PK_PEKeyboardConfigurationGet", v1.keyboard, "reference 10", "C"),
    _e(PEV1, 0x15, "PK_PEKeyboardConfigurationSet", v1.keyboard, "reference 10", "C"),
    _e(PEV1, 0x20, "PK_PEHomingStart", v1.homing, "reference 10; seed v1", "C",
       "Axes without an enabled home switch go to ERROR (D); the engine ends in HOME (I)."),
    _e(PEV1, 0x30, "PK_PEInfoGet", v1.info, "reference 10; seed v1", "C", "3 / 25 / 128 / 1."),
    _e(PEV1, 0x35, "PK_PEBufferFill", v1.fill, "reference 10; seed v1", "C",
       "Up to 18 slots per frame (55 bytes); more is silent (D). Nothing accepted while the "
       "internal controller owns the buffer (D). Pulses above 25 clipped at run time (D)."),
    _e(PEV1, 0x36, "PK_PEBufferFlush", v1.flush, "reference 10; seed v1", "C"),
    _e(PEV1, 0x37, "PK_PEBufferFreeSizeGet", v1.free_slots, "reference 10; seed v1", "C",
       "In INTERNAL/JOGGING the controller's look-ahead (<= 10 slots) is not free (I)."),
]

_BY_KEY: Final = {(e.command, e.sub): e for e in ENTRIES}

NOT_MODELLED: Final = (
    "0x85 0x0A/0x0B synced PWM and outputs, 0x18/0x19 drivers, 0x30-0x36 threading, "
    "0x40/0x41 backlash, 0x50-0x53 PoStep, hybrid probing; every other PoKeys command "
    "(I/O, encoders, LCD, ...): silent.")


def lookup(command: int, sub: int) -> CommandEntry | None:
    return _BY_KEY.get((command, sub)) or _BY_KEY.get((command, ANY))


def dispatch(device: PoKeysDevice, request: Request) -> bytes | None:
    """The reply frame for a valid request, or None (silence)."""
    entry = lookup(request.command, request.sub)
    if entry is None:
        return None
    reply = entry.handler(device, request)
    return None if reply is None else reply.finish()

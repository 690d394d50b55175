"""The PoKeys command table: (command byte, sub-command) -> handler, with where each
behaviour comes from and how sure we are:

- ``C`` certain: the seeds or the reference (PoKeysLib as run or read) state it;
- ``I`` inferred: deduced from how the library uses the command;
- ``D`` decided: neither settles it; our choice, explained in ``note``.

A well-formed request is always answered: a request whose (command, sub) is not here
gets the refusal with status UNKNOWN in [2], one a handler refuses (it returns None) the
refusal with status REFUSED (packet.py; D). Only a frame the device cannot take as a
request (wrong length, header or checksum) gets no reply (session.py).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Final

from ...personalities.pokeys.device import PoKeysDevice
from ..line_session import log_fault
from ..tables import unique_table
from . import device_commands as dev
from . import io_commands as io
from . import legacy_commands as old
from . import peripheral_commands as per
from . import pev1_commands as v1
from . import pev2_commands as v2
from . import sensor_commands as sensors
from .packet import REFUSED, UNKNOWN, Reply, Request

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
    _e(0x02, ANY, "Set user ID (protocol specification)", dev.set_user_id,
       "protocol specification (command list)", "I",
       "[2] = the new user ID; read back by 0x03 and named in the discovery answer [0]."),
    _e(0x03, ANY, "PK_DeviceDataGet (user ID, lock)", dev.read_user_id, "reference 4", "C",
       "User ID 0 at power-up (D), unlocked."),
    _e(0x04, ANY, "PK_DeviceDataGet (build date, old ID)", dev.read_build_date,
       "reference 4", "C", "Parts 0, 1, 2 give 4 + 4 + 3 date characters; part > 2 refused "
       "([2]=1, D)."),
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
       "Axis >= 8 refused ([2]=1; the library refuses it locally). Bytes [8..52] come "
       "back as set."),
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
       "Engine goes to state [3]; a state that cannot be set is refused ([2]=1, D)."),
    _e(PEV2, 0x23, "PK_PEv2_ProbingStart", v2.probing_start, "reference 6; seed v2", "C",
       "Speed f32 = fraction of max speed (library comment), constant (D); the probe "
       "triggers when its level equals polarity [45] (D); reaching the max position without "
       "a trigger is PROBE_ERROR (I). Hybrid probing ([4]=1) is not modelled: refused ([2]=1)."),
    _e(PEV2, 0x24, "PK_PEv2_ProbingFinish(Simple)", v2.probing_finish, "reference 6", "C",
       "Status [40]: 0 none, 1 probed, 2 max position reached (D); back to the state before "
       "probing (D)."),
    _e(PEV2, 0xF0, "PK_PEv2_BufferClear", v2.buffer_clear, "reference 6", "C",
       "Clears the slot buffer only: internal controllers use their own (seed v2)."),
    _e(PEV2, 0xFF, "PK_PEv2_BufferFill", v2.buffer_fill_8, "reference 6, 8", "C",
       "Accepted = min(N, free slots), [2]; N*AX > 56 or AX outside 1..8 is refused "
       "as 0 accepted, [2]=0, with the status block (D: a fill's only result). "
       "Pulses above 125 per slot are clipped when the slot runs (D)."),
    _e(PEV2, 0xFE, "PK_PEv2_BufferFill_16", v2.buffer_fill_16, "reference 6, 8", "C",
       "u16 little-endian, bit 15 direction."),
    _e(MULTIPART, ANY, "PK_PEv2_BufferFillLarge[_16]", v2.buffer_fill_large,
       "reference 8", "C",
       "8 frames, one reply with the last frame's ID; a group that arrives incomplete or out "
       "of order is refused at its last frame as 0 accepted (D)."),
    # ---- pulse engine v1 -----------------------------------------------------------------
    _e(PEV1, 0x00, "PK_PEStatusGet", v1.status, "reference 10", "C",
       "Position counters are 32-bit and wrap past 2^31 pulses (D)."),
    _e(PEV1, 0x01, "PK_PECurrentPositionSet", v1.set_position, "reference 10", "C",
       "Sets all three counters; a moving axis stops (D)."),
    _e(PEV1, 0x02, "PK_PEStateSet", v1.set_state, "reference 10; seed v1", "C",
       "STOPPED, INTERNAL, BUFFER, JOGGING; others refused ([2]=1, D). Leaving INTERNAL/JOGGING "
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
       "Up to 18 slots per frame (55 bytes); more is refused ([2]=1, D). Nothing "
       "accepted while the internal controller owns the buffer (D). Pulses above 25 "
       "clipped at run time (D)."),
    _e(PEV1, 0x36, "PK_PEBufferFlush", v1.flush, "reference 10; seed v1", "C"),
    _e(PEV1, 0x37, "PK_PEBufferFreeSizeGet", v1.free_slots, "reference 10; seed v1", "C",
       "In INTERNAL/JOGGING the controller's look-ahead (<= 10 slots) is not free (I)."),
    # ---- the older single-pin requests (protocol specification; hosts of their own) ----
    _e(0x10, ANY, "Set pin function (protocol specification)", old.set_pin_function,
       "protocol specification; home-automation host", "I",
       "Pin [2] 0-based, PinFunction byte [3] as in 0xC0; [2]=0 done, [2]=1 refused "
       "(pin out of range or without the capability), nothing changed (D for the status)."),
    _e(0x15, ANY, "Get pin function (protocol specification)", old.get_pin_function,
       "protocol specification; home-automation host", "I",
       "Function byte in [3] (the host reads 2 input, 4 output there); [2]=1 for no pin."),
    _e(0x35, ANY, "Read analog input (protocol specification)", old.analog_input,
       "protocol specification", "D",
       "Pin [2] 40..46; 12-bit code, high byte [3], low [4] (D); another pin: [2]=1."),
    _e(0xE6, ANY, "PoLED (protocol specification)", old.poled,
       "protocol specification (command list); home-automation host", "D",
       "[2]=0x20 set channel [3] to state [4], [2]=0x10 read it back into [4] (D); other "
       "sub-commands: [2]=0xFF. States kept, no LED module drawn."),
    # ---- pins and I/O (PoKeysLibIO.c) ----------------------------------------------------
    _e(0xC0, ANY, "PK_PinConfigurationGet/Set", io.pin_configuration, "PoKeysLibIO.c", "C",
       "[2]=0 [3]=0 get, [2]=1 set functions; [3]=1/2 counter options get/set. Each "
       "model's pin capabilities from the library's device tables; a set-up with any pin "
       "refused changes nothing and gets no reply (D: the library then reports a transfer "
       "error, the device's way of refusing a frame)."),
    _e(0xC1, ANY, "PK_PinConfigurationGet/Set (key mapping type)", io.key_mapping,
       "PoKeysLibIO.c", "I", "USB keyboard emulation only; over the network: zeros (D)."),
    _e(0xC2, ANY, "PK_PinConfigurationGet/Set (key codes)", io.key_mapping, "PoKeysLibIO.c",
       "I", "As 0xC1."),
    _e(0xC3, ANY, "PK_PinConfigurationGet/Set (key modifiers)", io.key_mapping,
       "PoKeysLibIO.c", "I", "As 0xC1."),
    _e(0xD7, ANY, "PK_PinConfigurationGet/Set (triggered inputs)", io.key_mapping,
       "PoKeysLibIO.c", "I", "As 0xC1."),
    _e(0xCC, ANY, "PK_DigitalIOGet/Set/SetGet", io.digital_io, "PoKeysLibIO.c", "C",
       "Inputs: world digital input p = pin p (D); outputs only on output pins; [20..26] "
       "keeps a pin. Output pins read back their driven level (D)."),
    _e(0x30, ANY, "PK_DigitalIOGetSingle", io.digital_get_single, "PoKeysLibIO.c", "C",
       "[2]=0 ok, [3] level; a pin past 55 answers [2]=1 (D)."),
    _e(0x40, ANY, "PK_DigitalIOSetSingle", io.digital_set_single, "PoKeysLibIO.c", "C",
       "[2]=1 when the pin is not a digital output: nothing changes (D)."),
    _e(0x3A, ANY, "PK_AnalogIOGet", io.analog_get, "PoKeysLibIO.c", "C",
       "Pins 41..47, 12-bit big-endian; 0..3.3 V full scale (D); 0 on a pin not "
       "configured as analog input (D)."),
    _e(0x38, ANY, "PK_AnalogRCFilterGet", io.analog_filter, "PoKeysLibIO.c", "C",
       "u32 at [2..5]: the analog inputs' first-order low-pass, time constant in ms "
       "(0 off; D for the unit), sampled once a slot."),
    _e(0x39, ANY, "PK_AnalogRCFilterSet", io.analog_filter, "PoKeysLibIO.c", "C"),
    _e(0xD8, ANY, "PK_DigitalCounterGet", io.counters_get, "PoKeysLibIO.c", "C",
       "Edges of the world's input on a pin configured as counter, an input that "
       "follows time or an axis sampled every slot; counter options (0xC0 [3]=2): 0/1 "
       "rising, 2 falling, 3 both edges, bit 2 down (D); a pin without a counter reads 0."),
    _e(0x1D, ANY, "PK_DigitalCounterClear", io.counters_clear, "PoKeysLibIO.c", "C"),
    _e(0xCB, ANY, "PK_PWMConfigurationGet/Set, PK_PWMUpdate", io.pwm, "PoKeysLibIO.c", "C",
       "Channel n on pin 22-n, period and duty in 25 MHz clocks; update ([3]=1) sets the "
       "duties only (I); a channel on a pin that cannot drive refuses the frame (D)."),
    _e(0xDA, ANY, "PK_PoExtBusGet/Set", per.poextbus, "PoKeysLibIO.c", "C",
       "10 bytes; the set is echoed (the library compares)."),
    # ---- encoders (PoKeysLibEncoders.c) ------------------------------------------------
    _e(0xC4, ANY, "PK_EncoderConfigurationGet/Set (options)", io.encoder_options,
       "PoKeysLibEncoders.c", "C", "Bit 0 enables counting; bit 1 4x, bit 2 2x sampling "
       "(the library's names): a stage pulse is one quadrature cycle (D), counted 1, 2 "
       "or 4 times."),
    _e(0xC5, ANY, "PK_EncoderConfigurationGet/Set (channel pins)", io.encoder_options,
       "PoKeysLibEncoders.c", "C", "A pins [8+i], B pins [33+i]; stored (the world gives "
       "the counts)."),
    _e(0xC6, ANY, "PK_EncoderConfigurationGet/Set (direction A keys)", io.encoder_options,
       "PoKeysLibEncoders.c", "I", "USB only: zeros (D)."),
    _e(0xC7, ANY, "PK_EncoderConfigurationGet/Set (direction B keys)", io.encoder_options,
       "PoKeysLibEncoders.c", "I", "USB only: zeros (D)."),
    _e(0xCE, ANY, "PK_EncoderConfigurationGet/Set (fast encoders)", io.fast_encoders,
       "PoKeysLibEncoders.c", "C",
       "[2]=2 get; a set's configuration is 0, 1 or 10 (I), others refused; a nonzero one "
       "makes encoders 0..2 count (D)."),
    _e(0x1C, ANY, "PK_EncoderConfigurationGet/Set (ultra-fast)", io.ultra_fast_encoder,
       "PoKeysLibEncoders.c", "C", "[2]=0xFF get; nonzero configuration = encoder 25 "
       "counts (D)."),
    _e(0xCD, ANY, "PK_EncoderValuesGet/Set", io.encoder_values, "PoKeysLibEncoders.c", "C",
       "An encoder attached to an axis counts its stage's pulses exactly, 1 count a pulse "
       "(D), while enabled."),
    _e(PEV2, 0x37, "PK_EncoderValuesGet (ultra-fast test values)",
       io.ultra_fast_test_values, "PoKeysLibEncoders.c", "I",
       "Index count, ticks per rotation, velocity: 0 (no spindle model, D)."),
    # ---- the rest of the device ------------------------------------------------------------
    _e(0x83, ANY, "PK_RTCGet/Set", per.rtc, "PoKeysLibRTC.c", "C",
       "Runs on virtual time from 2018-01-10 00:00:00 (D); day of week 0 = Sunday (D); a "
       "set with an impossible date is refused (D)."),
    _e(0xCA, ANY, "PK_MatrixKBConfigurationGet/Set, PK_MatrixKBStatusGet",
       per.matrix_keyboard, "PoKeysLibMatrixKB.c", "C",
       "Key n = row * 8 + column (D); keys report only inside the configured size while "
       "the keyboard is on ([8] bit 0, I)."),
    _e(0xD0, ANY, "PK_LCDConfigurationGet/Set", per.lcd_configuration, "PoKeysLibLCD.c",
       "C", "Up to 4 rows of 20 columns (D)."),
    _e(0xD1, ANY, "PK_LCD operations (init, clear, cursor, print, update, ...)",
       per.lcd_operation, "PoKeysLibLCD.c", "C",
       "Text kept as the display shows it; characters past column 20 are dropped (D)."),
    _e(0xDD, ANY, "PK_PoNET (status, module settings, status, LEDs, light, PWM)", per.ponet,
       "PoKeysLibPoNET.c", "C",
       "One kbd48CNC on module 0 (type/address 0x10, D) whose 48 keys the world presses."),
    _e(0x81, ANY, "PK_FailsafeSettingsGet/Set", per.failsafe, "PoKeysLibFailsafe.c", "C",
       "After [3] x 100 ms with no valid request, the peripherals of [4] (I/O, PoExtBus, "
       "PWM in % of the period (D), pulse engine stopped and its buffer cleared) take "
       "their safe values, once until a host speaks (failsafe.py)."),
    _e(0x50, ANY, "PK_SaveConfiguration", per.save_configuration, "PoKeysLibDeviceData.c",
       "C", "Pins, counters' options, PWM, encoders, RC filter, matrix keyboard, LCD and "
       "failsafe set-ups survive a reset, and the run with an archive file (D)."),
    _e(0x52, ANY, "PK_ClearConfiguration", per.save_configuration, "PoKeysLibDeviceData.c",
       "C", "The saved set-up is the factory one again (D)."),
    _e(PEV2, 0x0A, "PK_PEv2_SyncedPWMSetup", per.synced_pwm, "PoKeysLibPulseEngine_v2.c", "I",
       "The channel's output duty follows the axis's speed / max speed (D)."),
    _e(PEV2, 0x0B, "PK_PEv2_SyncOutputsSetup", per.sync_outputs, "PoKeysLibPulseEngine_v2.c",
       "I", "Axis [4]'s buffer entries are output bits while the buffer runs: bit i drives "
       "pin mapping[8 + i] (1..55, 0 none, D), slot by slot, bytes as sent (16-bit: the "
       "low byte, D); the axis does not move."),
    *[_e(PEV2, sub, name, per.threading_request, "PoKeysLibPulseEngine_v2.c", "D",
         "Answered with zeros; threading is not modelled (nothing prepared or active).")
      for sub, name in ((0x30, "PK_PEv2_ThreadingPrepareForTrigger"),
                        (0x31, "PK_PEv2_ThreadingForceTriggerReady"),
                        (0x32, "PK_PEv2_ThreadingTrigger"),
                        (0x33, "PK_PEv2_ThreadingRelease"), (0x34, "PK_PEv2_ThreadingCancel"),
                        (0x35, "PK_PEv2_ThreadingStatusGet"),
                        (0x36, "PK_PEv2_ThreadingSetup"))],
    _e(PEV2, 0x40, "PK_PEv2_BacklashCompensationSettings_Get", per.backlash,
       "PoKeysLibPulseEngine_v2.c", "C", "On a reversal the register takes up the width "
       "(half the play) at [4] pulses a slot (0 at once; the acceleration is kept, D): "
       "the stage gets the register's pulses, the counter not. Registers at [40 + 2i]."),
    _e(PEV2, 0x41, "PK_PEv2_BacklashCompensationSettings_Set", per.backlash,
       "PoKeysLibPulseEngine_v2.c", "C"),
    _e(PEV2, 0x50, "PK_PoStep_ConfigurationGet/Set", per.postep,
       "PoKeysLibPulseEngine_v2.c", "C", "Stored and echoed."),
    _e(PEV2, 0x51, "PK_PoStep_StatusGet", per.postep, "PoKeysLibPulseEngine_v2.c", "C",
       "No PoStep answers: every status byte 0 (D)."),
    _e(PEV2, 0x52, "PK_PoStep_DriverConfigurationGet/Set (currents)", per.postep,
       "PoKeysLibPulseEngine_v2.c", "C"),
    _e(PEV2, 0x53, "PK_PoStep_DriverConfigurationGet/Set (modes)", per.postep,
       "PoKeysLibPulseEngine_v2.c", "C"),
    _e(0x82, ANY, "PK_PoIL* (state, core, memory, tasks)", per.poil, "PoKeysLibPoIL.c", "I",
       "No PoIL program runs (D): state zeros, no tasks; memory types 1..7 keep what is "
       "written (shared slots = type 4), reads of other memory give zeros (D)."),
    _e(0xD5, ANY, "PK_MatrixLEDConfigurationGet/Set", per.matrix_led,
       "PoKeysLibMatrixLED.c", "C", "Stored and read back."),
    _e(0xD6, ANY, "PK_MatrixLEDUpdate", per.matrix_led, "PoKeysLibMatrixLED.c", "C",
       "Display rows kept, not shown (D)."),
    _e(0x4B, ANY, "PK_WS2812_Update / SendLEDdata", per.taken, "PoKeysLibWS2812.c", "I",
       "Taken; no LED strip is modelled (D)."),
    _e(0xDE, ANY, "PK_UARTConfigure/Write/Read", per.uart, "PoKeysLibUART.c", "C",
       "Nothing on the line: writes taken whole, reads give 0 bytes (D)."),
    _e(0x07, ANY, "PK_Get/SetFastUSBEnableStatus", per.fast_usb, "PoKeysLibDeviceData.c",
       "I", "A network device: fast USB off (D)."),
    _e(0x84, ANY, "PK_ReadDeviceLog", per.device_log, "PoKeysLibDeviceData.c", "I",
       "An empty log (D)."),
    _e(PEV2, 0x18, "PK_PEv2_InternalDriversConfigurationGet", per.internal_drivers,
       "PoKeysLibPulseEngine_v2.c", "C", "Stored and read back; no internal driver (D)."),
    _e(PEV2, 0x19, "PK_PEv2_InternalDriversConfigurationSet", per.internal_drivers,
       "PoKeysLibPulseEngine_v2.c", "C"),
    _e(0xBB, ANY, "PK_GetDebugValues", per.taken, "PoKeysLibDeviceData.c", "I",
       "13 x i32 at [8] per part: zeros (D)."),
    _e(0x76, ANY, "PK_EasySensorsSetupGet/Set", sensors.easy_sensors_setup,
       "PoKeysLibEasySensors.c", "C", "100 sensors' set-ups stored (D)."),
    _e(0x77, ANY, "PK_EasySensorsValueGetAll", sensors.easy_sensors_values,
       "PoKeysLibEasySensors.c", "C", "Nothing attached: values 0, OK bits 0 (D)."),
    _e(0xDB, ANY, "PK_I2C*", per.i2c, "PoKeysLibI2C.c", "C",
       "Nothing on the bus: transfers end in error, a scan finds no address (D)."),
    _e(0xE5, ANY, "PK_SPI*", per.spi, "PoKeysLibSPI.c", "C",
       "Writes are sent; reads give 0xFF (nothing drives MISO, D)."),
    _e(0xDC, ANY, "PK_1Wire*", per.one_wire, "PoKeysLib1Wire.c", "C",
       "No presence pulse: read status 2 (D), scans find nothing."),
    _e(0x86, ANY, "PK_CAN*", per.can, "PoKeysLibCAN.c", "C", "No message is ever received."),
]

_BY_KEY: Final = unique_table(ENTRIES, lambda e: (e.command, e.sub), "PoKeys table")

NOT_MODELLED: Final = (
    "Hybrid probing: refused. "
    "Threading, PoIL programs, WS2812 and matrix LED displays, the UART line: answered, "
    "not modelled.")


ENGINE_OF: Final = {PEV1: 1, PEV2: 2, MULTIPART: 2}
"""Each engine's requests: a device answers the other engine's as unknown commands (D)."""
FILLS: Final = (0xFF, 0xFE, MULTIPART)


def lookup(command: int, sub: int) -> CommandEntry | None:
    return _BY_KEY.get((command, sub)) or _BY_KEY.get((command, ANY))


def answer(device: PoKeysDevice, request: Request) -> tuple[bytes, bool]:
    """The reply frame for a valid request and whether it is the device's refusal."""
    entry = lookup(request.command, request.sub)
    engine = device.identity.engine_version
    if entry is None or ENGINE_OF.get(request.command, engine) != engine:
        if request.command in FILLS or (request.command == PEV2 and request.sub in FILLS):
            return Reply(request).refuse(0).finish(), True  # a fill's refusal: 0 accepted
        return Reply(request).refuse(UNKNOWN).finish(), True
    try:
        reply = entry.handler(device, request)
    except Exception:  # a fault of ours: logged, refused with REFUSED (D), never silent
        log_fault(f"PoKeys request 0x{request.command:02X}", request.raw[:8].hex())
        return Reply(request).refuse(REFUSED).finish(), True
    if reply is None:
        return Reply(request).refuse(REFUSED).finish(), True
    return reply.finish(), reply.refused


def dispatch(device: PoKeysDevice, request: Request) -> bytes:
    """The reply frame for a valid request: the handler's, or the device's refusal."""
    return answer(device, request)[0]

"""The rest of the PoKeys behind PoKeysLib: real-time clock, PoExtBus, matrix keyboard,
LCD, PoNET (a kbd48CNC), failsafe, saving the configuration, the pulse engine's extra
settings (backlash, synced PWM and outputs, PoStep) and the buses with nothing on them
(PoKeysLibRTC.c, PoKeysLibMatrixKB.c, PoKeysLibLCD.c, PoKeysLibPoNET.c,
PoKeysLibFailsafe.c, PoKeysLibDeviceData.c, PoKeysLibPulseEngine_v2.c, the bus files).

As in io_commands.py: None is silence (a request the device does not take, nothing
changed); requests whose replies carry a status byte answer refusals there.
"""

from __future__ import annotations

import datetime as _dt
import struct

from ...personalities.pokeys.device import PoKeysDevice
from ...personalities.pokeys.io import (
    LCD_COLUMNS,
    LCD_ROWS,
    MATRIX_KEYS,
    POEXTBUS,
    PWM_CHANNELS,
    pressed_bits,
    rtc_now,
    rtc_set,
)
from .packet import Reply, Request


# ---- real-time clock ---------------------------------------------------------------------------
def rtc(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x83: [2]=0 get, [2]=0x10 set: [8] s [9] min [10] h [11] day of week [12] day
    [13] month [14] u16 day of year [16] u16 year. A set with a field out of range (or a
    date that does not exist) is refused; day of week and of year follow the date."""
    io = device.io
    seconds = device.slot / 1000.0
    if req.param(1) == 0x10:
        raw = req.raw
        year = raw[16] | raw[17] << 8
        try:
            when = _dt.datetime(year, raw[13], raw[12], raw[10], raw[9], raw[8])
        except ValueError:
            return None
        rtc_set(io, seconds, when)
    elif req.param(1) != 0:
        return None
    now = rtc_now(io, seconds)
    r = Reply(req)
    r[8], r[9], r[10] = now.second, now.minute, now.hour
    r[11] = now.isoweekday() % 7  # 0 = Sunday (D)
    r[12], r[13] = now.day, now.month
    r.put(14, struct.pack("<HH", now.timetuple().tm_yday, now.year))
    return r


# ---- PoExtBus, matrix keyboard, LCD ------------------------------------------------------------
def poextbus(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xDA: [2]=1 set the 10 output bytes [8..17] (the reply echoes them, which the
    library checks), [2]=2 get."""
    if req.param(1) == 1:
        device.io.poextbus = bytes(req.raw[8:8 + POEXTBUS])
    elif req.param(1) != 2:
        return None
    r = Reply(req)
    r.put(8, device.io.poextbus)
    return r


def matrix_keyboard(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xCA: 1 set / 10 get the configuration ([8] on, [9] size, rows/columns pins,
    macro bits [26..41], rows 8-15 [42..49]; [51] decimation), 50 decimation, 20 key
    states (128 bits at [8]); 2-9/22-29 key mapping set, 12-19/32-39 get (stored)."""
    io = device.io
    sub = req.param(1)
    r = Reply(req)
    if sub == 1:
        io.matrix_config = bytes(req.raw[8:50])
    elif sub == 50:
        io.matrix_decimation = req.raw[8]
    elif sub == 10:
        r.put(8, io.matrix_config)
        r[51] = io.matrix_decimation
    elif sub == 20:
        keys: set[int] = set()
        config = io.matrix_config
        if config[0] & 1:
            height, width = (config[1] & 0x0F) + 1, (config[1] >> 4 & 0x0F) + 1
            keys = {k for k in io.matrix_keys if k // 8 < height and k % 8 < width}
        r.put(8, pressed_bits(keys, MATRIX_KEYS))
    elif 2 <= sub <= 9 or 22 <= sub <= 29:
        io.matrix_mapping[sub] = bytes(req.raw[8:42])
    elif 12 <= sub <= 19 or 32 <= sub <= 39:
        r.put(8, io.matrix_mapping.get(sub - 10, bytes(34)))
    else:
        return None
    return r


def lcd_configuration(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xD0: [2]=1 get ([3] configuration, [4] rows, [5] columns), [2]=0 set from [3..5];
    more than 4 rows or 20 columns is refused."""
    lcd = device.io.lcd
    if req.param(1) == 0:
        config, rows, cols = req.param(2), req.param(3), req.param(4)
        if rows > LCD_ROWS or cols > LCD_COLUMNS:
            return None
        lcd.configuration, lcd.rows, lcd.columns = config, rows, cols
    elif req.param(1) != 1:
        return None
    r = Reply(req)
    r[3], r[4], r[5] = lcd.configuration, lcd.rows, lcd.columns
    return r


def lcd_operation(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xD1: 0x00 init, 0x10 clear, 0x20 cursor (column [3], row [4]), 0x30 print [8..]
    to NUL (20 max), 0x31 put char [8], 0x40 custom character [8] = index, [9..16],
    0x50 entry mode, 0x60 display on/off, 0x80 mode [3], 0x85 row [3] (1..4) = [8..27]."""
    lcd = device.io.lcd
    sub, raw = req.param(1), req.raw
    if sub == 0x00 or sub == 0x10:
        lcd.clear()
    elif sub == 0x20:
        col, row = req.param(2), req.param(3)
        if row >= LCD_ROWS or col >= LCD_COLUMNS:
            return None
        lcd.cursor = (row, col)
    elif sub in (0x30, 0x31):
        text = raw[8:28].split(b"\0")[0] if sub == 0x30 else raw[8:9]
        row, col = lcd.cursor
        for ch in text:
            if col < LCD_COLUMNS:
                lcd.text[row][col] = ch
            col += 1
        lcd.cursor = (row, min(col, LCD_COLUMNS))
    elif sub == 0x40:
        if raw[8] > 7:
            return None
        lcd.custom[raw[8]] = bytes(raw[9:17])
    elif sub == 0x50:
        lcd.entry = (raw[8], raw[9])
    elif sub == 0x60:
        lcd.display = (raw[8], raw[9], raw[10])
    elif sub == 0x80:
        lcd.mode = req.param(2)
    elif sub == 0x85:
        row = req.param(2)
        if not 1 <= row <= LCD_ROWS:
            return None
        lcd.text[row - 1][:] = raw[8:28]
    else:
        return None
    return Reply(req)


# ---- PoNET: a kbd48CNC on module 0 -------------------------------------------------------------
KBD48_MODULE = 0
KBD48_TYPE = 0x10  # module type byte the settings report (D)
KBD48_ADDRESS = 0x10  # its I2C address (D)


def ponet(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xDD: 0x00 bus status [8]; 0x10 module settings (module [3]: address [8], type
    [9], size [10], options [11]); 0x50 status request ([3]=0x10, module [4]) / read
    ([3]=0x30: [3]=1, [8]=0, 16 bytes at [9], the keys pressed); 0x55 LEDs [8..23];
    0x60 light request/read ([8]=0, [9] value); 0x70 PWM ([3] module, [4] duty).
    Another module ID: settings all zero, reads fail ([3]=0 / [8]=1), D."""
    kbd = device.io.kbd48
    sub = req.param(1)
    r = Reply(req)
    if sub == 0x00:
        r[8] = 1  # bus present and running (D)
    elif sub == 0x10:
        if req.param(2) == KBD48_MODULE:
            r[8], r[9], r[10], r[11] = KBD48_ADDRESS, KBD48_TYPE, 6, 0
    elif sub in (0x50, 0x60):
        phase, module = req.param(2), req.param(3)
        if phase == 0x10:
            ok = module == KBD48_MODULE
            if sub == 0x50:
                kbd.status_requested = ok
            else:
                kbd.light_requested = ok
        elif phase == 0x30:
            if sub == 0x50:
                if kbd.status_requested:
                    r[3], r[8] = 1, 0
                    r.put(9, pressed_bits(kbd.keys, 128))
                else:
                    r[3], r[8] = 0, 1
            elif kbd.light_requested:
                r[8], r[9] = 0, kbd.light
            else:
                r[8] = 1
        else:
            return None
    elif sub == 0x55:
        if req.param(2) == KBD48_MODULE:
            kbd.leds = bytes(req.raw[8:24])
    elif sub == 0x70:
        if req.param(2) == KBD48_MODULE:
            kbd.pwm = req.param(3)
    else:
        return None
    return r


# ---- failsafe, configuration -------------------------------------------------------------------
def failsafe(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x81: [2]=0 get, 1 set: [3] enabled, [4] peripherals, [8..14] I/O, [15..24]
    PoExtBus, [25..30] PWM; the device's FailsafeWatch acts on them (failsafe.py)."""
    io = device.io
    if req.param(1) == 1:
        io.failsafe = bytes(req.raw[3:5]) + bytes(req.raw[8:31])
    elif req.param(1) != 0:
        return None
    r = Reply(req)
    r[3], r[4] = io.failsafe[0], io.failsafe[1]
    r.put(8, io.failsafe[2:])
    return r


def save_configuration(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x50 AA 55 save, 0x52 AA 55 clear the saved configuration; other keys are silent."""
    if req.param(1) != 0xAA or req.param(2) != 0x55:
        return None
    try:
        if req.command == 0x50:
            device.io.save()
        else:
            device.io.clear_saved()
    except OSError:
        return None  # the flash (archive file) cannot be written: the host sees no reply
    return Reply(req)


def _pev2(device: PoKeysDevice) -> bool:
    """0x85 requests belong to pulse engine v2: a PoKeys56E (v1) is silent on them."""
    return device.identity.engine_version == 2


# ---- pulse engine extras -----------------------------------------------------------------------
def backlash(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x85 0x40 get / 0x41 set: [3] enabled, [4] max speed, per axis u16 width [8 + 4i]
    and acceleration [10 + 4i]; the registers i16 [40 + 2i] (device.apply_backlash)."""
    if not _pev2(device):
        return None
    io = device.io
    if req.sub == 0x41:
        io.backlash = bytes(req.raw[3:5]) + bytes(req.raw[8:40])
        device.apply_backlash()
    r = Reply(req)
    r[3], r[4] = io.backlash[0], io.backlash[1]
    r.put(8, io.backlash[2:34])
    for a in device.engine.axes[:8]:
        r.put(40 + 2 * a.index, struct.pack("<h", a.backlash_register))
    return r


def synced_pwm(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x85 0x0A enabled [3], source axis [4], PWM channel [5]: the channel's duty then
    follows the axis's speed as a fraction of its max speed (D); axis >= 8 or channel
    >= 6 is refused."""
    if not _pev2(device):
        return None
    enabled, axis, channel = req.param(2), req.param(3), req.param(4)
    if axis >= len(device.engine.axes) or channel >= PWM_CHANNELS:
        return None
    device.io.synced_pwm = (1 if enabled else 0, axis, channel)
    return Reply(req)


def sync_outputs(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x85 0x0B: fast outputs synced to axis [4] (when [3]), mapping [8..15]: the axis's
    buffer entries then drive the mapped outputs slot by slot (device.sync_outputs)."""
    if not _pev2(device):
        return None
    if req.param(2) and req.param(3) >= len(device.engine.axes):
        return None
    device.io.sync_outputs = bytes(req.raw[3:5]) + bytes(req.raw[8:16])
    device.apply_sync_outputs()
    return Reply(req)


def postep(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x85 0x50 configuration ([3]=0x10 set: [4] communication on, 8 x (type, I2C
    address, update) at [8 + 3i]); 0x51 status (no PoStep answers on the bus: zeros, D);
    0x52 currents (3 x u16 at [8 + 6i]) and 0x53 modes ([8 + 6i] mode, step mode,
    temperature limit), [3]=0x10 set. Replies carry the stored values."""
    if not _pev2(device):
        return None
    io = device.io
    sub, setting = req.sub, req.param(2) == 0x10
    r = Reply(req)
    if sub == 0x50:
        if setting:
            io.postep = bytes([req.param(3)]) + bytes(req.raw[8:32])
        r[4] = io.postep[0]
        r.put(8, io.postep[1:])
    elif sub == 0x51:
        pass
    elif sub == 0x52:
        if setting:
            io.postep_currents = bytes(req.raw[8:56])
        r.put(8, io.postep_currents)
    elif sub == 0x53:
        if setting:
            modes = bytearray(48)
            for i in range(8):
                modes[6 * i:6 * i + 3] = req.raw[8 + 6 * i:11 + 6 * i]
            io.postep_modes = bytes(modes)
        r.put(8, io.postep_modes)
    else:
        return None
    return r


# ---- buses with nothing on them ----------------------------------------------------------------
I2C_ERROR, I2C_COMPLETE = 0, 1


def i2c(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xDB: 0/1 activate, 2 status ([3]); 0x10 write (and read) start, 0x20 read start;
    0x11/0x21 status: no device acknowledges, [3] = error (0); 0x30 scan, 0x31 results:
    complete ([3]=1), no address present (bits [9..24] all 0)."""
    io = device.io
    sub = req.param(1)
    r = Reply(req)
    if sub in (0, 1):
        io.i2c_active = sub
    elif sub == 2:
        r[3] = io.i2c_active
    elif sub in (0x10, 0x20, 0x30):
        pass
    elif sub in (0x11, 0x21):
        r[3] = I2C_ERROR
    elif sub == 0x31:
        r[3] = I2C_COMPLETE
    else:
        return None
    return r


def spi(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xE5: 0x01 configure, 0x10 write ([3]=1 sent: SPI has no acknowledge), 0x20 read
    [3] bytes ([3]=1, bytes 0xFF: nothing drives MISO, D); more than 56 is refused."""
    sub = req.param(1)
    r = Reply(req)
    if sub == 0x01:
        pass
    elif sub in (0x10, 0x20):
        length = req.param(2)
        if length > 56:
            return None
        r[3] = 1
        if sub == 0x20:
            r.put(8, b"\xff" * length)
    else:
        return None
    return r


def one_wire(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xDC: 0/1 activate; 0x10 write/read start; 0x11 status ([3] active, [8] read
    status 2 = no presence pulse, D; nothing read); 0x20-0x23 scan: results [8]=1
    done, [9]=0 no device."""
    io = device.io
    sub = req.param(1)
    r = Reply(req)
    if sub in (0, 1):
        io.onewire_active = sub
    elif sub == 0x11:
        r[3], r[8], r[9] = io.onewire_active, 2, 0
    elif sub == 0x21:
        r[8], r[9] = 1, 0
    elif sub in (0x10, 0x20, 0x22, 0x23):
        pass
    else:
        return None
    return r


def can(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x86: 0x01 configure, 0x10 filter, 0x20 write (taken; nobody acknowledges), 0x31
    read: [3]=0 no message, 0x32 flush."""
    if req.param(1) not in (0x01, 0x10, 0x20, 0x31, 0x32):
        return None
    return Reply(req)


POIL_MEMORIES = 8  # memory types kept (D); 4 = the shared slots
POIL_MEMORY = 0x10000 + 64  # bytes per type: a 16-bit address and one chunk past it


def poil(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x82: PoIL, the device's own program core. No program runs (D): the state (0x00)
    is all zeros; core state, master enable, reset, debug mode (0x01-0x05) and erase
    (0x16) are taken; task status (0x20) lists none; memory reads (0x10/0x11: type [3],
    address [4..5], length [8] <= 54) give what was written (0x15: length [8], bytes
    [9..]) to memory types 1..7, zeros elsewhere (shared slots are type 4)."""
    sub = req.param(1)
    r = Reply(req)
    memories = device.io.poil_memory
    if sub in (0x00, 0x01, 0x02, 0x03, 0x05, 0x20):
        return r
    kind, address, length = req.param(2), req.param(3) | req.param(4) << 8, req.raw[8]
    if sub == 0x16:
        memories.pop(kind, None)
    elif sub in (0x10, 0x11):
        if length > 54 or kind >= POIL_MEMORIES:
            return None
        memory = memories.get(kind)
        if memory is not None and sub == 0x10:
            r.put(8, bytes(memory[address:address + length]))
    elif sub == 0x15:
        if kind == 0:
            return r  # "write the buffer to flash": nothing runs it (D)
        if length > 55 or kind >= POIL_MEMORIES:
            return None
        memory = memories.setdefault(kind, bytearray(POIL_MEMORY))
        memory[address:address + length] = req.raw[9:9 + length]
    else:
        return None
    return r


def taken(device: PoKeysDevice, req: Request) -> Reply:
    """A request the device takes with an empty reply (what it drives is not modelled:
    its table entry says what)."""
    return Reply(req)


def matrix_led(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xD5: [2]=0 set ([3] displays on, [4]/[5] rows + columns * 16), [2]=1 get; 0xD6
    display update (rows [8..15], kept)."""
    io = device.io
    if req.command == 0xD6:
        io.matrix_led_data[req.param(1) & 0xFF] = bytes(req.raw[8:16])
        return Reply(req)
    if req.param(1) == 0:
        io.matrix_led = bytes(req.raw[3:6])
    elif req.param(1) != 1:
        return None
    r = Reply(req)
    r.put(3, io.matrix_led)
    return r


def uart(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xDE: 0x10 configure, 0x20 write [4] bytes (all taken: [3] = [4]), 0x30 read
    (nothing on the line: [3] = 0 bytes)."""
    sub = req.param(1)
    r = Reply(req)
    if sub == 0x20:
        if req.param(3) > 55:
            return None
        r[3] = req.param(3)
    elif sub == 0x30:
        r[3] = 0
    elif sub != 0x10:
        return None
    return r


def threading_request(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x85 0x30-0x36 threading: set-up (0x36) taken; prepare, force ready, trigger,
    release, cancel taken; status (0x35) reports nothing preparing, prepared, pending or
    active and no spindle (zeros): threading is not modelled (D)."""
    if not _pev2(device):
        return None
    return Reply(req)


def fast_usb(device: PoKeysDevice, req: Request) -> Reply:
    """0x07: fast USB on/off ([2]) or its status ([2]=10 -> [2]): a network device has
    it off (0, D)."""
    r = Reply(req)
    r[2] = 0
    return r


def internal_drivers(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x85 0x18 get / 0x19 set: 4 x (step, current) configuration at [8 + 2i]; stored
    and read back (the 57 series here drives external drivers, D)."""
    if not _pev2(device):
        return None
    if req.sub == 0x19:
        device.io.internal_drivers = bytes(req.raw[8:16])
    r = Reply(req)
    r.put(8, device.io.internal_drivers)
    return r


def device_log(device: PoKeysDevice, req: Request) -> Reply:
    """0x84: the device's log, [2] entries of u16 at [8]: empty (D)."""
    r = Reply(req)
    r[2] = 0
    return r

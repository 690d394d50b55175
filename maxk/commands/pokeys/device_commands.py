"""Device-level commands of the connect sequence (reference section 4) and discovery."""

from __future__ import annotations

from ...personalities.pokeys.device import PoKeysDevice
from .packet import Reply, Request


def read_serial_firmware(device: PoKeysDevice, req: Request) -> Reply:
    """0x00: serial and firmware; 'PKEx' at [8..11] selects the extended layout."""
    ident = device.identity
    r = Reply(req)
    r[2], r[3] = ident.serial >> 8 & 0xFF, ident.serial & 0xFF
    r[4], r[5] = ident.firmware
    if ident.extended_id:
        r.put(8, b"PKEx")
        r.put(12, (ident.serial & 0xFFFFFFFF).to_bytes(4, "little"))
        r[18] = ident.hw_type
        r.put(20, ident.build_date.encode("ascii")[:11].ljust(11, b"\0"))
        r.put(31, ident.model.encode("ascii")[:10].ljust(10, b"\0"))
        r[41] = 0  # firmware type: main firmware
        r[42], r[43] = ident.firmware  # secondary firmware version
        r[57] = ident.product_id
        r[61] = 0  # not the bootloader
    return r


def set_user_id(device: PoKeysDevice, req: Request) -> Reply:
    """0x02: the user ID becomes [2] (the reply and 0x03 report it at [2]); the user ID
    is what tells devices apart on a discovery (byte 0 of its answer)."""
    device.user_id = req.param(1)
    r = Reply(req)
    r[2] = device.user_id
    return r


def read_user_id(device: PoKeysDevice, req: Request) -> Reply:
    """0x03: user ID [2], device lock status [3]."""
    r = Reply(req)
    r[2], r[3] = device.user_id, device.lock_status
    return r


def read_build_date(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x04 part 0/1/2: build date bytes at [2..5] (4 + 4 + 3 characters)."""
    part = req.param(1)
    if part > 2:
        return None
    date = device.identity.build_date.encode("ascii")[:11].ljust(12, b"\0")
    r = Reply(req)
    r.put(2, date[part * 4:part * 4 + 4] if part < 2 else date[8:11] + b"\0")
    return r


def device_name(device: PoKeysDevice, req: Request) -> Reply | None:
    """0x06: get ([2]=0) the short name [8..17] and long name [35..54]; set ([2]=1)."""
    if req.param(1) == 1:
        device.name = req.raw[8:18].split(b"\0")[0].decode("latin-1")
    elif req.param(1) != 0:
        return None
    r = Reply(req)
    name = device.name.encode("latin-1")
    r.put(8, name[:10].ljust(10, b"\0"))
    r.put(35, name[:20].ljust(20, b"\0"))
    return r


def network_config(device: PoKeysDevice, req: Request) -> Reply | None:
    """0xE0: get ([2]=0) or set ([2]=10) the network configuration."""
    net = device.network
    if req.param(1) == 10:
        raw = req.raw
        net.dhcp = raw[8]
        net.ip_setup = (raw[9], raw[10], raw[11], raw[12])
        net.tcp_timeout = raw[17] | raw[18] << 8
        if raw[27] == 1:
            net.gateway = (raw[19], raw[20], raw[21], raw[22])
            net.subnet_mask = (raw[23], raw[24], raw[25], raw[26])
            net.options = raw[28]
    elif req.param(1) != 0:
        return None
    r = Reply(req)
    r[8] = net.dhcp
    r.put(9, bytes(net.ip_setup))
    r.put(13, bytes(net.ip_current))
    r[17], r[18] = net.tcp_timeout & 0xFF, net.tcp_timeout >> 8
    r.put(19, bytes(net.gateway))
    r.put(23, bytes(net.subnet_mask))
    r[27] = net.options
    return r


def activated_options(device: PoKeysDevice, req: Request) -> Reply:
    """0x8F: activated options [8] (activation codes are not modelled: unchanged)."""
    r = Reply(req)
    r[8] = device.identity.activated_options
    return r


def discovery_reply(device: PoKeysDevice, host_ip: tuple[int, int, int, int]) -> bytes:
    """Answer to a zero-length discovery datagram (reference section 5): the 19-byte
    form on extended-ID devices, the 14-byte form on the old-ID PoKeys56E."""
    ident, net = device.identity, device.network
    reply = bytearray(19 if ident.extended_id else 14)
    reply[0] = device.user_id
    reply[1], reply[2] = ident.serial >> 8 & 0xFF, ident.serial & 0xFF
    reply[3], reply[4] = ident.firmware
    reply[5:9] = bytes(net.ip_current)
    reply[9] = net.dhcp
    reply[10:14] = bytes(host_ip)
    if ident.extended_id:
        reply[14:18] = (ident.serial & 0xFFFFFFFF).to_bytes(4, "little")
        reply[18] = ident.hw_type
    return bytes(reply)

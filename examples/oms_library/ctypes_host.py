"""A Python host written for the vendor's Windows library, run against maxk.

Code that drove a MAXk through OmsMAXkMC.dll with ctypes runs unchanged but for the line
that loads the library. On Windows it read

    lib = ctypes.WinDLL("C:/.../OmsMAXkMC.dll")

and here it reads (the path `maxk library` prints):

    lib = ctypes.CDLL(LIBRARY)

Run a board and this host:

    maxk serve --shm /dev/shm/maxk &
    python3 examples/oms_library/ctypes_host.py

(`MAXK_OMSMAXK1=tcp:HOST:PORT` reaches a board over TCP instead; docs/oms-library.md.)
Everything below the loading line is written the way such hosts are: the name in a
string buffer, 80-byte reply buffers, `byref(c_long)` for values, the handle kept as the
plain int ctypes returns, 0 meaning "driver not loaded", return codes 0..6 by name.
"""

import ctypes as ct
import os
import sys

LIBRARY = os.environ.get("OMS_LIBRARY") or os.popen("maxk library --path").read().strip()
RETURN_CODES = ["Success", "Command time out", "Response time out", "Invalid axis selection",
                "Move time out", "Invalid parameter", "Invalid bit number"]


def said(code: int) -> str:
    return RETURN_CODES[code] if 0 <= code < len(RETURN_CODES) else f"unknown code {code}"


def main() -> int:
    lib = ct.CDLL(LIBRARY)  # the one changed line (was: ct.WinDLL(".../OmsMAXkMC.dll"))

    name = [ct.create_string_buffer(b"OmsMAXk1")]
    handle = lib.GetOmsHandle((ct.c_char_p)(*map(ct.addressof, name)))
    if handle == 0:
        print("Driver for device was not loaded.")
        return 1

    model = ct.create_string_buffer(80)
    print("description:", said(lib.GetOmsControllerDescription(handle, model)),
          model.value.decode())

    x = ct.c_long(1)  # OMS_X_AXIS
    print("base velocity:", said(lib.SetOmsAxisBaseVelocity(handle, x, ct.c_long(100))))
    print("velocity:", said(lib.SetOmsAxisVelocity(handle, x, ct.c_long(20000))))
    print("acceleration:", said(lib.SetOmsAxisAcceleration(handle, x, ct.c_long(200000))))
    print("too fast:", said(lib.SetOmsAxisVelocity(handle, x, ct.c_long(4000001))))
    print("two axes at once:", said(lib.MoveOmsAxisRel(handle, ct.c_long(3), ct.c_long(10))))
    print("load position:", said(lib.SetOmsAxisPosition(handle, x, ct.c_long(0))))
    print("move:", said(lib.MoveOmsAxisRelWait(handle, x, ct.c_long(2500), ct.c_long(5000))))

    position = ct.c_long(0)
    lib.GetOmsAxisMotorPosition(handle, x, ct.byref(position))
    velocity = ct.c_long(0)
    lib.GetOmsAxisVelocity(handle, x, ct.byref(velocity))
    print("position:", position.value, "velocity:", velocity.value)

    print("bit 12 high:", said(lib.SetOmsIOBit(handle, ct.c_long(12), ct.c_long(1))))
    print("bit 16:", said(lib.SetOmsIOBit(handle, ct.c_long(16), ct.c_long(1))))
    bits = ct.c_long(0)
    lib.GetAllOmsIOBits(handle, ct.byref(bits))
    print(f"bits: {bits.value:04x}")

    reply = ct.create_string_buffer(80)
    lib.SendAndGetString(handle, ct.create_string_buffer(b"AXRP"), reply)
    print("AXRP:", reply.value.decode())
    lib.CloseOmsHandle(handle)
    return 0


if __name__ == "__main__":
    sys.exit(main())

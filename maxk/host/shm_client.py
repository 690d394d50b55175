"""A host-side client for the shared-memory door: what a legacy PCI program does, in
Python. It touches only the mapped file: the rings, the indices, the doorbell.

    host = SharedMemoryHost("/dev/shm/maxk")
    host.send("AX;VL5000;AC50000;MR1000;GO;ID;")
    host.wait_doorbell(0x1)            # done X
    host.clear_doorbell(0x1)           # write-one-to-clear
    print(host.query("AX RP"))         # through the command and response rings

A mapping touched past the end of a file that shrank is SIGBUS for the whole process, so
every access first checks the file's size (`MapTruncated` instead of the signal). The
server never shrinks its map (it clears a reused one in place); this guards against any
other process that does. The check and the access are two steps: a file cut between
them still faults, which only a reader with pread (libOmsMAXkMC) is safe from.
"""

from __future__ import annotations

import mmap
import os
import struct
import time

from maxk.host import memory_map as M

_U32 = struct.Struct(">I")
_I32 = struct.Struct(">i")


class MapTruncated(ConnectionError):
    """The map file is shorter than the map: touching it would be SIGBUS."""


class SharedMemoryHost:
    def __init__(self, path: str) -> None:
        self._fd = os.open(path, os.O_RDWR | os.O_CLOEXEC)
        try:
            self._check()
            self.mem = mmap.mmap(self._fd, M.SIZE)
        except BaseException:
            os.close(self._fd)
            raise
        self._text = b""

    def _check(self) -> None:
        size = os.fstat(self._fd).st_size
        if size < M.SIZE:
            raise MapTruncated(f"the map file holds {size} bytes, not {M.SIZE}")

    def _get(self, offset: int) -> int:
        self._check()
        return _U32.unpack_from(self.mem, offset)[0]

    def _put(self, offset: int, value: int) -> None:
        self._check()
        _U32.pack_into(self.mem, offset, value & 0xFFFF_FFFF)

    # ---- text ------------------------------------------------------------------------
    def send(self, text: str) -> None:
        """Write command text at the insert index and advance it (waits for ring room)."""
        data = text.encode("latin-1")
        while data:
            insert = self._get(M.CMD_INSERT) % M.RING_SIZE
            process = self._get(M.CMD_PROCESS) % M.RING_SIZE
            free = (process - insert - 1) % M.RING_SIZE
            if not free:
                time.sleep(0.0002)
                continue
            chunk, data = data[:free], data[free:]
            self._check()
            for i, byte in enumerate(chunk):
                self.mem[M.CMD_RING + (insert + i) % M.RING_SIZE] = byte
            self._put(M.CMD_INSERT, (insert + len(chunk)) % M.RING_SIZE)

    def read_line(self, timeout: float = 5.0) -> str:
        """The next reply from the response ring (advancing the process index)."""
        deadline = time.monotonic() + timeout
        while b"\n" not in self._text:
            insert = self._get(M.RESP_INSERT) % M.RING_SIZE
            process = self._get(M.RESP_PROCESS) % M.RING_SIZE
            if insert != process:
                n = (insert - process) % M.RING_SIZE
                self._check()
                self._text += bytes(self.mem[M.RESP_RING + (process + i) % M.RING_SIZE]
                                    for i in range(n))
                self._put(M.RESP_PROCESS, insert)
                self._put(M.OMR0, 0)
                continue
            if time.monotonic() > deadline:
                raise TimeoutError("no reply in the response ring")
            time.sleep(0.0002)
        line, self._text = self._text.split(b"\n", 1)
        return line.decode("latin-1")

    def query(self, text: str, timeout: float = 5.0) -> str:
        self.send(text if text.endswith((";", "\r", "\n")) else text + ";")
        return self.read_line(timeout)

    # ---- registers -------------------------------------------------------------------
    @property
    def doorbell(self) -> int:
        return self._get(M.ODBR)

    def clear_doorbell(self, mask: int, timeout: float = 5.0) -> None:
        """Write ones to clear doorbell bits. The clear word is a mailbox: wait until the
        board has taken the last one (it writes 0 back), then write, so no clear is lost."""
        deadline = time.monotonic() + timeout
        while self._get(M.ODBR_CLEAR):
            if time.monotonic() > deadline:
                raise TimeoutError("the board has not taken the last doorbell clear")
            time.sleep(0.0002)
        self._put(M.ODBR_CLEAR, mask)

    def wait_doorbell(self, mask: int, timeout: float = 5.0) -> int:
        deadline = time.monotonic() + timeout
        while not self.doorbell & mask:
            if time.monotonic() > deadline:
                raise TimeoutError(f"doorbell bits {mask:#x} never set")
            time.sleep(0.0002)
        return self.doorbell

    @property
    def firmware_flags(self) -> int:
        return self._get(M.FIRMWARE_FLAGS)

    def motor_position(self, axis: int) -> int:
        self._check()
        return _I32.unpack_from(self.mem, M.motor_offset(axis))[0]

    def encoder_position(self, axis: int) -> int:
        self._check()
        return _I32.unpack_from(self.mem, M.encoder_offset(axis))[0]

    def snapshot(self, axes: int, timeout: float = 5.0) -> list[tuple[int, int]]:
        """Ask for a coherent snapshot (position request mailbox) and read it."""
        self._put(M.POSITION_REQUEST, 1)
        deadline = time.monotonic() + timeout
        while self._get(M.POSITION_REQUEST):
            if time.monotonic() > deadline:
                raise TimeoutError("no snapshot")
            time.sleep(0.0002)
        self._check()
        return [(_I32.unpack_from(self.mem, M.snapshot_motor_offset(a))[0],
                 _I32.unpack_from(self.mem, M.snapshot_encoder_offset(a))[0])
                for a in range(axes)]

    def kill_all(self, timeout: float = 5.0) -> None:
        """The direct command mailbox: kill all motion without the text buffer."""
        self._put(M.DIRECT_MAILBOX, M.DIRECT_KILL_ALL)
        deadline = time.monotonic() + timeout
        while self._get(M.DIRECT_MAILBOX) == M.DIRECT_KILL_ALL:
            if time.monotonic() > deadline:
                raise TimeoutError("direct command not taken")
            time.sleep(0.0002)

    def close(self) -> None:
        self.mem.close()
        os.close(self._fd)

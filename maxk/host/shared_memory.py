"""The PCI shared-memory door: the Table 3-1 map as a file other processes can mmap.

After every pacing pass (about every millisecond of wall time) the door:
- applies what the host wrote: doorbell bits to clear, a direct command (kill all
  motion), a position request (answered with a coherent snapshot), and new text in the
  command ring (consumed up to the insert index, process index advanced);
- writes what the board shows: positions, encoders, limit/home/I/O words, W/K status,
  DAC outputs, absolute encoder positions, the capture ring, the doorbell image, the
  tick counter, and replies into the response ring (insert index advanced, OMR0 set).

Replies in the response ring end with LF, as MAXv replies do from firmware 1.30
(evidence 3.2). Layout and every choice the manual leaves open: memory_map.py and
docs/shared-memory.md.
"""

from __future__ import annotations

import contextlib
import mmap
import os
import struct

from maxk.commands.max.interpreter import Interpreter
from maxk.host import memory_map as M

_U32 = struct.Struct(">I")
_I32 = struct.Struct(">i")
MAX_PENDING_REPLIES = 64 * 1024  # bytes held while the host does not read the ring


class SharedMemoryDoor:
    def __init__(self, service, path: str) -> None:  # type: ignore[no-untyped-def]
        self.service = service
        self.maxk = service.controller  # a MAXk: the PCI map is a MAXk door
        self.board = service.controller.board
        self.interpreter = Interpreter(self.board)
        self.path = path
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_TRUNC, 0o666)
        try:
            os.ftruncate(fd, M.SIZE)
            self.mem = mmap.mmap(fd, M.SIZE)
        finally:
            os.close(fd)
        self._pending = bytearray()  # replies not yet in the response ring
        self._put(M.FIRMWARE_FLAGS, self.board.firmware_flags)
        self.mem[M.LAYOUT : M.LAYOUT + 4] = M.LAYOUT_MAGIC
        self._put(M.BOARD_NUMBER, service.number)
        self._written_removal = 0

    # ---- raw access -------------------------------------------------------------------
    def _get(self, offset: int) -> int:
        return _U32.unpack_from(self.mem, offset)[0]

    def _put(self, offset: int, value: int) -> None:
        _U32.pack_into(self.mem, offset, value & 0xFFFF_FFFF)

    def _put_signed(self, offset: int, value: int) -> None:
        _I32.pack_into(self.mem, offset, value)

    # ---- one pass ---------------------------------------------------------------------
    def update(self) -> None:
        board = self.board
        self.service.pacer.sync()
        # Table 3-4: 0xFFFFFFFF until power-up (or reset) initialization has run
        self._put(M.FIRMWARE_FLAGS, board.firmware_flags)
        clear = self._get(M.ODBR_CLEAR)
        if clear:
            board.write_doorbell(clear)
            self._put(M.ODBR_CLEAR, 0)
        code = self._get(M.DIRECT_MAILBOX)
        if code:
            if code == M.DIRECT_KILL_ALL:
                board.kill_all()
                self._put(M.DIRECT_MAILBOX, M.DIRECT_DONE)
            elif code == M.DIRECT_RESET:
                board.reset()
                self.interpreter = Interpreter(board)  # a half-received command is lost
                self._pending.clear()
                self._put(M.DIRECT_MAILBOX, M.DIRECT_DONE)
                self._put(M.FIRMWARE_FLAGS, board.firmware_flags)
            elif code != M.DIRECT_UNKNOWN:
                self._put(M.DIRECT_MAILBOX, M.DIRECT_UNKNOWN)
        self._read_commands()
        self._write_status()
        if self._get(M.POSITION_REQUEST):
            self._write_snapshot()
            self._put(M.POSITION_REQUEST, 0)
        self._write_replies()

    def _read_commands(self) -> None:
        if len(self._pending) >= MAX_PENDING_REPLIES:
            return  # the host is not reading replies: leave its commands in the ring
        insert = self._get(M.CMD_INSERT) % M.RING_SIZE
        process = self._get(M.CMD_PROCESS) % M.RING_SIZE
        if insert == process:
            return
        if insert > process:
            data = self.mem[M.CMD_RING + process : M.CMD_RING + insert]
        else:
            data = (self.mem[M.CMD_RING + process : M.CMD_RING + M.RING_SIZE]
                    + self.mem[M.CMD_RING : M.CMD_RING + insert])
        self._put(M.CMD_PROCESS, insert)
        for reply in self.interpreter.write(data):
            self._pending += reply.encode("latin-1") + b"\n"

    def _write_replies(self) -> None:
        insert = self._get(M.RESP_INSERT) % M.RING_SIZE
        process = self._get(M.RESP_PROCESS) % M.RING_SIZE
        if self._pending:
            free = (process - insert - 1) % M.RING_SIZE  # one byte kept empty: full != empty
            n = min(free, len(self._pending))
            for i in range(n):
                self.mem[M.RESP_RING + (insert + i) % M.RING_SIZE] = self._pending[i]
            del self._pending[:n]
            insert = (insert + n) % M.RING_SIZE
            self._put(M.RESP_INSERT, insert)
        unread = (insert - process) % M.RING_SIZE
        self._put(M.MESSAGE_SEMAPHORE, unread)
        if unread:
            self._put(M.OMR0, 1)

    def _write_status(self) -> None:
        board = self.board
        put_signed = self._put_signed
        for axis in board.axes:
            i = axis.index
            put_signed(M.motor_offset(i), axis.motor_position(board))
            put_signed(M.encoder_offset(i), axis.encoder_position(board))
            put_signed(M.dac_offset(i), axis.dac)
            put_signed(M.ABSOLUTE_ENCODERS + 4 * i, axis.encoder_position(board))
            if i >= 8:
                self._put(M.STATUS_WK + 4 * (i - 8), axis.flags)
        self._put(M.LIMIT_WORD, board.limit_status_word())
        self._put(M.HOME_WORD, board.home_status_word())
        self._put(M.IO_WORD, board.io.word(board))
        self._put(M.ODBR, board.doorbell)
        self._put(M.TICK, board.tick)
        ring = board.capture_ring
        host_removal = self.mem[M.CAPTURE + 1]
        # The host takes entries by advancing the removal index (0x1541). It can only move
        # forward over entries that exist; anything else is ignored.
        if (host_removal != self._written_removal and host_removal < 55
                and (host_removal - ring.removal) % 55 <= len(ring)):
            ring.removal = host_removal
        self.mem[M.CAPTURE : M.CAPTURE + 552] = ring.to_bytes()
        self._written_removal = ring.removal
        self._put(M.OMR1, 0x2 if len(ring) else 0)

    def _write_snapshot(self) -> None:
        board = self.board
        for axis in board.axes:
            i = axis.index
            self._put_signed(M.snapshot_motor_offset(i), axis.motor_position(board))
            self._put_signed(M.snapshot_encoder_offset(i), axis.encoder_position(board))
            self._put_signed(M.snapshot_dac_offset(i), axis.dac)

    def close(self) -> None:
        with contextlib.suppress(ValueError):
            self.mem.close()
        with contextlib.suppress(FileNotFoundError):
            os.unlink(self.path)


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

The map file (decisions D, issue 18): a new file is created exclusively, mode 0600; an
existing path is taken over only when it is a regular file holding a map of this board
number (the layout tag and board number a killed server left), and then cleared in
place, never truncated (a host may still have it mapped: issue 34). A symbolic
link is never followed, anything else is refused untouched. The server holds an
exclusive flock on its map for as long as it runs, so a second server on the same path
refuses. On exit the file is deleted only while the path still names the file we used.

The server itself never maps the file: it reads and writes it with pread/pwrite, which
share the page cache with the hosts' mappings. Another process may truncate the file
at any moment, and a mapping touched past the new end kills the whole server with
SIGBUS; a short pread is only a short read. Before each pass the door checks the file's
size and that the path still names it; a truncated, removed or replaced map is
reported on stderr and that door alone stops (decision D: the host broke the map, so
recreating it under the host would hide that). The board and its other doors go on.
"""

from __future__ import annotations

import asyncio
import contextlib
import fcntl
import os
import stat
import struct
import sys
import threading
import time

from maxk.commands.max.interpreter import Interpreter
from maxk.host import memory_map as M
from maxk.host.client import SYNC_BUDGET

WATCH_SECONDS = 0.0002  # how often the watcher reads the command ring's insert index

_U32 = struct.Struct(">I")
_I32 = struct.Struct(">i")
MAX_PENDING_REPLIES = 64 * 1024  # bytes held while the host does not read the ring
LOCK_PATIENCE = 0.2  # seconds a reused map's lock is waited for (a host's probe is brief)
MAP_MODE = 0o600  # the map, as every file the server writes for its user (issue 34)

# Regions only the board writes, copied from the door's image to the file after a pass
# when they changed (one pwrite each); the host-written words between them are never
# overwritten.
_STATUS_BLOCKS = (
    (M.MOTOR_XS, M.FIRMWARE_FLAGS),  # motor and encoder X..S, limit and home words
    (M.IO_WORD, M.IO_WORD + 4),
    (M.MOTOR_WK, M.STATUS_WK + 8),  # W K motor, encoder, their snapshots, W K status
    (M.DAC_XS, M.DAC_WK + 8),  # DACs X..S, their snapshots, W K
    (M.ABSOLUTE_ENCODERS, M.ABSOLUTE_ENCODERS + 40),
    (M.ODBR, M.ODBR + 4),
    (M.OMR1, M.TICK + 4),
)
_SNAPSHOT_BLOCKS = (
    (M.SNAP_MOTOR_XS, M.SNAP_ENCODER_XS + 32),
    (M.SNAP_MOTOR_WK, M.SNAP_ENCODER_WK + 8),
    (M.SNAP_DAC_XS, M.DAC_WK),
)


class MapLost(Exception):
    """The map file shrank, vanished or was replaced under the door."""


class SharedMemoryDoor:
    def __init__(self, service, path: str) -> None:  # type: ignore[no-untyped-def]
        self.service = service
        self.maxk = service.controller  # a MAXk: the PCI map is a MAXk door
        self.board = service.controller.board
        self.interpreter = Interpreter(self.board)
        self.path = path
        self.fd = _open_map(path, service.number)
        self.stopped: str | None = None  # why the door stopped (the map was broken)
        try:
            # Ours now: nothing of an earlier run stays. Cleared in place, never truncated:
            # a host of the killed server may still have the file mapped, and a mapping
            # touched past a shrunken end is SIGBUS for that host (issue 34). The file is
            # new (size 0) or a map of exactly M.SIZE bytes (_open_map checked).
            if os.fstat(self.fd).st_size < M.SIZE:
                os.ftruncate(self.fd, M.SIZE)  # only ever grows
            os.pwrite(self.fd, bytes(M.SIZE), 0)
            self._identity = _identity(os.fstat(self.fd))
            self._image = bytearray(M.SIZE)  # the board's regions as it sees them now
            self._flushed = bytearray(M.SIZE)  # ... and as last written to the file
            self._pending = bytearray()  # replies not yet in the response ring
            self._put(M.FIRMWARE_FLAGS, self.board.firmware_flags)
            self._write(M.LAYOUT, M.LAYOUT_MAGIC)
            self._put(M.BOARD_NUMBER, service.number)
        except BaseException:
            self._remove_file()
            os.close(self.fd)
            raise
        self._written_removal = 0
        self._capture_written = b""
        # the map's host in the controller's book of hosts, like any door's (`-vv`)
        self.traffic = service.open_traffic("shm", path)

    # ---- raw access -------------------------------------------------------------------
    def _read(self, offset: int, size: int) -> bytes:
        try:
            data = os.pread(self.fd, size, offset)
            if len(data) != size:
                raise MapLost(f"was truncated to {os.fstat(self.fd).st_size} bytes by "
                              "another process")
        except OSError as error:
            raise MapLost(f"cannot be read: {error.strerror or error}") from None
        return data

    def _write(self, offset: int, data: bytes | bytearray | memoryview) -> None:
        try:
            os.pwrite(self.fd, data, offset)
        except OSError as error:
            raise MapLost(f"cannot be written: {error.strerror or error}") from None

    def _get(self, offset: int) -> int:
        return _U32.unpack(self._read(offset, 4))[0]

    def _put(self, offset: int, value: int) -> None:
        """A word the host may also write (indices, mailboxes): written at once."""
        self._write(offset, _U32.pack(value & 0xFFFF_FFFF))

    def _set(self, offset: int, value: int) -> None:
        """A word of the board's own regions: into the image, written by _flush."""
        _U32.pack_into(self._image, offset, value & 0xFFFF_FFFF)

    def _put_signed(self, offset: int, value: int) -> None:
        _I32.pack_into(self._image, offset, value)

    def _flush(self, blocks: tuple[tuple[int, int], ...]) -> None:
        """Write the blocks that changed since they were last written."""
        image, flushed = self._image, self._flushed
        for start, end in blocks:
            if image[start:end] != flushed[start:end]:
                self._write(start, image[start:end])
                flushed[start:end] = image[start:end]

    def _check_file(self) -> None:
        try:
            size = os.fstat(self.fd).st_size
            now = _identity(os.lstat(self.path))
        except FileNotFoundError:
            raise MapLost("was removed by another process") from None
        except OSError as error:
            raise MapLost(f"cannot be checked: {error.strerror or error}") from None
        if size < M.SIZE:
            raise MapLost(f"was truncated to {size} bytes by another process")
        if now != self._identity:
            raise MapLost("was replaced by another file")

    # ---- one pass ---------------------------------------------------------------------
    def update(self) -> None:
        """One pass; if the map file was broken, say so once and stop this door."""
        if self.stopped is not None:
            return
        try:
            self._check_file()
            self._update()
        except MapLost as error:
            self.stopped = str(error)
            print(f"maxk serve: board {self.service.number}: shared memory {self.path} "
                  f"{self.stopped}; that door is closed, the board and its other doors go "
                  "on", file=sys.stderr, flush=True)

    def _update(self) -> None:
        board = self.board
        self.service.pacer.sync(SYNC_BUDGET)  # a bounded turn, as every door's
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
        late = self.interpreter.late_replies
        if late:  # queries a WQ held, answered since the queue emptied
            for reply in late:
                self._pending += reply.encode("latin-1") + b"\n"
            late.clear()
        insert = self._get(M.CMD_INSERT) % M.RING_SIZE
        process = self._get(M.CMD_PROCESS) % M.RING_SIZE
        if insert == process:
            return
        if insert > process:
            data = self._read(M.CMD_RING + process, insert - process)
        else:
            data = (self._read(M.CMD_RING + process, M.RING_SIZE - process)
                    + self._read(M.CMD_RING, insert))
        self._put(M.CMD_PROCESS, insert)
        self.traffic.incoming(data)
        for reply in self.interpreter.write(data):
            out = reply.encode("latin-1") + b"\n"
            self.traffic.outgoing(out)
            self._pending += out

    def _write_replies(self) -> None:
        insert = self._get(M.RESP_INSERT) % M.RING_SIZE
        process = self._get(M.RESP_PROCESS) % M.RING_SIZE
        if self._pending:
            free = (process - insert - 1) % M.RING_SIZE  # one byte kept empty: full != empty
            n = min(free, len(self._pending))
            first = min(n, M.RING_SIZE - insert)  # up to the end of the ring, then wrap
            self._write(M.RESP_RING + insert, self._pending[:first])
            if n > first:
                self._write(M.RESP_RING, self._pending[first:n])
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
                self._set(M.STATUS_WK + 4 * (i - 8), axis.flags)
        self._set(M.LIMIT_WORD, board.limit_status_word())
        self._set(M.HOME_WORD, board.home_status_word())
        self._set(M.IO_WORD, board.io.word(board))
        self._set(M.ODBR, board.doorbell)
        self._set(M.TICK, board.tick)
        ring = board.capture_ring
        host_removal = self._read(M.CAPTURE + 1, 1)[0]
        # The host takes entries by advancing the removal index (0x1541). It can only move
        # forward over entries that exist; anything else is ignored.
        if (host_removal != self._written_removal and host_removal < 55
                and (host_removal - ring.removal) % 55 <= len(ring)):
            ring.removal = host_removal
        entries = ring.to_bytes()
        if host_removal != ring.removal or entries != self._capture_written:
            self._write(M.CAPTURE, entries)
            self._capture_written = entries
        self._written_removal = ring.removal
        self._set(M.OMR1, 0x2 if len(ring) else 0)
        self._flush(_STATUS_BLOCKS)

    def _write_snapshot(self) -> None:
        board = self.board
        for axis in board.axes:
            i = axis.index
            self._put_signed(M.snapshot_motor_offset(i), axis.motor_position(board))
            self._put_signed(M.snapshot_encoder_offset(i), axis.encoder_position(board))
            self._put_signed(M.snapshot_dac_offset(i), axis.dac)
        self._flush(_SNAPSHOT_BLOCKS)

    # ---- waking on a host's command ----------------------------------------------------
    def watch(self, loop: asyncio.AbstractEventLoop) -> None:
        """Run a pass as soon as a host puts a command into the ring, not at the next
        pacing pass (about 1 ms away, and the event loop cannot sleep for less): one
        thread for every map reads each ring's insert index every WATCH_SECONDS and wakes
        the loop when it moves. The real board sees the host's doorbell write at once;
        this brings a round trip through the map under 1 ms (issue 28)."""
        _WATCHER.add(self, loop)

    def close(self) -> None:
        _WATCHER.remove(self)
        if self.fd < 0:
            return
        self._remove_file()
        os.close(self.fd)  # releases the lock, after the file is gone
        self.fd = -1

    def _remove_file(self) -> None:
        """Delete the map, but only while the path still names our file (another
        process may have put its own file there)."""
        with contextlib.suppress(OSError):
            if _identity(os.lstat(self.path)) == _identity(os.fstat(self.fd)):
                os.unlink(self.path)


class _RingWatcher:
    """The one thread that watches every served map's command ring (see `watch`): a
    thread a map would cost a core's tenth each; one costs that for all of them."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._doors: dict[SharedMemoryDoor, tuple[asyncio.AbstractEventLoop, int]] = {}
        self._thread: threading.Thread | None = None

    def add(self, door: SharedMemoryDoor, loop: asyncio.AbstractEventLoop) -> None:
        with self._lock:
            self._doors[door] = (loop, -1)
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="maxk-shm-watch",
                                                daemon=True)
                self._thread.start()

    def remove(self, door: SharedMemoryDoor) -> None:
        with self._lock:
            self._doors.pop(door, None)

    def _run(self) -> None:
        while True:
            time.sleep(WATCH_SECONDS)
            with self._lock:
                if not self._doors:
                    self._thread = None
                    return
                doors = list(self._doors.items())
            for door, (loop, seen) in doors:
                try:
                    value = os.pread(door.fd, 4, M.CMD_INSERT)
                except OSError:
                    continue  # closed or gone: its pacing pass says so
                if int.from_bytes(value, "big") == seen:
                    continue
                with self._lock:
                    if door in self._doors:
                        self._doors[door] = (loop, int.from_bytes(value, "big"))
                try:
                    loop.call_soon_threadsafe(door.update)
                except RuntimeError:  # that loop has closed
                    self.remove(door)


_WATCHER = _RingWatcher()


def _identity(st: os.stat_result) -> tuple[int, int]:
    return st.st_dev, st.st_ino


def _lock_briefly(fd: int) -> bool:
    """The exclusive lock, waiting a moment for it: a host's library takes a shared lock
    for a few microseconds to see whether anyone serves the map (docs/oms-library.md);
    a second server holds it for good."""
    deadline = time.monotonic() + LOCK_PATIENCE
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            if time.monotonic() > deadline:
                return False
            time.sleep(0.001)


def _open_map(path: str, board_number: int) -> int:
    """The map file, open and exclusively locked: created new, or a map a killed server
    of this board left. Refuses (OSError) a symlink, a second server and anything else."""
    flags = os.O_RDWR | os.O_NOFOLLOW | os.O_NOCTTY | os.O_CLOEXEC
    try:
        fd = os.open(path, flags | os.O_CREAT | os.O_EXCL, MAP_MODE)
    except FileExistsError:
        pass
    else:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)  # a checker may hold it for a moment, no more
        except BaseException:
            with contextlib.suppress(OSError):
                os.unlink(path)
            os.close(fd)
            raise
        return fd
    if os.path.islink(path):
        raise OSError(f"--shm {path} is a symbolic link: not followed, not touched")
    try:
        fd = os.open(path, flags)
    except OSError as error:
        if os.path.islink(path):  # replaced by a link since we looked
            raise OSError(f"--shm {path} is a symbolic link: not followed, not touched"
                          ) from None
        raise OSError(f"--shm {path}: {error.strerror or error}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise OSError(f"--shm {path} exists and is not a regular file: not touched")
        if not _lock_briefly(fd):
            raise OSError(f"--shm {path} is in use by another maxk serve")
        if (st.st_size != M.SIZE or os.pread(fd, 4, M.LAYOUT) != M.LAYOUT_MAGIC
                or _U32.unpack(os.pread(fd, 4, M.BOARD_NUMBER))[0] != board_number):
            raise OSError(f"--shm {path} exists and is not a maxk map of board "
                          f"{board_number}: not touched (remove it or choose another path)")
    except BaseException:
        os.close(fd)
        raise
    return fd


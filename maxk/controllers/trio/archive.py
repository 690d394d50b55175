"""The MC405's flash across runs of the emulator: `maxk serve` stopped and started again
on the same archive is a power cycle (EX's and FLASHVR's pages: the VRs stay; the FLASH
parameters, personalities/trio/flash.py; FLASHTABLE's flash pages; FLASH_DATA's backup
of TABLE's first 4096 values; FLASHVR(-1)'s copy of TABLE).

They are kept as ``flash.json`` in the program directory (ProgramStore's). Bounded: the
VRs are the fixed VR_COUNT, a flash page FLASHTABLE's 16000 values and at most its 32
pages, the TABLE backup AUTO_BACKUP values, FLASHVR's copy TABLE_SIZE; zeros are left
out. Written safely: a new file is written beside it and renamed over it
(``os.replace``), never cut in place.

When (D): the controller's own check, at most once a second of virtual time (the server
calls it after each pacing turn) writes only when something kept changed; EX writes at
once; the server's shutdown writes last. A hard kill loses at most the last second.

A file that is not ours, damaged, or out of bounds is refused with its reason (logged,
and shown by the console's `:programs`), renamed aside as ``flash.json.refused-N`` for a
person to look at, and the controller starts with empty flash: the server never stops.
"""

from __future__ import annotations

import json
import logging
import math
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

from maxk.commands.trio.network import FLASH_PAGE_SIZE, FLASH_PAGES
from maxk.commands.trio.system import ProgramCommands
from maxk.personalities.trio.flash import AUTO_BACKUP, FLASH_PARAMETERS
from maxk.personalities.trio.machine import SERVO_PERIODS, MC405Machine
from maxk.personalities.trio.memory import TABLE_SIZE, VR_COUNT


class MC405(Protocol):
    """What the flash needs of the controller (controller.MC405)."""

    machine: MC405Machine
    runtime: ProgramCommands

FILE_NAME = "flash.json"
FORMAT = "maxk MC405 flash"
VERSION = 1
SAVE_EVERY_S = 1.0  # virtual seconds between the checks for a change (D)
MAX_BYTES = 64 << 20  # larger than any file the bounds above allow
_LOG = logging.getLogger("maxk.trio.flash")


class FlashRefused(Exception):
    """The flash file is not one this controller wrote, or is damaged."""


@dataclass
class Flash:
    """What the flash keeps (sparse: zeros left out)."""

    vr: dict[int, float] = field(default_factory=dict)
    parameters: dict[str, float] = field(default_factory=dict)
    pages: dict[int, list[float]] = field(default_factory=dict)  # each FLASH_PAGE_SIZE long
    backup: list[float] | None = None  # FLASH_DATA = 1: TABLE(0..AUTO_BACKUP-1)
    table: list[float] | None = None  # FLASHVR(-1): the whole TABLE for power-up


def _pairs(values: list[float]) -> list[list[float]]:
    return [[i, v] for i, v in enumerate(values) if v != 0.0]


def _number(raw: object, what: str) -> float:
    if type(raw) not in (int, float):
        raise FlashRefused(f"{what} is not a number")
    return float(raw)  # type: ignore[arg-type]


def _sparse(raw: object, size: int, what: str) -> dict[int, float]:
    """[[index, value], ...] with each index in 0..size-1, once."""
    if not isinstance(raw, list) or len(raw) > size:
        raise FlashRefused(f"{what} is not a list of index/value pairs")
    out: dict[int, float] = {}
    for pair in raw:
        if not isinstance(pair, list) or len(pair) != 2 or type(pair[0]) is not int \
                or not 0 <= pair[0] < size or pair[0] in out:
            raise FlashRefused(f"{what}: an index is out of range or repeated")
        out[pair[0]] = _number(pair[1], what)
    return out


def decode(text: str) -> Flash:
    """The file's text as a Flash, every field checked (FlashRefused with the reason)."""
    try:
        raw = json.loads(text)
    except ValueError:
        raise FlashRefused("it is not JSON") from None
    if not isinstance(raw, dict) or raw.get("format") != FORMAT:
        raise FlashRefused(f"it is not a {FORMAT} file")
    if raw.get("version") != VERSION:
        raise FlashRefused(f"its version {raw.get('version')!r} is not {VERSION}")
    if set(raw) != {"format", "version", "vr", "parameters", "flash_pages", "auto_backup",
                    "flashvr_table"}:
        raise FlashRefused("its fields are not a flash file's")
    flash = Flash(vr=_sparse(raw["vr"], VR_COUNT, "vr"))
    parameters = raw["parameters"]
    if not isinstance(parameters, dict) or not set(parameters) <= FLASH_PARAMETERS:
        raise FlashRefused("parameters are not the FLASH parameters")
    flash.parameters = {k: _number(v, k) for k, v in parameters.items()}
    if "SERVO_PERIOD" in flash.parameters and \
            flash.parameters["SERVO_PERIOD"] not in SERVO_PERIODS:
        raise FlashRefused("SERVO_PERIOD is not one the MC405 runs at")
    if any(not math.isfinite(v) for v in flash.parameters.values()):
        raise FlashRefused("a parameter is not finite")
    pages = raw["flash_pages"]
    if not isinstance(pages, dict) or len(pages) > FLASH_PAGES:
        raise FlashRefused("flash_pages is not FLASHTABLE's pages")
    for key, values in pages.items():
        if not key.isdigit() or not 0 <= int(key) < FLASH_PAGES:
            raise FlashRefused(f"flash page {key[:8]!r} is not 0..{FLASH_PAGES - 1}")
        page = [0.0] * FLASH_PAGE_SIZE
        for k, v in _sparse(values, FLASH_PAGE_SIZE, f"flash page {key}").items():
            page[k] = v
        flash.pages[int(key)] = page
    if raw["auto_backup"] is not None:
        backup = [0.0] * AUTO_BACKUP
        for k, v in _sparse(raw["auto_backup"], AUTO_BACKUP, "auto_backup").items():
            backup[k] = v
        flash.backup = backup
    if raw["flashvr_table"] is not None:
        table = [0.0] * TABLE_SIZE
        for k, v in _sparse(raw["flashvr_table"], TABLE_SIZE, "flashvr_table").items():
            table[k] = v
        flash.table = table
    return flash


def encode(flash: Flash) -> str:
    return json.dumps({
        "format": FORMAT, "version": VERSION,
        "vr": [[i, v] for i, v in sorted(flash.vr.items()) if v != 0.0],
        "parameters": dict(sorted(flash.parameters.items())),
        "flash_pages": {str(p): _pairs(values) for p, values in sorted(flash.pages.items())},
        "auto_backup": None if flash.backup is None else _pairs(flash.backup),
        "flashvr_table": None if flash.table is None else _pairs(flash.table)},
        separators=(",", ":"))


def take(controller: MC405) -> Flash:
    """What the controller's flash holds now."""
    m = controller.machine
    values = m.vr.values()
    return Flash(
        vr={i: v for i, v in enumerate(values) if v != 0.0},
        parameters={n: float(m.system[n]) for n in sorted(FLASH_PARAMETERS & m.system.keys())},
        pages=dict(controller.runtime.flash_pages),  # (FLASHTABLE writes a new list)
        backup=m.table.read_run(0, AUTO_BACKUP - 1)
        if m.system.get("FLASH_DATA", 0.0) == 1 else None,
        table=controller.runtime.flash_table)  # (FLASHVR(-1) makes a new list)


def _same(a: Flash, b: Flash) -> bool:
    return (a.vr == b.vr and a.parameters == b.parameters and a.backup == b.backup
            and (a.table is b.table or a.table == b.table)
            and a.pages.keys() == b.pages.keys()
            and all(a.pages[p] is b.pages[p] or a.pages[p] == b.pages[p] for p in a.pages))


class FlashArchive:
    """The flash file of one controller (None directory: flash in memory only)."""

    def __init__(self, directory: Path | None) -> None:
        self.path = None if directory is None else directory / FILE_NAME
        self.damage: str | None = None  # why a file found at start-up was refused
        self.saved: Flash | None = None  # what the file holds, or the power-up's flash
        self.checked_at = -math.inf  # virtual time of the last check
        self.writes = 0

    def load(self) -> Flash | None:
        """The flash as last run left it; None when there is none or it was refused."""
        if self.path is None or not self.path.exists():
            return None
        try:
            if self.path.stat().st_size > MAX_BYTES:
                raise FlashRefused("it is larger than the flash")
            flash = decode(self.path.read_text(encoding="utf-8"))
        except (FlashRefused, OSError, UnicodeDecodeError) as error:
            self._refuse(str(error) or error.__class__.__name__)
            return None
        self.saved = flash
        return flash

    def _refuse(self, reason: str) -> None:
        assert self.path is not None
        n = 1
        while (aside := self.path.with_name(f"{FILE_NAME}.refused-{n}")).exists():
            n += 1
        try:
            os.replace(self.path, aside)
            where = f"set aside as {aside.name}"
        except OSError as error:
            where = f"it could not be set aside ({error.__class__.__name__}): not written"
            self.path = None
        self.damage = f"flash file refused: {reason}; {where}; the flash starts empty"
        _LOG.warning("MC405 %s", self.damage)

    def started(self, controller: MC405) -> None:
        """The controller powered up (with the file's flash, or none): nothing to write
        until something kept changes."""
        self.saved = take(controller)

    def keep(self, controller: MC405, now: bool = False) -> bool:
        """Write the flash if it changed; unless `now`, at most once every SAVE_EVERY_S
        of virtual time. True when written. A write that fails is logged, not raised."""
        if self.path is None:
            return False
        time = controller.machine.time
        if not now and time - self.checked_at < SAVE_EVERY_S:
            return False
        self.checked_at = time
        flash = take(controller)
        if self.saved is not None and _same(flash, self.saved):
            return False
        try:
            self._write(encode(flash))
        except OSError as error:
            _LOG.error("MC405 flash not written to %s: %s", self.path, error)
            return False
        self.saved = flash
        self.writes += 1
        return True

    def _write(self, text: str) -> None:
        assert self.path is not None
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, temp = tempfile.mkstemp(dir=self.path.parent, prefix=".flash-")
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                f.write(text)
                f.flush()
                os.fsync(f.fileno())
            os.replace(temp, self.path)
        except BaseException:
            Path(temp).unlink(missing_ok=True)
            raise


def restore(controller: MC405, flash: Flash, keep_servo_period: bool) -> None:
    """Power up with what the flash kept: the FLASH parameters (SERVO_PERIOD too unless
    the caller chose a rate), the VRs, the flash pages, TABLE's backed-up values and
    FLASHVR(-1)'s TABLE (the power-up then writes it: ProgramCommands.start_autorun)."""
    m = controller.machine
    parameters = dict(flash.parameters)
    if not keep_servo_period:
        parameters.pop("SERVO_PERIOD", None)
    if parameters:
        for name, value in parameters.items():
            m.system[name] = value
        m.restart()  # (carries them into the power-up values; a new period takes effect)
    for index, value in flash.vr.items():
        m.vr.write(index, value)
    controller.runtime.flash_pages = dict(flash.pages)
    controller.runtime.flash_table = flash.table  # (TABLE from it at the power-up)
    if flash.backup is not None:
        m.table.write(0, flash.backup)


__all__ = ["FILE_NAME", "Flash", "FlashArchive", "FlashRefused", "decode", "encode",
           "restore", "take"]

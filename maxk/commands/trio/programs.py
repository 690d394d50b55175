"""Program storage: the controller's programs as a directory of files.

Each program is ``NAME.<ext>`` (its lines, each ending in LF) and the directory's
``directory.json`` holds each program's type, run type and compiled size. A change is
written to a temporary file and moved into place with ``os.replace``, so the store
survives a restart (EX) or a new emulator process; the one exception is atrio's download
a line at a time, where each line appended is one append at the end of the lines before
it (the file is cut there first, so a line torn by a crash is dropped on reload and
overwritten by the next one, never glued to it).
"""

from __future__ import annotations

import json
import logging
import os
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path

from .lexer import TrioError

PROGRAM_TYPES = {0: ".BAS", 3: ".TXT", 7: ".PROJ", 9: ".MCC", 12: ".BAL"}
CODE_TYPES = {0: "Normal", 3: "Text", 7: "Project", 9: "MC_CONFIG", 12: "BASIC Lib"}
_INDEX = "directory.json"
_NAME_CHARS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_")
_LOG = logging.getLogger("maxk.trio.programs")

# The controller's program memory (D: sized like an MC405's user memory; the manuals give
# the memory size per model, the split into these three limits is ours).
MAX_PROGRAMS = 256
MAX_PROGRAM_BYTES = 512 * 1024
MAX_TOTAL_BYTES = 2 * 1024 * 1024


class StoreDamaged(Exception):
    """The store's index cannot be trusted (unreadable, wrong shape, a bad name)."""


def crc16(data: bytes, crc: int = 0) -> int:
    """CRC-16, polynomial 0x8005, initial 0, not reflected (atrio's trioCRC16)."""
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else crc << 1
            crc &= 0xFFFF
    return crc


def program_checksum(lines: list[str]) -> int:
    """EDPROG "N",10: the CRC over each line (no CR/LF) followed by the byte 0xAA."""
    crc = 0
    for line in lines:
        crc = crc16(line.encode("latin-1", "replace") + b"\xaa", crc)
    return crc


@dataclass
class ProgramInfo:
    name: str
    type: int = 0
    autorun: bool = False
    process: int = -1  # autorun process, -1: the controller picks
    code_size: int = 0  # 0 until compiled (and again after an edit)


def check_name(name: str) -> str:
    """A program name as the controller takes it: letters, digits and underscores, up to
    32 (upper-cased): never a path. A name may start with a digit (I: a public Motion
    Perfect project keeps its data files as 0123.TXT and opens them by name)."""
    upper = name.upper()
    if not upper or len(upper) > 32 or not set(upper) <= _NAME_CHARS:
        raise TrioError("Invalid program name")
    return upper


def _entry(raw: object) -> ProgramInfo:
    """One index entry, checked field by field (StoreDamaged when anything is off)."""
    fields = {"name": str, "type": int, "autorun": bool, "process": int, "code_size": int}
    if not isinstance(raw, dict) or set(raw) - set(fields) or "name" not in raw:
        raise StoreDamaged("an entry is not a program record")
    for key, kind in fields.items():
        if key in raw and (type(raw[key]) is not kind):
            raise StoreDamaged(f"an entry's {key} is not {kind.__name__}")
    name = raw["name"]
    try:
        if check_name(name) != name:
            raise StoreDamaged(f"program name {name!r} is not upper case")
    except TrioError:
        raise StoreDamaged(f"program name {name!r} is not a program name") from None
    info = ProgramInfo(**raw)
    if info.type not in PROGRAM_TYPES or not -1 <= info.process < 64 or info.code_size < 0:
        raise StoreDamaged(f"program {name}: a field is out of range")
    return info


class ProgramStore:
    """The programs, kept in memory and mirrored to a directory."""

    def __init__(self, directory: str | os.PathLike[str] | None = None) -> None:
        self.directory = Path(directory) if directory is not None else None
        self.info: dict[str, ProgramInfo] = {}
        self.lines: dict[str, list[str]] = {}
        self._sizes: dict[str, int] = {}  # bytes of each program's file as last written
        self.total = 0  # bytes of every program's lines
        self.damage: str | None = None  # why the store found at start-up was set aside
        if self.directory is not None:
            self.directory.mkdir(parents=True, exist_ok=True)
            try:
                self._load()
            except StoreDamaged as exc:
                self._set_aside(str(exc))

    # ---- persistence ------------------------------------------------------------------
    def _load(self) -> None:
        assert self.directory is not None
        index = self.directory / _INDEX
        if not index.exists():
            return
        try:
            if index.stat().st_size > 1 << 20:
                raise StoreDamaged("the index is larger than any store's")
            entries = json.loads(index.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise StoreDamaged(f"the index cannot be read ({exc.__class__.__name__})") from None
        if not isinstance(entries, list) or len(entries) > MAX_PROGRAMS:
            raise StoreDamaged("the index is not a list of programs")
        infos = [_entry(raw) for raw in entries]
        if len({i.name for i in infos}) != len(infos):
            raise StoreDamaged("a program is listed twice")
        lines: dict[str, list[str]] = {}
        for info in infos:
            path = self.directory / (info.name + PROGRAM_TYPES[info.type])
            try:
                size = path.stat().st_size if path.exists() else 0
                if size > MAX_PROGRAM_BYTES:
                    raise StoreDamaged(f"program {info.name} is larger than memory holds")
                text = path.read_text(encoding="latin-1") if size else ""
            except OSError as exc:
                raise StoreDamaged(f"program {info.name} cannot be read "
                                   f"({exc.__class__.__name__})") from None
            lines[info.name] = text.split("\n")[:-1]  # each line ends in LF
        for info in infos:
            self.info[info.name] = info
            self.lines[info.name] = lines[info.name]
            self._sizes[info.name] = sum(len(line) + 1 for line in lines[info.name])
        self.total = sum(self._sizes.values())
        if self.total > MAX_TOTAL_BYTES:
            self.info.clear()
            self.lines.clear()
            raise StoreDamaged("the programs are larger than memory holds")

    def _set_aside(self, reason: str) -> None:
        """Rename the damaged store aside (kept for a person to look at) and start empty,
        as a damaged MAXk archive does: start-up goes on."""
        assert self.directory is not None
        self.info.clear()
        self.lines.clear()
        self._sizes.clear()
        self.total = 0
        n = 1
        while (aside := self.directory.with_name(f"{self.directory.name}.damaged-{n}")).exists():
            n += 1
        try:
            os.replace(self.directory, aside)
            self.directory.mkdir(parents=True)
        except OSError as exc:  # cannot even move it: run on an empty store in memory
            self.directory = None
            self.damage = (f"program store damaged: {reason}; it could not be set aside "
                           f"({exc.__class__.__name__}): programs are kept in memory only")
            _LOG.warning("%s", self.damage)
            return
        self.damage = f"program store damaged: {reason}; set aside as {aside.name}"
        _LOG.warning("%s", self.damage)

    def _write(self, path: Path, text: str) -> None:
        fd, temp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-")
        try:
            with os.fdopen(fd, "w", encoding="latin-1", newline="") as f:
                f.write(text)
            os.replace(temp, path)
        except BaseException:
            Path(temp).unlink(missing_ok=True)
            raise

    def _save_index(self) -> None:
        if self.directory is None:
            return
        entries = [asdict(self.info[name]) for name in sorted(self.info)]
        self._write(self.directory / _INDEX, json.dumps(entries, indent=1))

    def _save_program(self, name: str) -> None:
        self._sizes[name] = sum(len(line) + 1 for line in self.lines[name])
        if self.directory is None:
            return
        info = self.info[name]
        text = "".join(line + "\n" for line in self.lines[name])
        self._write(self.directory / (name + PROGRAM_TYPES[info.type]), text)
        self._save_index()

    # ---- operations ---------------------------------------------------------------------
    def exists(self, name: str) -> bool:
        return name.upper() in self.info

    def get(self, name: str) -> ProgramInfo:
        info = self.info.get(name.upper())
        if info is None:
            raise TrioError("Program not found")
        return info

    def create(self, name: str, program_type: int) -> ProgramInfo:
        name = check_name(name)
        if program_type not in PROGRAM_TYPES:
            raise TrioError("Parameter out of range")
        if name in self.info:
            if self.info[name].type != program_type:
                raise TrioError("Program type mismatch")
            return self.info[name]
        if len(self.info) >= MAX_PROGRAMS:
            raise TrioError("Too many programs")
        self.info[name] = ProgramInfo(name, program_type)
        self.lines[name] = []
        self._save_program(name)
        return self.info[name]

    def delete(self, name: str) -> None:
        info = self.get(name)
        del self.info[info.name]
        del self.lines[info.name]
        self.total -= self._sizes.pop(info.name, 0)
        if self.directory is not None:
            (self.directory / (info.name + PROGRAM_TYPES[info.type])).unlink(missing_ok=True)
        self._save_index()

    def edit(self, name: str, number: int, action: str, text: str = "") -> None:
        """The ``!NAME,n<action>text`` line edits: R replaces line n (appends at the end),
        I inserts before line n, D deletes line n."""
        info = self.get(name)
        lines = self.lines[info.name]
        appended = number == len(lines) and action in "RI"
        growth = len(text) + 1
        if action == "R" and 0 <= number < len(lines):
            growth -= len(lines[number]) + 1
        elif action == "D":
            growth = -(len(lines[number]) + 1) if 0 <= number < len(lines) else 0
        size = self._sizes.get(info.name, 0)
        if growth > 0 and size + growth > MAX_PROGRAM_BYTES:
            raise TrioError("Program too large")
        if growth > 0 and self.total + growth > MAX_TOTAL_BYTES:
            raise TrioError("Not enough memory")
        if action == "R" and number == len(lines) or action == "I" and number <= len(lines):
            lines.insert(number, text)
        elif action == "R" and 0 <= number < len(lines):
            lines[number] = text
        elif action == "D" and 0 <= number < len(lines):
            del lines[number]
        else:
            raise TrioError("Invalid line number")
        index_changed = info.code_size != 0
        info.code_size = 0
        self.total += growth
        self._sizes[info.name] = size + growth
        if appended:  # atrio's download, a line at a time: each costs one line's write
            self._append_line(info.name, text)
            if index_changed:
                self._save_index()
        else:
            self._save_program(info.name)

    def _append_line(self, name: str, text: str) -> None:
        """Write the program's last line after the ones before it (see the module's
        docstring); a missing file is written whole."""
        if self.directory is None:
            return
        path = self.directory / (name + PROGRAM_TYPES[self.info[name].type])
        line = (text + "\n").encode("latin-1", "replace")
        before = self._sizes.get(name, 0) - len(line)
        if not path.exists():
            self._save_program(name)
            return
        with path.open("r+b") as f:
            f.seek(before)
            f.truncate()
            f.write(line)

    def clear(self, name: str) -> None:
        info = self.get(name)
        self.lines[info.name] = []
        self.total -= self._sizes.get(info.name, 0)
        info.code_size = 0
        self._save_program(info.name)

    def set_runtype(self, name: str, autorun: bool, process: int) -> None:
        info = self.get(name)
        if info.type != 0:
            raise TrioError("Program cannot be run")
        info.autorun, info.process = autorun, process
        self._save_index()

    def set_compiled(self, name: str, code_size: int) -> None:
        self.get(name).code_size = code_size
        self._save_index()

    def source_size(self, name: str) -> int:
        return sum(len(line) + 1 for line in self.lines[name.upper()])

    def checksum(self, name: str) -> int:
        return program_checksum(self.lines[self.get(name).name])

    def names(self) -> list[str]:
        return sorted(self.info)

    def directory_lines(self) -> list[str]:
        """DIR: a header ending in dashes, one line per program, OK (atrio's regex)."""
        out = [f"{'Program':<16} {'Source':>7} {'Code':>7}  {'Run':<9} Type", "-" * 50]
        for name in self.names():
            info = self.info[name]
            if info.type == 9:
                run = "Power Up"
            elif info.type != 0:
                run = "None"
            elif info.autorun:
                run = f"Auto({info.process})"
            else:
                run = "Manual"
            out.append(f"{name:<16} {self.source_size(name):>7} {info.code_size:>7}  "
                       f"{run:<9} {CODE_TYPES[info.type]}")
        out.append("OK")
        return out

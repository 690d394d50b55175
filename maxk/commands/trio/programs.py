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
import os
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path

from .lexer import TrioError

PROGRAM_TYPES = {0: ".BAS", 3: ".TXT", 7: ".PROJ", 9: ".MCC", 12: ".BAL"}
CODE_TYPES = {0: "Normal", 3: "Text", 7: "Project", 9: "MC_CONFIG", 12: "BASIC Lib"}
_INDEX = "directory.json"
_NAME_CHARS = frozenset("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_")


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
    upper = name.upper()
    if not upper or len(upper) > 32 or not set(upper) <= _NAME_CHARS or upper[0].isdigit():
        raise TrioError("Invalid program name")
    return upper


class ProgramStore:
    """The programs, kept in memory and mirrored to a directory."""

    def __init__(self, directory: str | os.PathLike[str] | None = None) -> None:
        self.directory = Path(directory) if directory is not None else None
        self.info: dict[str, ProgramInfo] = {}
        self.lines: dict[str, list[str]] = {}
        self._sizes: dict[str, int] = {}  # bytes of each program's file as last written
        if self.directory is not None:
            self.directory.mkdir(parents=True, exist_ok=True)
            self._load()

    # ---- persistence ------------------------------------------------------------------
    def _load(self) -> None:
        assert self.directory is not None
        index = self.directory / _INDEX
        if not index.exists():
            return
        for entry in json.loads(index.read_text()):
            info = ProgramInfo(**entry)
            path = self.directory / (info.name + PROGRAM_TYPES.get(info.type, ".BAS"))
            text = path.read_text(encoding="latin-1") if path.exists() else ""
            self.info[info.name] = info
            self.lines[info.name] = text.split("\n")[:-1]  # each line ends in LF
            self._sizes[info.name] = sum(len(line) + 1 for line in self.lines[info.name])

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
        if self.directory is None:
            return
        info = self.info[name]
        text = "".join(line + "\n" for line in self.lines[name])
        self._write(self.directory / (name + PROGRAM_TYPES[info.type]), text)
        self._sizes[name] = len(text.encode("latin-1", "replace"))
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
        self.info[name] = ProgramInfo(name, program_type)
        self.lines[name] = []
        self._save_program(name)
        return self.info[name]

    def delete(self, name: str) -> None:
        info = self.get(name)
        del self.info[info.name]
        del self.lines[info.name]
        if self.directory is not None:
            (self.directory / (info.name + PROGRAM_TYPES[info.type])).unlink(missing_ok=True)
        self._save_index()

    def edit(self, name: str, number: int, action: str, text: str = "") -> None:
        """The ``!NAME,n<action>text`` line edits: R replaces line n (appends at the end),
        I inserts before line n, D deletes line n."""
        info = self.get(name)
        lines = self.lines[info.name]
        appended = number == len(lines) and action in "RI"
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
        before = self._sizes.get(name)
        if before is None or not path.exists():
            self._save_program(name)
            return
        line = (text + "\n").encode("latin-1", "replace")
        with path.open("r+b") as f:
            f.seek(before)
            f.truncate()
            f.write(line)
        self._sizes[name] = before + len(line)

    def clear(self, name: str) -> None:
        info = self.get(name)
        self.lines[info.name] = []
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

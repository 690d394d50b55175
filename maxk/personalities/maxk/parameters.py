"""The user-definable power-up defaults (manual 2.14): what APP saves, RDP and power-up
restore, and RDF replaces with the factory set.

The archive is a file per board (the board's flash). It is written whole to a temporary
file beside it, flushed to disk, then renamed over the old one, so a crash or a kill at
any moment leaves either the old archive or the new one, never a torn file. A SHA-256
checksum over the contents catches a corrupted or truncated file at power-up, which
then loads the factory set and says so in the firmware state flags (Table 3-4).

A writer holds an exclusive flock on its temporary file until the rename, so the
temporaries a killed APP leaves (unlocked, named as tempfile.mkstemp names ours:
.<archive name>.<8 characters>.tmp) can be told from one being written, and are swept
when the archive is attached at start-up and before each APP (decision D).
"""

from __future__ import annotations

import contextlib
import fcntl
import hashlib
import json
import math
import os
import re
import tempfile
from dataclasses import fields, replace
from pathlib import Path

from maxk.firmware_model.profiles import RampShape
from maxk.firmware_model.servo import Gains
from maxk.personalities.maxk.config import AxisConfig
from maxk.personalities.maxk.models import MAX_ACCELERATION, MAX_VELOCITY

FORMAT = "maxk-parameter-archive"
VERSION = 1

# Manual 2.14's list, as AxisConfig fields (the servo gains travel as one group).
ARCHIVED_FIELDS: tuple[str, ...] = (
    "limit_hard_stop",  # over travel limit: soft or hard
    "limits_enabled",  # over travel limit enabled or disabled
    "limit_active_high",  # over travel limit polarity
    "move_direction",  # direction bit polarity (MP/MM)
    "acceleration", "deceleration",
    "ramp", "ramp_factor", "scurve_factor", "ramp_parameter",  # trajectory profile
    "velocity", "base_velocity",
    "user_units",  # UU factor, or None when off
    "settle_ms", "aux_auto",  # auxiliary output settle time and automatic control
    "encoder_ratio", "slip_tolerance",
    "home_active_high",
    "hold_deadband", "hold_gain", "hold_velocity",  # position maintenance
    "servo_bipolar", "servo_polarity",
    "gains",  # KP KI KD KU KV KA KF KO
)


class ArchiveError(Exception):
    """The archive cannot be read (missing, truncated, corrupted) or written."""


def default_archive_dir() -> Path:
    """Per-user: $XDG_DATA_HOME/maxk (~/.local/share/maxk)."""
    base = os.environ.get("XDG_DATA_HOME") or os.path.join(os.path.expanduser("~"),
                                                            ".local", "share")
    return Path(base) / "maxk"


def default_archive_path(model: str, board_number: int = 1) -> Path:
    return default_archive_dir() / f"{model}-board{board_number}.params.json"


# ---- one axis's parameters <-> plain data ---------------------------------------------
def snapshot(config: AxisConfig) -> dict:
    """The archived parameters of one axis as JSON-ready data."""
    out: dict = {}
    for name in ARCHIVED_FIELDS:
        value = getattr(config, name)
        if isinstance(value, RampShape):
            value = value.value
        elif isinstance(value, Gains):
            value = {f.name: getattr(value, f.name) for f in fields(Gains)}
        elif isinstance(value, tuple):
            value = list(value)
        out[name] = value
    return out


def _number(value: object, low: float, high: float, integer: bool) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{value!r} is not a number")
    if not math.isfinite(value) or not low <= value <= high:
        raise ValueError(f"{value!r} is outside {low:g}..{high:g}")
    if integer and value != int(value):
        raise ValueError(f"{value!r} is not a whole number")
    return int(value) if integer else float(value)


# The ranges the commands themselves accept (the command table), for archived values.
_RANGES: dict[str, tuple[float, float]] = {
    "acceleration": (1, MAX_ACCELERATION), "deceleration": (1, MAX_ACCELERATION),
    "velocity": (1, MAX_VELOCITY), "base_velocity": (0, MAX_VELOCITY),
    "ramp_factor": (0, 8), "scurve_factor": (0, 100), "ramp_parameter": (0, 100),
    "settle_ms": (0, 2**31 - 1), "slip_tolerance": (0, 2**31 - 1),
    "hold_deadband": (0, 32767), "hold_gain": (0, 32767), "hold_velocity": (0, MAX_VELOCITY),
}


def restore(config: AxisConfig, data: dict) -> AxisConfig:
    """A config with the archived parameters applied (others left as they are). Every
    value is checked as the command that sets it would check it: ValueError if not."""
    if not isinstance(data, dict):
        raise ValueError("an axis set is not an object")
    changes: dict = {}
    factory = AxisConfig()
    for name in ARCHIVED_FIELDS:
        if name not in data:
            continue
        value = data[name]
        template = getattr(factory, name)
        if name == "ramp":
            value = RampShape(value)
        elif name == "gains":
            if not isinstance(value, dict) or set(value) - {f.name for f in fields(Gains)}:
                raise ValueError("gains must be an object of KP..KO")
            value = Gains(**{k: _number(v, -32767 if k == "ko" else 0, 32767, False)
                             for k, v in value.items()})
        elif name == "encoder_ratio":
            if not isinstance(value, list) or len(value) != 2:
                raise ValueError("encoder_ratio is [counts, steps]")
            value = (_number(value[0], 1, 2**31 - 1, True), _number(value[1], 1, 2**31 - 1,
                                                                    True))
        elif name == "user_units":
            value = None if value is None else _number(value, 1e-6, 1e9, False)
        elif name in ("move_direction", "servo_polarity"):
            if value not in (1, -1) or isinstance(value, bool):
                raise ValueError(f"{name} is 1 or -1")
        elif isinstance(template, bool):
            if not isinstance(value, bool):
                raise ValueError(f"{name} is true or false")
        else:
            low, high = _RANGES[name]
            value = _number(value, low, high, isinstance(template, int))
        changes[name] = value
    # VB may stand above VL here: the pair is checked when a move uses it (issue 40), so
    # an archive saved between a host's VL and its VB loads as it was saved.
    return replace(config, **changes)


# ---- the file ------------------------------------------------------------------------
def _checksum(body: dict) -> str:
    canonical = json.dumps(body, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode("utf-8")).hexdigest()


def encode(model: str, axes: list[dict]) -> bytes:
    body = {"format": FORMAT, "version": VERSION, "model": model, "axes": axes}
    document = dict(body, checksum=_checksum(body))
    return (json.dumps(document, indent=1, sort_keys=True) + "\n").encode("utf-8")


def decode(raw: bytes, model: str) -> list[dict]:
    """The per-axis parameter sets; ArchiveError if anything is wrong with them."""
    try:
        document = json.loads(raw.decode("utf-8"))
        checksum = document.pop("checksum")
        computed = _checksum(document)
    # RecursionError: JSON nested thousands deep, read or re-encoded for the checksum
    except (UnicodeDecodeError, ValueError, KeyError, AttributeError, TypeError,
            RecursionError) as exc:
        raise ArchiveError(f"unreadable archive ({exc.__class__.__name__})") from None
    if computed != checksum:
        raise ArchiveError("archive checksum does not match its contents")
    if document.get("format") != FORMAT or document.get("version") != VERSION:
        raise ArchiveError("not a maxk parameter archive of this version")
    if document.get("model") != model:
        raise ArchiveError(f"archive is for a {document.get('model')}, not a {model}")
    axes = document.get("axes")
    if not isinstance(axes, list):
        raise ArchiveError("archive has no axis list")
    return axes


def sweep_temporaries(path: Path) -> None:
    """Delete the temporary files writers of `path` were killed before renaming: only
    regular files named exactly as write_atomically names them, and only when no
    writer holds their lock. Never follows a symlink; errors leave a file alone."""
    pattern = re.compile(re.escape(f".{path.name}.") + r"[a-z0-9_]{8}" + re.escape(".tmp"))
    try:
        entries = list(os.scandir(path.parent))
    except OSError:
        return
    for entry in entries:
        if not pattern.fullmatch(entry.name):
            continue
        with contextlib.suppress(OSError):
            if not entry.is_file(follow_symlinks=False):
                continue
            fd = os.open(entry.path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK
                         | os.O_CLOEXEC)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # fails while written
                st, now = os.fstat(fd), os.lstat(entry.path)
                if (st.st_dev, st.st_ino) == (now.st_dev, now.st_ino):
                    os.unlink(entry.path)
            finally:
                os.close(fd)


def _locked_temporary(path: Path) -> tuple[int, str]:
    """A new temporary file beside `path`, locked against sweep_temporaries. A sweeper
    may delete it between creation and lock: then it is not ours any more, try again."""
    while True:
        fd, temporary = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp",
                                         dir=path.parent)
        try:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX)
            except OSError:  # no locks on this file system: no sweeper can lock it either
                return fd, temporary
            if os.fstat(fd).st_nlink:
                return fd, temporary
        except BaseException:
            os.close(fd)
            raise
        os.close(fd)


def write_atomically(path: Path, data: bytes) -> None:
    """Replace `path` with `data` so that a crash at any moment leaves the old file or
    the new one: temporary file in the same directory, fsync, rename, fsync the dir."""
    path.parent.mkdir(parents=True, exist_ok=True)
    sweep_temporaries(path)  # left by a writer killed mid-way
    fd, temporary = _locked_temporary(path)
    try:
        with os.fdopen(fd, "wb") as file:
            file.write(data)
            file.flush()
            os.fsync(file.fileno())
            os.replace(temporary, path)  # before the close: the lock lasts until here
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
    try:
        directory = os.open(path.parent, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(directory)
    finally:
        os.close(directory)


class ParameterArchive:
    """The board's flash: a file, or (with no path) memory that lasts as long as the
    process. ``load`` returns None when nothing was ever saved."""

    def __init__(self, path: str | os.PathLike | None = None) -> None:
        self.path = None if path is None else Path(path)
        self._memory: bytes | None = None
        if self.path is not None:
            sweep_temporaries(self.path)  # start-up: what a killed APP left

    def save(self, model: str, configs: list[AxisConfig]) -> None:
        data = encode(model, [snapshot(c) for c in configs])
        if self.path is None:
            self._memory = data
            return
        try:
            write_atomically(self.path, data)
        except OSError as exc:
            raise ArchiveError(f"cannot write {self.path}: {exc.strerror or exc}") from None

    def load(self, model: str) -> list[dict] | None:
        if self.path is None:
            raw = self._memory
        else:
            try:
                raw = self.path.read_bytes()
            except FileNotFoundError:
                return None
            except OSError as exc:
                raise ArchiveError(f"cannot read {self.path}: {exc.strerror or exc}") from None
        if raw is None:
            return None
        return decode(raw, model)

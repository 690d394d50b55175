"""The vendor's motion-control library API (OmsMAXkMC) as a C library over the board's
doors: legacy host code written for the Windows DLL links against libOmsMAXkMC.so and
reaches a board served by `maxk serve --shm` (or over TCP) unchanged. This module only
finds, builds and describes the library (docs/oms-library.md); the library is C.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
SOURCE = HERE / "OmsMAXkMC.c"
INCLUDE_DIR = HERE / "include"
HEADERS = (INCLUDE_DIR / "OmsMAXkMC.h", INCLUDE_DIR / "OmsMAXkMC.H", INCLUDE_DIR / "windows.h")
LIBRARY_NAME = "libOmsMAXkMC.dylib" if sys.platform == "darwin" else "libOmsMAXkMC.so"
# the flags every build uses: the install (setup.py), `maxk library --build`, the tests
COMPILE_FLAGS = ("-O2", "-fPIC", "-shared", "-fvisibility=hidden", "-Wall")
LINK_LIBRARIES = ("-lpthread",)


def installed_library() -> Path:
    """Where the install puts the library: beside its source, in the package."""
    return HERE / LIBRARY_NAME


def cache_library() -> Path:
    """Where `maxk library --build` puts it when the package directory is not writable."""
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "maxk" / LIBRARY_NAME


def library_path() -> Path | None:
    """The built library, newest of the package's and the cache's; None if neither exists."""
    found = [p for p in (installed_library(), cache_library()) if p.exists()]
    return max(found, key=lambda p: p.stat().st_mtime) if found else None


def compiler() -> str | None:
    """The C compiler to use: $CC, else cc, gcc or clang on the PATH."""
    for name in (os.environ.get("CC"), "cc", "gcc", "clang"):
        if name and shutil.which(name.split()[0]):
            return name
    return None


def build(target: Path | None = None, cc: str | None = None) -> Path:
    """Compile the library to `target` (default: the package, else the cache)."""
    cc = cc or compiler()
    if cc is None:
        raise RuntimeError("no C compiler found (set CC, or install gcc or clang)")
    if target is None:
        target = installed_library()
        if not os.access(target.parent, os.W_OK):
            target = cache_library()
    target.parent.mkdir(parents=True, exist_ok=True)
    command = [*cc.split(), *COMPILE_FLAGS, f"-I{INCLUDE_DIR}", "-o", str(target),
               str(SOURCE), *LINK_LIBRARIES]
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"building {target.name} failed:\n{result.stderr}")
    return target


def compile_command(program: str = "program.c", library: Path | None = None) -> str:
    """One line that compiles a user's program against the library."""
    lib = library or library_path() or installed_library()
    return (f"cc -I{INCLUDE_DIR} -o {Path(program).stem} {program} "
            f"-L{lib.parent} -lOmsMAXkMC -Wl,-rpath,{lib.parent}")


def describe(path_only: bool = False, rebuild: bool = False) -> int:
    """`maxk library`: the library's path, its headers and a compile line (builds the
    library first when the install could not, or when asked)."""
    lib = library_path()
    stale = lib is not None and lib.stat().st_mtime < SOURCE.stat().st_mtime
    if rebuild or lib is None or (stale and compiler() is not None):
        try:
            lib = build()
        except RuntimeError as error:
            print(f"maxk library: {error}", file=sys.stderr)
            return 1
    if path_only:
        print(lib)
        return 0
    print(f"library: {lib}")
    print(f"headers: {INCLUDE_DIR} (OmsMAXkMC.h, OmsMAXkMC.H, windows.h)")
    print(f"compile: {compile_command('program.c', lib)}")
    print("boards:  MAXK_OMSMAXK<N>=shm:PATH or tcp:HOST:PORT, or ~/.config/maxk/oms.conf "
          "(docs/oms-library.md)")
    return 0

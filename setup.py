"""The compiled servo kernel, built where a C compiler exists and skipped where none does:
without it maxk runs its servo loop in Python (README, "Servo speed"). Beside it, the same
way, libOmsMAXkMC: the vendor motion-control library API for legacy host programs
(docs/oms-library.md); without a compiler `maxk library` says how to get it. And the same
way again, the typed hot modules compiled with mypyc (maxk/compiled.py lists them;
MAXK_PURE_PYTHON=1 at install skips them, at run time ignores them): without them maxk
runs those modules as Python, with the same replies (README, "Speed")."""

import os
import runpy
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

OMS_LIBRARY_DIR = Path("maxk") / "host" / "oms_library"
OMS_LIBRARY_NAME = "libOmsMAXkMC.dylib" if sys.platform == "darwin" else "libOmsMAXkMC.so"


class OptionalBuildExt(build_ext):
    """Build the kernel if possible; never fail the install for want of a compiler."""

    def run(self) -> None:
        if self.inplace:
            self._remove_stale_modules()
        try:
            super().run()
        except Exception as exc:  # no compiler at all (distutils' own errors vary)
            self._skip(exc)
        try:
            self._build_oms_library()
        except Exception as exc:
            print(f"maxk: libOmsMAXkMC was not built ({exc}); `maxk library --build` "
                  "builds it once a C compiler is installed")

    def _build_oms_library(self) -> None:
        """A plain shared library (not a Python extension), beside its source."""
        if sys.platform == "win32":
            return  # Windows hosts use the vendor's own DLL or build ours (docs)
        target = OMS_LIBRARY_DIR if self.inplace else Path(self.build_lib) / OMS_LIBRARY_DIR
        target.mkdir(parents=True, exist_ok=True)
        objects = self.compiler.compile(
            [str(OMS_LIBRARY_DIR / "OmsMAXkMC.c")], output_dir=self.build_temp,
            include_dirs=[str(OMS_LIBRARY_DIR / "include")],
            extra_postargs=["-O2", "-fPIC", "-fvisibility=hidden"])
        self.compiler.link_shared_object(objects, str(target / OMS_LIBRARY_NAME),
                                         libraries=["pthread"])

    def _remove_stale_modules(self) -> None:
        """An in-place (editable) build leaves the shared libraries of an earlier build
        beside the sources: one for a module no longer compiled (or a build with
        MAXK_PURE_PYTHON=1) would shadow its .py and fail to import. Remove those."""
        current = {ext.name for ext in self.extensions}
        for source in Path("maxk").rglob("*.py"):
            name = ".".join(source.with_suffix("").parts)
            if name in current:
                continue
            for library in source.parent.glob(source.stem + ".*"):
                if library.suffix in (".so", ".pyd") and library.name.split(".")[0] == source.stem:
                    library.unlink()
        for library in Path("maxk").glob("_compiled__mypyc.*"):
            if "maxk._compiled__mypyc" not in current:
                library.unlink()

    def build_extensions(self) -> None:
        self._mypyc_failed = False
        super().build_extensions()

    def build_extension(self, ext: Extension) -> None:
        mypyc = ext.name in MYPYC_NAMES
        if mypyc and self._mypyc_failed:
            return
        try:
            super().build_extension(ext)
        except Exception as exc:
            if not mypyc:
                self._skip(exc)
                return
            # all or none: a module whose shared library is missing would not import
            self._mypyc_failed = True
            for name in MYPYC_NAMES:
                Path(self.get_ext_fullpath(name)).unlink(missing_ok=True)
            print(f"maxk: the compiled modules were not built ({exc}); they run as "
                  "Python (the same replies, slower)")

    @staticmethod
    def _skip(exc: Exception) -> None:
        print(f"maxk: the compiled servo kernel was not built ({exc}); the servo loop "
              "runs in Python (the same replies, slower)")


def _mypyc_extensions() -> list[Extension]:
    """mypyc's extensions for maxk/compiled.py's modules, or none (no mypy, no compiler,
    or MAXK_PURE_PYTHON=1)."""
    listed = runpy.run_path(str(Path("maxk") / "compiled.py"))
    if os.environ.get(listed["PURE_PYTHON_VARIABLE"], "") not in ("", "0"):
        print("maxk: MAXK_PURE_PYTHON is set: the hot modules stay Python")
        return []
    try:
        from mypyc.build import mypycify
    except ImportError:
        print("maxk: mypy is not installed: the hot modules stay Python")
        return []
    paths = [name.replace(".", "/") + ".py" for name in listed["COMPILED_MODULES"]]
    try:
        extensions = mypycify(paths, opt_level="3", group_name=listed["GROUP"])
    except BaseException as exc:  # mypy's own errors exit
        print(f"maxk: mypyc could not compile the hot modules ({exc!r}): they stay Python")
        return []
    for ext in extensions:
        # floats rounded as CPython rounds them: no fused multiply-adds (bit-identical)
        if sys.platform != "win32":
            ext.extra_compile_args = [*ext.extra_compile_args, "-ffp-contract=off"]
    return extensions


MYPYC_EXTENSIONS = _mypyc_extensions()
MYPYC_NAMES = {ext.name for ext in MYPYC_EXTENSIONS}

setup(
    ext_modules=[*MYPYC_EXTENSIONS, Extension(
        "maxk.firmware_model._servo_kernel",
        ["maxk/firmware_model/_servo_kernel.c"],
        # every float operation rounded as CPython rounds it: no fused multiply-adds,
        # no fast-math reassociation (the kernel must agree with the Python loop bit
        # for bit)
        extra_compile_args=["-O2", "-ffp-contract=off", "-fno-fast-math"],
        optional=True,
    )],
    cmdclass={"build_ext": OptionalBuildExt},
)

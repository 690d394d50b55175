"""The compiled servo kernel, built where a C compiler exists and skipped where none does:
without it maxk runs its servo loop in Python (README, "Servo speed"). Beside it, the same
way, libOmsMAXkMC: the vendor motion-control library API for legacy host programs
(docs/oms-library.md); without a compiler `maxk library` says how to get it."""

import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

OMS_LIBRARY_DIR = Path("maxk") / "host" / "oms_library"
OMS_LIBRARY_NAME = "libOmsMAXkMC.dylib" if sys.platform == "darwin" else "libOmsMAXkMC.so"


class OptionalBuildExt(build_ext):
    """Build the kernel if possible; never fail the install for want of a compiler."""

    def run(self) -> None:
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

    def build_extension(self, ext: Extension) -> None:
        try:
            super().build_extension(ext)
        except Exception as exc:
            self._skip(exc)

    @staticmethod
    def _skip(exc: Exception) -> None:
        print(f"maxk: the compiled servo kernel was not built ({exc}); the servo loop "
              "runs in Python (the same replies, slower)")


setup(
    ext_modules=[Extension(
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

"""The compiled servo kernel, built where a C compiler exists and skipped where none does:
without it maxk runs its servo loop in Python (README, "Servo speed")."""

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext


class OptionalBuildExt(build_ext):
    """Build the kernel if possible; never fail the install for want of a compiler."""

    def run(self) -> None:
        try:
            super().run()
        except Exception as exc:  # no compiler at all (distutils' own errors vary)
            self._skip(exc)

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

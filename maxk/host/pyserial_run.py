"""Run an unchanged pyserial program with `maxk://` ports available:

    python -m maxk.host.pyserial_run legacy_script.py [args...]

Importing maxk registers the handler; the script then runs as `__main__`.
"""

from __future__ import annotations

import runpy
import sys

import maxk  # noqa: F401  (registers the maxk:// handler with pyserial)


def main() -> int:
    if len(sys.argv) < 2:
        print("usage: python -m maxk.host.pyserial_run SCRIPT [ARGS...]", file=sys.stderr)
        return 2
    sys.argv = sys.argv[1:]
    runpy.run_path(sys.argv[0], run_name="__main__")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

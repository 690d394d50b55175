"""Break features on purpose and see the tests catch it (issue 41).

Each fault below is a text substitution in one source file: an anchor string that must
occur exactly once, and what it becomes. The script copies the tree to a temporary
directory, runs the fault's test files there once unbroken (they must pass), then, fault
by fault, applies the substitution to the copy, runs the same files against the copy
(PYTHONPATH is the copy, so the broken code is what the tests import and what the C
library is built from), and restores the file. A fault the tests do not fail on is
"NOT CAUGHT"; an anchor that is not found (the code moved) is "ANCHOR MISSING", and both
make the exit status non-zero.

    python3 tools/fault_check.py               # every fault, its own test files
    python3 tools/fault_check.py --list        # the faults and their anchors
    python3 tools/fault_check.py 4 7           # some of them, by number or name
    python3 tools/fault_check.py --suite       # each fault against the whole suite (slow)

It is a developer's tool, not part of the default test run (a few minutes for all the
faults); `tests/test_fault_check.py` only checks that every anchor is still in the tree.
When you move code an anchor names, move the anchor with it.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CONTROL = "tests/test_caught_faults_control.py"
POKEYS = "tests/test_caught_faults_pokeys.py"
LIBRARY = "tests/test_caught_faults_library.py"


@dataclass(frozen=True)
class Fault:
    name: str
    what: str
    path: str  # relative to the repository's root
    anchor: str
    replacement: str
    tests: tuple[str, ...]


FAULTS: tuple[Fault, ...] = (
    Fault("trigger-late", "control door: a position trigger fires 20% late",
          "maxk/host/control_board.py",
          "position >= t.target if t.rising else position <= t.target)]:",
          "position >= t.target * 1.2 if t.rising else position <= t.target * 1.2)]:",
          (CONTROL, "tests/test_control.py")),
    Fault("json-level-false", "control door: {\"input\": n, \"level\": false} sets it high",
          "maxk/host/control_board.py",
          "{'high' if level else 'low'}",
          "{'high' if level or True else 'low'}",
          (CONTROL, "tests/test_control.py")),
    Fault("stuck-inactive", "world: a switch stuck inactive behaves as no fault",
          "maxk/firmware_model/world.py",
          "if fault == STUCK_INACTIVE:\n                return False",
          "if fault == 'never':\n                return False",
          (CONTROL, "tests/test_world_settings.py")),
    Fault("inactive-words", "world words: `fault SWITCH inactive` read as `none`",
          "maxk/controllers/world_settings.py",
          'state = None if args[1].lower() == "none" else args[1].lower()',
          'state = None if args[1].lower() in ("none", "inactive") else args[1].lower()',
          (CONTROL, "tests/test_world_settings.py")),
    Fault("pokeys-byte-3", "PoKeys status [3] (soft-limit bits) always 0",
          "maxk/commands/pokeys/pev2_commands.py",
          "r[3] = e.soft_limit_bits()", "r[3] = 0", (POKEYS,)),
    Fault("pokeys-byte-5", "PoKeys status [5] (limit override) always 0",
          "maxk/commands/pokeys/pev2_commands.py",
          "r[5] = e.limit_override", "r[5] = 0", (POKEYS,)),
    Fault("pokeys-byte-11", "PoKeys status [11] (charge pump) always 0",
          "maxk/commands/pokeys/pev2_commands.py",
          "r[11] = e.charge_pump", "r[11] = 0", (POKEYS,)),
    Fault("pokeys-byte-14", "PoKeys status [14] (home bits) always 0",
          "maxk/commands/pokeys/pev2_commands.py",
          "r[12], r[13], r[14] = lim_p, lim_n, home",
          "r[12], r[13], r[14] = lim_p, lim_n, 0", (POKEYS,)),
    Fault("pokeys-byte-60", "PoKeys status [60] (e-stop polarity) always 0",
          "maxk/commands/pokeys/pev2_commands.py",
          "r[60] = e.estop_polarity", "r[60] = 0", (POKEYS,)),
    Fault("cmd-buffer-free", "C library: GetCmdBufferFree always 512",
          "maxk/host/oms_library/OmsMAXkMC.c",
          "    return free_bytes;", "    return 512;", (LIBRARY,)),
    Fault("s-curve-text", "C library: SelectOmsSCurveRamp sends only `SC;`",
          "maxk/host/oms_library/OmsMAXkMC.c",
          '"SC;SS%ld;PR%ld;", n, n)', '"SC;")', (LIBRARY,)),
    Fault("absolute-encoder", "C library: GetAbsoluteEncoderPositions reads the motor counter",
          "maxk/host/oms_library/OmsMAXkMC.c",
          "GetAbsoluteEncoderPositions(HANDLE h, PAXES_DATA d) "
          "{ return positions(h, OMS_ALL_AXES, d, POS_ABSOLUTE); }",
          "GetAbsoluteEncoderPositions(HANDLE h, PAXES_DATA d) "
          "{ return positions(h, OMS_ALL_AXES, d, POS_MOTOR); }", (LIBRARY,)),
    Fault("clear-controller-flags", "C library: ClrOmsControllerFlags does nothing",
          "maxk/host/oms_library/OmsMAXkMC.c",
          "ClrOmsControllerFlags(HANDLE h, long status) { return clear_status(h, status); }",
          "ClrOmsControllerFlags(HANDLE h, long status) "
          "{ (void)h; (void)status; return SUCCESS; }", (LIBRARY,)),
    # more of the same kind, beyond the ten
    Fault("time-trigger-late", "control door: a time trigger fires one tick late",
          "maxk/host/control_board.py",
          "engine.add_observer(self._due, max(1, earliest - engine.tick))",
          "engine.add_observer(self._due, max(1, earliest - engine.tick) + 1)",
          ("tests/test_control.py",)),
    Fault("encoder-ratio-text", "C library: SetOmsEncoderRatio swaps its operands",
          "maxk/host/oms_library/OmsMAXkMC.c",
          '"ER%ld,%ld;", counts, steps)', '"ER%ld,%ld;", steps, counts)', (LIBRARY,)),
    Fault("departed-input-lost", "doors: a departed host's bytes behind a wait never run",
          "maxk/host/client.py",
          "        if self not in service.departed:\n",
          "        self._inbox.clear()\n        if self not in service.departed:\n",
          ("tests/test_isolation.py",)),
    Fault("velocity-query", "C library: GetOmsAxisVelocity asks RC (the acceleration)",
          "maxk/host/oms_library/OmsMAXkMC.c",
          'GetOmsAxisVelocity(HANDLE h, long axis, long *v) '
          '{ return axis_report(h, axis, "RV", v); }',
          'GetOmsAxisVelocity(HANDLE h, long axis, long *v) '
          '{ return axis_report(h, axis, "RC", v); }',
          (LIBRARY,)),
    Fault("wk-plus-limit", "C library: W/K plus limit sensors land on the minus bits",
          "maxk/host/oms_library/OmsMAXkMC.c",
          "*out |= 1L << (18 + i);", "*out |= 1L << (8 + i);", (LIBRARY,)),
    Fault("io-bit-low", "C library: SetOmsIOBit(bit, 0) sets the bit high",
          "maxk/host/oms_library/OmsMAXkMC.c",
          '"AA;%s%ld;", state ? "BH" : "BL", bit)', '"AA;%s%ld;", "BH", bit)', (LIBRARY,)),
)

IGNORED = shutil.ignore_patterns(".git", "build", "__pycache__", "*.egg-info", ".pytest_cache",
                                 ".mypy_cache", ".ruff_cache", ".hypothesis")


def anchor_problem(fault: Fault, root: Path = ROOT) -> str | None:
    """None if the fault's anchor is in its file exactly once, else what is wrong."""
    path = root / fault.path
    if not path.exists():
        return f"{fault.path} does not exist (moved?)"
    count = path.read_text().count(fault.anchor)
    if count == 1:
        return None
    if count == 0:
        return f"anchor not found in {fault.path} (the code moved?): {fault.anchor!r}"
    return f"anchor found {count} times in {fault.path} (make it unique): {fault.anchor!r}"


def run_tests(copy: Path, tests: tuple[str, ...], timeout: float) -> tuple[int, str]:
    env = {**os.environ, "PYTHONPATH": str(copy), "PYTHONDONTWRITEBYTECODE": "1"}
    command = [sys.executable, "-m", "pytest", "-q", "-x", "-rf", "-p", "no:cacheprovider",
               *tests]
    try:
        done = subprocess.run(command, cwd=copy, env=env, capture_output=True, text=True,
                              timeout=timeout)
    except subprocess.TimeoutExpired:
        return -1, "timed out"
    lines = [line for line in done.stdout.splitlines() if line.strip()]
    if done.returncode == 0:
        dots = sum(line.split(" [")[0].count(".") for line in lines)
        return 0, f"{dots} tests passed"
    failed = [line.split(" - ")[0].removeprefix("FAILED ") for line in lines
              if line.startswith("FAILED ")]
    return done.returncode, (failed[0] if failed else lines[-1] if lines
                             else done.stderr.strip()[-200:])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("faults", nargs="*", help="numbers (1-based) or names; default all")
    parser.add_argument("--list", action="store_true", help="list the faults and stop")
    parser.add_argument("--suite", action="store_true",
                        help="run the whole suite for each fault, not its own files")
    parser.add_argument("--timeout", type=float, default=900.0,
                        help="seconds one test run may take")
    args = parser.parse_args(argv)
    chosen = [f for i, f in enumerate(FAULTS, start=1)
              if not args.faults or str(i) in args.faults or f.name in args.faults]
    if args.list:
        for i, f in enumerate(FAULTS, start=1):
            problem = anchor_problem(f)
            print(f"{i:2} {f.name:24} {f.what}\n   {f.path}: {f.anchor!r}"
                  + (f"\n   !! {problem}" if problem else ""))
        return 0
    failed = 0
    with tempfile.TemporaryDirectory(prefix="maxk-faults-") as tmp:
        copy = Path(tmp) / "tree"
        shutil.copytree(ROOT, copy, ignore=IGNORED)
        files = sorted({t for f in chosen for t in f.tests})
        suite = ("tests",) if args.suite else tuple(files)
        started = time.monotonic()
        rc, last = run_tests(copy, suite, args.timeout)
        print(f"baseline (no fault): {'passes' if rc == 0 else 'FAILS'} ({last}, "
              f"{time.monotonic() - started:.0f} s)", flush=True)
        if rc != 0:
            print("the tests fail on the unbroken tree: fix that first")
            return 2
        for i, fault in enumerate(FAULTS, start=1):
            if fault not in chosen:
                continue
            problem = anchor_problem(fault)
            if problem is not None:
                print(f"{i:2} {fault.name:24} ANCHOR MISSING: {problem}")
                failed += 1
                continue
            target = copy / fault.path
            original = target.read_text()
            target.write_text(original.replace(fault.anchor, fault.replacement))
            started = time.monotonic()
            try:
                rc, last = run_tests(copy, ("tests",) if args.suite else fault.tests,
                                     args.timeout)
            finally:
                target.write_text(original)
            took = time.monotonic() - started
            if rc == 1:
                verdict = "caught"
            elif rc == 0:
                verdict = "NOT CAUGHT"
                failed += 1
            else:
                verdict = f"ERROR (pytest exit {rc})"
                failed += 1
            print(f"{i:2} {fault.name:24} {verdict:10} {fault.what} [{last}; {took:.0f} s]",
                  flush=True)
    total = len(chosen)
    print(f"{total - failed} of {total} faults caught")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

"""Before and after, side by side in one run: the benchmarks of another revision and of
this tree, alternating figure by figure so that both see the same machine load.

    python3 -m benchmarks.compare REVISION [names ...] [--rounds 2] [--these-benchmarks]

The other revision is exported with `git archive` into a temporary folder (nothing in
this checkout changes) and run with its own code on the path; each figure is the best of
`--rounds` runs per side. Prints a table: figure, before, after, after/before, and, when
`naive` is among the names (first, as it is by default), each rate as a multiple of the
naive loop (issue 19's table; the best of its runs on either side, as it is the same
loop on both with `--these-benchmarks`). `--these-benchmarks` runs this
tree's benchmark scripts against the other revision's maxk (for figures it had no
script for yet).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

from benchmarks.figure import is_rate

ROOT = Path(__file__).resolve().parent.parent
DEFAULT = ["naive", "steppers_free", "steppers_polled", "steppers_varied", "servos_short",
           "servos_long", "circle", "trajectory_scan", "hole_polled", "commands", "lexer"]


def _export(revision: str, into: Path) -> None:
    archive = into / "tree.tar"
    subprocess.run(["git", "-C", str(ROOT), "archive", "-o", str(archive), revision],
                   check=True)
    with tarfile.open(archive) as tar:
        tar.extractall(into / "tree", filter="data")


def _figures(tree: Path, name: str) -> dict[str, dict]:
    env = {**os.environ, "PYTHONPATH": str(tree)}
    result = subprocess.run([sys.executable, "-m", "benchmarks", name, "--json"], cwd=tree,
                            env=env, capture_output=True, text=True, check=False)
    if result.returncode != 0:
        print(f"{name} failed in {tree}:\n{result.stderr}", file=sys.stderr)
        return {}
    out = {}
    for line in result.stdout.splitlines():
        if line.startswith("{"):
            figure = json.loads(line)
            out[figure["name"]] = figure
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks.compare")
    parser.add_argument("revision", help="the 'before' revision (e.g. a commit or tag)")
    parser.add_argument("names", nargs="*", default=DEFAULT)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--these-benchmarks", action="store_true",
                        help="run this tree's benchmarks/ against the other revision's maxk")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="maxk-before-") as tmp:
        _export(args.revision, Path(tmp))
        before_tree = Path(tmp) / "tree"
        if args.these_benchmarks:
            shutil.rmtree(before_tree / "benchmarks", ignore_errors=True)
            shutil.copytree(ROOT / "benchmarks", before_tree / "benchmarks",
                            ignore=shutil.ignore_patterns("__pycache__"))
        rows = []
        naive: dict[str, float] = {}
        print(f"{'figure':<36} {'before':>12} {'after':>12}  {'ratio':>6}  {'unit':<24}"
              f"{'x naive before':>15} {'after':>8}", flush=True)
        for name in args.names:
            best: dict[str, dict[str, dict]] = {"before": {}, "after": {}}
            for _ in range(args.rounds):
                for side, tree in (("before", before_tree), ("after", ROOT)):
                    for fig_name, figure in _figures(tree, name).items():
                        kept = best[side].get(fig_name)
                        if kept is None or figure["value"] > kept["value"]:
                            best[side][fig_name] = figure
            for fig_name, after in best["after"].items():
                before = best["before"].get(fig_name)
                if fig_name == "naive_10_pid_axes":  # the same loop on both sides: its
                    # best run is the least disturbed measure of the machine
                    best_naive = max(after["value"], before["value"] if before else 0.0)
                    naive = {"before": best_naive, "after": best_naive}
                rows.append((fig_name, before["value"] if before else None, after["value"],
                             after["unit"]))
                print(_row(rows[-1]) + _multiples(rows[-1], naive), flush=True)
    return 0


def _row(row: tuple[str, float | None, float, str]) -> str:
    name, before, after, unit = row
    ratio = f"{after / before:5.2f}x" if before else "  new"
    shown = f"{before:>12,.0f}" if before is not None else f"{'-':>12}"
    return f"{name:<36} {shown} {after:>12,.0f}  {ratio}  {unit:<24}"


def _multiples(row: tuple[str, float | None, float, str], naive: dict[str, float]) -> str:
    """Both sides as multiples of the naive loop (blank without one)."""
    _name, before, after, unit = row
    if not naive or not is_rate(unit):
        return ""
    shown = f"{before / naive['before']:>14,.1f}x" if before and naive["before"] else \
        f"{'-':>15}"
    return f"{shown} {after / naive['after']:>7,.1f}x"


if __name__ == "__main__":
    raise SystemExit(main())

"""Before and after, side by side in one run: the benchmarks of another revision and of
this tree, alternating figure by figure so that both see the same machine load.

    python3 -m benchmarks.compare REVISION [names ...] [--rounds 2]

The other revision is exported with `git archive` into a temporary folder (nothing in
this checkout changes) and run with its own code on the path; each figure is the best of
`--rounds` runs per side. Prints a table: figure, before, after, after/before.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tarfile
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DEFAULT = ["steppers_free", "steppers_polled", "steppers_varied", "servos_short",
           "servos_long", "trajectory_scan", "hole_polled", "commands", "lexer"]


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
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="maxk-before-") as tmp:
        _export(args.revision, Path(tmp))
        before_tree = Path(tmp) / "tree"
        rows = []
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
                rows.append((fig_name, before["value"] if before else None, after["value"],
                             after["unit"]))
                print(_row(rows[-1]), flush=True)
    return 0


def _row(row: tuple[str, float | None, float, str]) -> str:
    name, before, after, unit = row
    ratio = f"{after / before:5.2f}x" if before else "  new"
    shown = f"{before:>12,.0f}" if before is not None else f"{'-':>12}"
    return f"{name:<36} {shown} {after:>12,.0f}  {ratio}  {unit}"


if __name__ == "__main__":
    raise SystemExit(main())

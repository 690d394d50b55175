"""The MAXk before and after the engine refactor, side by side (skipped without the old
tree at /tmp/before, or $MAXK_BEFORE). The refactor's rule: nothing changes for a MAXk
user. What this found is documented here: a regression (fixed) as a test, an intended
door change as a test of what changed and what did not.

The long runs are the standalone runners (tests/differential_maxk.py,
tests/differential_doors.py); this file runs a fixed, bounded sample of each.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import differential_doors as doors  # noqa: E402
import differential_maxk as diff  # noqa: E402


def _predates_issue_17(tree: Path) -> bool:
    """Issue 17 changed what a MAXk user sees on purpose: the commands host code sends
    (SD, JF, WQ, ...), CL/HN/HF accepted on an open-loop stepper, WT in update cycles,
    Table 6-2's I/O lines and analog inputs per model, RE equal to RP after homing an
    open-loop stepper, a reply before a later command's notification. Against a tree
    from before it nothing can be identical; point MAXK_BEFORE at a tree with those
    changes to compare a later refactor."""
    tables = [tree / "maxk" / "commands" / "max" / "table.py",  # after the refactor
              tree / "maxk" / "commands" / "table.py"]  # before it
    return not any(t.exists() and '("SD",' in t.read_text() for t in tables)


pytestmark = pytest.mark.skipif(
    not diff.OLD_TREE.exists() or _predates_issue_17(diff.OLD_TREE),
    reason=f"no old tree at {diff.OLD_TREE}, or one from before issue 17's intended changes")


@pytest.fixture(scope="module")
def pair():
    p = diff.Pair()
    yield p
    p.close()


def run_in(tree: Path, code: str) -> str:
    """Run code in a fresh interpreter with `tree` providing maxk (and its tests/)."""
    env = dict(os.environ, PYTHONPATH=str(tree), XDG_DATA_HOME="/tmp/maxk-diff-xdg")
    done = subprocess.run([sys.executable, "-P", "-c", code], capture_output=True,
                          text=True, env=env, cwd="/tmp", timeout=120)
    assert done.returncode == 0, done.stderr
    return done.stdout


# ---- in-process, virtual time -----------------------------------------------------------

@pytest.mark.parametrize("seed", range(24))
def test_random_command_streams_are_identical(pair, seed):
    job = diff.make_stream(seed, 60)
    old, new = pair.run(job)
    found = diff.first_difference(old, new)
    assert found is None, diff.describe(job, found)


def test_exchanges_and_old_test_inputs_are_identical(pair):
    streams = diff.exchange_streams() + diff.test_function_streams()
    assert len(streams) > 100
    for job in streams:
        found = diff.first_difference(*pair.run(job))
        assert found is None, f"{job['seed']}: {found}"


def test_scripts_are_identical(pair):
    """Every example script and every script text in the old tests: same transcript,
    failures and final state (but the unknown-model message, next test)."""
    scripts = diff.example_scripts() + diff.test_scripts()
    assert len(scripts) > 50
    for name, text in scripts:
        if "MAXk-9999" in text:
            continue
        boards = [line.split()[1:] for line in text.splitlines() if line.startswith("@board")]
        if any(not m.lower().startswith("maxk") for b in boards for m in b):
            continue  # another controller's script: the old tree had only the MAXk
        old, new = pair.run({"kind": "script", "text": text, "path": name})
        assert old == new, name


def test_unknown_model_message_names_every_controller(pair):
    """Intended: the registry now knows other controllers, and the message says so. The
    only difference the scripts showed; it is a message to a person, not a reply."""
    old, new = pair.run({"kind": "script", "text": "@board MAXk-9999\n", "path": "t.maxk"})
    assert "unknown board model 'MAXk-9999'" in old["exception"]
    assert "unknown controller model 'MAXk-9999'" in new["exception"]
    assert "MC405" in new["exception"]


@pytest.mark.parametrize("example", ["limits_and_homing.maxk", "queue_loops_and_units.maxk",
                                     "epics_asyn_startup.maxk", "io_and_sw.maxk"])
def test_maxk_run_output_and_trace_are_identical(example):
    assert diff.compare_cli([example]) == []


# ---- the TCP door -----------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(6))
def test_door_streams_are_identical(seed):
    """Pipelined, split and garbage bytes from one or two hosts on a manual clock: the
    same bytes, except where notifications fall among the replies of input above the
    2 KiB slice (next test)."""
    old, new = doors.DoorWorker(diff.OLD_TREE), doors.DoorWorker(diff.NEW_TREE)
    try:
        job = doors.door_job(seed)
        old.submit(job)
        new.submit(job)
        found, _ = doors.compare_door(old.receive(), new.receive())
    finally:
        old.close()
        new.close()
    assert found is None, found


BURST = """
from tests.hosting import HostedBoards, Client
hosted = HostedBoards(models=("MAXk-1000",))
c = Client(hosted.ports[0])
c.send(b"AX RP;" * 700 + b"XQ;\\n#WS\\n")
out = b""
while not out.endswith(b"=0\\n\\r"):
    out += c.sock.recv(65536)
print(repr(out.split(b"\\n\\r")[:3]), out.count(b"\\n\\r"))
hosted.close()
"""


def test_a_burst_above_2k_hears_its_notification_in_slice_order():
    """Intended (hosts take turns in 2 KiB slices): a 4 KiB burst whose last command is
    bad. The old door ran the whole read at once and sent the command-error notification
    before all 700 replies; the new one answers slice by slice, so the replies of the
    first slices come first. Same lines, same count; only the notification moved later,
    nearer the command that caused it."""
    old = run_in(diff.OLD_TREE, BURST)
    new = run_in(diff.NEW_TREE, BURST)
    assert old.split()[-1] == new.split()[-1] == "702"  # 700 replies, 1 notification, =0
    assert "%000 01000000" in old.split("]")[0]
    assert "%000 01000000" not in new.split("]")[0]


# What a host sends just before it hangs up still runs: found here as a regression of
# the sliced door, fixed, and held by tests/test_door_robustness.py (deterministic). The
# real servers' comparison depends on wall-clock time, so it is the standalone runner's
# (`python3 tests/differential_doors.py --serve N`), not a test.

"""Differential test of the MAXk emulator: the tree before the engine refactor (c4c36cf,
a plain copy at /tmp/before) against this tree, on the same random command streams, in
virtual time. The refactor's rule: nothing changes for a MAXk user, so every reply, tick,
position, encoder, doorbell, flag word, output change, capture-ring byte, command-error
record and archive file must be identical after every step.

Each tree runs in its own subprocess (tests/differential_worker.py with that tree first
on PYTHONPATH). Standalone:

    python3 tests/differential_maxk.py --seconds 300 --seed 1     # random streams
    python3 tests/differential_maxk.py --scripts                  # examples, test scripts

The pytest side is tests/test_differential_maxk.py (skipped without /tmp/before).
"""

from __future__ import annotations

import argparse
import ast
import json
import os
import random
import re
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
NEW_TREE = Path(os.environ.get("MAXK_AFTER", str(HERE.parent)))
OLD_TREE = Path(os.environ.get("MAXK_BEFORE", "/tmp/before"))
WORKER = HERE / "differential_worker.py"

MODELS = {"MAXk-1000": "X", "MAXk-2000": "XY", "MAXk-4000": "XYZT",
          "MAXk-A000": "XYZTUVRSWK"}
RATES = (8192, 8192, 4096, 2048, 1024)
Step = list  # ["send", text] | ["write", text] | ["advance", s, ticks] | ...


class Worker:
    """A long-lived subprocess running jobs against one tree."""

    def __init__(self, tree: Path) -> None:
        env = dict(os.environ, PYTHONPATH=str(tree), PYTHONHASHSEED="0")
        env["XDG_DATA_HOME"] = "/tmp/maxk-diff-xdg"  # never the user's archives
        self.tree = tree
        self.proc = subprocess.Popen(
            [sys.executable, "-P", str(WORKER)], stdin=subprocess.PIPE,
            stdout=subprocess.PIPE, text=True, env=env, cwd="/tmp")

    def submit(self, job: dict[str, Any]) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.write(json.dumps(job) + "\n")
        self.proc.stdin.flush()

    def receive(self) -> dict[str, Any]:
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        if not line:
            raise RuntimeError(f"worker for {self.tree} died")
        return json.loads(line)

    def close(self) -> None:
        if self.proc.stdin:
            self.proc.stdin.close()
        self.proc.wait(10)


class Pair:
    """The old and the new tree side by side; jobs run in both at once (2 cores)."""

    def __init__(self) -> None:
        self.old = Worker(OLD_TREE)
        self.new = Worker(NEW_TREE)
        for worker, tree in ((self.old, OLD_TREE), (self.new, NEW_TREE)):
            worker.submit({"kind": "where"})
            where = worker.receive()["file"]
            assert where.startswith(str(tree)), (where, tree)

    def run(self, job: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
        self.old.submit(job)
        self.new.submit(job)
        return self.old.receive(), self.new.receive()

    def close(self) -> None:
        self.old.close()
        self.new.close()


# ---- comparing ----------------------------------------------------------------------

@dataclass
class Difference:
    step: int  # index into steps (0: the fresh board)
    key: str
    old: Any
    new: Any

    def __str__(self) -> str:
        return f"step {self.step} {self.key}: old {self.old!r} new {self.new!r}"


def first_difference(old: dict[str, Any], new: dict[str, Any]) -> Difference | None:
    """Steps report only what changed, so the first differing step holds the cause."""
    for key in ("crash", "exception"):
        if old.get(key) != new.get(key):
            return Difference(-1, key, old.get(key), new.get(key))
    for n, (a, b) in enumerate(zip(old["steps"], new["steps"], strict=True)):
        for key in sorted(set(a) | set(b)):
            if a.get(key) != b.get(key):
                return Difference(n, key, a.get(key), b.get(key))
    if old["archive"] != new["archive"]:
        return Difference(len(old["steps"]), "archive", old["archive"], new["archive"])
    return None


# ---- generating -----------------------------------------------------------------------

class Gen:
    """Random but meaningful MAX command streams for one model."""

    def __init__(self, r: random.Random, model: str, extended: bool = False) -> None:
        self.extended = extended  # also input waits, inputs as functions, observers, polls
        self.r = r
        self.model = model
        self.letters = MODELS[model]
        self.mode = "single"

    # operands
    def int_(self, lo: int, hi: int) -> str:
        r = self.r
        value = r.randint(lo, hi)
        roll = r.random()
        if roll < 0.06:
            return f"{value}.{r.randint(0, 99)}"
        if roll < 0.08 and value >= 0:
            return f"+{value}"
        if roll < 0.09:
            return r.choice(["", "-", ".", "1e3", "--5", "0x10", "99999999999"])
        return str(value)

    def per_axis(self, lo: int, hi: int) -> str:
        """One operand in single mode, a comma list (with blanks) in AA/AM."""
        if self.mode == "single":
            return self.int_(lo, hi)
        r = self.r
        n = r.randint(1, len(self.letters) + (1 if r.random() < 0.05 else 0))
        return ",".join("" if r.random() < 0.2 else self.int_(lo, hi) for _ in range(n))

    def letter_list(self, choices: str) -> str:
        if self.mode == "single":
            return self.r.choice(choices)
        n = self.r.randint(1, len(self.letters))
        return ",".join(self.r.choice(choices + " ") .strip() for _ in range(n))

    def axis_mode(self) -> str:
        r = self.r
        roll = r.random()
        if roll < 0.55:
            letter = r.choice(self.letters)
            if r.random() < 0.03:
                letter = r.choice("XYZTUVRSWK")  # maybe not on this model
            self.mode = "single"
            return "A" + letter
        self.mode = "AA" if roll < 0.8 else "AM"
        return self.mode

    def command(self) -> str:
        r = self.r
        p = self.per_axis
        kind = r.choices(
            ["mode", "setting", "move", "stop", "queue", "loop", "query", "home", "io",
             "servo", "encoder", "switch", "vector", "misc"],
            [10, 14, 14, 5, 6, 4, 16, 5, 4, 4, 4, 4, 5, 3])[0]
        if kind == "mode":
            return self.axis_mode()
        if kind == "setting":
            m = r.choice(["VL", "VB", "AC", "DC", "LA", "PN", "PF", "SC", "SS", "PR", "CN",
                          "VL", "AC"])
            ranges = {"VL": (1, 300000), "VB": (0, 5000), "AC": (1, 3000000),
                      "DC": (1, 3000000), "PN": (0, 500), "SS": (0, 500), "PR": (0, 500)}
            if m in ranges:
                if m == "PN" and r.random() < 0.3:
                    return "PN"
                return m + p(*ranges[m])
            return m
        if kind == "move":
            m = r.choice(["MA", "MR", "MR", "GO", "GO", "GD", "GN", "JG", "MT", "ML", "MP",
                          "MM", "MO", "LP", "LO", "LPE"])
            if m in ("MA", "MT", "LP", "LO", "LPE"):
                return m + p(-60000, 60000)
            if m in ("MR", "ML"):
                return m + p(-40000, 40000)
            if m == "JG":
                return m + p(-80000, 80000)
            return m
        if kind == "stop":
            m = r.choice(["ST", "SA", "KL", "KS", "KS0", "KS1", "FL", "SI1", "SI0"])
            if m == "SI1" and self.mode != "single":
                return "SI" + ",".join(r.choice("01") for _ in self.letters)
            return m
        if kind == "queue":
            m = r.choice(["WT", "ID", "ID", "CA", "IC", "RQC"])
            return m + (self.int_(0, 800) if m == "WT" else "")
        if kind == "loop":
            return r.choice(["LS" + self.int_(1, 4), "LE", "LS2", "LE"])
        if kind == "query":
            return r.choice(
                ["RP", "RE", "RV", "RC", "QA", "RA", "RI", "QI", "PP", "PE", "RQC", "EA",
                 "QL", "WY", "#WS", "?PS", "PS?", "LT?", "?LS", "LM?", "CL?", "?PM", "?KA",
                 "?KP", "#UR?", "?UR", "BX", "RB", "AI" + str(r.randint(0, 4)), "AB?",
                 "VRV", "VRC", "CC", "HT?", "RP", "QA", "RI"])
        if kind == "home":
            m = r.choice(["HM", "HR", "KM", "KR", "HS", "HE", "HH", "HL", "HI0", "HI1",
                          "EH", "HT", "HN", "HF"])
            if m in ("HM", "HR", "KM", "KR"):
                return m + (p(-2000, 2000) if r.random() < 0.4 else "")
            if m == "EH":
                return "EH" + "".join(r.choice("01X") for _ in range(4))
            if m == "HT":
                return "HT" + r.choice("HL")
            return m
        if kind == "io":
            m = r.choice(["BH", "BL", "BD", "BS", "IO", "SW", "AN", "AF", "PA", "SE", "AO"])
            if m in ("BH", "BL"):
                return m + str(r.randint(0, 16))
            if m in ("BD", "BS"):
                return m + format(r.randint(0, 0xFFFF), "x")
            if m == "IO":
                return f"IO{r.randint(0, 15)},{r.randint(0, 1)}"
            if m == "SW":
                return m + p(0, 15)
            if m == "PA":
                return "PA" + self.letter_list("01")
            if m == "SE":
                return m + p(0, 2000)
            if m == "AO":
                return m + p(-32768, 32767)
            return m
        if kind == "servo":
            m = r.choice(["KP", "KI", "KD", "KU", "KV", "KA", "KF", "KO", "SVB", "SVN",
                          "SVP", "PSM"])
            ranges = {"KP": (0, 60), "KI": (0, 5), "KD": (0, 200), "KU": (0, 100),
                      "KV": (0, 50), "KA": (0, 50), "KF": (0, 50), "KO": (-100, 100),
                      "SVB": (0, 1)}
            if m in ranges:
                return m + p(*ranges[m])
            if m == "SVP":
                return "SVP" + self.letter_list("+-")
            return m
        if kind == "encoder":
            m = r.choice(["PSE", "PSO", "PSM", "ER", "ES", "TN", "TF", "IS", "HV", "HD",
                          "HG", "UU", "UF"])
            if m == "ER":
                return f"ER{r.randint(1, 4000)},{r.randint(1, 4000)}"
            if m == "ES":
                return m + p(0, 500)
            if m == "HV":
                return m + p(0, 20000)
            if m in ("HD", "HG"):
                return m + p(0, 500)
            if m == "UU":
                return "UU" + r.choice(["1", "2", "0.5", "1000", "3.25", "0"])
            return m
        if kind == "switch":
            m = r.choice(["LT" + r.choice("HL"), "LH", "LL", "LM" + r.choice("HSFN"), "SL",
                          "SF", "LN", "LF", "CL" + r.choice("01"), "PS" + r.choice("OEM")])
            return m
        if kind == "vector":
            return self.vector()
        return r.choice(["#UR" + r.choice(["1024", "2048", "4096", "8192", "1000"]),
                         "APP", "RDP", "RDF", "TN", "AA", "AM"])

    def vector(self) -> str:
        r = self.r
        task = r.choice(["", "", "", "[1]", "[2]", "[9]"])
        m = r.choice(["VA", "VV", "VP", "VP", "VC", "VE", "VG", "VH", "VID", "VIO", "VO",
                      "VOA", "VRV", "VRC"])
        if m == "VA":
            return f"VA{task}{r.randint(1, 500000)}"
        if m == "VV":
            if r.random() < 0.5:
                return f"VV{task}{r.randint(0, 20000)}"
            return f"VV{task}{r.randint(0, 20000)},{r.choice([0, r.randint(1, 20000)])}"
        if m == "VP":
            n = r.randint(2, max(2, len(self.letters)))
            form = r.choice(["", "", "A", "R"]) if task else ""
            slots = ",".join("" if r.random() < 0.25 else str(r.randint(-20000, 20000))
                             for _ in range(n))
            return f"VP{task}{form}{slots}"
        if m == "VC":
            return (f"VC{task}{r.randint(-10000, 10000)},{r.randint(-10000, 10000)},"
                    f"{r.choice([90, -90, 180, -180, 360, 45, -720, 30])}")
        if m in ("VE", "VG", "VRV", "VRC"):
            return m + task
        if m in ("VH", "VID"):
            return f"{m}{task}{r.randint(0, 1)}"
        if m == "VIO":
            return (f"VIO{task}{format(r.randint(0, 0xFFFF), '04x')},"
                    f"{r.choice(['', format(r.randint(0, 0xFFFF), '04x')])},"
                    f"{format(r.randint(0, 0xFFFF), '04x')}")
        if m == "VO":
            return f"VO[{r.randint(1, 2)}]={r.randint(0, 200)}" if task else \
                f"VO{r.randint(0, 210)}"
        return f"VOA{r.randint(0, 3)},{r.randint(0, 10)}"

    def template(self) -> str:
        """A sequence a host would really send, so streams get somewhere."""
        r = self.r
        L = r.choice(self.letters)
        n = len(self.letters)
        v, a, d = r.randint(1000, 100000), r.randint(10000, 2000000), r.randint(-30000, 30000)
        k = r.randint(1, n)

        def lst(lo: int, hi: int) -> str:
            return ",".join(str(r.randint(lo, hi)) for _ in range(k))

        choices = [
            f"A{L}; VL{v}; AC{a}; MR{d}; GO; ID;",
            f"A{L} VL{v} VB{r.randint(0, 500)} AC{a} MA{d} GD ID",
            f"A{L};CA;AC{a};VL{v};VB100;HM;MA0;GO;ID;",
            f"A{L}; JG{r.randint(-50000, 50000)};",
            f"A{L}; ST; ID;",
            f"AA; VL{lst(1000, 50000)}; AC{lst(10000, 500000)}; MR{lst(-20000, 20000)}; GO; ID;",
            f"AM; VL{lst(1000, 50000)}; AC{lst(10000, 500000)}; MT{lst(-20000, 20000)}; GO; ID;",
            f"AM; ML{lst(-20000, 20000)}; GO; ID;",
            f"A{L}; LS{r.randint(1, 3)}; MR{r.randint(-500, 500)}; GO; WT{r.randint(0, 50)}; "
            f"LE; ID;",
            f"A{L}; PSM; KP{r.randint(1, 40)}; KI{r.randint(0, 2)}; KD{r.randint(0, 100)}; "
            f"VL{r.randint(1000, 20000)}; AC{r.randint(50000, 500000)}; "
            f"MR{r.randint(-300, 300)}; GO; ID;",
            f"A{L}; PSE; ER{r.choice([1, 2, 4000])},{r.choice([1, 2, 4000])}; "
            f"UU{r.choice(['1', '2', '0.5'])}; MR{r.randint(-50, 50)}; GO; ID;",
            f"A{L}; KM; ID;",
            f"A{L}; HR; ID;",
            "AM RP; AM RE; RI",
            f"#UR{r.choice([1024, 2048, 4096, 8192])}; #UR?",
        ]
        if self.extended:
            choices += [
                f"A{L}; MR{d}; GO; SW{r.randint(0, 15)}; MR{-d}; GO; ID;",
                f"A{L}; BW{r.randint(0, 15)}; MR{d}; GO; ID;",
                f"AA; SW{r.randint(0, 15)},{r.randint(0, 15)}; MR{lst(-20000, 20000)}; GO; ID;",
                f"A{L}; LMS; JG{r.choice([-1, 1]) * v}; WT{r.randint(0, 300)}; ST; ID;",
                f"A{L}; LMS; MR{d * 3}; GO; HM; ID;",
                f"A{L}; PSM; KP{r.randint(1, 40)}; JG{r.randint(-50000, 50000)}; WT50; ST; ID;",
                f"AA; LMS; JG{lst(-50000, 50000)}; WT{r.randint(0, 300)}; ST; ID;",
            ]
        if n >= 2:
            choices += [
                f"AA; VA{r.randint(10000, 500000)}; VV{r.randint(500, 8000)},"
                f"{r.randint(500, 8000)}; VP{r.randint(-5000, 5000)},{r.randint(-5000, 5000)}; "
                f"VC0,0,{r.choice([90, 180, -360])}; VV{r.randint(500, 5000)},0; "
                f"VP{r.randint(-5000, 5000)},{r.randint(-5000, 5000)}; VE;",
                "AA; VOA0,5; VV1000,1000; VP0,0; VIO0100,,0100; VC0,500,-180; "
                "VIO0,,0100; VV1000,0; VP-100,0; VE;",
                f"AM; VIO[1]0100,0000,0100; VID[1]1; VH[1]{r.randint(0, 1)}; "
                f"VA[1]{r.randint(1000, 50000)};VV[1]1,1000;VP[1]A{r.randint(10, 200)},,;"
                f"VV[1]1000,0;VP[1]A{r.randint(300, 900)},,; VE[1];",
                "VG[1]", "VH[1]1", f"VO[1]={r.randint(0, 200)}",
            ]
        return r.choice(choices)

    def line(self) -> str:
        r = self.r
        if r.random() < 0.35:
            text = self.template()
            self.mode = "single"  # templates set their own mode; be safe
            return text + r.choice(["", "\r", "\n", ";"])
        parts = [self.command() for _ in range(r.randint(1, 6))]
        out = parts[0]
        for part in parts[1:]:
            out += r.choice([";", " ", "; ", "", ";", "\t"]) + part
        return out + r.choice(["", "\r", "\n", ";", "\r\n", ";\r"])

    def garbage(self) -> str:
        r = self.r
        alphabet = ("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789,.;?#=[]+- \r\n\t"
                    "\x00\x01\x06\x1b\x7f\x80\xa0\xff\"'!@$%^&*()_{}|\\<>/~`")
        return "".join(r.choice(alphabet) for _ in range(r.randint(1, 25)))

    def world(self) -> Step:
        r = self.r
        L = r.choice(self.letters)
        m = r.choice(["limits", "limits", "home", "home", "fault", "bounce", "index", "miss",
                      "input", "analog", "capture"])
        if m == "limits":
            kw = {}
            if r.random() < 0.8:
                kw["plus"] = r.choice([None, r.randint(500, 40000)])
            if r.random() < 0.8:
                kw["minus"] = r.choice([None, -r.randint(500, 40000)])
            return ["world", "set_limits", [L], kw]
        if m == "home":
            lo = r.randint(-3000, 3000)
            pair: list[int | None] = r.choice([[lo, lo + r.randint(1, 500)], [None, None]])
            return ["world", "set_home", [L, *pair], {}]
        if m == "fault":
            return ["world", "fault", [L, r.choice(["plus", "minus", "home"]),
                                       r.choice(["active", "inactive", None])], {}]
        if m == "bounce":
            return ["world", "bounce", [L, r.choice(["plus", "minus", "home"]),
                                        r.randint(0, 20)], {}]
        if m == "index":
            return ["world", "set_index", [L, r.randint(100, 5000), r.randint(1, 10),
                                           r.randint(-2000, 2000)], {}]
        if m == "miss":
            return ["world", "miss_steps", [L, r.randint(-50, 50)], {}]
        if m == "input":
            return ["world", "set_input", [r.randint(0, 15), r.random() < 0.5], {}]
        if m == "analog":
            return ["world", "set_analog", [r.randint(0, 3), r.uniform(-10, 10)], {}]
        return ["world", "capture", [L], {
            "home": r.choice([False, None, "rising", "falling", "both"]),
            "index": r.choice([None, True, False]),
            "inputs_rising": r.choice([None, r.randint(0, 0xFFFF)])}]

    def steps(self, count: int) -> list[Step]:
        r = self.r
        out: list[Step] = []
        while len(out) < count:
            roll = r.random()
            if roll < 0.55:
                text = self.line()
                if r.random() < 0.3:
                    cuts = sorted(r.sample(range(len(text) + 1), min(len(text), 3)))
                    pieces = [text[i:j] for i, j in zip([0, *cuts], [*cuts, len(text)],
                                                        strict=True)]
                    out += [["write", p] for p in pieces if p]
                elif text[-1:] in ("\r", "\n", ";"):
                    out.append(["write", text])
                else:
                    out.append(["send", text])
            elif roll < 0.75:
                if r.random() < 0.5:
                    out.append(["advance", 0.0, r.randint(1, 200)])
                else:
                    out.append(["advance", r.choice([0.001, 0.01, 0.05, 0.2, 0.5, 1.0]), 0])
            elif roll < 0.81:
                if r.random() < 0.5:
                    out.append(["until_idle", r.choice([0.5, 2.0])])
                else:
                    out.append(["until_done", [r.choice(self.letters)], r.choice([0.5, 2.0])])
            elif roll < 0.92:
                out.append(self.world())
            elif roll < 0.94 and self.extended:
                x = r.random()
                if x < 0.35:  # an input that is a function of time (polled while captured)
                    out.append(["input_fn", r.randint(0, 15), r.randint(1, 400),
                                r.randint(0, 400)])
                elif x < 0.6:  # an input that is a function of an axis's position
                    out.append(["input_pos", r.randint(0, 15), r.choice(self.letters),
                                r.randint(-20000, 20000)])
                elif x < 0.7:  # events of its own; records the axes at each
                    out.append(["observer", r.choice([None, 1, 7, 100, 1000])])
                else:  # QA and RP every few ticks
                    out.append(["poll", r.randint(1, 30), r.choice([1, 1, 3, 50, 400])])
            elif roll < 0.96:
                out.append(["writeb", self.garbage()])
            elif roll < 0.985:
                out.append(["velocity", r.choice(self.letters)])
            else:
                out.append(["reset"])
        return out


def make_stream(seed: int, count: int = 40, extended: bool = False) -> dict[str, Any]:
    r = random.Random(seed)
    model = r.choice(list(MODELS))
    rate = r.choice(RATES)
    return {"kind": "stream", "seed": seed, "model": model, "rate": rate,
            "steps": Gen(r, model, extended).steps(count)}


# ---- shrinking ---------------------------------------------------------------------------

def differs(pair: Pair, job: dict[str, Any]) -> Difference | None:
    old, new = pair.run(job)
    return first_difference(old, new)


def shrink(pair: Pair, job: dict[str, Any], budget_s: float = 60.0) -> dict[str, Any]:
    """Delta debugging on the steps: keep removing chunks while a difference remains."""
    deadline = time.monotonic() + budget_s
    found = differs(pair, job)
    if found is None:
        return job
    steps = job["steps"][: max(found.step, 1)]  # nothing after the first difference
    job = dict(job, steps=steps)
    if differs(pair, job) is None:
        job = dict(job, steps=steps + [[]])  # cannot happen often; keep the original
        return job
    chunk = max(1, len(steps) // 2)
    while chunk >= 1 and time.monotonic() < deadline:
        i, changed = 0, False
        while i < len(job["steps"]) and time.monotonic() < deadline:
            trial = dict(job, steps=job["steps"][:i] + job["steps"][i + chunk:])
            if trial["steps"] and differs(pair, trial) is not None:
                job, changed = trial, True
            else:
                i += chunk
        if not changed:
            chunk //= 2
    return job


def describe(job: dict[str, Any], difference: Difference) -> str:
    lines = [f"model {job['model']} at {job['rate']} Hz (seed {job.get('seed')}):"]
    lines += [f"  {n + 1}: {json.dumps(step)}" for n, step in enumerate(job["steps"])]
    lines.append(f"  -> {difference}")
    return "\n".join(lines)


# ---- scripts ---------------------------------------------------------------------------

def example_scripts() -> list[tuple[str, str]]:
    """Every MAXk example script of the old tree (the new tree's are the same files plus
    other controllers' examples, which the old tree cannot run)."""
    out = []
    for path in sorted((OLD_TREE / "examples").glob("*.maxk")):
        out.append((path.name, path.read_text()))
    for path in sorted((NEW_TREE / "examples").glob("*.maxk")):
        text = path.read_text()
        if "@board MC" in text or "@board MM" in text:
            continue
        if path.name not in {name for name, _ in out}:
            out.append((path.name, text))
    return out


def test_scripts() -> list[tuple[str, str]]:
    """Script-like texts in the old tests: every string literal with a line break whose
    lines look like MAX commands or script directives (what tests give run_script, write
    into .maxk files or send through the doors)."""
    out: list[tuple[str, str]] = []
    looks = re.compile(r"^(@|//|<|#|;|\?|[A-Z]{2})")
    for path in sorted((OLD_TREE / "tests").glob("test_*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                text = node.value
                lines = [x for x in text.replace("\r", "\n").split("\n") if x.strip()]
                if "\n" in text and lines and all(looks.match(x.strip()) for x in lines):
                    out.append((f"{path.name}:{node.lineno}", text))
    return out


def exchange_streams() -> list[dict[str, Any]]:
    """The evidence exchanges E1-E8 (tests/test_exchange_replay.py) as in-process streams:
    what a host sends, then the wall time it lets pass."""
    path = OLD_TREE / "tests" / "test_exchange_replay.py"
    out = []
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name):
            name = node.targets[0].id
            if name.startswith("E") and name[1:].isdigit():
                steps: list[Step] = []
                for sent, _, wait in ast.literal_eval(node.value):
                    steps.append(["write", sent])
                    if wait:
                        steps.append(["advance", float(wait), 0])
                out.append({"kind": "stream", "seed": name, "model": "MAXk-8000",
                            "rate": 8192, "steps": steps})
    return out


def test_function_streams() -> list[dict[str, Any]]:
    """Per old test function, the command lines it sends (send/query/write/command string
    literals) and the time it lets pass, in source order, as one in-process stream (the
    world set-up of the test is not replayed: the commands still meet the same code)."""
    out: list[dict[str, Any]] = []
    for path in sorted((OLD_TREE / "tests").glob("test_*.py")):
        for fn in ast.walk(ast.parse(path.read_text())):
            if not isinstance(fn, ast.FunctionDef) or not fn.name.startswith("test"):
                continue
            model = "MAXk-4000" if "board4" in [a.arg for a in fn.args.args] else "MAXk-8000"
            calls = sorted((n for n in ast.walk(fn) if isinstance(n, ast.Call)),
                           key=lambda n: (n.lineno, n.col_offset))
            steps: list[Step] = []
            for call in calls:
                name = getattr(call.func, "attr", getattr(call.func, "id", ""))
                try:
                    args = [ast.literal_eval(a) for a in call.args]
                except ValueError:
                    continue
                if name == "MAXk" and args and isinstance(args[0], str):
                    model = args[0]
                elif name in ("send", "query", "command") and args and isinstance(args[0], str):
                    steps.append(["send", args[0]])
                elif name == "write" and args and isinstance(args[0], (str, bytes)):
                    data = args[0]
                    steps.append(["writeb", data.decode("latin-1")] if isinstance(data, bytes)
                                 else ["write", data])
                elif name == "advance" and (args or call.keywords):
                    seconds = float(args[0]) if args and isinstance(args[0], (int, float)) else 0.0
                    ticks = 0
                    for kw in call.keywords:
                        try:
                            value = ast.literal_eval(kw.value)
                        except ValueError:
                            continue
                        if kw.arg == "ticks" and isinstance(value, int):
                            ticks = value
                        elif kw.arg == "seconds" and isinstance(value, (int, float)):
                            seconds = float(value)
                    steps.append(["advance", min(seconds, 30.0), min(ticks, 10**6)])
                elif name in ("run_until_idle", "run_until_done"):
                    steps.append(["until_idle", 5.0])
            if steps and model.upper().startswith("MAXK-"):
                out.append({"kind": "stream", "seed": f"{path.name}::{fn.name}",
                            "model": model, "rate": 8192, "steps": steps})
    return out


def cli_run(tree: Path, script: Path, workdir: Path, *extra: str) -> dict[str, Any]:
    """`maxk run -v --trace` in one tree: stdout, stderr, exit code and the CSV bytes."""
    trace = workdir / "trace.csv"
    if trace.exists():
        trace.unlink()
    env = dict(os.environ, PYTHONPATH=str(tree), XDG_DATA_HOME="/tmp/maxk-diff-xdg")
    done = subprocess.run(
        [sys.executable, "-P", "-m", "maxk", "run", "-v", str(script), "--trace", str(trace),
         *extra], capture_output=True, text=True, env=env, cwd="/tmp", timeout=600)
    return {"rc": done.returncode, "stdout": done.stdout, "stderr": done.stderr,
            "trace": trace.read_bytes() if trace.exists() else None}


def compare_scripts(pair: Pair, verbose: bool = True) -> list[str]:
    problems: list[str] = []
    scripts = example_scripts() + test_scripts()
    for name, text in scripts:
        old, new = pair.run({"kind": "script", "text": text, "path": name})
        if old != new:
            problems.append(f"script {name}: old {str(old)[:600]}\n    new {str(new)[:600]}")
    streams = exchange_streams() + test_function_streams()
    for job in streams:
        found = differs(pair, job)
        if found:
            problems.append(f"stream {job['seed']}: {found}")
    if verbose:
        print(f"{len(scripts)} scripts, {len(streams)} exchange and test-function streams "
              f"({sum(len(j['steps']) for j in streams)} steps) in-process")
    return problems


def compare_cli(names: list[str] | None = None, trace_every: str | None = None) -> list[str]:
    import tempfile

    problems = []
    work = Path(tempfile.mkdtemp(prefix="maxk-diff-cli-"))
    for path in sorted((OLD_TREE / "examples").glob("*.maxk")):
        if names and path.name not in names:
            continue
        extra = ["--trace-every", trace_every] if trace_every else []
        old = cli_run(OLD_TREE, path, work, *extra)
        new = cli_run(NEW_TREE, path, work, *extra)
        for key in ("rc", "stdout", "stderr", "trace"):
            if old[key] != new[key]:
                a, b = old[key], new[key]
                if isinstance(a, (str, bytes)) and isinstance(b, (str, bytes)):
                    n = next((i for i, (x, y) in enumerate(zip(a, b, strict=False)) if x != y),
                             min(len(a), len(b)))
                    a, b = a[max(0, n - 80): n + 120], b[max(0, n - 80): n + 120]
                problems.append(f"maxk run {path.name} {key}: old {a!r}\n    new {b!r}")
    return problems


# ---- main ----------------------------------------------------------------------------

def fuzz(pair: Pair, seed: int, seconds: float, count: int, shrink_s: float,
         extended: bool = False) -> list[str]:
    deadline = time.monotonic() + seconds
    reports, seen = [], set()
    n = streams = steps = 0
    while time.monotonic() < deadline:
        job = make_stream(seed + n, count, extended)
        n += 1
        streams += 1
        steps += len(job["steps"])
        found = differs(pair, job)
        if found is None:
            continue
        signature = (found.key, str(found.old)[:40], str(found.new)[:40])
        print(f"seed {job['seed']}: {found}"[:400], flush=True)
        if signature in seen:
            continue
        seen.add(signature)
        small = shrink(pair, job, shrink_s)
        again = differs(pair, small)
        reports.append(describe(small, again) if again else describe(job, found))
        print(reports[-1], flush=True)
    print(f"{streams} streams, {steps} steps, {len(reports)} distinct differences")
    return reports


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seconds", type=float, default=60)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--steps", type=int, default=40)
    parser.add_argument("--shrink", type=float, default=60, help="seconds per shrink")
    parser.add_argument("--scripts", action="store_true", help="scripts and exchanges")
    parser.add_argument("--cli", action="store_true", help="`maxk run` on the examples")
    parser.add_argument("--replay", type=int, help="run one seed and print its steps")
    parser.add_argument("--extended", action="store_true",
                        help="streams also with input waits, inputs as functions of time "
                             "or position, observers and tick-by-tick polls")
    args = parser.parse_args()
    if not OLD_TREE.exists():
        print(f"no old tree at {OLD_TREE}")
        return 2
    pair = Pair()
    try:
        if args.replay is not None:
            job = make_stream(args.replay, args.steps, args.extended)
            old, new = pair.run(job)
            print(describe(job, first_difference(old, new) or Difference(0, "-", 0, 0)))
            return 0
        problems = []
        if args.scripts:
            problems += compare_scripts(pair)
        if args.cli:
            problems += compare_cli()
        if not (args.scripts or args.cli):
            problems += fuzz(pair, args.seed, args.seconds, args.steps, args.shrink,
                             args.extended)
        for p in problems:
            print(p)
        return 1 if problems else 0
    finally:
        pair.close()


if __name__ == "__main__":
    sys.exit(main())

"""Measure the MC405's TrioBASIC against a directory of real programs.

    python3 tools/trio_corpus.py DIR [--seconds 10] [--verbose]

DIR holds one sub-directory per project (a flat DIR is one project). Every file of a
project is a program named after its file (``MAIN.BAS`` -> ``MAIN``; ``.BAL`` files are
BASIC libraries, ``.MCC`` the MC_CONFIG program, any other extension a BASIC program),
and the programs of one project share one program store, as real projects INCLUDE and
RUN each other. The report gives:

- lines parsed: the logical code lines (``_`` continuations joined; blank and
  comment-only lines left out) the parser accepts, and each line it refuses with its
  error;
- keywords: the distinct words the programs use that the keyword table holds, split into
  modelled and only accepted (their note says "Not modelled"), and the words that are
  neither a keyword nor declared by the program (a label, an assignment target, a FOR
  variable, a DIM, FUNCTION or CONSTANT/GLOBAL name): each is a keyword the table lacks
  or a variable that is only read;
- runs: each BASIC program of the project started on a fresh controller holding the
  whole project, run for the simulated seconds asked (10 by default); it runs clean when
  it neither fails to compile nor stops on an error, and no error is caught by its ON
  BASICERROR handler. Every error is listed with its program and line.

The programs stay where they are: nothing of them is copied into the report beyond the
failing line's text (with --verbose).
"""

from __future__ import annotations

import argparse
import re
import sys
from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from maxk.commands.trio import tasks as trio_tasks
from maxk.commands.trio.keywords import KEYWORDS
from maxk.commands.trio.lexer import Tok, TrioError, tokenize
from maxk.commands.trio.parser import parse_line
from maxk.commands.trio.programs import check_name
from maxk.commands.trio.tasks import _INCLUDE, join_continued
from maxk.controllers.trio.controller import MC405

_TYPES = {".BAL": 12, ".MCC": 9}
_DATA = re.compile(r"[0-9_]+\.TXT$", re.IGNORECASE)  # 0123.TXT: a data file a program OPENs
_DECLARING = {"FOR", "DIM", "FUNCTION", "GOTO", "GOSUB", "NEXT"}


@dataclass
class Program:
    name: str
    path: Path
    type: int
    lines: list[str]


@dataclass
class Report:
    code_lines: int = 0
    parsed: int = 0
    refused: list[tuple[str, int, str, str]] = field(default_factory=list)
    used: Counter[str] = field(default_factory=Counter)
    declared: set[str] = field(default_factory=set)
    runs: list[tuple[str, str, list[str]]] = field(default_factory=list)  # project, program, errors


def program_name(path: Path) -> str:
    stem = path.name.split(".")[0]
    name = re.sub(r"[^A-Za-z0-9_]", "_", stem).upper() or "P"
    try:
        return check_name(name[:32])
    except TrioError:  # a store whose names must start with a letter
        return check_name(("P" + name)[:32])


def read_program(path: Path) -> Program:
    text = path.read_bytes().decode("latin-1")
    lines = text.replace("\r\n", "\n").replace("\r", "\n").split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    suffix = path.suffix.upper()
    kind = 3 if _DATA.match(path.name) else _TYPES.get(suffix, 0)
    return Program(program_name(path), path, kind, lines)


def projects(root: Path) -> Iterator[tuple[str, list[Program]]]:
    subdirs = sorted(p for p in root.iterdir() if p.is_dir())
    groups = [(d.name, d) for d in subdirs] or [(root.name, root)]
    for title, directory in groups:
        programs: dict[str, Program] = {}
        for path in sorted(p for p in directory.rglob("*") if p.is_file()):
            program = read_program(path)
            if program.lines and program.lines[0].lstrip().startswith("<"):
                continue  # an XML file (an EtherCAT slave description), no program
            if program.lines and program.name not in programs:
                programs[program.name] = program
        if programs:
            yield title, list(programs.values())


def _code(text: str) -> bool:
    stripped = text.strip()
    return bool(stripped) and not stripped.startswith("'") and not re.match(
        r"REM\b", stripped, re.IGNORECASE)


def scan(project: str, program: Program, report: Report) -> None:
    """Parse every logical line; gather the words used and the names declared."""
    if program.type == 3:
        return  # a text (data) file: no code
    for number, text in join_continued(program.lines):
        if not _code(text):
            continue
        report.code_lines += 1
        try:
            if not _INCLUDE.match(text):  # INCLUDE is resolved at COMPILE, not parsed
                parse_line(text)
            report.parsed += 1
        except TrioError as exc:
            report.refused.append((f"{project}/{program.name}", number, exc.message,
                                   text.strip()))
        try:
            tokens = tokenize(text)
        except TrioError:
            continue
        for k, tok in enumerate(tokens):
            if tok.kind is not Tok.NAME:
                continue
            report.used[tok.text] += 1
            before = tokens[k - 1] if k else None
            after = tokens[k + 1]
            if before is not None and before.kind is Tok.NAME and before.text in _DECLARING:
                report.declared.add(tok.text)
            elif after.kind is Tok.OP and after.text == ":" and k == 0:
                report.declared.add(tok.text)  # a label
            elif after.kind is Tok.OP and after.text == "=" and (
                    before is None or before.text in (":", "THEN", "ELSE")):
                report.declared.add(tok.text)
            elif before is not None and before.text in ("(", ",") and k >= 2 and \
                    any(t.text == "FUNCTION" for t in tokens[:k]):
                report.declared.add(tok.text)  # a FUNCTION's parameter
        words = [t.text for t in tokens]
        if words and words[0] == "DIM":  # DIM a, b(3), c AS ...
            depth = 0
            for tok in tokens[1:]:
                if tok.text == "AS" or tok.kind is Tok.END:
                    break
                depth += tok.text == "("
                depth -= tok.text == ")"
                if tok.kind is Tok.NAME and depth == 0:
                    report.declared.add(tok.text)
        if words and words[0] in ("GET", "INPUT", "LINPUT", "DEFCONST"):
            report.declared.update(t.text for t in tokens[1:] if t.kind is Tok.NAME)
        for k, tok in enumerate(tokens[:-2]):
            if tok.kind is Tok.NAME and tok.text in ("CONSTANT", "GLOBAL") and \
                    tokens[k + 1].kind is Tok.STRING:
                report.declared.add(tokens[k + 1].text.upper())


def run_alone(program: Program, programs: list[Program], seconds: float) -> str:
    """`RUN` one program on a fresh MC405 holding its whole project, for the simulated
    seconds asked (less when no process is left); what its session printed."""
    controller = MC405()
    store = controller.programs
    for other in programs:
        store.create(other.name, other.type)
        for n, line in enumerate(other.lines):
            store.edit(other.name, n, "R", line)
    session = controller.open_session()
    session.feed(f'RUN "{program.name}"\r'.encode())
    step = 0.5
    elapsed = 0.0
    while elapsed < seconds:
        controller.advance(step)
        elapsed += step
        if not controller.runtime.tasks:
            break
    return session.read().decode("latin-1")


def run(project: str, programs: list[Program], seconds: float, report: Report) -> None:
    """Start each BASIC program alone on a controller holding the whole project."""
    caught: list[str] = []
    original = trio_tasks.error_code

    def record(message: str) -> float:
        caught.append(message)
        return original(message)

    trio_tasks.error_code = record  # type: ignore[assignment]
    try:
        for program in programs:
            if program.type != 0:
                continue
            caught.clear()
            out = run_alone(program, programs, seconds)
            errors = [line.strip() for line in out.split("\r\n") if "%[" in line]
            errors += [f"(caught by ON BASICERROR) {m}" for m in caught]
            report.runs.append((project, program.name, errors))
    finally:
        trio_tasks.error_code = original


def keyword_state(name: str) -> str:
    """modelled, accepted (a token-table word the emulator does not model), unknown."""
    keyword = KEYWORDS.get(name)
    if keyword is None:
        return "unknown"
    if keyword.confidence == "D" and keyword.note.startswith("Not modelled"):
        return "accepted"
    return "modelled"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory", type=Path)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--verbose", action="store_true", help="show each refused line")
    parser.add_argument("--no-run", action="store_true", help="parse only")
    args = parser.parse_args(argv)
    report = Report()
    count = 0
    for project, programs in projects(args.directory):
        count += len(programs)
        for program in programs:
            scan(project, program, report)
        if not args.no_run:
            run(project, programs, args.seconds, report)
    print(f"programs: {count}")
    share = report.parsed / report.code_lines if report.code_lines else 1.0
    print(f"lines parsed: {report.parsed}/{report.code_lines} = {share:.1%}")
    states: dict[str, list[str]] = {"modelled": [], "accepted": [], "unknown": []}
    for word in sorted(report.used):
        state = keyword_state(word)
        if state == "unknown" and word in report.declared:
            continue
        states[state].append(word)
    known = len(states["modelled"]) + len(states["accepted"])
    total = known + len(states["unknown"])
    print(f"keywords used: {total}: modelled {len(states['modelled'])}, accepted only "
          f"{len(states['accepted'])}, not in the table {len(states['unknown'])} "
          f"= {known / total if total else 1:.1%} understood")
    print("  accepted only:", " ".join(states["accepted"]))
    print("  not in the table (keyword or read-only variable):",
          " ".join(f"{w}({report.used[w]})" for w in states["unknown"]))
    if report.runs:
        clean = [r for r in report.runs if not r[2]]
        print(f"programs running {args.seconds:g} s clean: {len(clean)}/{len(report.runs)} "
              f"= {len(clean) / len(report.runs):.1%}")
        for project, name, errors in report.runs:
            for error in errors[:3]:
                print(f"  run {project}/{name}: {error}")
    messages = Counter(message for _p, _n, message, _t in report.refused)
    print(f"refused lines: {len(report.refused)} {dict(messages)}")
    for where, number, message, text in report.refused:
        shown = f": {text[:100]}" if args.verbose else ""
        print(f"  {where} line {number}: {message}{shown}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

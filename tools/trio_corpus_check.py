"""Run a directory of TrioBASIC programs on the MC405 and print one row a program.

    python3 tools/trio_corpus_check.py DIR [--seconds 10] [--causes]

DIR is laid out as for tools/trio_corpus.py (one sub-directory a project; the programs
of a project share one store). Each BASIC program is started alone on a fresh MC405
holding its project, as a user would `RUN` it, and run for the simulated seconds asked.
A row gives the program, its code lines and how many parse, and how it stopped:

- ``clean``: ended, or still running (waiting on an input, a loop) with no error;
- ``compile``: refused by COMPILE (the message and the line);
- ``runtime``: stopped by an error while running, or an error its ON BASICERROR caught;
- ``crash``: a Python exception escaped the emulator, or the run made no way in
  ``--hang`` seconds of wall time (a defect whatever the program).

The closing table counts the stops by message, so the causes can be told apart (a
parse error, a missing language form, a keyword the emulator refuses). The programs
are read where they are; nothing of them is written anywhere.
"""

from __future__ import annotations

import argparse
import re
import signal
import sys
import traceback
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from trio_corpus import (  # noqa: E402
    Program,
    Report,
    keyword_state,
    projects,
    run_alone,
    scan,
)

from maxk.commands.trio import tasks as trio_tasks  # noqa: E402

_COMPILE = re.compile(r"%\[COMMAND LINE\] - Program (\w+) line (\d+): (.*)")
_RUNTIME = re.compile(r"%\[Process \d+:Program (\w+) Line (\d+)\] - (.*)")


class Hang(Exception):
    """The emulator made no way through the run in the wall time allowed."""


def _alarm(_signum: int, _frame: object) -> None:
    raise Hang


def run_one(program: Program, programs: list[Program], seconds: float,
            hang: int = 0) -> tuple[str, str, str]:
    """(status, message, the failing line's text) of one program run alone; a run that
    takes more than `hang` seconds of wall time (0: no limit) is a crash (a hang)."""
    caught: list[str] = []
    original = trio_tasks.error_code
    if hang:
        signal.signal(signal.SIGALRM, _alarm)
        signal.alarm(hang)

    def record(message: str) -> float:
        caught.append(message)
        return original(message)

    trio_tasks.error_code = record  # type: ignore[assignment]
    try:
        out = run_alone(program, programs, seconds)
    except Hang:
        return "crash", f"hang: still in the run after {hang} s of wall time", ""
    except Exception as exc:  # a defect of the emulator: reported, the run goes on
        frame = traceback.extract_tb(exc.__traceback__)[-1]
        return "crash", f"{type(exc).__name__}: {exc} ({Path(frame.filename).name}:"\
            f"{frame.lineno})", ""
    finally:
        signal.alarm(0)
        trio_tasks.error_code = original
    texts = {other.name: other.lines for other in programs}
    for line in out.split("\r\n"):
        for pattern, status in ((_COMPILE, "compile"), (_RUNTIME, "runtime")):
            found = pattern.search(line)
            if found:
                name, number, message = found.group(1), int(found.group(2)), found.group(3)
                lines = texts.get(name, [])
                text = lines[number - 1].strip() if 0 < number <= len(lines) else ""
                return status, message.strip(), text
    if caught:
        return "runtime", f"(caught by ON BASICERROR) {caught[0]}", ""
    return "clean", "", ""


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory", type=Path)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--quiet", action="store_true", help="the summary only")
    parser.add_argument("--progress", action="store_true", help="each program on stderr")
    parser.add_argument("--hang", type=int, default=60,
                        help="wall seconds after which a run counts as a hang (0: none)")
    args = parser.parse_args(argv)
    rows = []
    total = Report()
    words: Counter[tuple[str, str]] = Counter()  # (state, word) -> programs using it
    for project, programs in projects(args.directory):
        reports = []
        for program in programs:
            report = Report()
            scan(project, program, report)
            reports.append(report)
            total.code_lines += report.code_lines
            total.parsed += report.parsed
        declared = set().union(*(r.declared for r in reports))
        for report in reports:
            for word in report.used:
                state = keyword_state(word)
                if state != "modelled" and not (state == "unknown" and word in declared):
                    words[(state, word)] += 1
        for program, report in zip(programs, reports, strict=True):
            if program.type != 0:
                continue
            status, message, text = run_one(program, programs, args.seconds, args.hang)
            rows.append((f"{project}/{program.name}", report.code_lines, report.parsed,
                         status, message, text))
            if args.progress:
                print(f"{project}/{program.name}: {status}", file=sys.stderr, flush=True)
    if not args.quiet:
        print(f"{'program':40} {'lines':>5} {'parsed':>6}  status    message | line")
        for where, lines, parsed, status, message, text in rows:
            shown = f"{message} | {text[:60]}" if message else ""
            print(f"{where[:40]:40} {lines:5d} {parsed:6d}  {status:8}  {shown}")
    statuses = Counter(row[3] for row in rows)
    share = total.parsed / total.code_lines if total.code_lines else 1.0
    print(f"programs: {len(rows)}; code lines parsed: {total.parsed}/{total.code_lines} "
          f"= {share:.1%}")
    print("runs: " + ", ".join(f"{k} {statuses[k]}" for k in
                               ("clean", "compile", "runtime", "crash")))
    causes = Counter((row[3], row[4].split(" (")[0] if row[3] == "crash" else row[4])
                     for row in rows if row[3] != "clean")
    for (status, message), count in causes.most_common():
        print(f"  {count:4d}  {status:8} {message}")
    # a run is clean only as far as the words it reached: a keyword the table lacks (read
    # as a variable) or one only accepted shows here however the run ended
    for state, title in (("unknown", "not in the table, never declared"),
                         ("accepted", "accepted only (Not modelled)")):
        found = sorted(((-n, w) for (s, w), n in words.items() if s == state))
        shown = " ".join(f"{w}({-n})" for n, w in found[:20])
        print(f"words {title}: {len(found)}" + (f": {shown}" if found else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Run every benchmark and print a table, or one JSON object per figure with --json.

Figures are ratios (simulated seconds per wall second, commands per second) measured
on one core; targets are printed beside them for the reader, not enforced.
"""

from __future__ import annotations

import argparse
import json
import time
import tracemalloc
from collections.abc import Callable

from benchmarks.figure import Figure, is_rate
from benchmarks.servo_figures import circle, naive_reference
from maxk import MAXk


def _best_of(runs: int, fn: Callable[[], tuple[float, float]]) -> tuple[float, float]:
    """Run fn (returning work, wall seconds) a few times; keep the fastest rate."""
    best = (0.0, float("inf"))
    for _ in range(runs):
        work, wall = fn()
        if work / wall > best[0] / best[1]:
            best = (work, wall)
    return best


BACK_AND_FORTH = ("MR7001,-5003,3002,1999,777,-7001,5003,-3002,-1999,-777",
                  "MR-7001,5003,-3002,-1999,-777,7001,-5003,3002,1999,777")
"""Ten axes' moves there and back: 0.1-0.4 s each, about three a second per axis."""


def _back_to_back(setup: str, moves: tuple[str, str], poll_hz: float | None,
                  sim_seconds: float, poll: str) -> tuple[MAXk, float]:
    """A 10-axis board looping `moves` forever at varied VL/AC; run `sim_seconds` free
    or with a host sending `poll` at `poll_hz`. Returns the board and the wall time."""
    there, back = moves
    board = MAXk("MAXk-A000")
    board.send(setup)
    board.send("AA; VL50000,40000,30000,20000,10000,50000,40000,30000,20000,10000;")
    board.send("AC500000,400000,300000,200000,100000,500000,400000,300000,200000,100000;")
    board.send("AM; LS1000000,1000000,1000000,1000000,1000000,1000000,1000000,1000000,"
               f"1000000,1000000; {there}; GO; {back}; GO; LE;")
    board.advance(0.01)  # first-use costs (python-control builds servo plants) stay out
    start = time.perf_counter()
    if poll_hz is None:
        board.advance(sim_seconds)
    else:
        step = board.ticks(1.0 / poll_hz)
        end = board.tick + board.ticks(sim_seconds)
        while board.tick < end:
            board.advance(ticks=step)
            board.send(poll)
    return board, time.perf_counter() - start


def steppers_back_to_back(poll_hz: float | None, sim_seconds: float = 600.0) -> Figure:
    """10 stepper axes, each running an endless loop of back-to-back moves."""

    def run() -> tuple[float, float]:
        board, wall = _back_to_back("", BACK_AND_FORTH, poll_hz, sim_seconds, "AM;RI;AM PP;")
        assert board.board.axes[0].motion is not None or board.board.axes[0].wait is not None
        return sim_seconds, wall

    work, wall = _best_of(3, run)
    label = "no host polling" if poll_hz is None else f"host polling RI+PP at {poll_hz:g} Hz"
    return Figure(f"steppers_10_axes_{'free' if poll_hz is None else 'polled'}",
                  work / wall, "simulated s per wall s", 500.0, label)


def steppers_varied(moves_per_axis: int = 250) -> Figure:
    """10 axes, every move a different length and speed (no plan is ever reused)."""
    import random

    def run() -> tuple[float, float]:
        rng = random.Random(1234)
        board = MAXk("MAXk-A000")
        for letter in "XYZTUVRSWK":
            parts = [f"A{letter}"]
            for _ in range(moves_per_axis):
                parts.append(f"VL{rng.randint(1000, 200_000)};AC{rng.randint(10_000, 2_000_000)};"
                             f"MR{rng.randint(-50_000, 50_000)};GO")
            board.send(";".join(parts) + ";")
        assert not board.command_error, board.last_error  # 250 moves x 10 units fit the queue
        start = time.perf_counter()
        board.run_until_idle(timeout=10_000)
        wall = time.perf_counter() - start
        return board.time, wall

    work, wall = _best_of(3, run)
    return Figure("steppers_10_axes_varied", work / wall, "simulated s per wall s", 500.0,
                  f"{moves_per_axis} different moves per axis, nothing reused")


SERVO_GAINS = "KP100,100,100,100,100,100,100,100,100,100; KD400,400,400,400,400,400,400,400," \
    "400,400; KI40,40,40,40,40,40,40,40,40,40; KU400,400,400,400,400,400,400,400,400,400; " \
    "KV680,680,680,680,680,680,680,680,680,680;"


SERVO_MOVES = {
    # the stepper benchmark's moves: 0.1-0.4 s each, about three a second per axis
    "short": BACK_AND_FORTH,
    # moves on the scale of the manual's tuning check (MR64000): 1.3-13 s each
    "long": ("MR64000,-48000,32000,16000,64000,-64000,48000,-32000,-16000,-64000",
             "MR-64000,48000,-32000,-16000,-64000,64000,-48000,32000,16000,64000"),
}


def servos_back_to_back(poll_hz: float | None, moves: str = "short",
                        sim_seconds: float = 60.0) -> Figure:
    """10 servo axes in closed loop (PID on the default motor plant every tick, Coulomb
    friction included), each running an endless loop of back-to-back moves."""

    def run() -> tuple[float, float]:
        setup = "AA; PSM,M,M,M,M,M,M,M,M,M; LP0,0,0,0,0,0,0,0,0,0; " + SERVO_GAINS + \
            " CL1,1,1,1,1,1,1,1,1,1;"
        board, wall = _back_to_back(setup, SERVO_MOVES[moves], poll_hz, sim_seconds,
                                    "AM;RI;AM PE;")
        assert board.query("AM;CL?;") == ",".join(["on"] * 10)  # no axis tripped
        return sim_seconds, wall

    work, wall = _best_of(3, run)
    label = "no host polling" if poll_hz is None else f"host polling RI+PE at {poll_hz:g} Hz"
    label += f", {moves} moves"
    return Figure(f"servos_10_axes_{moves}_{'free' if poll_hz is None else 'polled'}",
                  work / wall, "simulated s per wall s", 100.0, label)


def trajectory_scan(segments: int = 500, tasks: int = 8) -> list[Figure]:
    """The EPICS trajectory scan's load and run (evidence 2.8): one vector task per axis,
    `segments` segments each at varied speeds, started together, polled with QI and
    nudged with VO every 0.2 s as the sequencer does."""
    board = MAXk("MAXk-A000")
    lines = []
    for task in range(1, tasks + 1):
        lines += [f"AM; VID[{task}]1;", f"AM; VH[{task}]0;"]
        position = 0
        for i in range(segments):
            speed = 1000 + 500 * (i % 7)
            position += speed // 10  # 0.1 s per segment at its speed
            slots = "," * (task - 1) + str(position) + "," * (tasks - task)
            lines.append(f"AM; VA[{task}]100000;VV[{task}]{speed};VP[{task}]A{slots};")
        lines.append(f"AM; VE[{task}];")
    start = time.perf_counter()
    for line in lines:
        board.write(line)
    load_wall = time.perf_counter() - start
    assert not board.command_error, board.last_error
    board.send("AM;" + "".join(f"VG[{t}];" for t in range(1, tasks + 1)))
    start = time.perf_counter()
    step = board.ticks(0.2)
    polls = 0
    while True:
        board.advance(ticks=step)
        polls += 1
        status = board.query("QI")
        board.send(f"AM; VO[{polls % tasks + 1}]={95 + polls % 11};")
        if all(status[5 * t + 1] == "D" for t in range(tasks)):
            break
    wall = time.perf_counter() - start
    return [Figure("trajectory_scan_load", len(lines) * 3 / load_wall, "commands/s", None,
                   f"{tasks} tasks x {segments} segments (VA, VV, VP each)"),
            Figure("trajectory_scan_run", board.time / wall, "sim s / wall s", 100.0,
                   f"{tasks} single-axis tasks, QI + VO every 0.2 s, {board.time:.0f} s")]


def hole_polled(poll_hz: float = 10.0) -> Figure:
    """The manual's hole-cutting contour, a host asking RP and VRV at poll_hz."""
    board = MAXk("MAXk-4000")
    board.send("AA; VOA0,5; VV1000,1000; VP0,0; VIO0100,,0100; VC0,5000,-180; "
               "VC0,0,-360; VIO0,,0100; VV1000,0; VP-1000,0; VE; AA ID;")
    step = board.ticks(1.0 / poll_hz)
    start = time.perf_counter()
    while not board.done("X"):
        board.advance(ticks=step)
        board.query("AA RP")
        board.query("VRV")
    wall = time.perf_counter() - start
    return Figure("hole_contour_polled", board.time / wall, "sim s / wall s", 100.0,
                  f"Appendix C contour, RP+VRV at {poll_hz:g} Hz")


def _commands_in(line: str) -> int:
    """How many commands the lexer sees in a line (the figure's honest count)."""
    from maxk.commands.max.lexer import Lexer, LexError

    parsed = Lexer().feed(line)
    assert not any(isinstance(c, LexError) for c in parsed), parsed
    return len(parsed)


def command_throughput(n_lines: int = 4000) -> Figure:
    """Commands per second through lexer, interpreter and queues (executing as they go)."""
    line = ("AX;VL5000;AC50000;VB100;MR1000;LP0;ID;RP;AY;VL6000;MA-250;LPE5;CA;"
            "AA;VL1000,2000,3000,4000,5000,6000,7000,8000;MR1,,3;LP0,0,0;RQC;")
    per_line = _commands_in(line)  # 18

    def run() -> tuple[float, float]:
        board = MAXk()
        start = time.perf_counter()
        for _ in range(n_lines):
            board.write(line)
        wall = time.perf_counter() - start
        assert not board.command_error, board.last_error
        return n_lines * per_line, wall

    work, wall = _best_of(3, run)
    return Figure("commands_per_second", work / wall, "commands/s", 200_000.0,
                  "mixed queued, immediate and AA-list commands, one line again and again")


def lexer_throughput(n_lines: int = 4000) -> list[Figure]:
    """The lexer alone: every line different (the state machine at work), and one line
    sent again and again (a host's poll: the split is remembered)."""
    from maxk.commands.max.lexer import Lexer

    def line(k: int) -> str:
        return (f"AX;VL{5000 + k};AC50000;MR{1000 + k};GO;ID;AM;RI;AM PP;AXMA{k};GDID;"
                "LMH,H,H,H;")

    per_line = _commands_in(line(0))  # 15

    def run(lines: list[str]) -> tuple[float, float]:
        lexer = Lexer()
        start = time.perf_counter()
        for text in lines:
            lexer.feed(text)
        return len(lines) * per_line, time.perf_counter() - start

    runs = iter(range(3))  # new lines for every run: none was seen before

    def fresh() -> tuple[float, float]:
        first = 10_000_000 + next(runs) * n_lines
        return run([line(k) for k in range(first, first + n_lines)])

    work, wall = _best_of(3, fresh)
    same = [line(0)] * n_lines
    work2, wall2 = _best_of(3, lambda: run(same))
    return [Figure("lexer_commands_per_second", work / wall, "commands/s", None,
                   "lexer alone, every line different"),
            Figure("lexer_repeated_commands_per_second", work2 / wall2, "commands/s", None,
                   "lexer alone, one line again and again (its split remembered)")]


def memory_per_board() -> Figure:
    tracemalloc.start()
    boards = [MAXk("MAXk-A000") for _ in range(16)]
    for b in boards:
        b.send("AA; MR1,2,3,4,5,6,7,8,9,10; GO; ID;")
    current, _ = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return Figure("memory_per_10_axis_board", current / len(boards) / 1024, "KiB", None,
                  "16 boards, each with one queued move per axis")


def doors(seconds: float = 5.0, rate: float | None = None) -> list[Figure]:
    from benchmarks.doors import run

    r = run(seconds, rate=rate)
    load = "as fast as possible" if rate is None else f"polled at {rate:g}/s"
    note = (f"4 x MAXk-A000 moving in real time, {int(r['queries'])} queries in {seconds:g} s "
            f"({load})")
    return [
        Figure("tcp_query_round_trip_p50", r["p50_ms"], "ms", None, note),
        Figure("tcp_query_round_trip_p99", r["p99_ms"], "ms", None, "target p99 < 2 ms"),
        Figure("pacer_worst_lag", r["worst_lag_ms"], "ms", None,
               "virtual time behind the wall clock after a pacing pass; target < 1 ms"),
        Figure("pacer_worst_gap", r["worst_gap_ms"], "ms", None,
               "longest time between pacing passes (queries always sync first)"),
    ]


def trio_example_2() -> list[Figure]:
    """The MC405 PWM note's example 2 for 10 simulated minutes, every mark traced."""
    from benchmarks.trio import TARGET, example_2

    figures = []
    for name, poll in (("trio_example_2_free", None), ("trio_example_2_polled", 10.0)):
        ratio, cycles = example_2(poll_hz=poll)
        note = f"{cycles:,} servo cycles' marks traced" + (", PWM_MARK read at 10 Hz"
                                                          if poll else "")
        figures.append(Figure(name, ratio, "simulated s per wall s", TARGET, note))
    return figures


BENCHMARKS: dict[str, Callable[[], Figure | list[Figure]]] = {
    "naive": naive_reference,
    "steppers_free": lambda: steppers_back_to_back(None),
    "steppers_polled": lambda: steppers_back_to_back(10.0, sim_seconds=120.0),
    "steppers_varied": steppers_varied,
    "servos_short": lambda: servos_back_to_back(None, "short", 30.0),
    "servos_long": lambda: servos_back_to_back(None, "long", 120.0),
    "servos_long_polled": lambda: servos_back_to_back(10.0, "long", 60.0),
    "circle": circle,
    "trajectory_scan": trajectory_scan,
    "hole_polled": hole_polled,
    "commands": command_throughput,
    "lexer": lexer_throughput,
    "memory": memory_per_board,
    "doors": doors,
    "mm4005": lambda: __import__("benchmarks.mm4005", fromlist=["figures"]).figures(),
    "trio": trio_example_2,
    "servo_serve": lambda: __import__("benchmarks.servo_serve", fromlist=["figures"]).figures(),
    "fairness": lambda: __import__("benchmarks.fairness", fromlist=["figures"]).figures(),
    "pokeys_io": lambda: __import__("benchmarks.pokeys_io", fromlist=["figures"]).figures(),
    "oms_library": lambda: __import__("benchmarks.oms_library",
                                      fromlist=["figures"]).figures(),
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks")
    parser.add_argument("--json", action="store_true", help="one JSON object per figure")
    parser.add_argument("--door-seconds", type=float, default=5.0,
                        help="how long the doors benchmark runs (60 for the one-minute check)")
    parser.add_argument("--door-rate", type=float, default=None,
                        help="queries per second the doors benchmark's host sends (default: "
                        "as fast as replies come back)")
    parser.add_argument("names", nargs="*", help=f"which of {', '.join(BENCHMARKS)} "
                        "(default: all)")
    args = parser.parse_args(argv)
    unknown = [n for n in args.names if n not in BENCHMARKS]
    if unknown:
        parser.error(f"unknown benchmark {unknown[0]!r}; choose from {', '.join(BENCHMARKS)}")
    names = args.names or list(BENCHMARKS)
    if not args.json:
        print(f"{'figure':<34} {'value':>14}  {'unit':<24} {'target':>10}  {'x naive':>8}  "
              "note")
    naive: float | None = None  # the yardstick's rate, once measured in this run
    for name in names:
        if name == "doors":
            result: Figure | list[Figure] = doors(args.door_seconds, args.door_rate)
        else:
            result = BENCHMARKS[name]()
        for fig in result if isinstance(result, list) else [result]:
            if fig.name == "naive_10_pid_axes":
                naive = fig.value
            multiple = fig.value / naive if naive and is_rate(fig.unit) else None
            if args.json:
                record = {"name": fig.name, "value": round(fig.value, 3), "unit": fig.unit}
                if multiple is not None:
                    record["x_naive"] = round(multiple, 3)
                print(json.dumps(record))
            else:
                target = f">= {fig.target:,.0f}" if fig.target else ""
                shown = f"{multiple:>7,.1f}x" if multiple is not None else ""
                print(f"{fig.name:<34} {fig.value:>14,.3f}  {fig.unit:<24} {target:>10}  "
                      f"{shown:>8}  {fig.note}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

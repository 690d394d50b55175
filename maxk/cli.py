"""The `maxk` command: repl, run, commands, --version."""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
from pathlib import Path
from typing import Any

from maxk import __version__
from maxk.controllers.registry import DEFAULT_MODEL


def _model(text: str) -> str:
    from maxk.controllers.registry import canonical_model

    try:
        return canonical_model(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from None


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="maxk", description="An emulator of motion controllers: the OMS MAXk, the "
        "Newport MM4005, the Trio MC405 and the PoKeys.",
        epilog="Without a command maxk runs the REPL, whose options may be given "
        "directly: maxk --manual-time.")
    parser.add_argument("--version", action="version", version=f"maxk {__version__}")
    sub = parser.add_subparsers(dest="command")

    repl = sub.add_parser("repl", help="interactive terminal, like MAXkComm (the default)")
    repl.add_argument("--model", type=_model, default=DEFAULT_MODEL,
                      help=f"controller model: MAXk-1000..MAXk-A000, MM4005, ... (maxk "
                      f"models; default {DEFAULT_MODEL})")
    repl.add_argument("--rate", type=int, default=None,
                      help="update rate in Hz, one the controller runs at (default its own: "
                      "a MAXk's 8192 Hz, 122.07 us; maxk models lists them)")
    clock = repl.add_mutually_exclusive_group()
    clock.add_argument("--manual-time", action="store_true",
                       help="virtual time moves only on :advance / :run (default: follows "
                       "the wall clock)")
    clock.add_argument("--speed", type=float, default=1.0,
                       help="with the wall clock: K times faster than real time")
    repl.add_argument("--history", type=Path, default=None,
                      help="history file (default ~/.maxk_history)")
    store = repl.add_mutually_exclusive_group()
    store.add_argument("--archive", type=Path, default=None,
                       help="parameter archive file APP writes and power-up reads (default "
                       "~/.local/share/maxk/<model>-board1.params.json)")
    store.add_argument("--no-archive", action="store_true",
                       help="keep saved parameters in memory only")

    run = sub.add_parser("run", help="run a command script in virtual time, print replies")
    run.add_argument("script", type=Path)
    run.add_argument("--model", type=_model, default=None,
                     help="board model (overrides the script's @board)")
    run.add_argument("--rate", type=int, default=None,
                     help="update rate in Hz, one the controller runs at (overrides the "
                     "script's @rate)")
    run.add_argument("--verbose", "-v", action="store_true",
                     help="show each command line with its tick before its replies")
    run.add_argument("--record", action="store_true",
                     help="write the replies into the script as expected replies (< lines)")
    run.add_argument("--trace", type=Path, metavar="CSV",
                     help="write positions, velocities and flags to a CSV file")
    run.add_argument("--trace-every", metavar="DURATION", default=None,
                     help="trace every DURATION (e.g. 1 ms, 10 ticks) instead of per event")
    run.add_argument("--plot", type=Path, metavar="PNG",
                     help="draw the XY path of two axes into a PNG (needs the plot extra)")
    run.add_argument("--plot-axes", default="X,Y", metavar="A,B",
                     help="the two axes to plot (default X,Y)")
    run.add_argument("--plot-bit", type=int, default=None, metavar="BIT",
                     help="colour the path where this I/O bit is high (e.g. 8)")
    run.add_argument("--plot-every", metavar="DURATION", default="1 ms",
                     help="sample the path every DURATION (default 1 ms)")

    cmds = sub.add_parser("commands", help="list the command table")
    cmds.add_argument("--markdown", action="store_true",
                      help="print the generated reference (docs/commands.md)")
    cmds.add_argument("mnemonic", nargs="?", help="show one command in full")
    cmds.add_argument("--model", type=_model, default=None,
                      help=f"the controller whose table to show (default {DEFAULT_MODEL})")

    serve = sub.add_parser("serve", help="boards in real time behind TCP, serial and "
                           "shared-memory doors, for legacy host code")
    from maxk.host.serve import add_arguments

    add_arguments(serve)

    tune = sub.add_parser("tune", help="tuning assistant: run a move on a servo axis and "
                          "plot commanded vs actual position, velocity, error and DAC")
    tune.add_argument("gains", nargs="?", default="",
                      help='gain commands, e.g. "KP100; KD400; KI40; KU400; KV680;"')
    tune.add_argument("--move", default=None,
                      help='the move, e.g. "AC100000; VL5000; MR6400; GO;" (the default)')
    tune.add_argument("--seconds", type=float, default=None,
                      help="sample this long (default: until done, plus settling)")
    tune.add_argument("--motor", action="append", default=[], metavar="NAME=VALUE",
                      help="a motor parameter (inertia, viscous_friction, coulomb_friction, "
                      "torque_constant, amplifier, amplifier_gain, resistance, "
                      "encoder_lines); repeat for more")
    tune.add_argument("-o", "--output", type=Path, default=Path("tune.png"),
                      help="the PNG to write (default tune.png)")
    tune.add_argument("--no-plot", action="store_true", help="print the summary only")

    sub.add_parser("models", help="list the board models")

    library = sub.add_parser("library", help="where the vendor-API C library "
                             "(libOmsMAXkMC) and its headers are, and how to compile with them")
    library.add_argument("--path", action="store_true", help="print the library's path only")
    library.add_argument("--build", action="store_true", help="(re)build it with the C compiler")
    return parser


def main(argv: list[str] | None = None) -> int:
    """The `maxk` command. A reader that goes away (`maxk commands | head`) ends it
    quietly, with the status a shell gives a program its closed pipe ended (128 + 13)."""
    try:
        return _main(argv)
    except BrokenPipeError:
        # nobody reads stdout any more: point it at /dev/null so that the interpreter's
        # last flush at exit does not complain a second time
        with contextlib.suppress(OSError, ValueError):
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            os.close(devnull)
        return 141


def _main(argv: list[str] | None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if argv and argv[0].startswith("-") and argv[0] not in ("-h", "--help", "--version"):
        argv = ["repl", *argv]  # the REPL is the default command, its options too
    args = build_parser().parse_args(argv)
    if args.command in (None, "repl"):
        from maxk.repl import run_repl

        if args.command is None:
            return run_repl()
        archive: Path | bool = False if args.no_archive else (args.archive or True)
        return run_repl(model=args.model, rate=args.rate, manual_time=args.manual_time,
                        speed=args.speed, history=args.history, archive=archive)
    if args.command == "run":
        return _run(args)
    if args.command == "commands":
        return _commands(args)
    if args.command == "serve":
        from maxk.host.serve import main as serve_main

        return serve_main(args)
    if args.command == "tune":
        return _tune(args)
    if args.command == "library":
        from maxk.host.oms_library import describe

        return describe(path_only=args.path, rebuild=args.build)
    if args.command == "models":
        from maxk.controllers.registry import KINDS, build

        for kind in KINDS:
            rates = ", ".join(str(r) for r in kind.update_rates_hz)
            print(f"{kind.name}: {kind.summary} (update rates {rates} Hz)")
            for model in kind.models:
                names = " ".join(build(model).world_view().axis_names)
                print(f"  {model}  axes {names}")
        return 0
    return 2


def _run(args: argparse.Namespace) -> int:
    """One path for every controller: the script's controller, its world view for
    `--trace` and `--plot`, or its own recording where it keeps a richer one (the
    MM4005's pulses, the MC405's PWM)."""
    from maxk.controllers.contract import BuildOptions
    from maxk.controllers.registry import build
    from maxk.pathplot import PathRecorder, draw_path
    from maxk.script import ScriptError, load_script, parse_duration, run_script
    from maxk.trace import TraceWriter

    try:
        script = load_script(args.script)
    except UnicodeDecodeError as error:
        print(f"maxk run: {args.script}: not UTF-8 text ({error.reason} at byte "
              f"{error.start})", file=sys.stderr)
        return 2
    except (OSError, ScriptError) as error:
        print(f"maxk run: {error}", file=sys.stderr)
        return 2
    try:
        controller = build(args.model or script.model,
                           BuildOptions(update_rate_hz=args.rate or script.update_rate_hz))
    except ValueError as error:
        print(f"maxk run: {error}", file=sys.stderr)
        return 2
    rate = controller.engine.update_rate_hz
    record = getattr(controller, "record", None)  # a controller's own richer recording
    recording = tracer = recorder = trace_file = None
    on_step = None
    try:
        if (args.trace or args.plot) and record is not None:
            recording = record(max(1, parse_duration(args.plot_every, rate))
                               if args.plot_every else 20)
        if args.trace and recording is None:
            every = (max(1, parse_duration(args.trace_every, rate))
                     if args.trace_every else None)
            trace_file = open(args.trace, "w", encoding="utf-8", newline="")  # noqa: SIM115
            tracer = TraceWriter(trace_file, controller, every)
            tracer.attach()
            writer = tracer

            def on_step(step):  # type: ignore[no-untyped-def]
                writer.sample(f"line {step.line}")

        if args.plot and recording is None:
            letters = tuple(a.strip().upper() for a in args.plot_axes.split(","))
            if len(letters) != 2:
                raise ValueError("--plot-axes: name two axes, e.g. X,Y")
            recorder = PathRecorder(controller, letters,  # type: ignore[arg-type]
                                    max(1, parse_duration(args.plot_every, rate)),
                                    args.plot_bit)
            recorder.attach()
    except (OSError, ValueError, KeyError) as error:
        if trace_file is not None:
            trace_file.close()
        message = error.args[0] if isinstance(error, KeyError) else error
        print(f"maxk run: {message}", file=sys.stderr)
        return 2
    try:
        transcript = run_script(script, board=controller, check=not args.record,
                                on_step=on_step)
    finally:
        if trace_file is not None:
            trace_file.close()
    try:
        if recording is not None:
            if args.trace:
                recording.write_csv(str(args.trace))
            if args.plot:
                recording.plot(str(args.plot), args.script.name, draw_path)
                print(f"plot: {args.plot}", file=sys.stderr)
        if recorder is not None:
            recorder.sample()
            print(f"plot: {recorder.plot(args.plot, title=args.script.name)}", file=sys.stderr)
    except (ImportError, OSError) as error:
        print(f"maxk run: {error}", file=sys.stderr)
        return 2
    errors = [f"line {line} (tick {tick}): {text}" for line, tick, text in transcript.errors]
    return _report(args, script, transcript, errors)


def _report(args: argparse.Namespace, script: Any, transcript: Any, errors: list[str]) -> int:
    """Print the replies (and errors), record or report failures: the run's exit code."""
    from maxk.script import record

    for _line, tick, text, replies in transcript.entries:
        if args.verbose:
            print(f"[{tick:>8}] > {text.strip()}")
        for reply in replies:
            print(reply)
    for error in errors:
        print(f"maxk run: {error}", file=sys.stderr)
    if args.record:
        args.script.write_text(record(script, transcript), encoding="utf-8")
        print(f"maxk run: recorded {len(transcript.replies)} replies into {args.script}",
              file=sys.stderr)
        return 0
    if transcript.failures:
        for failure in transcript.failures:
            print(f"FAIL {args.script}:{failure}", file=sys.stderr)
        return 1
    return 0


def _tune(args: argparse.Namespace) -> int:
    from maxk.tuning import DEFAULT_MOVE, tune

    motor: dict[str, object] = {}
    for item in args.motor:
        key, _, value = item.partition("=")
        if not value:
            print(f"maxk tune: --motor {item!r}: say NAME=VALUE", file=sys.stderr)
            return 2
        key = key.replace("-", "_")
        try:
            motor[key] = value if key == "amplifier" else (
                int(value) if key == "encoder_lines" else float(value))
        except ValueError:
            print(f"maxk tune: --motor {item!r}: not a number", file=sys.stderr)
            return 2
    try:
        run = tune(args.gains, args.move or DEFAULT_MOVE, seconds=args.seconds, motor=motor)
    except (ValueError, TypeError) as error:
        print(f"maxk tune: {error}", file=sys.stderr)
        return 2
    print(run.summary())
    if args.no_plot:
        return 0
    try:
        path = run.plot(args.output)
    except ImportError as error:
        print(f"maxk tune: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        print(f"maxk tune: {args.output}: {error}", file=sys.stderr)
        return 2
    print(f"plot: {path}")
    return 0


def _commands(args: argparse.Namespace) -> int:
    """Any controller's command table, through its console (help, summaries); the
    Markdown reference where its kind has one (the MAX table's docs/commands.md)."""
    from maxk.controllers.registry import build, kind_of

    model = args.model or DEFAULT_MODEL
    if args.markdown:
        reference = kind_of(model).reference
        if reference is None:
            print(f"maxk commands: the {kind_of(model).name} has no Markdown reference; "
                  "see its docs", file=sys.stderr)
            return 1
        sys.stdout.write(reference())
        return 0
    console = build(model).console()
    if args.mnemonic:
        lines = console.help(args.mnemonic)
        if lines is None:
            print(f"maxk commands: no command {args.mnemonic!r}", file=sys.stderr)
            return 1
        print("\n".join(lines))
        return 0
    for word in console.words():
        print(f"{word:<16} {console.summary(word)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

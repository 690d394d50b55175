"""A regression fails on a command the controller refuses, unless the script expects it.

Each controller refuses in its own words (the MAXk's command error record, the MM4005's
error letter and text, the MC405's TrioBASIC error, the PoKeys console's `!` reply); a
script with any `<` line fails on one it did not mark with `@expect error [TEXT]` (or
match as a `<` reply, where the controller prints it as one), naming the line, the tick
and the message.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from maxk.controllers.registry import build
from maxk.script import parse_script, record, run_script


def run(text: str, check: bool = True):  # type: ignore[no-untyped-def]
    return run_script(parse_script(text, "t.maxk"), check=check)


# model, a line it refuses, the whole message, 10 ms in its ticks (its default rate),
# a line it accepts and that line's reply
REFUSALS = [
    ("MAXk-2000", "AX; VL5000; MRX; GO;", "'MR': MR needs an operand", 82, "AX RP", "0"),
    ("MM4005", "1PA99999999", "C Parameter out of limits", 20, "1TP", "1TP0.0000"),
    ("MC405", "MOVEE(10)", "Variable not defined", 10, "?1", "1"),
]
IDS = [r[0] for r in REFUSALS]


@pytest.mark.parametrize("model,bad,message,tick,good,reply", REFUSALS, ids=IDS)
def test_an_unexpected_refusal_fails_with_line_tick_and_message(model, bad, message, tick,
                                                                good, reply):
    t = run(f"@board {model}\n@wait 10 ms\n{bad}\n{good}\n< {reply}\n")
    assert [(f.line, f.tick, f.command, f.expected, f.actual) for f in t.failures] == [
        (3, tick, bad, "(no command error)", message)]


@pytest.mark.parametrize("model,bad,message,tick,good,reply", REFUSALS, ids=IDS)
@pytest.mark.parametrize("mark", ["@expect error", "@expect error {part}",
                                  "@expect error {PART}"])
def test_an_expected_refusal_passes(model, bad, message, tick, good, reply, mark):
    part = message.split()[-2]  # a word of the message, in any case
    mark = mark.format(part=part, PART=part.upper())
    t = run(f"@board {model}\n{bad}\n{mark}\n{good}\n< {reply}\n")
    assert not t.failures, t.failures


@pytest.mark.parametrize("model,bad,message,tick,good,reply", REFUSALS, ids=IDS)
def test_expecting_another_message_fails(model, bad, message, tick, good, reply):
    t = run(f"@board {model}\n{bad}\n@expect error no such words\n{good}\n< {reply}\n")
    assert [(f.line, f.actual) for f in t.failures] == [
        (3, f"command error: {message} (not 'no such words')")]


def test_a_pokeys_refusal_is_its_reply():
    """The PoKeys console answers a refused word with a `!` line: matched by a `<` line
    it is expected; left unmatched it fails as a reply and as a refusal."""
    assert not run("@board PoKeys57CNC\nfrob\n< ! unknown word 'frob'; try help\n").failures
    t = run("@board PoKeys57CNC\nfrob\n@wait 1 ms\nfrob\n< ! unknown word 'frob'; try help\n")
    assert [(f.line, f.expected, f.actual) for f in t.failures] == [
        (2, "(no more replies)", "! unknown word 'frob'; try help"),
        (2, "(no command error)", "unknown word 'frob'; try help")]
    assert [f.tick for f in t.failures] == [0, 0]


def test_expecting_an_error_where_none_came_fails():
    t = run("@board MC405\n?1\n< 1\n@expect error\n")
    assert [(f.line, f.actual) for f in t.failures] == [(4, "no command error")]


def test_the_maxk_expect_error_still_reads_the_latched_flag():
    """On a MAXk `@expect error` with no new refusal reads the command-error flag
    (doorbell bit 24), latched until IC: an older error still satisfies it."""
    text = ("@board MAXk-2000\nAX; MR; GO;\n@expect error\nAX RP\n< 0\n@expect error\n"
            "IC\n@expect no error\n")
    assert not run(text).failures
    t = run("@board MAXk-2000\nAX RP\n< 0\n@expect error\n")
    assert [(f.line, f.actual) for f in t.failures] == [(4, "no error")]


def test_expect_no_error_fails_on_a_refusal_not_yet_expected():
    t = run("@board MC405\nMOVEE(10)\n@expect no error\n?1\n< 1\n")
    assert [(f.line, f.actual) for f in t.failures] == [
        (3, "command error: Variable not defined")]


def test_a_script_without_expected_replies_only_lists_errors():
    """Not a regression (no `<` line): it runs, its errors are listed, nothing fails."""
    t = run("@board MAXk-2000\n@wait 2 ticks\nAX; MR; GO;\n")
    assert not t.failures
    assert t.errors == [(3, 2, "'MR': MR needs an operand")]


MC405_PROGRAM = ('@board MC405\nSELECT "P",0\n!P,0RWA(100)\n!P,1Rx = 1/0\nCOMPILE\n'
                 'RUN "P"\n@wait 1 s\n?1\n')
PROGRAM_ERROR = "%[Process 19:Program P Line 2] - Divide by zero"


def test_a_program_error_printed_unasked_is_a_refusal():
    """An MC405 program's runtime error reaches the host unasked, `%[...] - message`,
    with the next reply: a `<` line expects it; `@expect error` does too; else it fails
    where it surfaced (line 8, at 1 s: tick 1000 at 1 kHz)."""
    assert not run(MC405_PROGRAM + f"< {PROGRAM_ERROR}\n< 1\n").failures
    t = run(MC405_PROGRAM + "< 1\n")
    assert [(f.line, f.tick, f.expected, f.actual) for f in t.failures] == [
        (9, 1000, "1", PROGRAM_ERROR), (8, 1000, "(no command error)", PROGRAM_ERROR),
        (8, 1000, "(no more replies)", "1")]


def test_record_writes_the_expectation(tmp_path: Path):
    path = tmp_path / "s.maxk"
    path.write_text("@board MAXk-2000\nAX; VL5000; MRX; GO;\nAX RP\n< 7\n")
    script = parse_script(path.read_text(), str(path))
    recorded = record(script, run_script(script, check=False))
    assert recorded == ("@board MAXk-2000\nAX; VL5000; MRX; GO;\n"
                        "@expect error 'MR': MR needs an operand\nAX RP\n< 0\n")
    assert not run_script(parse_script(recorded, str(path))).failures
    again = parse_script(recorded, str(path))  # recorded again: written once, not twice
    assert record(again, run_script(again, check=False)) == recorded


def test_record_of_an_mc405_error_and_a_program_error():
    script = parse_script("@board MC405\nPRINT 1/0\n?2\n", "m.maxk")
    recorded = record(script, run_script(script, check=False))
    assert recorded == "@board MC405\nPRINT 1/0\n@expect error Divide by zero\n?2\n< 2\n"
    assert not run_script(parse_script(recorded)).failures
    script = parse_script(MC405_PROGRAM, "p.maxk")
    recorded = record(script, run_script(script, check=False))
    assert recorded.endswith(f"?1\n< {PROGRAM_ERROR}\n< 1\n")  # the reply says it
    assert not run_script(parse_script(recorded)).failures


def test_the_cli_fails_an_unexpected_error(tmp_path: Path, capsys):
    from maxk.cli import main

    path = tmp_path / "typo.maxk"
    path.write_text("@board MAXk-2000\nAX; VL5000; MRX; GO;\nAX RP\n< 0\n")
    assert main(["run", str(path)]) == 1
    err = capsys.readouterr().err
    assert f"FAIL {path}:line 2 (tick 0): AX; VL5000; MRX; GO;" in err
    assert "actual:   'MR': MR needs an operand" in err
    assert main(["run", "--record", str(path)]) == 0
    assert "@expect error 'MR': MR needs an operand\n" in path.read_text()
    assert main(["run", str(path)]) == 0


def test_the_plugin_fails_an_unexpected_error_and_passes_an_expected_one(pytester):
    pytester.makefile(".maxk", typo="@board MAXk-2000\nAX; VL5000; MRX; GO;\nAX RP\n< 0\n")
    pytester.makefile(".maxk", marked="@board MAXk-2000\nAX; VL5000; MRX; GO;\n"
                      "@expect error needs an operand\nAX RP\n< 0\n")
    result = pytester.runpytest()
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines([
        "*typo.maxk on MAXk-2000 at 8192 Hz: 1 failure(s)*",
        "*line 2 (tick 0): AX; VL5000; MRX; GO;*",
        "*expected: (no command error)*",
        "*actual:   'MR': MR needs an operand*",
    ])


def test_every_kind_names_its_refusals():
    """What the regression reads is each console's own: nothing a kind prints for a
    refused line is lost between the console and the script."""
    for model, bad, message, *_ in REFUSALS:
        console = build(model).console()
        replies = console.execute(bad)
        assert console.refused(replies, console.new_errors()) in (
            [message], [f"! {message}"]), model

"""The pytest plugin, tested the way pytest documents it: with pytester."""

import pytest

MOVE = """\
// a move and its position
@board MAXk-2000
AX; VL5000; AC50000; MR1000; GO; ID;
@wait until X done within 5 s
AX RP
< 1000
"""


def test_a_passing_script(pytester: pytest.Pytester):
    pytester.makefile(".maxk", move=MOVE)
    result = pytester.runpytest("-v")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["*move.maxk::script PASSED*"])


def test_a_failing_script_shows_command_expected_actual_tick_and_state(pytester):
    pytester.makefile(".maxk", move=MOVE.replace("< 1000", "< 999"))
    result = pytester.runpytest()
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines([
        "*move.maxk on MAXk-2000 at 8192 Hz: 1 failure(s)*",
        "*line 6 (tick 2458): AX RP*",
        "*expected: 999*",
        "*actual:   1000*",
        "*board state:*",
        "*X      1000      1000         0  PDNN    0*",
        "*doorbell 0x00000001*",
    ])
    assert "Traceback" not in result.stdout.str()


def test_a_timeout_fails_the_test(pytester):
    pytester.makefile(".maxk", slow="AX; VL1; MR100; GO; ID;\n@wait until X done within 1 s\n")
    result = pytester.runpytest()
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*@wait until X done within 1 s*", "*timed out after 1 s*"])


def test_a_malformed_script_is_a_clear_collection_error(pytester):
    pytester.makefile(".maxk", bad="AX RP\n< 0\n@wiat 1 s\n")
    result = pytester.runpytest()
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["*bad.maxk:3: unknown directive @wiat*"])
    assert "Traceback" not in result.stdout.str()


def test_models_and_rates_parametrize(pytester):
    pytester.makefile(".maxk", both="@board MAXk-2000 MAXk-4000\n@rate 1024 8192\n"
                                     "AX; MR10; GO; ID;\n@wait until X done\nAX RP\n< 10\n")
    result = pytester.runpytest("-v")
    result.assert_outcomes(passed=4)
    result.stdout.fnmatch_lines(["*both.maxk::MAXk-2000-1024Hz PASSED*",
                                 "*both.maxk::MAXk-4000-8192Hz PASSED*"])


def test_command_line_overrides_the_model(pytester):
    pytester.makefile(".maxk", axes="@board MAXk-2000\nAA RP\n< 0,0\n")
    pytester.runpytest().assert_outcomes(passed=1)
    result = pytester.runpytest("--maxk-model", "MAXk-3000")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*actual:   0,0,0*"])
    result = pytester.runpytest("--maxk-model", "MAXk-2000", "--maxk-rate", "1024",
                                "--maxk-rate", "2048", "-v")
    result.assert_outcomes(passed=2)
    # a rate the MAXk does not run at leaves it at its own (a suite may mix controllers);
    # one that no controller runs at is an error
    result = pytester.runpytest("--maxk-rate", "1000", "-v")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["*axes.maxk::script PASSED*"])
    pytester.runpytest("--maxk-rate", "999").assert_outcomes(errors=1)


def test_plain_python_tests_still_run_beside_scripts(pytester):
    pytester.makefile(".maxk", move=MOVE)
    pytester.makepyfile(test_other="def test_ok():\n    assert True\n")
    pytester.runpytest().assert_outcomes(passed=2)


def test_a_malformed_wait_timeout_is_a_collection_error(pytester):
    pytester.makefile(".maxk", bad="AX; MR5; GO;\n@wait until X done within abc\n")
    result = pytester.runpytest()
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["*bad.maxk:2: not a duration: 'abc'*"])
    assert "Traceback" not in result.stdout.str()

"""The command-script format: directives, expectations, clear errors naming the line."""

import pytest

from maxk.script import ScriptError, parse_duration, parse_script, run_script


def run(text):
    return run_script(parse_script(text, "t.maxk"))


def test_expected_reply_mismatch_is_reported_with_line_and_tick():
    t = run("AX; MR100; GO; ID;\n@wait until X done\nAX RP\n< 99\n")
    assert len(t.failures) == 1
    f = t.failures[0]
    assert (f.line, f.expected, f.actual) == (4, "99", "100")
    assert "AX RP" in str(f) and "tick" in str(f)


def test_unexpected_extra_reply_fails_in_a_regression_script():
    t = run("AX RP\n< 0\nAX RP RE\n< 0\n")
    assert len(t.failures) == 1
    assert t.failures[0].actual == "0"


def test_plain_script_without_expectations_only_collects_replies():
    t = run("AX RP RE\nWY\n")
    assert not t.failures
    assert t.replies[:2] == ["0", "0"]


def test_wait_until_timeout_fails():
    t = run("AX; VL1; MR100; GO; ID;\n@wait until X done within 1 s\n")
    assert t.failures and t.failures[0].actual == "timed out after 1 s"


def test_expectations():
    t = run("AY; MR5; GO; ID;\n@wait until idle\n@expect Y position 5\n@expect Y done\n"
            "@expect X not done\n@expect no error\n@expect doorbell 0x2\n@expect Y encoder 5\n"
            "@expect Y velocity 0\n")
    assert not t.failures, t.failures
    t = run("@expect X position 1\n@expect error\n")
    assert len(t.failures) == 2


def test_board_and_rate_directives():
    script = parse_script("@board maxk-2000\n@rate 1024\nAA RP\n< 0,0\n")
    assert (script.model, script.update_rate_hz) == ("MAXk-2000", 1024)
    assert not run_script(script).failures


@pytest.mark.parametrize("text,message", [
    ("@frobnicate\n", "unknown directive @frobnicate"),
    ("< 10\n", "an expected reply must follow a command line"),
    ("AX RP\n@board MAXk-1000\n", "@board must come before the first command"),
    ("@board MAXk-9999\n", "unknown controller model"),
    ("@wait soon\n", "not a duration"),
    ("@expect X happy\n", "cannot read @expect"),
    ("@rate 1000\n", "the MAXk runs at 1024, 2048, 4096, 8192 Hz, not 1000"),
    ("@wait until X done within abc\n", "not a duration: 'abc'"),
    ("@wait until idle within -1 s\n", "not a duration: '-1 s'"),
    ("@wait until all done within 1.5 ticks\n", "ticks must be whole"),
    ("@wait 2.5 ticks\n", "ticks must be whole"),
])
def test_malformed_scripts_name_the_line(text, message):
    with pytest.raises(ScriptError) as info:
        parse_script("// first\n" + text, "bad.maxk")
    line = text.count("\n") + 1  # the offending line is the last one
    assert info.value.line == line
    assert message in str(info.value)
    assert str(info.value).startswith(f"bad.maxk:{line}:")


def test_durations():
    assert parse_duration("1 s", 8192) == 8192
    assert parse_duration("250ms", 8192) == 2048
    assert parse_duration("100 ticks", 8192) == 100
    assert parse_duration("0.1", 8192) == 820  # rounded up to whole ticks
    with pytest.raises(ValueError):
        parse_duration("1.5 ticks", 8192)


def test_same_script_same_bytes():
    text = "AA; VL5000,6000; MR1000,-2000; GO; ID;\n@wait 0.1 s\nAA RP\nRV\n@wait until idle\nRI\n"
    first = run(text)
    second = run(text)
    assert first.entries == second.entries
    assert first.replies == ["494,-591,0,0,0,0,0,0", "5000,-6000,0,0,0,0,0,0",
                             "PDNN,MDNN,PDNN,PDNN,PDNN,PDNN,PDNN,PDNN"]


def test_record_round_trip(tmp_path):
    from maxk.script import load_script, record

    path = tmp_path / "r.maxk"
    path.write_text("// keep me\nAX; MR5; GO; ID;\n@wait until X done\nAX RP RE\n< stale\n"
                    "\n@expect X done\nWY\n")
    script = load_script(path)
    recorded = record(script, run_script(script, check=False))
    assert recorded == ("// keep me\nAX; MR5; GO; ID;\n@wait until X done\nAX RP RE\n< 5\n< 5\n"
                        "\n@expect X done\nWY\n< MAXk-8000, ver:1.33, S/N: 000001, FPGA:20\n")
    path.write_text(recorded)
    assert not run_script(load_script(path)).failures


def test_wait_for_an_axis_the_model_lacks_is_refused_when_read():
    with pytest.raises(ScriptError) as info:
        parse_script("@board MAXk-1000\n@wait until K done\n")
    assert "no axis 'K'" in str(info.value) and info.value.line == 2
    # the same script on a controller given at run time fails the run, cleanly
    t = run_script(parse_script("@board MAXk-A000\n@wait until K done\n"), model="MAXk-1000")
    assert t.failures and "no axis 'K'" in t.failures[0].actual

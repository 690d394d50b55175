"""World settings through the doors: @world in scripts, :world in the REPL."""

import pytest

from maxk.repl import ReplSession
from maxk.script import ScriptError, parse_script, run_script


def run(text):
    return run_script(parse_script(text, "w.maxk"))


def test_script_limits_inputs_and_io_expectations():
    t = run("@world X limits 2000 -2000\n@world input 3 high\n"
            "AX; VL10000; MR5000; GO; ID;\n@wait until idle\n"
            "@expect X overtravel\n@expect X not done\n@expect bit 3 high\n@expect bit 9 low\n"
            "AX QA\n< PNLN\nBH9\n@expect bit 9 high\n")
    assert not t.failures, [str(f) for f in t.failures]


def test_script_home_index_fault_and_capture():
    t = run("@world X home 500 520\n@world X index 1000 4 510\n@world X capture home both\n"
            "AX; PSE; VL10000; HM7; ID;\n@wait until X done\n@expect captures 2\n"
            "@world X fault minus active\nAX; MR-100; GO;\n@expect X overtravel\n")
    assert not t.failures, [str(f) for f in t.failures]
    assert t.board.board.axes[0].steps >= 500


def test_script_analog_and_bad_world_lines():
    t = run("@world analog 2 -5\nAI2\n< -16384\n")
    assert not t.failures
    for bad, message in [("@world X limits 1\n", "cannot read"),
                         ("@world input 22 high\n", "0..15"),
                         ("@world X fault plus sideways\n", "active|inactive|none"),
                         ("@world X capture home sometimes\n", "capture home"),
                         ("@expect bit 3 maybe\n", "cannot read @expect")]:
        with pytest.raises(ScriptError) as info:
            parse_script(bad, "w.maxk")
        assert message in str(info.value) and info.value.line == 1


def test_world_for_an_axis_the_model_lacks_is_refused_when_read():
    with pytest.raises(ScriptError) as info:
        parse_script("@board MAXk-1000\n@world K limits 1 -1\n", "w.maxk")
    assert "no axis 'K'" in str(info.value) and info.value.line == 2


def test_repl_world_and_capture():
    s = ReplSession(manual_time=True)
    assert s.handle(":world X capture index on") == ["X capture index on"]
    assert s.handle(":world X limits 10000 none") == ["X limits 10000 none"]
    s.handle("AX; PSE; VL100000; MR9000; GO;")
    s.handle(":run")
    assert s.handle(":capture") == ["X encoder 1280 home 0x02 inputs +0x0000 -0x0000",
                                    "X encoder 5280 home 0x02 inputs +0x0000 -0x0000"]
    assert s.handle(":capture") == ["capture ring empty"]
    world = s.handle(":world")
    assert world[0].startswith("X: at 9000 steps; limits 10000 / none; home 1234..1333")
    assert s.handle(":world nonsense here")[0].startswith("world: cannot read")


def test_bad_world_values_are_refused_not_crashing():
    from maxk import MAXk

    b = MAXk()
    for call in (lambda: b.set_limits("X", plus=float("inf")),
                 lambda: b.set_home("X", 500, 100),
                 lambda: b.set_analog(0, float("nan")),
                 lambda: b.fault("X", "sideways", "active")):
        with pytest.raises(ValueError):
            call()
    s = ReplSession(manual_time=True)
    assert s.handle(":world X home none 300") == ["X home none 300"]
    assert s.handle(":world")[0].startswith("X: at 0 steps; limits 1000000000 / -1000000000;"
                                            " home none..300")

"""Issue 34: every world setting checks its values' range and finiteness, wherever it
comes from: the words (`@world`, `:world`, the control door), the Python API, a script
run by `maxk run` or the pytest plugin. A bad value is an error that names the range,
never a traceback or a 500, and nothing of it is applied."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest

from maxk.control import ControlError
from maxk.controllers.registry import build
from maxk.controllers.world_settings import parse_world
from tests.test_control import Hosted

ROOT = Path(__file__).parent.parent
HUGE = "9" * 400

BAD_WORDS = [
    (f"X limits {HUGE} 0", "within +/-9007199254740992 steps"),
    (f"X plus-limit -{HUGE}", "within +/-9007199254740992 steps"),
    ("X minus-limit 9007199254740993", "within +/-9007199254740992 steps"),  # 2^53 + 1
    ("X home 1e400 2", "not a position in steps"),
    ("X limits inf 0", "not a position in steps"),
    ("X miss 1e40", "missed steps: not a whole number"),
    (f"X miss {HUGE}", "missed steps must be from -2147483647 to 2147483647"),
    ("X miss 2147483648", "missed steps must be from -2147483647 to 2147483647"),
    ("X backlash 1e40", "backlash (steps): not a whole number"),
    ("X backlash 2147483648", "backlash (steps) must be from 0 to 2147483647"),
    ("X backlash -1", "backlash (steps) must be from 0 to 2147483647"),
    ("X bounce home -5", "bounce (steps) must be from 0 to 1000"),
    ("X bounce plus 1001", "bounce (steps) must be from 0 to 1000"),
    (f"X index {HUGE} 4 0", "the index period must be from 0 to 2147483647"),
    ("X index 4000 -1 0", "the index width must be from 0 to 2147483647"),
    ("X motor inertia=nan", "inertia must be a number from 1e-12 to 1e+12, not nan"),
    ("X motor resistance=inf", "resistance must be a number from 1e-12 to 1e+12, not inf"),
    ("X motor inertia=1e-300", "inertia must be a number from 1e-12"),
    ("X motor viscous_friction=-1", "viscous_friction must be a number from 0 to 1e+12"),
    ("X motor coulomb_friction=nan", "coulomb_friction must be a number from 0"),
    ("X motor encoder_lines=1e30", "encoder_lines must be a whole number from 1 to 10,000,000"),
    ("X motor encoder_lines=inf", "encoder_lines must be a whole number, not inf"),
    ("X motor encoder_lines=2.5", "encoder_lines must be a whole number, not 2.5"),
    ("analog 0 nan", "volts must be a finite number"),
    ("analog 0 -inf", "volts must be a finite number"),
    (f"input {HUGE} high", "input number must be from 0 to 2147483647"),
    (f"analog {HUGE} 1", "channel must be from 0 to 2147483647"),
]


@pytest.mark.parametrize("words, reason", BAD_WORDS, ids=[w[:30] for w, _ in BAD_WORDS])
def test_bad_values_are_refused_when_the_words_are_read(words: str, reason: str) -> None:
    with pytest.raises(ValueError) as error:
        parse_world(words)
    message = str(error.value)
    assert reason in message
    assert len(message) < 200  # a 400-digit word is quoted cut short


def test_the_edges_of_each_range_are_taken() -> None:
    controller = build("MAXk-4000")
    view = controller.world_view()
    for words in ("X limits 9007199254740992 -9007199254740992", "X bounce home 1000",
                  "X bounce home 0", "X miss 2147483647", "X miss -2147483647",
                  "X backlash 2147483647", "X backlash 0", "X index 2147483647 0 -5",
                  "X motor inertia=1e-12 resistance=1e12 viscous_friction=0",
                  "X motor encoder_lines=10000000", "analog 0 -10"):
        parse_world(words)(controller)
    stage = view.stage("X")
    assert (stage.plus_limit.low, stage.minus_limit.high) == (2.0 ** 53, -(2.0 ** 53))
    assert stage.lost_steps == 0 and stage.backlash == 0 and stage.home.bounce == 0
    assert (stage.index_period, stage.index_width, stage.index_offset) == (2 ** 31 - 1, 0, -5)
    assert stage.motor.encoder_lines == 10_000_000 and stage.motor.inertia == 1e-12


def test_the_python_api_checks_the_same_ranges_and_changes_nothing() -> None:
    controller = build("MAXk-4000")
    view = controller.world_view()
    before = view.snapshot()
    for call, reason in [
        (lambda: view.set_limits("X", plus=math.inf), "finite number of steps"),
        (lambda: view.set_limits("X", minus=float("nan")), "finite number of steps"),
        (lambda: view.set_home("X", 0, 1e300), "finite number of steps within"),
        (lambda: view.bounce("X", "home", -5), "bounce (steps) must be from 0 to 1000"),
        (lambda: view.bounce("X", "home", 2.5), "bounce (steps) must be a whole number"),
        (lambda: view.miss_steps("X", 1e40), "missed steps must be from"),
        (lambda: view.miss_steps("X", math.nan), "missed steps must be a whole number"),
        (lambda: view.set_backlash("X", 10 ** 40), "backlash (steps) must be from 0"),
        (lambda: view.set_index("X", -1), "the index period must be from 0"),
        (lambda: view.set_index("X", 4000, 4, 10 ** 40), "the index offset must be from"),
        (lambda: view.set_motor("X", inertia=math.nan), "inertia must be a number"),
        (lambda: view.set_motor("X", resistance=math.inf), "resistance must be a number"),
        (lambda: view.set_motor("X", encoder_lines=0), "encoder_lines must be a whole"),
        (lambda: view.set_analog(0, math.nan), "volts must be a number"),
    ]:
        with pytest.raises(ValueError) as error:
            call()
        assert reason in str(error.value)
    assert view.snapshot() == before
    # missed steps add up, within the positions' range
    view.miss_steps("X", 2 ** 31 - 1)
    assert view.stage("X").lost_steps == 2 ** 31 - 1


@pytest.mark.parametrize("body, reason", [
    ({"words": f"X limits {HUGE} 0"}, "within +/-9007199254740992 steps"),
    ({"words": "X miss 1e40"}, "missed steps: not a whole number"),
    ({"words": "X backlash 1e40"}, "backlash (steps): not a whole number"),
    ({"words": "X bounce home -5"}, "bounce (steps) must be from 0 to 1000"),
    ({"words": "X motor inertia=nan"}, "inertia must be a number"),
    ({"words": "X motor resistance=inf"}, "resistance must be a number"),
    ({"axis": "X", "set": "limits", "values": [10 ** 400, 0]}, "within +/-"),
    # infinity is no JSON number: the door refuses the body before any world word
    ({"axis": "X", "set": "limits", "values": [1e308 * 10, 0]}, "a finite number only"),
    ({"axis": "X", "set": "miss", "values": [1e40]}, "missed steps: not a whole number"),
    ({"analog": 0, "volts": float("nan")}, "a finite number only"),
])
def test_the_control_door_answers_400_with_the_reason(body, reason) -> None:
    hosted = Hosted(("MAXk-8000",))
    try:
        before = hosted.client.board(1)["world"]
        with pytest.raises(ControlError) as error:
            hosted.client.request("POST", "/api/boards/1/world", body)
        assert error.value.status == 400, error.value.reason
        assert reason in error.value.reason
        assert hosted.client.board(1)["world"] == before
        # a trigger of the same words is refused the same way, nothing armed
        if "words" in body:
            with pytest.raises(ControlError) as error:
                hosted.client.arm(1, body["words"], after=1.0)
            assert error.value.status == 400 and reason in error.value.reason
            assert hosted.client.request("GET", "/api/boards/1/triggers")["triggers"] == []
    finally:
        hosted.close()


@pytest.mark.parametrize("words, reason", [
    (f"X limits {HUGE} 0", "a position must be within +/-9007199254740992 steps"),
    ("X motor inertia=nan", "inertia must be a number"),
    ("X bounce home -5", "bounce (steps) must be from 0 to 1000"),
], ids=["huge", "nan", "negative"])
def test_maxk_run_reports_a_bad_world_value_on_its_line(tmp_path, words, reason) -> None:
    script = tmp_path / "bad.maxk"
    script.write_text(f"@board MAXk-4000\nAX RP\n< 0\n@world {words}\nAX RP\n< 0\n")
    result = subprocess.run([sys.executable, "-m", "maxk", "run", str(script)],
                            capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert result.returncode == 2
    assert f"bad.maxk:4: {reason}" in result.stderr
    assert "Traceback" not in result.stderr + result.stdout


def test_the_pytest_plugin_reports_a_bad_world_value_on_its_line(pytester) -> None:
    pytester.makefile(".maxk", bad=f"AX RP\n< 0\n@world X limits {HUGE} 0\n")
    pytester.makefile(".maxk", nan="@world X motor resistance=inf\nAX RP\n< 0\n")
    result = pytester.runpytest()
    result.assert_outcomes(errors=2)
    result.stdout.fnmatch_lines(["*bad.maxk:3: a position must be within*"])
    result.stdout.fnmatch_lines(["*nan.maxk:1: resistance must be a number*"])
    assert "Traceback" not in result.stdout.str()

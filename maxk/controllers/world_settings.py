"""World settings as text, one language for every controller: command scripts
(`@world ...`), the REPL (`:world ...`) and the control door say the same words, and
each controller's `WorldView` carries them out with its own axis names (docs/io.md).

    X limits 5000 -5000        plus and minus limit positions (physical steps; none = no switch)
    X plus-limit none          one side only (also minus-limit)
    X home 200 260             the home switch is active from 200 to 260 (home none: none)
    X index 4000 4 1280        index marks: period, width, offset
    X fault plus active        stick a switch (plus, minus, home) active/inactive; none clears
    X bounce home 3            the switch chatters within 3 steps of its edges (0: clean)
    X miss 20                  the stage misses 20 steps now (an encoder sees the slip)
    X backlash 25              the stage has 25 steps of play
    X motor inertia=2e-5       the motor a servo axis drives
    input 3 high               a digital input (high/low/1/0)
    analog 0 2.5               an analog input in volts

Axis names are the controller's own (X..K on a MAXk, 1..4 on an MM4005, 0..n on an
MC405, X..C or 1..8 on a PoKeys). A controller may know more words (the MAXk's
`X capture home both`): those it checks when the setting is applied.
"""

from __future__ import annotations

import math
from dataclasses import fields
from typing import Any

from maxk.controllers.world_view import Setting, WorldView
from maxk.firmware_model.motor import MotorPlant
from maxk.firmware_model.world import (
    BOUNCE_LIMIT,
    COUNT_LIMIT,
    POSITION_LIMIT,
    SWITCHES,
    checked_position,
)

__all__ = ["Setting", "parse_world", "view_of"]


def view_of(target: Any) -> WorldView:
    """A controller's world view (a view stays itself)."""
    return target if isinstance(target, WorldView) else target.world_view()


def _position(text: str) -> float | None:
    """Whole steps within the world's range (firmware_model/world.py), or none."""
    if text.lower() == "none":
        return None
    try:
        steps = int(text)
    except ValueError:
        raise ValueError(f"not a position in steps: {_shown(text)} (or none)") from None
    if abs(steps) > POSITION_LIMIT:
        raise ValueError(f"a position must be within +/-{POSITION_LIMIT} steps (2^53), "
                         f"not {_shown(text)}")
    return checked_position(steps)


def _int(text: str, what: str, low: int = -COUNT_LIMIT, high: int = COUNT_LIMIT) -> int:
    """A whole number in a range: words never reach the world as a huge or a float."""
    try:
        number = int(text, 0)
    except ValueError:
        raise ValueError(f"{what}: not a whole number: {_shown(text)}") from None
    if not low <= number <= high:
        raise ValueError(f"{what} must be from {low} to {high}, not {_shown(text)}")
    return number


def _shown(text: str) -> str:
    """A word as an error message quotes it: a 400-digit one is cut."""
    return repr(text if len(text) <= 40 else text[:20] + "..." + text[-8:])


def _setting(apply: Any, said: str) -> Setting:
    """A setting that applies to a view (or to a controller, through its view)."""

    def run(target: Any) -> str:
        apply(view_of(target))
        return said

    return run


def parse_world(text: str) -> Setting:
    """Check a world setting's words now; return what applies it to a controller later."""
    words = text.split()
    if not words:
        raise ValueError("say what to set, e.g. 'X limits 5000 -5000' or 'input 3 high'")
    head = words[0].lower()
    if head == "input":
        if len(words) != 3 or words[2].lower() not in ("high", "low", "1", "0"):
            raise ValueError("input NUMBER high|low")
        number = _int(words[1], "input number", 0, COUNT_LIMIT)
        level = words[2].lower() in ("high", "1")
        return _setting(lambda v: v.set_input(number, level),
                        f"input {number} {'high' if level else 'low'}")
    if head == "analog":
        if len(words) != 3:
            raise ValueError("analog CHANNEL VOLTS")
        channel = _int(words[1], "channel", 0, COUNT_LIMIT)
        try:
            volts = float(words[2])
        except ValueError:
            raise ValueError(f"not volts: {_shown(words[2])}") from None
        if not math.isfinite(volts):
            raise ValueError(f"volts must be a finite number, not {_shown(words[2])}")
        return _setting(lambda v: v.set_analog(channel, volts), f"analog {channel} {volts:g} V")
    if len(words) < 2:
        raise ValueError(f"cannot read {text!r}: start with an axis name, 'input' or "
                         "'analog'")
    name = words[0].upper()
    what = words[1].lower()
    args = words[2:]
    said = f"{name} {what} {' '.join(args)}".strip()
    if what == "limits" and len(args) == 2:
        plus, minus = _position(args[0]), _position(args[1])
        return _setting(lambda v: v.set_limits(name, plus=plus, minus=minus), said)
    if what in ("plus-limit", "minus-limit") and len(args) == 1:
        pos = _position(args[0])
        key = "plus" if what == "plus-limit" else "minus"
        return _setting(lambda v: v.set_limits(name, **{key: pos}), said)
    if what == "home" and args and (len(args) == 2 or [a.lower() for a in args] == ["none"]):
        low, high = ((None, None) if len(args) == 1
                     else (_position(args[0]), _position(args[1])))
        if low is not None and high is not None and low > high:
            raise ValueError(f"the home switch runs from low to high: {low:g} > {high:g}")
        return _setting(lambda v: v.set_home(name, low, high), said)
    if what == "index" and len(args) == 3:
        period = _int(args[0], "the index period", 0)
        width = _int(args[1], "the index width", 0)
        offset = _int(args[2], "the index offset", -POSITION_LIMIT, POSITION_LIMIT)
        return _setting(lambda v: v.set_index(name, period, width, offset),
                        f"{name} index {period} {width} {offset}")
    if what == "fault" and len(args) == 2 and args[0].lower() in SWITCHES:
        state = None if args[1].lower() == "none" else args[1].lower()
        if state not in (None, "active", "inactive"):
            raise ValueError("fault SWITCH active|inactive|none")
        switch = args[0].lower()
        return _setting(lambda v: v.fault(name, switch, state),
                        f"{name} fault {switch} {state}")
    if what == "bounce" and len(args) == 2 and args[0].lower() in SWITCHES:
        steps = _int(args[1], "bounce (steps)", 0, BOUNCE_LIMIT)
        switch = args[0].lower()
        return _setting(lambda v: v.bounce(name, switch, steps), said)
    if what == "miss" and len(args) == 1:
        missed = _int(args[0], "missed steps")
        return _setting(lambda v: v.miss_steps(name, missed), said)
    if what == "backlash" and len(args) == 1:
        play = _int(args[0], "backlash (steps)", 0)
        return _setting(lambda v: v.set_backlash(name, play), said)
    if what == "motor" and args:
        parameters = _motor(args)
        return _setting(lambda v: v.set_motor(name, **parameters), said)
    if what in ("limits", "plus-limit", "minus-limit", "home", "index", "fault", "bounce",
                "miss", "backlash"):
        raise ValueError(f"cannot read {text!r}; see docs/io.md for the world settings")

    def extra(target: Any) -> str:
        """A word only some controllers know: the controller checks it now."""
        view = view_of(target)
        try:
            view.index(name)
        except KeyError as error:
            raise ValueError(f"cannot read {text!r}: {error.args[0]}") from None
        done = view.extra_setting(name, [what, *args])
        if done is None:
            raise ValueError(f"cannot read {text!r}; see docs/io.md for the world settings")
        return done

    return extra


def _motor(args: list[str]) -> dict[str, object]:
    parameters: dict[str, object] = {}
    for arg in args:
        key, _, value = arg.partition("=")
        if not value:
            raise ValueError("motor NAME=VALUE ... (e.g. motor inertia=1e-5 "
                             "amplifier=current)")
        try:
            parameters[key.replace("-", "_")] = value if key == "amplifier" else float(value)
        except ValueError:
            raise ValueError(f"motor {key}: not a number: {_shown(value)}") from None
    if "encoder_lines" in parameters:
        lines = parameters["encoder_lines"]
        assert isinstance(lines, float)
        if not (math.isfinite(lines) and lines.is_integer()):
            raise ValueError(f"encoder_lines must be a whole number, not {lines}")
        parameters["encoder_lines"] = int(lines)
    try:
        MotorPlant(**parameters)  # type: ignore[arg-type]  # ValueError: out of range
    except TypeError:
        names = ", ".join(f.name for f in fields(MotorPlant))
        raise ValueError(f"motor parameters are {names}") from None
    return parameters

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

from dataclasses import fields
from typing import Any

from maxk.controllers.world_view import Setting, WorldView
from maxk.firmware_model.motor import MotorPlant
from maxk.firmware_model.world import SWITCHES

__all__ = ["Setting", "parse_world", "view_of"]


def view_of(target: Any) -> WorldView:
    """A controller's world view (a view stays itself)."""
    return target if isinstance(target, WorldView) else target.world_view()


def _position(text: str) -> float | None:
    if text.lower() == "none":
        return None
    try:
        return float(int(text))
    except ValueError:
        raise ValueError(f"not a position in steps: {text!r} (or none)") from None


def _int(text: str, what: str) -> int:
    try:
        return int(text, 0)
    except ValueError:
        raise ValueError(f"not {what}: {text!r}") from None


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
        number = _int(words[1], "an input number")
        level = words[2].lower() in ("high", "1")
        return _setting(lambda v: v.set_input(number, level),
                        f"input {number} {'high' if level else 'low'}")
    if head == "analog":
        if len(words) != 3:
            raise ValueError("analog CHANNEL VOLTS")
        channel = _int(words[1], "a channel")
        try:
            volts = float(words[2])
        except ValueError:
            raise ValueError(f"not volts: {words[2]!r}") from None
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
        period, width, offset = (_int(a, "a count") for a in args)
        if period < 0 or width < 0:
            raise ValueError("index period and width are counts >= 0")
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
        steps = _int(args[1], "a number of steps")
        switch = args[0].lower()
        return _setting(lambda v: v.bounce(name, switch, steps), said)
    if what == "miss" and len(args) == 1:
        missed = _int(args[0], "a number of steps")
        return _setting(lambda v: v.miss_steps(name, missed), said)
    if what == "backlash" and len(args) == 1:
        play = _int(args[0], "a number of steps")
        if play < 0:
            raise ValueError("backlash is a number of steps >= 0")
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
            raise ValueError(f"motor {key}: not a number: {value!r}") from None
    if "encoder_lines" in parameters:
        parameters["encoder_lines"] = int(parameters["encoder_lines"])  # type: ignore
    try:
        MotorPlant(**parameters)  # type: ignore[arg-type]
    except TypeError:
        names = ", ".join(f.name for f in fields(MotorPlant))
        raise ValueError(f"motor parameters are {names}") from None
    return parameters

"""World settings as text, shared by command scripts (`@world ...`) and the REPL
(`:world ...`), so the machine around the board can be set up without Python.

    X limits 5000 -5000        plus and minus limit positions (physical steps; none = no switch)
    X plus-limit none          one side only
    X home 200 260             the home switch is active from 200 to 260 (home none: none)
    X index 4000 4 1280        index marks: period, width, offset
    X fault plus active        stick a switch (plus, minus, home) active/inactive; none clears
    X bounce home 3            the switch chatters within 3 steps of its edges (0: clean)
    X backlash 25              the stage has 25 steps of play (a stepper; BC compensates)
    X capture home both        capture on home edges: rising, falling, both or off
    X capture index on         capture on every index mark (on/off)
    X capture inputs 0x5 0x4   capture on rising / falling edges of these input bits
    input 3 high               a general purpose input (high/low/1/0)
    analog 0 2.5               an analog input in volts
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import fields
from typing import Any

from maxk.firmware_model.motor import MotorPlant
from maxk.firmware_model.world import SWITCHES
from maxk.personalities.maxk.capture import EDGES

MAXk = Any
"""The controller a setting applies to: a `maxk.controllers.maxk.MAXk` (its world API:
set_limits, set_home, fault, capture, set_input...). Not imported here: the controller's
console imports this module."""

Setting = Callable[[MAXk], str]


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


def parse_world(text: str) -> Setting:
    """Check a world setting's words now; return what applies it to a board later."""
    words = text.split()
    if not words:
        raise ValueError("say what to set, e.g. 'X limits 5000 -5000' or 'input 3 high'")
    head = words[0].lower()
    if head == "input":
        if len(words) != 3 or words[2].lower() not in ("high", "low", "1", "0"):
            raise ValueError("input BIT high|low")
        bit = _int(words[1], "a bit number")
        if not 0 <= bit <= 15:
            raise ValueError("input bits are 0..15")
        level = words[2].lower() in ("high", "1")
        return lambda b: (b.set_input(bit, level), f"input {bit} {'high' if level else 'low'}")[1]
    if head == "analog":
        if len(words) != 3:
            raise ValueError("analog CHANNEL VOLTS")
        channel = _int(words[1], "a channel")
        try:
            volts = float(words[2])
        except ValueError:
            raise ValueError(f"not volts: {words[2]!r}") from None
        if not 0 <= channel <= 3:
            raise ValueError("analog inputs are 0..3")
        return lambda b: (b.set_analog(channel, volts), f"analog {channel} {volts:g} V")[1]
    if len(head) != 1 or not head.isalpha() or len(words) < 2:
        raise ValueError(f"cannot read {text!r}: start with an axis letter, 'input' or "
                         "'analog'")
    letter = head.upper()
    what = words[1].lower()
    args = words[2:]
    if what == "limits" and len(args) == 2:
        plus, minus = _position(args[0]), _position(args[1])
        return lambda b: (b.set_limits(letter, plus=plus, minus=minus),
                          f"{letter} limits {args[0]} {args[1]}")[1]
    if what in ("plus-limit", "minus-limit") and len(args) == 1:
        pos = _position(args[0])
        key = "plus" if what == "plus-limit" else "minus"
        return lambda b: (b.set_limits(letter, **{key: pos}), f"{letter} {what} {args[0]}")[1]
    if what == "home" and args and (len(args) == 2 or args == ["none"]):
        low, high = (None, None) if args == ["none"] else (_position(args[0]),
                                                         _position(args[1]))
        return lambda b: (b.set_home(letter, low, high), f"{letter} home {' '.join(args)}")[1]
    if what == "index" and len(args) == 3:
        period, width, offset = (_int(a, "a count") for a in args)
        return lambda b: (b.set_index(letter, period, width, offset),
                          f"{letter} index {period} {width} {offset}")[1]
    if what == "fault" and len(args) == 2 and args[0].lower() in SWITCHES:
        state = None if args[1].lower() == "none" else args[1].lower()
        if state not in (None, "active", "inactive"):
            raise ValueError("fault SWITCH active|inactive|none")
        switch = args[0].lower()
        return lambda b: (b.fault(letter, switch, state), f"{letter} fault {switch} {state}")[1]
    if what == "bounce" and len(args) == 2 and args[0].lower() in SWITCHES:
        steps = _int(args[1], "a number of steps")
        switch = args[0].lower()
        return lambda b: (b.bounce(letter, switch, steps), f"{letter} bounce {switch} {steps}")[1]
    if what == "miss" and len(args) == 1:
        steps = _int(args[0], "a number of steps")
        return lambda b: (b.miss_steps(letter, steps), f"{letter} miss {steps}")[1]
    if what == "backlash" and len(args) == 1:
        play = _int(args[0], "a number of steps")
        if play < 0:
            raise ValueError("backlash is a number of steps >= 0")
        return lambda b: (b.set_backlash(letter, play), f"{letter} backlash {play}")[1]
    if what == "motor" and args:
        parameters: dict[str, object] = {}
        for arg in args:
            key, _, value = arg.partition("=")
            if not value:
                raise ValueError("motor NAME=VALUE ... (e.g. motor inertia=1e-5 "
                                 "amplifier=current)")
            parameters[key.replace("-", "_")] = value if key == "amplifier" else float(value)
        if "encoder_lines" in parameters:
            parameters["encoder_lines"] = int(parameters["encoder_lines"])  # type: ignore
        try:
            MotorPlant(**parameters)  # type: ignore[arg-type]
        except TypeError:
            names = ", ".join(f.name for f in fields(MotorPlant))
            raise ValueError(f"motor parameters are {names}") from None
        return lambda b: (b.set_motor(letter, **parameters),
                          f"{letter} motor {' '.join(args)}")[1]
    if what == "capture" and args:
        return _capture(letter, args)
    raise ValueError(f"cannot read {text!r}; see docs/io.md for the world settings")


def _capture(letter: str, args: list[str]) -> Setting:
    kind = args[0].lower()

    def config(b: MAXk):  # type: ignore[no-untyped-def]
        return b.board.capture_config[b.board.axis(letter).index]

    def setter(attr: str, value: object, said: str) -> Setting:
        def apply(b: MAXk) -> str:
            setattr(config(b), attr, value)
            b.board.world_changed()  # a running motion now looks for these edges too
            return said

        return apply

    if kind == "home" and len(args) == 2 and args[1].lower() in (*EDGES, "off"):
        edge = None if args[1].lower() == "off" else args[1].lower()
        return setter("home", edge, f"{letter} capture home {args[1]}")
    if kind == "index" and len(args) == 2 and args[1].lower() in ("on", "off"):
        return setter("index", args[1].lower() == "on", f"{letter} capture index {args[1]}")
    if kind == "inputs" and len(args) == 3:
        rising, falling = _int(args[1], "a bit mask"), _int(args[2], "a bit mask")

        def apply(b: MAXk) -> str:
            b.capture(letter, inputs_rising=rising, inputs_falling=falling)
            return f"{letter} capture inputs {args[1]} {args[2]}"

        return apply
    raise ValueError("capture home rising|falling|both|off, capture index on|off, "
                     "or capture inputs RISING_MASK FALLING_MASK")


def describe_world(board: MAXk) -> list[str]:
    """The REPL's `:world`: every axis's stage and the inputs."""
    b = board.board
    lines = []
    for axis, stage, cap in zip(b.axes, b.world.axes, b.capture_config, strict=True):
        def side(switch, edge):  # type: ignore[no-untyped-def]
            where = "none" if edge is None else f"{edge:.0f}"
            return where + (f" (stuck {switch.fault})" if switch.fault else "")

        home = stage.home

        def at(x):  # type: ignore[no-untyped-def]
            return "none" if x is None else f"{x:.0f}"

        home_text = "none" if not home.present else f"{at(home.low)}..{at(home.high)}"
        if home.fault:
            home_text += f" (stuck {home.fault})"
        capture = []
        if cap.home:
            capture.append(f"home {cap.home}")
        if cap.index:
            capture.append("index")
        if cap.on_inputs:
            capture.append(f"inputs {cap.io_rising:#x}/{cap.io_falling:#x}")
        plus = side(stage.plus_limit, stage.plus_limit.low)
        minus = side(stage.minus_limit, stage.minus_limit.high)
        lines.append(
            f"{axis.letter}: at {axis.steps_now(b)} steps; limits {plus} / {minus}; "
            f"home {home_text}; index every {stage.index_period} from {stage.index_offset}"
            + (f"; backlash {stage.backlash}" if stage.backlash else "")
            + (f"; capture {', '.join(capture)}" if capture else ""))
    inputs = "".join("1" if b.world.digital_level(i, b) else "0" for i in range(15, -1, -1))
    lines.append(f"inputs (15..0): {inputs}; analog: " + ", ".join(
        f"{b.world.analog_volts(c, b):g} V" for c in range(4)))
    lines.append(f"capture ring: {len(b.capture_ring)} waiting, {b.capture_ring.lost} lost")
    return lines

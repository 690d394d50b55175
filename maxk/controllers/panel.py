"""What a front panel shows of a controller beyond the world contract: each kind's own
picture (the MM4005's pulses along its XY path, the MC405's PWM marks, the PoKeys slot
buffer). Read from what each controller already exposes; plain data (JSON-able), small
and bounded, asked 10-20 times a second by the control door's panel."""

from __future__ import annotations

from typing import Any

PULSES_SHOWN = 200  # the newest MM4005 path pulses in one picture


def panel_extras(controller: Any) -> dict[str, Any]:
    """The kind's own picture; {} for a kind that has none."""
    picture = _PICTURES.get(controller.kind)
    return {} if picture is None else picture(controller)


def _mm4005(controller: Any) -> dict[str, Any]:
    """Axes 1 and 2 are the XY path; the synchronized pulses where they fired."""
    pulses = controller.pulses
    shown = pulses[-PULSES_SHOWN:]
    return {"xy": ["1", "2"], "pulses": len(pulses),
            "pulse_points": [[p.x_counts, p.y_counts] for p in shown]}


def _mc405(controller: Any) -> dict[str, Any]:
    """The PWM outputs' marks now: the fraction of each period they are on."""
    machine = controller.machine
    bank = machine.outputs.bank
    return {"pwm": {str(axis): round(machine.duty(axis), 4) for axis in bank.outputs}}


def _pokeys(controller: Any) -> dict[str, Any]:
    """The pulse engine's slot buffer: how full it is."""
    buffer = controller.pulse_engine.buffer
    return {"buffer": {"count": int(buffer.count), "depth": int(buffer.depth)}}


_PICTURES = {"MM4005": _mm4005, "MC405": _mc405, "PoKeys": _pokeys}

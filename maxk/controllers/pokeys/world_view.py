"""The PoKeys's world behind the world contract (controllers/world_view.py): its axes by
the names its configuration software gives them, its pins as inputs and outputs, the
analog pins, encoders wired to axes, and its trace columns."""

from __future__ import annotations

from maxk.controllers.pokeys.status import PoKeysControls, axis_index
from maxk.controllers.world_view import AxisReading, WorldView
from maxk.firmware_model.world import InputSource
from maxk.personalities.pokeys import AXIS_LETTERS
from maxk.personalities.pokeys.constants import SLOT_SECONDS
from maxk.personalities.pokeys.io import PINS


class PoKeysWorldView(WorldView):
    """The PoKeys's world behind the contract: axes X Y Z A B C U V (or 1..8) as the
    device's configuration software names them, positions in pulses; digital inputs by
    number as the pulse engine reads them (0 the e-stop, n probe input n; pins 1..55 on
    the 57 series; edges on a counter pin count), analog inputs on pins 41..47 (0..3.3 V),
    the digital outputs' levels."""

    def __init__(self, dev: PoKeysControls) -> None:
        super().__init__(dev.world, AXIS_LETTERS[:dev.axes], inputs=range(56),
                         analog=range(41, 48), analog_volts=(0.0, 3.3),
                         changed=dev.device.machine.world_changed,
                         source_owner=dev.device.machine)
        self.dev = dev

    def set_input(self, number: int, level: bool | InputSource) -> None:
        if number not in self.inputs:
            raise ValueError(f"no input {number} (0 the e-stop, pins 1..55)")
        self.dev.device.pins.set_input(number, level)

    def output_level(self, number: int) -> bool | None:
        if not 1 <= number <= PINS or not self.dev.device.io.is_output(number):
            return None
        return self.dev.device.io.output_level(number)

    def extra_setting(self, name: str | None, words: list[str]) -> str | None:
        """`@world X encoder N [reverse]`: encoder N (0..25) counts axis X's stage."""
        if name is None or not words or words[0].lower() != "encoder":
            return None
        args = [w.lower() for w in words[1:]]
        if not 1 <= len(args) <= 2 or args[1:] not in ([], ["reverse"]):
            raise ValueError("encoder N [reverse] (N 0..25)")
        try:
            number = int(args[0])
        except ValueError:
            raise ValueError(f"encoder N [reverse]: {args[0][:12]!r} is no number") from None
        axis = self.index(name)
        self.dev.device.pins.attach_encoder(number, axis, -1 if args[1:] else 1)
        return f"{AXIS_LETTERS[axis]} encoder {number}{' reverse' if args[1:] else ''}"

    def describe(self) -> list[str]:
        """`:world`: the stages and inputs, then what the device drives and what the
        world wires to it (outputs, PWM, encoders, keys)."""
        device = self.dev.device
        lines = super().describe()
        outputs = device.pins.output_levels()
        if outputs:
            lines.append("outputs " + " ".join(f"{p} {'high' if v else 'low'}"
                                               for p, v in outputs.items()))
        for n in range(6):
            if device.io.pwm_enabled >> n & 1:
                lines.append(f"pwm {n} (pin {22 - n}) {device.pwm_output(n) * 100:.1f}%")
        for i, e in enumerate(device.io.encoders):
            if e.axis is not None:
                lines.append(f"encoder {i} on {AXIS_LETTERS[e.axis]}"
                             f"{' reversed' if e.direction < 0 else ''}: "
                             f"{device.pins.encoder_value(i)}")
        if device.io.matrix_keys:
            lines.append("matrix keys pressed " + " ".join(map(str, sorted(
                device.io.matrix_keys))))
        if device.io.kbd48.keys:
            lines.append("kbd48CNC keys pressed " + " ".join(map(str, sorted(
                device.io.kbd48.keys))))
        return lines

    def trace_columns(self) -> list[str]:
        """The output pins as a bit mask (bit p-1 = pin p) and each PWM channel's duty."""
        return ["outputs"] + [f"pwm{n}_duty" for n in range(6)]

    def trace_values(self) -> list[object]:
        device = self.dev.device
        mask = sum(1 << (p - 1) for p, level in device.pins.output_levels().items() if level)
        values: list[object] = [f"{mask:014x}"]
        return values + [f"{device.pwm_output(n) * 100:.2f}" for n in range(6)]

    def index(self, name: str) -> int:
        try:
            return axis_index(str(name).strip(), self.dev.axes)
        except ValueError as error:
            raise KeyError(str(error)) from None

    def reading(self, name: str) -> AxisReading:
        i = self.index(name)
        engine = self.dev.pulse_engine
        a = engine.axes[i]
        moving = engine.moving(a)
        state = engine.axis_state(a)
        velocity = 0.0
        planned = engine.motion_plan(i)
        if moving and planned is not None:  # pulses a slot, as counts per second
            t = (engine.slot - planned.start) * SLOT_SECONDS
            velocity = planned.plan.velocity(t)
        return AxisReading(AXIS_LETTERS[i], a.position, None, velocity, not moving, moving,
                           (state.name.lower(),))

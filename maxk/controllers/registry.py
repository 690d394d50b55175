"""Every controller `maxk` can be: found by model name (`--model MAXk-8000,MC405`)."""

from __future__ import annotations

from pathlib import Path

from maxk.controllers import pokeys
from maxk.controllers.contract import BuildOptions, Controller, ControllerKind
from maxk.controllers.maxk import MAXk
from maxk.controllers.mm4005 import MODELS as MM4005_MODELS
from maxk.controllers.mm4005 import MM4005Controller
from maxk.personalities.maxk.models import MODELS, model_by_name
from maxk.personalities.maxk.parameters import default_archive_dir, default_archive_path


def _build_maxk(model: str, options: BuildOptions) -> Controller:
    from maxk.commands.max.session import Framing

    kwargs = {} if options.update_rate_hz is None else {"update_rate_hz":
                                                         options.update_rate_hz}
    controller = MAXk(model, archive=options.archive, board_number=options.number, **kwargs)
    controller.framing = Framing.from_options(options.line_options)
    return controller


def _build_mm4005(model: str, options: BuildOptions) -> Controller:
    return MM4005Controller(model)  # nothing of BuildOptions applies (no flash modelled)


def _build_mc405(model: str, options: BuildOptions) -> Controller:
    from maxk.controllers.trio import MC405, SERVO_RATES_HZ

    # a rate it cannot run (the scripts plugin passes the MAXk's 8192 Hz to every board)
    # leaves the MC405 at its own 1000 us servo period, as the MM4005 keeps its own
    rate = options.update_rate_hz if options.update_rate_hz in SERVO_RATES_HZ else None
    return MC405(archive=options.archive, update_rate_hz=rate)


def _mc405_programs(model: str, number: int) -> Path:
    """The MC405's program directory (its flash) per user, beside the MAXk archives."""
    return default_archive_dir() / f"{model}-board{number}.programs"


KINDS: tuple[ControllerKind, ...] = (
    ControllerKind("MAXk", tuple(MODELS), _build_maxk,
                   "OMS MAXk (and MAX family) PCI motion controller, 1-10 axes",
                   default_archive_path),
    ControllerKind("MM4005", MM4005_MODELS, _build_mm4005,
                   "Newport MM4005 4-axis controller with trajectories and synchronized "
                   "pulses (MM4005-n: n axes installed)"),
    ControllerKind("MC405", ("MC405",), _build_mc405,
                   "Trio MC405 Motion Coordinator: TrioBASIC over telnet, PWM outputs",
                   _mc405_programs),
    ControllerKind("PoKeys", tuple(pokeys.MODELS), pokeys.build,
                   "PoLabs PoKeys56E (pulse engine v1) and PoKeys57E/57CNC (v2), "
                   "64-byte requests over TCP and UDP"),
)


def kind_of(model: str) -> ControllerKind:
    """The kind a model name belongs to (case-insensitive), or ValueError naming them."""
    for kind in KINDS:
        if kind.name == "MAXk":
            try:
                model_by_name(model)
            except ValueError:
                continue
            return kind
        if model.lower() in (m.lower() for m in kind.models):
            return kind
    known = ", ".join(m for kind in KINDS for m in kind.models)
    raise ValueError(f"unknown controller model {model!r} (models: {known})")


def canonical_model(model: str) -> str:
    """The model's name as its kind spells it."""
    kind = kind_of(model)
    if kind.name == "MAXk":
        return model_by_name(model).name
    return next(m for m in kind.models if m.lower() == model.lower())


def default_archive(model: str, number: int = 1) -> str | None:
    """The per-user flash file of a controller (None: that kind keeps nothing)."""
    kind = kind_of(model)
    if kind.default_archive is None:
        return None
    return str(kind.default_archive(canonical_model(model), number))


def build(model: str, options: BuildOptions | None = None) -> Controller:
    """A controller of that model, powered up."""
    name = canonical_model(model)
    return kind_of(name).build(name, options or BuildOptions())

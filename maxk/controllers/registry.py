"""Every controller `maxk` can be: found by model name (`--model MAXk-8000,MC405`)."""

from __future__ import annotations

from pathlib import Path

from maxk.commands.max.session import EOLS, FRAMINGS
from maxk.controllers.contract import BuildOptions, Controller, ControllerKind
from maxk.controllers.maxk.controller import MAXk
from maxk.controllers.mm4005.controller import MODELS as MM4005_MODELS
from maxk.controllers.mm4005.controller import MM4005Controller
from maxk.controllers.pokeys import controller as pokeys
from maxk.personalities.maxk.models import DEFAULT_MODEL as MAXK_DEFAULT
from maxk.personalities.maxk.models import (
    DEFAULT_UPDATE_RATE_HZ,
    MODELS,
    UPDATE_RATES_HZ,
    model_by_name,
)
from maxk.personalities.maxk.parameters import default_archive_dir, default_archive_path
from maxk.personalities.mm4005.machine import UPDATE_RATE_HZ as MM4005_RATE_HZ


def _build_maxk(model: str, options: BuildOptions) -> Controller:
    from maxk.commands.max.session import Framing

    kwargs = {} if options.update_rate_hz is None else {"update_rate_hz":
                                                         options.update_rate_hz}
    controller = MAXk(model, archive=options.archive, board_number=options.number, **kwargs)
    controller.framing = Framing.from_options(options.line_options)
    return controller


def _build_mm4005(model: str, options: BuildOptions) -> Controller:
    return MM4005Controller(model, archive=options.archive)  # one servo rate


def _build_mc405(model: str, options: BuildOptions) -> Controller:
    from maxk.controllers.trio.controller import MC405

    return MC405(archive=options.archive, update_rate_hz=options.update_rate_hz)


def _max_reference() -> str:
    from maxk.commands.max.reference import render_markdown

    return render_markdown()


def _mc405_programs(model: str, number: int) -> Path:
    """The MC405's program directory (its flash) per user, beside the MAXk archives."""
    return default_archive_dir() / f"{model}-board{number}.programs"


def _mm4005_programs(model: str, number: int) -> Path:
    """The MM4005's stored programs (its non-volatile program memory) per user."""
    return default_archive_dir() / f"{model}-board{number}.programs.json"


def _pokeys_configuration(model: str, number: int) -> Path:
    """A PoKeys's saved configuration (its flash) per user, beside the MAXk archives."""
    return default_archive_dir() / f"{model}-board{number}.pokeys.json"


KINDS: list[ControllerKind] = [
    ControllerKind("MAXk", tuple(MODELS), _build_maxk,
                   "OMS MAXk (and MAX family) PCI motion controller, 1-10 axes",
                   default_archive_path,
                   update_rates_hz=(DEFAULT_UPDATE_RATE_HZ,
                                    *(r for r in UPDATE_RATES_HZ
                                      if r != DEFAULT_UPDATE_RATE_HZ)),
                   line_options={"eol": tuple(sorted(EOLS)), "ack": (),
                                 "framing": FRAMINGS},
                   shared_memory=True, reference=_max_reference),
    ControllerKind("MM4005", MM4005_MODELS, _build_mm4005,
                   "Newport MM4005 4-axis controller with trajectories and synchronized "
                   "pulses (MM4005-n: n axes installed)", _mm4005_programs,
                   update_rates_hz=(MM4005_RATE_HZ,)),
    ControllerKind("MC405", ("MC405",), _build_mc405,
                   "Trio MC405 Motion Coordinator: TrioBASIC over telnet, PWM outputs",
                   _mc405_programs, update_rates_hz=(1000, 500, 2000, 4000),
                   default_port=23),  # atrio dials telnet's port
    ControllerKind("PoKeys", tuple(pokeys.MODELS), pokeys.build,
                   "PoLabs PoKeys56E (pulse engine v1) and PoKeys57E/57CNC (v2), "
                   "64-byte requests over TCP and UDP", _pokeys_configuration,
                   update_rates_hz=(1000,), default_port=20055),  # PoKeysLib's port
]


DEFAULT_MODEL = MAXK_DEFAULT
"""What the REPL, scripts and `serve` start without `--model`."""


def _spelled(model: str) -> str:
    """A MAXk model as its family spells it (`maxk8000`, `MAX-8000`...), else as given."""
    try:
        return model_by_name(model).name
    except ValueError:
        return model


def kind_of(model: str) -> ControllerKind:
    """The kind a model name belongs to (case-insensitive), or ValueError naming them."""
    name = _spelled(model).lower()
    for kind in KINDS:
        if name in (m.lower() for m in kind.models):
            return kind
    known = ", ".join(m for kind in KINDS for m in kind.models)
    raise ValueError(f"unknown controller model {model!r} (models: {known})")


def canonical_model(model: str) -> str:
    """The model's name as its kind spells it."""
    name = _spelled(model)
    return next(m for m in kind_of(name).models if m.lower() == name.lower())


def register(kind: ControllerKind) -> None:
    """Add a kind of controller (a plug-in, a test's own): every door takes its models
    from here on. Its model names must be new."""
    taken = {m.lower() for k in KINDS for m in k.models}
    clash = [m for m in kind.models if m.lower() in taken]
    if clash or any(k.name == kind.name for k in KINDS):
        raise ValueError(f"{kind.name}: the kind or model {clash[:1] or [kind.name]} is "
                         "taken")
    KINDS.append(kind)


def unregister(name: str) -> None:
    """Take a kind out again (a test cleaning up)."""
    KINDS[:] = [k for k in KINDS if k.name != name]


def line_option_choices(option: str) -> list[str]:
    """The values a `serve` line option takes, over every kind that has it."""
    return sorted({c for kind in KINDS for c in kind.line_options.get(option, ())})


def default_archive(model: str, number: int = 1) -> str | None:
    """The per-user flash file of a controller (None: that kind keeps nothing)."""
    kind = kind_of(model)
    if kind.default_archive is None:
        return None
    return str(kind.default_archive(canonical_model(model), number))


def build(model: str, options: BuildOptions | None = None) -> Controller:
    """A controller of that model, powered up; ValueError for a rate or a line option
    it does not have."""
    name = canonical_model(model)
    kind = kind_of(name)
    options = options or BuildOptions()
    kind.check_rate(options.update_rate_hz)
    unknown = sorted(set(options.line_options) - set(kind.line_options))
    if unknown:
        raise ValueError(f"the {kind.name} has no line option {unknown[0]!r}")
    return kind.build(name, options)

"""docs/commands.md, generated from the command table (`maxk commands --markdown`)."""

from __future__ import annotations

from maxk.commands.max.table import (
    COMMANDS,
    GROUP_TITLES,
    LINE_DISCIPLINE,
    CommandSpec,
    Timing,
)

_CONFIDENCE = {
    "C": "certain (manual or host code)",
    "I": "inferred from host code",
    "D": "our decision",
}


def _modes(spec: CommandSpec) -> str:
    order = [("single", "AX..AK"), ("AA", "AA"), ("AM", "AM")]
    return ", ".join(name for key, name in order if key in spec.modes)


def _timing(spec: CommandSpec) -> str:
    if spec.timing is Timing.QUEUED:
        return f"queued ({spec.units} unit{'s' if spec.units != 1 else ''})"
    return spec.timing.value


def _number(x: float) -> str:
    return f"{int(x):,}" if float(x).is_integer() else f"{x:,}"


def help_text(spec: CommandSpec) -> str:
    """The REPL's `help XX` text."""
    lines = [
        f"{spec.syntax}  —  {spec.summary}",
        f"  timing: {_timing(spec)}; modes: {_modes(spec)}",
    ]
    if spec.reply:
        lines.append(f"  reply: {spec.reply}")
    if spec.value_range is not None:
        lo, hi = spec.value_range
        lines.append(f"  range: {_number(lo)} to {_number(hi)}")
    lines.append(f"  source: {spec.source}; confidence: {_CONFIDENCE[spec.confidence]}")
    if spec.notes:
        lines.append(f"  notes: {spec.notes}")
    return "\n".join(lines)


def render_markdown() -> str:
    out = [
        "# MAXk command reference (as emulated)",
        "",
        "Generated from `maxk/commands/table.py` by `maxk commands --markdown`; do not edit by",
        "hand. Confidence: **C** certain (the MAXk manual or host code seen literally),",
        "**I** inferred from how host code uses the command, **D** our decision where neither",
        "settles it (the notes say why). Queue units are charged per addressed axis out of",
        "2559. `#` is a signed decimal operand; in AA/AM modes it is a comma list, one slot",
        "per axis in the order X Y Z T U V R S W K, an empty slot leaving that axis alone.",
        "",
    ]
    out += ["## The line discipline", "",
            "How the byte stream is read, for every host form (issue 40).", "",
            "| what | behaviour | source | conf. |", "|---|---|---|---|"]
    for what, behaviour, source, confidence in LINE_DISCIPLINE:
        out.append(f"| {what} | {behaviour} | {source} | {confidence} |")
    out.append("")
    for group, title in GROUP_TITLES.items():
        specs = [s for s in COMMANDS.values() if s.group == group]
        if not specs:
            continue
        out += [f"## {title}", "",
                "| command | what it does | timing | modes | reply | source | conf. |",
                "|---|---|---|---|---|---|---|"]
        for spec in specs:
            reply = f"`{spec.reply}`" if spec.reply else ""
            out.append(
                f"| `{spec.syntax}` | {spec.summary} | {_timing(spec)} | {_modes(spec)} | "
                f"{reply} | {spec.source} | {spec.confidence} |"
            )
        notes = [s for s in specs if s.notes]
        if notes:
            out.append("")
            for spec in notes:
                out.append(f"- **{spec.mnemonic}** ({spec.confidence}): {spec.notes}")
        out.append("")
    return "\n".join(out).rstrip() + "\n"

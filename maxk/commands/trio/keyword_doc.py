"""The keyword table of docs/trio.md, written from keywords.py: the table is the single
source of truth, so the page is generated from it (and a test holds the two equal).

`python3 -m maxk.commands.trio.keyword_doc docs/trio.md` rewrites the page's table.
"""

from __future__ import annotations

import sys
from pathlib import Path

from .keywords import KEYWORDS

HEADER = ("| keyword | kind | what the emulator does | source | conf. |\n"
          "|---|---|---|---|---|\n")


def row(name: str) -> str:
    """One keyword's line: its summary, then its note (how the emulator takes it)."""
    k = KEYWORDS[name]
    text = f"{k.summary} {k.note}".strip() if k.note else k.summary
    text = text.replace("|", "\\|")
    return f"| `{name}` | {k.kind.value} | {text} | {k.source} | {k.confidence} |"


def table() -> str:
    return HEADER + "".join(row(name) + "\n" for name in sorted(KEYWORDS))


def rewrite(page: Path) -> None:
    """Replace the table that starts at HEADER with the generated one."""
    text = page.read_text()
    start = text.index(HEADER)
    end = start + len(HEADER)
    lines = text[end:].split("\n")
    taken = 0
    while taken < len(lines) and lines[taken].startswith("| `"):
        taken += 1
    rest = "\n".join(lines[taken:])
    page.write_text(text[:start] + table() + rest)


if __name__ == "__main__":
    rewrite(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/trio.md"))

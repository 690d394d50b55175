"""The keyword table of docs/trio.md, written from keywords.py: the table is the single
source of truth, so the page is generated from it (and a test holds the two equal).

`python3 -m maxk.commands.trio.keyword_doc docs/trio.md` rewrites the page's table.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..tables import rewrite_table
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


if __name__ == "__main__":
    rewrite_table(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/trio.md"), HEADER, table(),
                  '| `')

"""The request table of docs/pokeys.md, written from table.py: the table is the single
source of truth, so the page is generated from it (and a test holds the two equal).
Every request the emulator knows is a row; the last rows say what every other request
gets (the refusal) and which frames get nothing.

`python3 -m maxk.commands.pokeys.table_doc docs/pokeys.md` rewrites the page's table.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..tables import rewrite_table
from .packet import REFUSED, UNKNOWN
from .table import ANY, ENTRIES, CommandEntry

HEADER = ("| request | name | what the emulator does | source | conf. |\n"
          "|---|---|---|---|---|\n")

OTHERS = (
    ("any other command or sub-command", "(none)",
     f"Refused: the header echoed, [2] = 0x{UNKNOWN:02X}, payload zero; a fill's refusal "
     "is 0 accepted. So are 0x80 on a pulse engine v2 device and 0x85/0xB0 on a v1 one.",
     "decision", "D"),
    ("a request a handler refuses", "(every row)",
     f"Refused: [2] = 0x{REFUSED:02X} (a parameter out of range, a pin without the "
     "capability), payload zero, nothing changed; fills answer 0 accepted.",
     "decision", "D"),
    ("a frame of another length, header or checksum", "(none)",
     "Silent: the device cannot take it as a request (reference 3). Also silent: a 0xB0 "
     "frame before its group's last.", "reference 3", "C"),
)


def key(entry: CommandEntry) -> str:
    if entry.sub == ANY:
        return f"0x{entry.command:02X}"
    return f"0x{entry.command:02X} 0x{entry.sub:02X}"


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def row(entry: CommandEntry) -> str:
    return (f"| `{key(entry)}` | {_cell(entry.name)} | {_cell(entry.note) or '-'} | "
            f"{_cell(entry.source)} | {entry.confidence} |")


def table() -> str:
    entries = sorted(ENTRIES, key=lambda e: (e.command, e.sub))
    rows = [row(e) for e in entries]
    rows += [f"| ({what}) | {name} | {_cell(does)} | {source} | {conf} |"
             for what, name, does, source, conf in OTHERS]
    return HEADER + "".join(r + "\n" for r in rows)


if __name__ == "__main__":
    rewrite_table(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/pokeys.md"), HEADER, table(),
                  '| ')

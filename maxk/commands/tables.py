"""What every language's table shares: one entry per name, a duplicate refused at import.

A table built with a dict comprehension keeps the last of two entries with one name and
says nothing; `unique_table` says which name came twice, so a table stays the single
source of truth it claims to be."""

from __future__ import annotations

from collections.abc import Callable, Hashable, Iterable
from pathlib import Path
from typing import TypeVar

Entry = TypeVar("Entry")
Key = TypeVar("Key", bound=Hashable)


class TableError(Exception):
    """A language's table is not well formed (found at import)."""


def unique_table(entries: Iterable[Entry], key: Callable[[Entry], Key],
                 what: str = "table") -> dict[Key, Entry]:
    table: dict[Key, Entry] = {}
    for entry in entries:
        name = key(entry)
        if name in table:
            raise TableError(f"{what}: {name!r} is listed twice")
        table[name] = entry
    return table


def rewrite_table(page: Path, header: str, table: str, row_start: str = "| ") -> None:
    """Put a generated Markdown table into its page: the rows after `header` (lines
    starting with `row_start`) are replaced by `table`; a page without the header gets the
    table at its end. The one way a language's generated reference is kept true."""
    text = page.read_text()
    if header not in text:
        page.write_text(text.rstrip("\n") + "\n\n" + table)
        return
    start = text.index(header)
    lines = text[start + len(header):].split("\n")
    taken = 0
    while taken < len(lines) and lines[taken].startswith(row_start):
        taken += 1
    page.write_text(text[:start] + table + "\n".join(lines[taken:]))

"""EXIT_LOOP and CONTINUE, linked at COMPILE into jumps of the innermost loop.

Their help pages: EXIT_LOOP leaves the WHILE, FOR or REPEAT loop it is in, CONTINUE goes
on with the loop's next pass. The compiler (tasks.py) has already checked the blocks'
structure; this pass gives each of the two words its jump target.
"""

from __future__ import annotations

from .lexer import TrioError
from .parser import Command, For, Next, Repeat, Stmt, Until, Wend, While


def loop_jump(stmt: Stmt) -> str | None:
    """EXIT_LOOP or CONTINUE, else None."""
    if isinstance(stmt, Command) and stmt.keyword.name in ("EXIT_LOOP", "CONTINUE"):
        return stmt.keyword.name
    return None


def link_loop_jumps(steps: list[tuple[int, Stmt]], targets: dict[int, int]) -> None:
    """Each EXIT_LOOP goes on after its loop's closing step (WEND, NEXT, UNTIL); each
    CONTINUE goes to that step, so it decides the next pass as at the end of the body
    (I: help pages EXIT_LOOP, CONTINUE; UNTIL's condition is tested, D). Outside any
    loop either word is a "Structure error" on its line (D: as a WEND alone)."""
    open_loops: list[list[tuple[int, str]]] = []  # each open loop's words so far
    for index, (line, stmt) in enumerate(steps):
        word = loop_jump(stmt)
        if isinstance(stmt, (While, Repeat, For)):
            open_loops.append([])
        elif isinstance(stmt, (Wend, Until, Next)):
            for step, name in open_loops.pop():
                targets[step] = index + 1 if name == "EXIT_LOOP" else index
        elif word is not None:
            if not open_loops:
                raise TrioError("Structure error", line)
            open_loops[-1].append((index, word))

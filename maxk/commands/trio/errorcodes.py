"""RUN_ERROR's numbers: each error text the emulator gives, numbered as the RUN_ERROR help
page numbers the controller's errors.

The page lists the controller's error numbers (9 is a divide by zero, 19 a parameter out of
range, 31 a program that stopped normally). Our texts are the emulator's own wording where
the page has none, so each entry says how its number was chosen: C the page gives this error
that number, I the page's error of the same meaning, D our decision (no error of that
meaning on the page; the nearest one). Source: TrioBASIC help RUN_ERROR.
"""

from __future__ import annotations

PROGRAM_STOPPED = 31  # "Program is stopped": a program that ended, STOP or HALT (page: C)

# text -> (number, confidence, why where not C)
RUN_ERRORS: dict[str, tuple[int, str]] = {
    "Syntax error": (1, "D"),  # the page's "Command not recognised"
    "Stack overflow": (7, "C"),
    "Divide by zero": (9, "C"),
    "Parameter out of range": (19, "C"),
    "Invalid axis number": (19, "D"),  # an axis outside the controller: out of range
    "Axis not enabled": (19, "D"),
    "Axis in error": (19, "D"),
    "Array index out of range": (19, "D"),
    "VR index out of range": (19, "D"),
    "Parameter is read only": (21, "I"),  # "Value is read only"
    "Cannot assign to a constant": (21, "D"),
    "Program not found": (27, "C"),
    "Label already defined": (28, "I"),  # "Duplicate Identifier"
    "Program is running": (30, "I"),  # "Program(s) running"
    "Not enough memory": (35, "I"),  # "Out of memory"
    "Program too large": (35, "D"),
    "Function too long": (35, "D"),
    "Too many programs": (34, "I"),  # "No more programs available"
    "No free process": (20, "I"),  # "No process available"
    "Structure error": (39, "I"),  # "Structure nesting error"
    "RETURN without GOSUB": (50, "C"),
    "Label not found": (53, "C"),
    "Program already exists": (58, "C"),
    "Variable not defined": (64, "I"),  # "VARIABLE not found"
    "TABLE index out of range": (65, "I"),  # "Table index range error"
    "Invalid line number": (67, "C"),
    "String too long": (68, "I"),  # "String exceeds permitted length"
    "Expression too complex": (83, "I"),  # "Too many nested OPERANDS"
    "Invalid program name": (92, "C"),
    "Program type mismatch": (103, "D"),  # "Cannot specify program type for an existing"
    "Channel not open": (137, "I"),  # "File not open"
    "Channel already open": (139, "I"),  # "File already open"
    "Arithmetic error": (141, "I"),  # "Numerical error: Invalid Floating-Point operation"
    "Type mismatch": (148, "I"),  # "Invalid mix of data types"
    "Program cannot be run": (157, "I"),  # "Program is not an executable type"
    "Function cannot wait": (194, "I"),  # "Command not permitted in FUNCTION"
    "Process is busy": (273, "I"),  # "Process in use"
    "Line too long": (223, "I"),  # "Command line too long"
}
OTHER_ERROR = 62  # "Evaluation error": a text of the machine's not listed above (D)


def run_error(message: str) -> int:
    """RUN_ERROR's number for an error text (the page's numbering; OTHER_ERROR if none)."""
    entry = RUN_ERRORS.get(message)
    return entry[0] if entry is not None else OTHER_ERROR

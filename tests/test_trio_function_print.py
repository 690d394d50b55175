"""PRINT of a function's result as its page prints it (typed printing, printformat.py):
FREE (page: 47104.0000) and DLINK (page: 1.0000, 463.0000) are FLOAT, so a whole result
has 4 decimals; INT, ASC and ULPDIFF print bare, as their pages do."""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405


def test_free_prints_with_four_decimals_and_int_of_it_bare() -> None:
    trio = MC405()  # nothing stored: the whole 1 MiB of program memory (FREE's entry, D)
    assert trio.send("PRINT FREE") == ["1048576.0000"]
    assert trio.send("?INT(FREE)") == ["1048576"]
    trio.load("P", "VR(1) = 1")  # stored: less memory, still FLOAT
    assert trio.send("?FREE")[0].endswith(".0000")


@pytest.mark.parametrize(("expression", "printed"), [
    ("DLINK(2, 0, 0)", "0.0000"),  # no SLM module: FALSE, printed as the page's 1.0000
    ("DLINK(9, 2)", "-1.0000"),  # no SLM on axis 2
    ("INT(1.79)", "1"),
    ('ASC("A")', "65"),
    ("ULPDIFF(10.0, 10.00000001)", "5629500"),
    ("SQR(4)", "2.0000"),
])
def test_a_function_prints_as_its_page(expression: str, printed: str) -> None:
    assert MC405().send(f"PRINT {expression}") == [printed]

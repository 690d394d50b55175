"""VECTOR_MAG from its help page: the magnitude of a vector of 1 to 6 components."""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405


@pytest.fixture
def trio() -> MC405:
    return MC405()


def test_the_pages_examples(trio: MC405) -> None:
    assert trio.query("?VECTOR_MAG(PI)") == "3.1416"  # |pi|
    assert trio.query("?VECTOR_MAG(3, 4) = 5") == "-1"  # TRUE: 3-4-5
    assert trio.query("?VECTOR_MAG(3, 4, 12) = 13") == "-1"  # 9 + 16 + 144 = 169
    assert trio.query("?VECTOR_MAG(1, 2, 3, 4, 5, 6)") == "9.5394"  # sqrt(91)


def test_signs_do_not_matter_and_huge_components_do_not_overflow(trio: MC405) -> None:
    assert trio.query("?VECTOR_MAG(-3, -4) = 5") == "-1"
    assert trio.query("?ABS(VECTOR_MAG(3E200, 4E200) / 1E200 - 5) < 1E-9") == "-1"


def test_one_to_six_numbers_only(trio: MC405) -> None:
    assert trio.send("?VECTOR_MAG()") == ["! Syntax error"]
    assert trio.send("?VECTOR_MAG(1, 1, 1, 1, 1, 1, 1)") == ["! Syntax error"]
    assert trio.send('?VECTOR_MAG("a")') == ["! Type mismatch"]

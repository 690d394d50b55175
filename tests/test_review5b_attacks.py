"""Review 5b: hostile input on the merged debug, system, error and language words of the
MC405 (issue 35), each a reproducer of a defect found by attacking them."""

from __future__ import annotations

from maxk.controllers.trio import MC405

POWER_UP_ADDRESS = str((192 << 24) | (168 << 16) | (0 << 8) | 250)


def test_a_three_field_address_is_a_syntax_error_not_zero() -> None:
    """``IP_ADDRESS = 1.2.3`` (a mistyped address) was taken as bit 3 of 1.2, i.e. 0, and
    silently set the address to 0.0.0.0."""
    trio = MC405()
    assert trio.query("?IP_ADDRESS") == POWER_UP_ADDRESS
    assert trio.send("IP_ADDRESS = 1.2.3") == ["! Syntax error"]
    assert trio.send("IP_ADDRESS = 10.1.2.3.4") == ["! Syntax error"]
    assert trio.query("?IP_ADDRESS") == POWER_UP_ADDRESS  # nothing applied
    assert trio.send("IP_ADDRESS = 10.1.2.3") == []
    assert trio.query("?IP_ADDRESS") == str((10 << 24) | (1 << 16) | (2 << 8) | 3)


def test_a_bit_of_a_variable_still_reads() -> None:
    trio = MC405()
    trio.send("a = 6")
    assert trio.query("?a.1") == "1"
    assert trio.query("?a.0") == "0"
    assert trio.query("?(a).2") == "1"


def test_ethernet_refuses_a_function_the_page_does_not_list() -> None:
    """ETHERNET's function table is 0-15 and 21-25; 999 (or 17, or -4) was accepted and
    did nothing."""
    trio = MC405()
    for function in (999, 17, 26, -4):
        assert trio.send(f"ETHERNET(0, -1, {function})") == ["! Parameter out of range"]
        assert trio.send(f"ETHERNET(1, -1, {function}, 1)") == ["! Parameter out of range"]
    assert trio.send("ETHERNET(0, -1, 4)") == ["23"]  # a listed one still answers
    assert trio.send("ETHERNET(2, -1, 25)") == []  # restart services: accepted

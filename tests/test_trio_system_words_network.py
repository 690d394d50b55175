"""ETHERNET and the IP_ parameters (one setting, two ways to reach it), CLEAR_PARAMS and
the FLASH parameters across EX, FREE's program memory (their TrioBASIC help pages)."""

from __future__ import annotations

import pytest

from maxk.controllers.trio import MC405


def test_the_pages_example_reads_the_default_address_and_writes_a_new_one() -> None:
    trio = MC405()
    assert trio.send("ETHERNET(0, -1, 0)") == ["192.168.0.250"]  # the page's default
    assert trio.send("ETHERNET(1, -1, 0, 192, 168, 0, 201)") == []
    assert trio.send("ETHERNET(0, -1, 0)") == ["192.168.0.201"]
    # the same setting as IP_ADDRESS: 192 x 2^24 + 168 x 2^16 + 0 x 2^8 + 201
    assert trio.query("?IP_ADDRESS") == str(192 * 2**24 + 168 * 2**16 + 201)


def test_ip_address_written_dotted_is_what_ethernet_prints() -> None:
    trio = MC405()
    assert trio.send("IP_ADDRESS = 192.168.2.100") == []  # the IP_ADDRESS page's example 2
    assert trio.send("ETHERNET(0, -1, 0)") == ["192.168.2.100"]
    assert trio.send("IP_NETMASK = 255.255.128.0") == []
    assert trio.send("ETHERNET(0, -1, 2)") == ["255.255.128.0"]
    assert trio.send("IP_GATEWAY = 192.168.0.254") == []  # the IP_GATEWAY page's example
    assert trio.send("ETHERNET(0, -1, 8)") == ["192.168.0.254"]


def test_netmask_default_and_write() -> None:
    trio = MC405()
    assert trio.send("ETHERNET(0, -1, 2)") == ["255.255.255.0"]  # the page's default
    assert trio.send("ETHERNET(1, -1, 2, 255, 255, 128, 0)") == []
    assert trio.query("?IP_NETMASK") == str(2**32 - 2**15)  # 255.255.128.0


def test_the_mac_address_is_ip_mac_and_read_only() -> None:
    trio = MC405()
    # the IP_MAC page's example: 27648852217 is hexadecimal 6700000F9, 00:06:70:00:00:F9
    assert trio.query("?IP_MAC") == "27648852217"
    assert trio.query("?HEX(IP_MAC)") == "6700000F9"
    assert trio.send("ETHERNET(0, -1, 3)") == ["00:06:70:00:00:F9"]
    assert trio.send("ETHERNET(1, -1, 3, 1, 2, 3, 4, 5, 6)") == ["! Parameter is read only"]
    assert trio.send("IP_MAC = 5") == ["! Parameter is read only"]


@pytest.mark.parametrize(("function", "default", "new"), [(4, 23, 5023), (5, 3240, 3241),
                                                          (10, 502, 1502), (7, 0, 1),
                                                          (9, 0, 1)])
def test_ports_and_modbus_modes_read_back(function: int, default: int, new: int) -> None:
    trio = MC405()
    assert trio.send(f"ETHERNET(0, -1, {function})") == [str(default)]
    assert trio.send(f"ETHERNET(1, -1, {function}, {new})") == []
    assert trio.send(f"ETHERNET(0, -1, {function})") == [str(new)]


@pytest.mark.parametrize("line", ["ETHERNET(0, 0, 0)", "ETHERNET(3, -1, 0)",
                                  "ETHERNET(1, -1, 0, 192, 168, 0, 256)",
                                  "ETHERNET(1, -1, 0, 192, 168, 0)",
                                  "ETHERNET(0, -1, 6)", "ETHERNET(1, -1, 7, 3)",
                                  "ETHERNET(1, -1, 4, 1.5)"])
def test_bad_ethernet_calls_change_nothing(line: str) -> None:
    trio = MC405()
    assert trio.send(line) == ["! Parameter out of range"]
    assert trio.send("ETHERNET(0, -1, 0)") == ["192.168.0.250"]
    assert trio.send("ETHERNET(0, -1, 7)") == ["0"]


def test_flash_parameters_survive_ex_and_clear_params_resets_them() -> None:
    trio = MC405()
    for line in ("IP_ADDRESS = 10.0.0.7", "IP_GATEWAY = 10.0.0.1", "SERVO_PERIOD = 500",
                 "VR(1) = 3"):
        assert trio.send(line) == []
    trio.send("EX")
    assert trio.send("ETHERNET(0, -1, 0)") == ["10.0.0.7"]
    assert trio.send("ETHERNET(0, -1, 8)") == ["10.0.0.1"]
    assert trio.query("?SERVO_PERIOD") == "500"
    assert trio.machine.period == pytest.approx(500e-6)  # the new period took effect
    assert trio.send("CLEAR_PARAMS") == []
    assert trio.send("ETHERNET(0, -1, 0)") == ["192.168.0.250"]
    assert trio.send("ETHERNET(0, -1, 8)") == ["0.0.0.0"]
    assert trio.query("?SERVO_PERIOD") == "1000"
    assert trio.machine.period == pytest.approx(500e-6)  # until the next EX (page)
    trio.send("EX")
    assert trio.machine.period == pytest.approx(1000e-6)


def test_free_falls_by_what_dir_lists() -> None:
    trio = MC405()
    empty = int(trio.query("?FREE"))
    trio.load("P", "a = 1\nb = 2\nPRINT a + b")
    dir_lines = trio.send("DIR")
    row = next(line.split() for line in dir_lines if line.startswith("P "))
    source, code = int(row[1]), int(row[2])
    # the source: three lines of 5, 5 and 11 characters, each with its end of line
    assert source == 6 + 6 + 12
    assert code > 0  # compiled
    assert int(trio.query("?FREE")) == empty - source - code
    assert trio.send('DEL "P"') == []
    assert int(trio.query("?FREE")) == empty

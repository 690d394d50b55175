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
    empty = int(float(trio.query("?FREE")))
    trio.load("P", "a = 1\nb = 2\nPRINT a + b")
    dir_lines = trio.send("DIR")
    row = next(line.split() for line in dir_lines if line.startswith("P "))
    source, code = int(row[1]), int(row[2])
    # the source: three lines of 5, 5 and 11 characters, each with its end of line
    assert source == 6 + 6 + 12
    assert code > 0  # compiled
    assert int(float(trio.query("?FREE"))) == empty - source - code
    assert trio.send('DEL "P"') == []
    assert int(float(trio.query("?FREE"))) == empty


# ---- FLASHTABLE and FLASHVR: TABLE kept in flash across EX ---------------------------------

def test_flashtable_saves_a_table_page_and_restores_it_after_ex() -> None:
    """FLASHTABLE's examples: TABLE page 2 (indices 32000..47999) saved to flash page 5,
    restored after a power-up that cleared TABLE, and to another TABLE page."""
    trio = MC405()
    assert trio.send("TABLE(32000, 1.5, 2.5)") == []
    assert trio.send("TABLE(47999, 9)") == []
    assert trio.send("TABLE(48000, 4)") == []  # page 3: not saved
    assert trio.send("FLASHTABLE(1, 5, 2)") == []
    assert trio.query("?FLASHTABLE(3, 5)") == "-1"  # in use
    assert trio.query("?FLASHTABLE(3, 6)") == "0"
    trio.send("EX")
    assert trio.query("?TABLE(32000)") == "0.0000"  # TABLE is RAM
    assert trio.send("FLASHTABLE(2, 5, 2)") == []
    assert trio.send("?TABLE(32000), TABLE(32001), TABLE(47999), TABLE(48000)") == [
        "1.5000\t2.5000\t9.0000\t0.0000"]
    assert trio.send("FLASHTABLE(2, 5, 0)") == []  # page 2's values into page 0 (0..15999)
    assert trio.send("?TABLE(0), TABLE(1), TABLE(15999)") == ["1.5000\t2.5000\t9.0000"]
    assert trio.query("?FLASHTABLE(4, 5)") == "-1"  # erased
    assert trio.query("?FLASHTABLE(3, 5)") == "0"


def test_a_program_checks_and_erases_a_flash_page_as_the_page_does() -> None:
    trio = MC405()
    trio.send("FLASHTABLE(1, 5, 0)")
    trio.load("P", "IF FLASHTABLE(3, 5) THEN\n  VR(1) = 1\n  IF FLASHTABLE(4, 5) THEN "
              "VR(2) = 1\nENDIF\nVR(3) = FLASHTABLE(3, 5)")
    trio.send('RUN "P"')
    trio.advance(ticks=5)
    assert trio.send("?VR(1), VR(2), VR(3)") == ["1.0000\t1.0000\t0.0000"]


@pytest.mark.parametrize("line", ["FLASHTABLE(1, 32, 0)", "FLASHTABLE(1, 0, 32)",
                                  "FLASHTABLE(5, 0, 0)", "FLASHTABLE(1, 0)",
                                  "FLASHTABLE(1, 0.5, 0)", "FLASHVR(-3)"])
def test_bad_flash_calls_are_refused(line: str) -> None:
    trio = MC405()
    assert trio.send(line) == ["! Parameter out of range"]
    assert trio.query("?FLASHTABLE(3, 0)") == "0"


def test_flashvr_minus_one_puts_table_back_at_each_power_up_until_minus_two() -> None:
    trio = MC405()
    trio.send("TABLE(100, 7, 8)")
    assert trio.send("FLASHVR(-1)") == []
    trio.send("TABLE(100, 1)")  # changed after: lost at power-up (page)
    trio.send("EX")
    assert trio.send("?TABLE(100), TABLE(101)") == ["7.0000\t8.0000"]
    trio.send("EX")
    assert trio.query("?TABLE(100)") == "7.0000"
    trio.send("FLASHVR(-2)")
    trio.send("EX")
    assert trio.query("?TABLE(100)") == "0.0000"

"""The language's remaining forms, each from the keyword pages' usage: bit assignment
``x.n = value`` on variables, array elements, VRs and parameters, and dotted network
addresses; the string functions with all their arguments."""

from __future__ import annotations

from tests.trio_helpers import Rig


def ask(rig: Rig, expr: str) -> str:
    return rig.command("?" + expr).decode()


def test_bit_assignment_on_a_variable() -> None:
    rig = Rig()
    rig.command("options = 0")
    rig.command("options.4 = ON")  # 16
    rig.command("options.0 = TRUE")  # TRUE is -1: any non-zero sets the bit
    assert ask(rig, "options") == "17"
    rig.command("options.4 = OFF")
    assert ask(rig, "options") == "1"
    rig.command("fresh.3 = 1")  # a variable never written reads 0 first
    assert ask(rig, "fresh") == "8"


def test_bit_assignment_keeps_the_other_bits_of_a_vr() -> None:
    rig = Rig()
    rig.command("VR(12) = 5")  # 0101
    rig.command("VR(12).1 = 1")
    rig.command("VR(12).0 = 0")
    assert ask(rig, "VR(12)") == "6"
    assert ask(rig, "VR(12).2") == "1"


def test_bit_assignment_on_parameters_and_their_axis() -> None:
    rig = Rig()
    rig.command("CORNER_MODE.1 AXIS(2) = ON")
    rig.command("BASE(3)")
    rig.command("CORNER_MODE.3 = ON")
    assert ask(rig, "CORNER_MODE AXIS(2)") == "2"
    assert ask(rig, "CORNER_MODE AXIS(3)") == "8"
    assert ask(rig, "CORNER_MODE AXIS(0)") == "0"


def test_bit_assignment_in_a_program_on_an_array_element() -> None:
    rig = Rig()
    rig.load("BITS", "DIM states(3) AS INTEGER\nstates(1) = 2\nstates(1).5 = 1\n"
             "moveoptions = 0\nmoveoptions.5 = TRUE\nVR(1) = states(1)\nVR(2) = moveoptions")
    rig.command('RUN "BITS"')
    rig.cycles(10)
    assert ask(rig, "VR(1)") == "34"
    assert ask(rig, "VR(2)") == "32"


def test_a_bit_beyond_52_and_a_bare_bit_are_refused() -> None:
    rig = Rig()
    assert b"Parameter out of range" in rig.send("x.53 = 1")
    assert b"Syntax error" in rig.send("VR(1).2")


def test_dotted_address_is_one_number() -> None:
    rig = Rig()
    rig.command("IP_ADDRESS = 192.168.1.250")
    assert ask(rig, "IP_ADDRESS") == str((192 << 24) | (168 << 16) | (1 << 8) | 250)
    rig.command("IP_NETMASK = 255.255.255.000")
    assert ask(rig, "IP_NETMASK") == str(0xFFFFFF00)
    assert b"Parameter out of range" in rig.send("IP_GATEWAY = 192.168.1.256")
    assert ask(rig, "IP_GATEWAY") == "0"  # nothing written


def test_spaced_dots_stay_a_bit_read() -> None:
    """A number with one dot keeps its value: only four fields make an address."""
    rig = Rig()
    assert ask(rig, "192.168") == "192.1680"
    assert ask(rig, "5.1") == "5.1000"

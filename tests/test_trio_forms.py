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
    assert ask(rig, "options") == "17.0000"  # a variable is FLOAT (help DIM)
    rig.command("options.4 = OFF")
    assert ask(rig, "options") == "1.0000"
    rig.command("fresh.3 = 1")  # a variable never written reads 0 first
    assert ask(rig, "fresh") == "8.0000"


def test_bit_assignment_keeps_the_other_bits_of_a_vr() -> None:
    rig = Rig()
    rig.command("VR(12) = 5")  # 0101
    rig.command("VR(12).1 = 1")
    rig.command("VR(12).0 = 0")
    assert ask(rig, "VR(12)") == "6.0000"
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
    assert ask(rig, "VR(1)") == "34.0000"
    assert ask(rig, "VR(2)") == "32.0000"


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


# ---- string functions, from their help pages' examples (own strings and numbers) --------
def test_asc_offset_counts_from_zero() -> None:
    rig = Rig()
    assert ask(rig, 'ASC("XYZ")') == "88"
    assert ask(rig, 'ASC("XYZ", 0)') == "88"
    assert ask(rig, 'ASC("XYZ", 2)') == "90"
    assert ask(rig, 'ASC("XYZ", 3)') == "0"  # outside the string
    assert ask(rig, 'ASC("")') == "0"


def test_asc_finds_a_decimal_point_as_the_page_does() -> None:
    rig = Rig()
    rig.load("DP", 'DIM s AS STRING(20)\ns = "4071.5"\nFOR i = 0 TO LEN(s) - 1\n'
             "  IF ASC(s, i) = $2E THEN VR(3) = i\nNEXT i")
    rig.command('RUN "DP"')
    rig.cycles(40)
    assert ask(rig, "VR(3)") == "4.0000"


def test_vrstring_reads_characters_to_the_first_zero() -> None:
    rig = Rig()
    for n, code in enumerate([72, 105, 33, 0, 88]):  # "Hi!", then the end
        rig.command(f"VR({100 + n}) = {code}")
    assert ask(rig, "VRSTRING(100)") == "Hi!"
    rig.command("VR(101) = 7")  # a bell is not printable: left out
    assert ask(rig, "VRSTRING(100)") == "H!"


def test_a_string_packed_into_vrs_with_mid_comes_back() -> None:
    """The MID page's second example, with our own text: each character into a VR,
    a 0 after them, VRSTRING reading them back."""
    rig = Rig()
    rig.load("PACK", 'DIM t AS STRING(16)\nt = "axis 3 homed"\nFOR i = 0 TO LEN(t) - 1\n'
             "  VR(40 + i) = ASC(MID(t, i, 1))\nNEXT i\nVR(40 + LEN(t)) = 0")
    rig.command('RUN "PACK"')
    rig.cycles(60)
    assert ask(rig, "VRSTRING(40)") == "axis 3 homed"


def test_mid_left_right_from_the_pages() -> None:
    rig = Rig()
    rig.command('t = 0')
    assert ask(rig, 'MID("GANTRY ROBOT CELL", 7, 5)') == "ROBOT"
    assert ask(rig, 'MID("GANTRY ROBOT CELL", 13)') == "CELL"
    assert ask(rig, 'LEFT("GANTRY ROBOT CELL", 6)') == "GANTRY"
    assert ask(rig, 'RIGHT("GANTRY ROBOT CELL", 4)') == "CELL"


def test_instr_is_zero_based_with_offset_and_wildcards() -> None:
    rig = Rig()
    text = '"PICK AND PLACE"'
    assert ask(rig, f'INSTR({text}, "AND")') == "5"
    assert ask(rig, f'INSTR(6, {text}, "AND")') == "-1"
    assert ask(rig, f'INSTR(3, {text}, "K")') == "3"
    assert ask(rig, f'INSTR({text}, "PL?CE", "?")') == "9"
    assert ask(rig, f'INSTR({text}, "A*D", 42)') == "5"  # 42 is '*'
    assert ask(rig, f'INSTR({text}, "XYZ")') == "-1"


def test_str_precision_and_width() -> None:
    rig = Rig()
    assert ask(rig, "STR(7, 0)") == "7"
    assert ask(rig, "STR(2.5)") == "2.50000"  # 5 decimals by default
    assert ask(rig, "STR(3.14159, 2, 7)") == "   3.14"
    assert ask(rig, '"Axis " + STR(4, 0) + " ready"') == "Axis 4 ready"


def test_chr_of_a_code_and_of_a_unicode_point() -> None:
    rig = Rig()
    assert ask(rig, "CHR(77)") == "M"
    assert rig.command("?CHR(176, 1)") == "°".encode()  # UTF-8 on the wire
    assert b"Parameter out of range" in rig.send("?CHR(300)")


def test_hex_and_val_from_their_pages() -> None:
    rig = Rig()
    assert ask(rig, "HEX(16)") == "10"
    assert ask(rig, 'VAL("-48.25") * 2') == "-96.5000"
    assert ask(rig, 'INT(VAL("41")) + 1') == "42"
    assert ask(rig, 'VAL("none")') == "0"


# ---- forms from the DIM, OPEN and FILE pages -----------------------------------------
def test_dim_string_arrays_with_their_sizes_in_the_type() -> None:
    """DIM's page: STRING(size, length) and STRING(size1, size2, length)."""
    rig = Rig()
    rig.load("SA", 'DIM tags AS STRING(3, 8)\ntags(0) = "feed"\ntags(2) = "cut"\n'
             'DIM grid AS STRING(2, 3, 4)\ngrid(1, 2) = "ok"\n'
             "VR(1) = LEN(tags(0)) * 10 + LEN(tags(2))\nVR(2) = LEN(grid(1, 2))")
    rig.command('RUN "SA"')
    rig.cycles(10)
    assert (ask(rig, "VR(1)"), ask(rig, "VR(2)")) == ("43.0000", "2.0000")


def test_open_takes_its_mode_arguments() -> None:
    rig = Rig()
    rig.command('OPEN #40 AS "LOG" FOR OUTPUT(1)')
    rig.command("CLOSE #40")
    rig.command('OPEN #41 AS "Q" FOR FIFO_WRITE(512)')


def test_file_without_an_sd_card_reads_false() -> None:
    """FILE's page: a function returns TRUE on success; the emulator has no SD card."""
    rig = Rig()
    assert ask(rig, 'FILE "DETECT"') == "0"
    rig.command('ok = FILE "CRC16" "PROG"')
    rig.command('nxt = FILE "FIND_NEXT", 20')
    assert ask(rig, "ok, nxt") == "0.0000\t0.0000"
    assert rig.command('IF FILE "DETECT" THEN PRINT "card" ELSE PRINT "none"') == b"none"

"""What an MC405 keeps over a restart (EX): its VRs (EX's page: the VRs remain in memory;
FLASHVR's page: the MC4xx keeps its VRs itself), the flash parameters and the programs;
not the axis parameters, the TABLE (unless FLASHVR(-1) kept it) or the motion."""

from __future__ import annotations

from maxk.controllers.trio import MC405


def test_a_vr_keeps_its_value_over_ex() -> None:
    trio = MC405()
    assert trio.send("VR(5) = 3.5") == []
    trio.send("EX")
    assert trio.query("?VR(5)") == "3.5000"


def test_a_power_up_counter_in_a_vr_counts_each_restart() -> None:
    """A machine counting its starts: an autorun program adds one to VR(10) at each."""
    trio = MC405()
    trio.load("STARTS", "VR(10) = VR(10) + 1")
    trio.send('RUNTYPE "STARTS", 1')
    for _ in range(3):
        trio.send("EX")
        trio.advance(ticks=5)
    assert trio.query("?VR(10)") == "3.0000"


def test_vrs_stay_while_axis_parameters_table_and_motion_start_again() -> None:
    trio = MC405()
    for line in ("VR(0) = -2", "VR(65535) = 12.25", "UNITS AXIS(1) = 40", "TABLE(7, 9)",
                 'VR(20) = "AB"'):
        assert trio.send(line) == []
    trio.reset()  # the controller's own restart, as EX on a session
    assert [trio.query(f"?VR({n})") for n in (0, 65535, 20, 21, 22)] == \
        ["-2.0000", "12.2500", "65.0000", "66.0000", "0.0000"]
    assert trio.query("?UNITS AXIS(1)") == "1" and trio.query("?TABLE(7)") == "0.0000"


def test_a_recipe_in_vrs_is_used_by_the_program_after_the_restart() -> None:
    """A recipe set before EX drives the move its autorun program makes after it."""
    trio = MC405()
    trio.load("RECIPE", "SPEED = 1000\nACCEL = 100000\nDECEL = 100000\nMOVE(VR(1))\n"
              "WAIT IDLE\nVR(2) = DPOS")
    trio.send('RUNTYPE "RECIPE", 1')
    trio.send("VR(1) = 125")
    trio.send("EX")
    trio.advance(0.5)
    assert trio.query("?VR(2)") == "125.0000"


def test_flash_data_1_in_mc_config_keeps_the_first_4096_table_values() -> None:
    """FLASH_DATA's page: set to 1 in MC_CONFIG, TABLE is the MC4x's automatic backup, its
    first 4096 elements only: TABLE(0..4095) come back at the power-up, 4096 on do not."""
    trio = MC405()
    trio.load("MC_CONFIG", "FLASH_DATA = 1")
    trio.send("EX")  # MC_CONFIG runs at this power-up
    trio.advance(ticks=5)
    assert trio.query("?FLASH_DATA") == "1"
    trio.send("TABLE(0, 1.5, 2.5)")
    trio.send("TABLE(4095, 9, 10)")  # the last kept, then the first not
    trio.send("EX")
    trio.advance(ticks=5)
    assert trio.send("?TABLE(0), TABLE(1), TABLE(4095), TABLE(4096)") == \
        ["1.5000\t2.5000\t9.0000\t0.0000"]


def test_without_flash_data_the_table_starts_again() -> None:
    trio = MC405()
    assert trio.query("?FLASH_DATA") == "0"  # power-up: the VRs are the backup
    trio.send("TABLE(0, 1.5)")
    trio.send("EX")
    assert trio.query("?TABLE(0)") == "0.0000"
    assert trio.send("FLASH_DATA = 2") == ["! Parameter out of range"]

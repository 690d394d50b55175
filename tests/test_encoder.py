"""Steppers with encoders (PSE): encoder ratio, slip (stall) detection, position
maintenance and the EA status letters."""

from maxk import MAXk
from maxk.personalities.maxk import flags as F


def encoder_stepper(setup: str = "") -> MAXk:
    board = MAXk()
    board.send(f"AX PSE; VL20000; AC200000; {setup}")
    return board


def test_encoder_ratio_puts_the_axis_in_encoder_mode():
    """ER4000,1000: 4 encoder counts per motor step; moves and speeds in counts."""
    board = encoder_stepper("ER4000,1000; VL20000; AC400000; MR8000; GO; ID;")
    axis = board.board.axis("X")
    assert axis.config.velocity == 5000  # 20000 counts/s = 5000 steps/s
    assert axis.config.acceleration == 100000
    assert board.run_until_done("X", timeout=5)
    assert board.query("AX RP") == "2000"  # the motor counter counts steps
    assert board.query("AX RE") == "8000"
    board.send("AX CA; MA-400; GO; ID;")  # an encoder position
    assert board.run_until_done("X", timeout=5)
    assert board.query("AX RE") == "-400"
    assert board.query("AX RP") == "-100"
    board.send("AX MR3; GO;")  # 3 counts is 0.75 steps: the nearest whole step
    board.run_until_idle()
    assert board.query("AX RP") == "-99"
    assert board.query("AX RE") == "-396"
    board.send("AX ER1,1; MR100; GO;")  # back to steps
    board.run_until_idle()
    assert board.query("AX RP") == "1"
    assert board.query("AX RE") == "-296"  # 1:1 again, reading on from where it was


def test_er_takes_two_positive_operands():
    board = encoder_stepper()
    board.send("AX ER4000")
    assert board.command_error
    board.send("IC; AX ER0,1")
    assert board.command_error
    board.send("IC; AA ER1,1")
    assert board.command_error  # single-axis only


def test_slip_detection_stops_the_axis_on_missed_steps():
    board = encoder_stepper("ES10; TN; MR100000; GO; ID;")
    heard = []
    board.board.add_flag_listener(heard.append)
    board.advance(0.5)
    assert board.query("AX EA") == "EDNNN"
    board.miss_steps("X", 8)  # within the tolerance
    board.advance(0.1)
    assert int(board.query("AX RV")) > 0
    assert not board.doorbell & (1 << F.SLIP_SHIFT)
    board.miss_steps("X", 5)  # 13 counts behind now
    assert board.doorbell & (1 << F.SLIP_SHIFT)
    assert heard == [F.maxnet_event_bits(0, F.AXIS_SLIP)]
    assert board.query("AX EA") == "EDSNN"
    assert board.query("AX RV") == "0"  # stopped at once
    rp, re = int(board.query("AX RP")), int(board.query("AX RE"))
    assert rp - re == 13  # the encoder shows exactly the steps missed
    board.advance(1.0)
    assert not board.done("X")  # the queue (its ID) was flushed
    assert board.query("AX RA") == "PNNN"
    assert board.query("AX EA") == "EDNNN"  # RA cleared the latched slip


def test_slip_with_an_encoder_ratio_counts_encoder_counts():
    board = encoder_stepper("ER4000,1000; ES10; TN; JG4000;")
    board.advance(0.2)
    board.miss_steps("X", 2)  # 8 counts
    assert not board.doorbell & (1 << F.SLIP_SHIFT)
    board.miss_steps("X", 1)  # 12 counts
    assert board.doorbell & (1 << F.SLIP_SHIFT)


def test_without_tn_a_slip_is_not_acted_on():
    board = encoder_stepper("ES10; MR100000; GO;")
    board.advance(0.2)
    board.miss_steps("X", 50)
    assert not board.doorbell & (1 << F.SLIP_SHIFT)
    assert int(board.query("AX RV")) > 0
    assert board.query("AX EA") == "DDNNN"


def test_position_maintenance_steps_the_stage_back_under_the_encoder():
    board = encoder_stepper("HD2; HV1000; HN; MR500; GO; ID;")
    assert board.run_until_done("X", timeout=5)
    assert board.query("AX EA") == "DENDN"  # maintaining, within the deadband
    board.miss_steps("X", 2)  # inside the deadband: nothing happens
    board.advance(0.1)
    assert board.query("AX RE") == "498"
    board.miss_steps("X", 5)  # 7 counts out
    assert board.query("AX EA") == "DENNN"
    board.advance(0.1)
    assert board.query("AX RE") == "500"
    assert board.query("AX RP") == "500"  # the correction leaves the motor counter alone
    assert board.query("AX EA") == "DENDN"
    assert board.query("AX CL?") == "on"
    board.send("AX HF")
    board.miss_steps("X", 5)
    board.advance(0.1)
    assert board.query("AX RE") == "495"
    assert board.query("AX CL?") == "off"


def test_position_maintenance_waits_for_the_queue():
    board = encoder_stepper("HD0; HN; MR500; GO; WT1639; ID;")
    board.advance(0.05)
    board.miss_steps("X", 10)
    assert board.run_until_done("X", timeout=5)
    board.advance(0.1)
    assert board.query("AX RE") == "500"


def test_loop_commands_on_an_open_loop_stepper_are_accepted_and_change_nothing():
    """Hosts send CL1/HN/HF to every axis (Appendix C on a factory board, VIPER, the
    DLL): a PSO axis takes them without an error and keeps no loop (decision D)."""
    board = MAXk()
    for command in ("HN", "CL1", "CL0", "HF"):
        board.send(f"IC; AX {command}")
        assert not board.command_error, command
        assert board.query("AX CL?") == "off"
    board.send("IC; AX EA")
    assert board.command_error  # still no encoder to report on


def test_load_position_during_a_correction_keeps_rp():
    board = encoder_stepper("LP0; VL200; HN;")
    board.miss_steps("X", 100)
    board.advance(0.1)  # correcting
    board.send("AX LP5000;")
    board.advance(2.0)
    assert board.send("AX RP; RE;") == ["5000", "5000"]


def test_a_fractional_encoder_ratio_gives_no_false_slip():
    board = encoder_stepper("ER3,2; MR2; GO;")
    board.advance(0.5)
    board.send("AX LP0; TN; ES0; MR2; GO;")
    board.advance(0.5)
    assert board.query("AX EA") == "EDNNN"
    board.send("AX TF; HD0; HN;")
    board.advance(1.0)
    assert board.board.axis("X").motion is None  # maintenance has nothing to correct


def test_slip_counts_from_when_the_axis_got_its_encoder_and_detection():
    board = MAXk()
    board.send("AX MR1000; GO;")
    board.advance(1.0)
    board.miss_steps("X", 13)  # an open-loop stepper: nobody sees it
    board.send("AX PSE; ES5; TN;")
    assert board.query("AX EA") == "EDNNN"
    board.miss_steps("X", 3)
    assert board.query("AX EA") == "EDNNN"
    board.send("AX TF; ES2;")
    board.send("AX TN;")  # the 3 missed steps are over the new tolerance
    assert board.query("AX EA") == "EDSNN"

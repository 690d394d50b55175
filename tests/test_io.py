"""General purpose I/O, SW waits, aux outputs and analog I/O."""

import math

from maxk import MAXk


def test_factory_directions_and_levels():
    b = MAXk()
    assert b.query("RB") == "ff00"  # bits 0-7 inputs, 8-15 outputs
    assert b.query("BX") == "0000"
    b.set_input(0, True)
    b.set_input(7, True)
    assert b.query("BX") == "0081"


def test_outputs_set_clear_and_word():
    b = MAXk()
    b.send("BH8; BH15; BL8;")
    assert b.query("BX") == "8000"
    b.send("BS00ff")  # only output bits take the word
    assert b.query("BX") == "0000"
    b.send("BSff00")
    assert b.query("BX") == "ff00"
    assert not b.command_error


def test_writing_an_input_bit_is_a_command_error():
    b = MAXk()
    b.send("BH3")
    assert b.command_error and "bit 3 is an input" in b.last_error.reason
    assert b.query("BX") == "0000"


def test_direction_changes_with_bd_and_io():
    b = MAXk()
    b.send("BD000f; BH2;")
    assert b.query("RB") == "000f" and b.query("BX") == "0004"
    b.send("IO2,0; IO9,1;")
    assert b.query("RB") == "020b" and b.query("BX") == "0000"
    b.send("IO9,2")
    assert b.command_error and "second operand" in b.last_error.reason


def test_queued_outputs_switch_in_step_with_the_axis():
    b = MAXk()
    b.send("AX; VL1000; MR500; GO; BH10; MR500; GO; BL10;")
    b.advance(0.25)
    assert b.query("BX") == "0000"
    b.advance(0.5)  # first move done after ~0.5 s
    assert b.query("BX") == "0400"
    assert b.run_until_idle()
    assert b.query("BX") == "0000"


def test_io_acts_at_once_in_aa_mode():
    b = MAXk()
    b.send("AA; VL1000,1000; MR500,500; GO; BH11;")
    assert b.query("BX") == "0800"


def test_sw_holds_the_queue_until_an_input_goes_high():
    b = MAXk()
    b.send("AX; SW4; MR100; GO; ID;")
    b.advance(2.0)
    assert b.position("X") == 0 and not b.done("X")
    b.set_input(4, True)
    assert b.run_until_done("X")
    assert b.position("X") == 100


def test_sw_with_an_input_that_is_a_function_of_time():
    b = MAXk()
    b.set_input(2, lambda board: board.time >= 0.5)
    b.send("AX; SW2; ID;")
    assert b.run_until_done("X", timeout=2)
    assert b.tick == math.ceil(0.5 * 8192)


def test_sw_on_an_input_driven_by_another_axis():
    from maxk.firmware_model.world import axis_position_source

    b = MAXk()
    b.set_input(1, axis_position_source("Y", lambda p: p >= 3000))
    b.send("AX; SW1; MR10; GO; ID; AY; VL10000; MR5000; GO;")
    assert b.run_until_done("X", timeout=2)
    assert 3000 <= b.position("Y") < 3100


def test_aux_output_manual_and_automatic():
    b = MAXk()
    assert b.query("AX AB?") == "=l"
    b.send("AN")
    assert b.query("AB?") == "=h"
    b.send("AF; PA1; SE100; VL1000; MR100; GO; ID;")
    assert b.query("AB?") == "=h"  # on while moving
    assert b.run_until_done("X")
    assert b.query("AB?") == "=h"  # still settling
    b.advance(0.1)
    assert b.query("AB?") == "=l"
    assert b.query("AM AB?").startswith("=l,=l")


def test_analog_inputs_and_outputs():
    b = MAXk()
    assert b.query("AI0") == "0"
    b.set_analog(1, 5.0)
    b.set_analog(2, -12.0)  # clipped at -10 V
    b.set_analog(3, lambda board: board.time)
    assert b.query("AI1") == "16384"
    assert b.query("AI2") == "-32768"
    b.advance(2.0)
    assert b.query("AI3") == str(round(2.0 / 10 * 32768))
    b.send("AI4")
    assert b.command_error
    b.send("IC; AY AO-1000")
    assert b.board.axes[1].dac == -1000


def test_an_output_in_aa_mode_releases_an_sw_waiting_on_it():
    b = MAXk()
    b.send("AX; SW12; MR10; GO; ID;")
    b.send("AA; BH12;")
    assert b.run_until_done("X")
    assert b.position("X") == 10

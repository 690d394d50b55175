"""The evidence file's host exchanges E1-E4, replayed over the in-process API."""

from maxk import MAXk


def test_e1_asyn_startup():
    b = MAXk()
    assert "ver:" in b.query("WY")
    assert b.send("IC;") == []
    assert b.send("AM SA;") == []
    assert b.send("AX LH PSO;") == []
    assert b.query("AA RP;") == "0,0,0,0,0,0,0,0"
    for letter in "XYZTUVRS":
        assert b.query(f"A{letter} PS?") == "=O"
        assert b.query(f"A{letter} LT?") == ("=h" if letter == "X" else "=l")
    assert b.query("AM PP;") == "0,0,0,0,0,0,0,0"
    assert b.query("#WS") == "=0"
    assert not b.command_error


def test_e2_asyn_poll_cycle():
    b = MAXk("MAXk-4000")
    b.send("AM; MR,,-250; GO; AY; MR1000; GO; ID;")
    b.run_until_idle()
    ri = b.query("AM;RI;")
    assert ri == "PNNN,PDNN,MNNN,PNNN"
    assert len(ri) >= 5 * 4 - 1 and ri[0] in "PM"
    assert b.query("AM PP;") == "0,1000,-250,0"
    assert b.query("AM PE;") == "0,1000,-250,0"
    assert b.query("AM;CL?;") == "off,off,off,off"
    assert b.query("AM;RV;") == "0,0,0,0"
    assert int(b.query("AM;QL;"), 16) == 0x0F0F
    assert b.query("#WS") == "=0"
    assert b.query("AM;RI;") == "PNNN,PNNN,MNNN,PNNN"  # RI reset the done field


def test_e3_asyn_absolute_and_relative_move():
    b = MAXk()
    b.send("AX LPE12345")
    re_ = b.query("AX;RE;")
    assert b.send(f"AX;LO{re_};") == []
    assert b.query("AX;RP;") == "12345"
    assert b.send("AX;AC200000;VL50000;VB1000;MA250000;GO;ID;") == []
    assert b.run_until_done("X", timeout=10)
    assert b.query("AM;RI;").startswith("PDNN,")
    assert b.query("AX;RP;") == "250000"
    b.send("AX;AC200000;VL50000;VB1000;MR-1000;GO;ID;")
    assert b.run_until_done("X", timeout=10)
    assert b.query("AX;RP;") == "249000"


def test_e4_asyn_jog_stop_set_position():
    b = MAXk()
    b.send("AX AC200000; JG-5000;")
    b.advance(1.0)
    assert b.query("AX RV") == "-5000"
    b.send("AX AC200000; ST ID;")
    assert b.run_until_done("X", timeout=1)
    assert b.query("AM;RV;").startswith("0,")
    assert b.query("AX QA")[:2] == "MD"
    b.send("AX LP1000;")
    assert b.query("AX RP") == "1000"
    b.send("AX LPE1000;")
    assert b.query("AX RE") == "1000"
    # E4's loop lines: an open-loop stepper has no loop to close; hosts send CL1 to every
    # axis, so it is accepted and changes nothing (CL? stays off); on a servo axis the
    # same lines close the loop (tests/test_servo.py).
    b.send("AX CL1")
    assert not b.command_error
    assert b.query("AX CL?") == "off"
    b.send("IC; AX PSM; CL1; KP0.500000; KI0.000000; KD0.000000;")
    assert not b.command_error
    assert b.query("AX CL?") == "on"
    b.send("AX CL0")
    assert b.query("AX CL?") == "off"


def test_e8_dll_and_sysal_style_strings():
    b = MAXk("MAXk-3000")
    assert b.query("wy").startswith("MAXk-3000")
    assert b.query("AXRP") == "0"
    b.send("AXMR10000;GDID")
    assert b.run_until_done("X", timeout=60)
    assert b.query(";AX;RP;") == "10000"
    assert b.query("?UR;") == "8192"
    b.send(";AX;ST;AX;AC100000;DC200000;VL20000;MA0;GO;")
    b.run_until_idle()
    assert b.position("X") == 0

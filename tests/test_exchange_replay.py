"""The evidence exchanges E1-E5 and E8, replayed byte for byte over TCP and over the pty,
with the framing the EPICS MAXnet driver uses (LF CR replies, %000 notifications)."""

import pytest
import serial

from tests.hosting import HostedBoards

# (what the host sends, the lines it reads back, seconds of wall time to let pass after)
E1 = [("WY\n", ["MAXk-8000, ver:1.33, S/N: 000001, FPGA:20"], 0), ("IC;\n", [], 0),
      ("AM SA;\n", [], 0), ("AX LH PSO;\n", [], 0),
      ("AA RP;\n", ["0,0,0,0,0,0,0,0"], 0), ("AX PS?\n", ["=O"], 0), ("AX LT?\n", ["=h"], 0),
      ("AY PS?\n", ["=O"], 0), ("AY LT?\n", ["=l"], 0),
      ("AM PP;\n", ["0,0,0,0,0,0,0,0"], 0), ("#WS\n", ["=0"], 0)]
E2 = [("AM;RI;\n", ["PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN"], 0),
      ("AM PP;\n", ["0,0,0,0,0,0,0,0"], 0), ("AM PE;\n", ["0,0,0,0,0,0,0,0"], 0),
      ("AM;CL?;\n", ["off,off,off,off,off,off,off,off"], 0),
      ("AM;RV;\n", ["0,0,0,0,0,0,0,0"], 0), ("AM;QL;\n", ["ffff"], 0), ("#WS\n", ["=0"], 0)]
E3 = [("AX;RE;\n", ["0"], 0), ("AX;LO0;\n", [], 0),
      ("AX;AC200000;VL50000;VB1000;MA250000;GO;ID;\n", [], 10),
      ("AM;RI;\n", ["%000 00000001", "PDNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN,PNNN"], 0),
      ("AX;AC200000;VL50000;VB1000;MR-1000;GO;ID;\n", [], 10),
      ("AX;RP;\n", ["%000 00000001", "249000"], 0)]
E4 = [("AX AC200000; JG-5000;\n", [], 1), ("AX RV\n", ["-5000"], 0),
      ("AX AC200000; ST ID;\n", [], 1), ("AX QA\n", ["%000 00000001", "MDNN"], 0),
      ("AX;CA;AC200000;VL10000;VB100;HM;MA0;GO;ID;\n", [], 5),
      ("AX RP\n", ["%000 00000001", "0"], 0), ("AX LP1000;\n", [], 0), ("AX RP\n", ["1000"], 0),
      ("AX LPE1000;\n", [], 0), ("AX RE\n", ["1000"], 0)]
E5 = [("IC;\n", [], 0), ("AA SA;\n", [], 0), ("WY;\n", ["MAXk-8000, ver:1.33, S/N: 000001, "
                                                        "FPGA:20"], 0),
      ("#WS;\n", ["=0"], 0), ("AA; LMH,H,H,H,H,H,H,H; AX LTH PSO; AY LTH PSO;\n", [], 0),
      ("AX LM?;\n", ["=h"], 0), ("AX QA;\n", ["PNNN"], 0),
      ("AX  VL4000 VB100 AC19500 MA5100 GD ID;\n", [], 5),
      ("AX RA;\n", ["%000 00000001", "PDNN"], 0),
      ("AX  VL4000 VB100 AC19500 MR-200.9 GD ID;\n", [], 5),
      ("AX RP;\n", ["%000 00000001", "4900"], 0)]
E8 = [(";WY;\n", ["MAXk-8000, ver:1.33, S/N: 000001, FPGA:20"], 0), ("?UR;\n", ["8192"], 0),
      ("AXMR10000;GDID\n", [], 1), ("AXRP\n", ["%000 00000001", "10000"], 0)]


@pytest.mark.parametrize("transport", ["tcp", "pty"])
@pytest.mark.parametrize("exchange", [E1, E2, E3, E4, E5, E8],
                         ids=["E1", "E2", "E3", "E4", "E5", "E8"])
def test_exchange(transport, exchange):
    hosted = HostedBoards(pty=transport == "pty")
    try:
        if transport == "tcp":
            client = hosted.connect()

            def send(data):
                client.command(data.rstrip("\n"))

            def read():
                return client.line()
        else:
            port = serial.Serial(hosted.ptys[0], timeout=5)
            hosted.on_close(port.close)
            held = []

            def send(data):
                port.write((data.rstrip("\n") + "\n#WS\n").encode())
                while True:  # the #WS probe shows the server has run everything before it
                    line = port.read_until(b"\n\r")[:-2].decode()
                    if line == "=0":
                        return
                    held.append(line)

            def read():
                return held.pop(0) if held else port.read_until(b"\n\r")[:-2].decode()

        for data, expected, wait in exchange:
            send(data)
            for line in expected:
                assert read() == line, data
            if wait:
                hosted.advance(wait)
    finally:
        hosted.close()

"""The serial doors: a pty that pyserial opens like a real port, and the maxk:// URL."""

import serial

import maxk  # noqa: F401  (registers maxk://)
from tests.hosting import HostedBoards


def read_line(port, eol=b"\n\r"):
    data = port.read_until(eol)
    assert data.endswith(eol), data
    return data[: -len(eol)].decode()


def test_pty_door_with_pyserial_e1_and_a_notification():
    hosted = HostedBoards(pty=True)
    try:
        port = serial.Serial(hosted.ptys[0], 115200, timeout=5)
        port.write(b"WY\n")
        assert read_line(port).startswith("MAXk-8000, ver:1.33")
        port.write(b"IC;\nAM SA;\nAX LH PSO;\nAA RP;\n")
        assert read_line(port) == "0,0,0,0,0,0,0,0"
        port.write(b"AX PS?\nAX LT?\n")
        assert [read_line(port), read_line(port)] == ["=O", "=h"]
        port.write(b"AX;MR10;GO;ID;#WS\n")
        assert read_line(port) == "=0"
        hosted.advance(1.0)
        assert read_line(port) == "%000 00000001"
        port.write(b"AX RP\n")
        assert read_line(port) == "10"
        port.close()
        # the pty survives a client leaving; the next one is served
        again = serial.Serial(hosted.ptys[0], timeout=5)
        again.write(b"AX RP\n")
        assert read_line(again) == "10"
        again.close()
    finally:
        hosted.close()


def test_url_handler_is_registered_and_speaks_maxnet_framing():
    assert "maxk.host" in serial.protocol_handler_packages
    port = serial.serial_for_url("maxk://MAXk-2000", timeout=1)
    port.write(b"AA RP\n")
    assert read_line(port) == "0,0"
    port.write(b"AX QQ\n")
    assert read_line(port) == "%000 01000000"
    port.close()


def test_url_options():
    port = serial.serial_for_url("maxk://MAXk-1000?eol=lf&ack&speed=1000", timeout=2)
    port.write(b"AX;VL5000;AC50000;MR1000;GO;ID;\n")
    assert port.read_until(b"\n") == b"%000 00000001\n"  # 0.3 s at 1000x: 0.3 ms of wall time
    port.write(b"AX RP\n")
    assert port.read_until(b"\n") == b"\x061000\n"
    for bad in ("maxk://MAXk-9999", "maxk://?speed=fast", "maxk://?eol=xx", "maxk://?color=1"):
        try:
            serial.serial_for_url(bad)
        except serial.SerialException:
            continue
        raise AssertionError(f"{bad} was accepted")


def test_pyserial_run_wrapper(tmp_path):
    import subprocess
    import sys

    legacy = tmp_path / "legacy.py"
    legacy.write_text(
        "import serial\n"
        "port = serial.serial_for_url('maxk://MAXk-3000', timeout=1)\n"
        "port.write(b'AA RP;')\n"
        "print(port.read_until(b'\\n\\r').decode().strip())\n")
    result = subprocess.run([sys.executable, "-m", "maxk.host.pyserial_run", str(legacy)],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "0,0,0"

"""The PCI shared-memory door: a separate host process drives the board through the
mapped file only (rings, indices, doorbell, mailboxes)."""

import shutil
import struct
import subprocess
import sys
from pathlib import Path

import pytest

from maxk.host import memory_map as M
from maxk.host.shm_client import SharedMemoryHost
from maxk.personalities.maxk import flags as F
from tests.hosting import HostedBoards

ROOT = Path(__file__).parent.parent


@pytest.fixture
def shm(tmp_path):
    path = str(tmp_path / "maxk-shm")
    h = HostedBoards(models=("MAXk-A000",), shm_paths=[path], real_time_speed=1000.0)
    host = SharedMemoryHost(path)
    yield h, host, path
    host.close()
    h.close()


def test_map_size_layout_and_power_up_flags(shm):
    h, host, path = shm
    assert Path(path).stat().st_size == 0xE010
    assert host.query("WY").startswith("MAXk-A000")
    assert host.firmware_flags == F.FIRMWARE_RUNNING | F.FACTORY_DEFAULTS_LOADED
    assert bytes(host.mem[M.LAYOUT:M.LAYOUT + 4]) == M.LAYOUT_MAGIC
    assert struct.unpack_from(">I", host.mem, M.BOARD_NUMBER)[0] == 1


def test_move_through_the_rings_and_doorbell(shm):
    h, host, _ = shm
    host.send("AX;VL5000;AC50000;MR1000;GO;ID;AK;MR-7;GO;ID;")
    host.wait_doorbell(0x1)
    host.wait_doorbell(1 << 26)  # K notifies through bit 26; its flags sit at 0xD0
    assert host.motor_position(0) == 1000 and host.encoder_position(0) == 1000
    assert host.motor_position(9) == -7  # K at 0xB0
    assert struct.unpack_from(">I", host.mem, M.STATUS_WK + 4)[0] & 0x1
    host.clear_doorbell(0x1 | 1 << 26)
    assert host.query("AX RP") == "1000"  # the clear has been applied by now
    assert host.doorbell & (0x1 | 1 << 26) == 0
    assert host.snapshot(10)[0] == (1000, 1000)


def test_words_io_limits_home_and_command_error(shm):
    h, host, _ = shm
    host.send("BH9;AY;LP1300;")
    assert host.query("BX") == "0200"
    assert struct.unpack_from(">I", host.mem, M.IO_WORD)[0] == 0x0200
    # Y's counter reads 1300 but the stage has not moved: not on the home switch
    assert struct.unpack_from(">I", host.mem, M.HOME_WORD)[0] == 0
    host.send("AY;MA1300;GO;MA1234;GO;")  # nothing moves: already at 1300
    host.send("AZ;LP0;MA1250;GO;ID;")
    host.wait_doorbell(1 << 2)
    assert host.query("AZ QA") == "PDNH"
    assert struct.unpack_from(">I", host.mem, M.HOME_WORD)[0] == 1 << 2
    host.send("QQ;")
    host.wait_doorbell(1 << 24)


def test_direct_kill_mailbox_stops_everything(shm):
    h, host, _ = shm
    host.send("AA;VL1000,1000;JG1000,-1000;")
    assert host.query("AX RV") in ("1000", "0")
    host.kill_all()
    assert host.query("AA RV") == "0,0,0,0,0,0,0,0,0,0"


def test_python_host_in_another_process(shm):
    h, host, path = shm
    script = (
        "import sys\n"
        "from maxk.host.shm_client import SharedMemoryHost\n"
        "host = SharedMemoryHost(sys.argv[1])\n"
        "host.send('AY;VL10000;AC100000;MR2500;GO;ID;')\n"
        "host.wait_doorbell(0x2)\n"
        "print(host.query('AY RP'), host.motor_position(1))\n")
    result = subprocess.run([sys.executable, "-c", script, path], capture_output=True,
                            text=True, timeout=60, cwd=ROOT)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["2500", "2500"]


@pytest.mark.skipif(shutil.which("cc") is None, reason="no C compiler")
def test_the_c_example_drives_a_move(shm, tmp_path):
    h, host, path = shm
    exe = tmp_path / "maxk_shm_move"
    subprocess.run(["cc", "-O2", "-Wall", "-Werror", "-o", str(exe),
                    str(ROOT / "examples" / "c" / "maxk_shm_move.c")], check=True, timeout=60)
    result = subprocess.run([str(exe), path, "AX;VL5000;AC50000;MR1000;GO;ID;"],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "done X, RP 1000, map X 1000"

"""The PCI shared-memory door: a separate host process drives the board through the
mapped file only (rings, indices, doorbell, mailboxes)."""

import os
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


# ---- the map file: never clobber, never follow, never delete what is not ours ----------
def _service(number=1, model="MAXk-4000"):
    from maxk import MAXk
    from maxk.host.pacing import Pacer
    from maxk.host.server import Service

    maxk = MAXk(model)
    return Service(number, maxk, Pacer(maxk, 1.0, lambda: 0.0))


def _door(path, number=1):
    from maxk.host.shared_memory import SharedMemoryDoor

    return SharedMemoryDoor(_service(number), str(path))


def test_an_existing_file_that_is_not_a_map_is_refused_and_kept(tmp_path):
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    with pytest.raises(OSError, match="not a maxk map"):
        _door(notes)
    assert notes.read_text() == "my notes\n"
    blank = tmp_path / "blank"  # the right size, but nothing of ours in it
    blank.write_bytes(bytes(M.SIZE))
    with pytest.raises(OSError, match="not a maxk map"):
        _door(blank)
    assert blank.read_bytes() == bytes(M.SIZE)


def _stale_map(path, number):
    """A map as a killed server of board `number` leaves it."""
    raw = bytearray(M.SIZE)
    raw[M.LAYOUT:M.LAYOUT + 4] = M.LAYOUT_MAGIC
    struct.pack_into(">I", raw, M.BOARD_NUMBER, number)
    struct.pack_into(">i", raw, M.motor_offset(0), 4242)
    path.write_bytes(bytes(raw))
    return bytes(raw)


def test_a_map_of_another_board_is_not_this_boards(tmp_path):
    path = tmp_path / "map"
    raw = _stale_map(path, 2)
    with pytest.raises(OSError, match="not a maxk map of board 1"):
        _door(path, number=1)
    assert path.read_bytes() == raw
    _door(path, number=2).close()  # board 2 takes its own map over
    assert not path.exists()


def test_a_symlink_is_never_followed(tmp_path):
    target = tmp_path / "target.txt"
    target.write_text("keep me")
    link = tmp_path / "map"
    link.symlink_to(target)
    with pytest.raises(OSError, match="symbolic link"):
        _door(link)
    assert target.read_text() == "keep me" and link.is_symlink()
    dangling = tmp_path / "dangling"
    dangling.symlink_to(tmp_path / "nowhere")
    with pytest.raises(OSError, match="symbolic link"):
        _door(dangling)
    assert not (tmp_path / "nowhere").exists() and dangling.is_symlink()


def test_a_second_door_on_one_map_refuses_and_the_first_keeps_it(tmp_path):
    path = tmp_path / "map"
    first = _door(path)
    try:
        first.update()
        with pytest.raises(OSError, match="in use"):
            _door(path)
        assert path.exists()
        assert path.read_bytes()[M.LAYOUT:M.LAYOUT + 4] == M.LAYOUT_MAGIC
        host = SharedMemoryHost(str(path))
        host.send("WY;")
        first.update()
        assert host.read_line().startswith("MAXk-4000")
        host.close()
    finally:
        first.close()
    assert not path.exists()


def test_close_never_deletes_a_file_that_replaced_the_map(tmp_path):
    path = tmp_path / "map"
    door = _door(path)
    other = tmp_path / "other"
    other.write_text("someone else's")
    os.replace(other, path)
    door.close()
    assert path.read_text() == "someone else's"


def test_a_map_left_by_a_killed_server_is_taken_over_cleared_and_removed(tmp_path):
    path = tmp_path / "map"
    proc = subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--no-tcp", "--shm",
                             str(path), "--model", "MAXk-4000", "--seconds", "60"],
                            stdout=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        assert proc.stdout.readline().startswith("board 1: MAXk-4000")
        host = SharedMemoryHost(str(path))
        host.send("AX;LP777;")
        assert host.query("AX RP") == "777"
        host.close()
    finally:
        proc.kill()
        proc.wait(20)
        proc.stdout.close()
    assert path.exists()  # a killed server cannot clean up
    door = _door(path)
    assert struct.unpack_from(">i", path.read_bytes(), M.motor_offset(0))[0] == 0  # cleared
    door.close()
    assert not path.exists()


def test_a_truncated_map_stops_that_door_once_and_the_others_go_on(tmp_path, capsys):
    p1, p2 = tmp_path / "map", tmp_path / "map2"
    d1, d2 = _door(p1, 1), _door(p2, 2)
    host2 = SharedMemoryHost(str(p2))
    try:
        os.truncate(p1, 0x1000)  # another process cuts board 1's map
        d1.update()
        d1.update()
        err = capsys.readouterr().err
        assert err.count(f"board 1: shared memory {p1} was truncated to 4096 bytes") == 1
        assert d1.stopped and p1.stat().st_size == 0x1000  # nothing written after
        host2.send("WY;")
        d2.update()
        assert host2.read_line().startswith("MAXk-4000")
        assert d2.stopped is None
    finally:
        host2.close()
        d1.close()
        d2.close()
    assert not p1.exists() and not p2.exists()


def test_a_map_truncated_in_the_middle_of_a_pass_stops_the_door(tmp_path, capsys):
    path = tmp_path / "map"
    door = _door(path)
    host = SharedMemoryHost(str(path))
    host.send("WY;")
    host.close()
    door._check_file = lambda: None  # the cut lands after the check, before the reads
    os.truncate(path, M.CMD_RING + 1)
    door.update()
    assert "was truncated" in capsys.readouterr().err and door.stopped
    door.close()
    assert not path.exists()


def test_a_removed_or_replaced_map_stops_that_door(tmp_path, capsys):
    path = tmp_path / "map"
    door = _door(path)
    path.unlink()
    door.update()
    assert f"shared memory {path} was removed" in capsys.readouterr().err
    door.close()
    other = tmp_path / "other"
    door = _door(other)
    os.replace(_new_file(tmp_path / "new"), other)
    door.update()
    assert "was replaced by another file" in capsys.readouterr().err
    door.close()
    assert other.read_text() == "new"  # not ours: kept


def _new_file(path):
    path.write_text("new")
    return path


def test_a_query_held_by_wq_answers_once_the_queue_is_empty(shm):
    h, host, _ = shm
    # RP waits behind WQ until the move has ended, then answers through the ring
    assert host.query("AX;VL50000;AC500000;MR2000;GO;WQ;RP;") == "2000"


def test_a_command_in_the_ring_wakes_the_door_without_a_pacing_pass(tmp_path):
    """The ring watcher (issue 28: a map round trip under 1 ms): with no pacing loop at
    all, a host's command in the ring is still run and answered, so the door woke on the
    host's write, not on a pass of the pacer."""
    import asyncio

    from maxk.controllers.registry import build
    from maxk.host.client import Service
    from maxk.host.pacing import Pacer
    from maxk.host.shared_memory import SharedMemoryDoor

    controller = build("MAXk-1000")
    service = Service(1, controller, Pacer(controller, 1.0, lambda: 0.0))
    path = str(tmp_path / "maxk-watched")

    async def main() -> str:
        door = SharedMemoryDoor(service, path)
        door.watch(asyncio.get_running_loop())
        host = SharedMemoryHost(path)
        try:
            return await asyncio.to_thread(host.query, "WY")
        finally:
            host.close()
            door.close()

    assert asyncio.run(main()) == "MAXk-1000, ver:1.33, S/N: 000001, FPGA:20"

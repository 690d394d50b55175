"""The MC405's flash across runs (controllers/trio/archive.py): a new emulator on the same
archive is a power cycle. EX's page: the VRs remain; FLASHVR's: an MC4xx keeps them in
flash; the FLASH parameters (IP_ADDRESS, SERVO_PERIOD, ...); FLASHTABLE's pages;
FLASH_DATA's backup of TABLE's first 4096 values. Bounded, written by rename, a foreign
or damaged file refused with its reason and set aside."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from maxk.controllers.trio.archive import FILE_NAME, SAVE_EVERY_S
from maxk.controllers.trio.controller import MC405
from tests.test_trio_doors import TrioHost

ROOT = Path(__file__).parent.parent


def ok(trio: MC405, *lines: str) -> None:
    for line in lines:
        assert trio.send(line) == [], line


def test_a_power_cycle_keeps_vrs_flash_parameters_pages_and_the_table_backup(tmp_path):
    first = MC405(archive=tmp_path)
    ok(first, "VR(5) = 3.5", "VR(65535) = -2", "TABLE(100, 2.25)", "FLASHTABLE(1, 3, 0)",
       "IP_ADDRESS = 192.168.1.250", "SERVO_PERIOD = 500", "FLASH_DATA = 1",
       "TABLE(7, 9)", "TABLE(5000, 4)")  # 5000: beyond the 4096 backed up
    first.save_archive(final=True)
    second = MC405(archive=tmp_path)
    assert second.query("?VR(5)") == "3.5000"
    assert second.query("?VR(65535)") == "-2.0000"
    assert second.query("?VR(6)") == "0.0000"
    assert second.query("?IP_ADDRESS") == str((192 << 24) + (168 << 16) + (1 << 8) + 250)
    assert second.query("?SERVO_PERIOD") == "500"
    assert second.machine.period == pytest.approx(500e-6)  # powered up at 500 us
    assert second.query("?TABLE(7)") == "9.0000"  # FLASH_DATA's backup
    assert second.query("?TABLE(100)") == "2.2500"
    assert second.query("?TABLE(5000)") == "0.0000"  # TABLE itself is not kept
    assert second.query("?FLASHTABLE(3, 3)") == "-1"  # page 3 holds data
    assert second.query("?FLASHTABLE(3, 4)") == "0"
    ok(second, "FLASHTABLE(2, 3, 1)")  # page 3 read into TABLE page 1 (16000..31999)
    assert second.query("?TABLE(16100)") == "2.2500"


def test_flashvr_minus_1_table_comes_back_at_the_next_run(tmp_path):
    """FLASHVR(-1) keeps the whole TABLE to replace TABLE at power-up (its page)."""
    first = MC405(archive=tmp_path)
    ok(first, "TABLE(0, 1.5)", "TABLE(511999, -3)", "FLASHVR(-1)", "TABLE(0, 8)")
    first.save_archive(final=True)
    second = MC405(archive=tmp_path)
    assert (second.query("?TABLE(0)"), second.query("?TABLE(511999)")) == \
        ("1.5000", "-3.0000")  # FLASHVR's copy, not TABLE as it was at the stop


def test_a_rate_given_at_start_up_wins_over_the_kept_servo_period(tmp_path):
    first = MC405(archive=tmp_path)
    ok(first, "SERVO_PERIOD = 500", "VR(1) = 1")
    first.save_archive(final=True)
    second = MC405(archive=tmp_path, update_rate_hz=1000)
    assert (second.query("?SERVO_PERIOD"), second.query("?VR(1)")) == ("1000", "1.0000")


def test_writes_are_checked_once_a_virtual_second_and_only_when_changed(tmp_path):
    trio = MC405(archive=tmp_path)
    path = tmp_path / FILE_NAME
    trio.save_archive()
    assert not path.exists()  # nothing kept yet: nothing written
    ok(trio, "VR(5) = 1")
    trio.advance(ticks=int(SAVE_EVERY_S * 1000))  # 1000 cycles of 1 ms: one second
    trio.save_archive()
    assert json.loads(path.read_text())["vr"] == [[5, 1.0]]
    inode = path.stat().st_ino
    ok(trio, "VR(5) = 2")
    trio.advance(ticks=999)
    trio.save_archive()  # 0.999 s after the last check: not yet
    assert json.loads(path.read_text())["vr"] == [[5, 1.0]]
    trio.advance(ticks=1)
    trio.save_archive()
    assert json.loads(path.read_text())["vr"] == [[5, 2.0]]
    assert path.stat().st_ino != inode  # a new file renamed over the old, never cut
    assert trio.flash.writes == 2
    trio.advance(ticks=5000)
    trio.save_archive()
    assert trio.flash.writes == 2  # unchanged: not written again
    assert sorted(os.listdir(tmp_path)) == [FILE_NAME]  # no temporary file left


def test_ex_writes_the_flash_at_once(tmp_path):
    trio = MC405(archive=tmp_path)
    ok(trio, "VR(3) = 7")
    trio.reset()  # EX
    assert MC405(archive=tmp_path).query("?VR(3)") == "7.0000"


@pytest.mark.parametrize("text, reason", [
    ("\x00garbage", "not JSON"),
    ('{"format": "somebody else", "vr": []}', "not a maxk MC405 flash file"),
    ('{"format": "maxk MC405 flash", "version": 9}', "version 9"),
    ('{"format": "maxk MC405 flash", "version": 1, "vr": [[65536, 1]], "parameters": {},'
     ' "flash_pages": {}, "auto_backup": null, "flashvr_table": null}',
     "index is out of range"),
    ('{"format": "maxk MC405 flash", "version": 1, "vr": [], "parameters": {},'
     ' "flash_pages": {"32": []}, "auto_backup": null, "flashvr_table": null}',
     "flash page '32'"),
    ('{"format": "maxk MC405 flash", "version": 1, "vr": [], "parameters": {"UNITS": 1},'
     ' "flash_pages": {}, "auto_backup": null, "flashvr_table": null}',
     "not the FLASH parameters"),
    ('{"format": "maxk MC405 flash", "version": 1, "vr": [], "parameters": '
     '{"SERVO_PERIOD": 7}, "flash_pages": {}, "auto_backup": null, "flashvr_table": null}',
     "SERVO_PERIOD"),
    ('{"format": "maxk MC405 flash", "version": 1, "vr": [[1, "x"]], "parameters": {},'
     ' "flash_pages": {}, "auto_backup": null, "flashvr_table": null}', "not a number"),
    ('{"format": "maxk MC405 flash", "version": 1, "vr": [], "parameters": {},'
     ' "flash_pages": {}, "auto_backup": null, "flashvr_table": [[512000, 1]]}',
     "flashvr_table: an index"),
    ('{"format": "maxk MC405 flash", "version": 1, "vr": [], "parameters": {},'
     ' "flash_pages": {}, "auto_backup": null}', "fields are not a flash file's"),
])
def test_a_foreign_or_damaged_file_is_refused_set_aside_and_the_controller_runs(
        tmp_path, text, reason):
    path = tmp_path / FILE_NAME
    path.write_text(text, encoding="latin-1")
    trio = MC405(archive=tmp_path)
    assert trio.flash.damage is not None and reason in trio.flash.damage
    assert trio.query("?VR(1)") == "0.0000"  # empty flash, the controller runs
    aside = tmp_path / f"{FILE_NAME}.refused-1"
    assert aside.read_text(encoding="latin-1") == text  # kept for a person to look at
    assert any(reason in line for line in trio.console().program_lines())
    ok(trio, "VR(1) = 4")
    trio.save_archive(final=True)  # a new file: the refused one is not touched
    assert aside.read_text(encoding="latin-1") == text
    assert MC405(archive=tmp_path).query("?VR(1)") == "4.0000"


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _serve(archive_dir: Path, port: int) -> subprocess.Popen[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--model", "MC405",
                             "--host", "127.0.0.1", "--port", str(port),
                             "--archive-dir", str(archive_dir)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=ROOT, env=env)


def _stop(proc: subprocess.Popen[str]) -> None:
    proc.terminate()
    _out, err = proc.communicate(timeout=30)
    assert proc.returncode == 0, err


def test_serve_stop_serve_again_keeps_the_vrs(tmp_path):
    """Through the real door: a telnet host writes VR(5), the server stops (SIGTERM) and
    starts again on the same archive directory; VR(5) reads back."""
    for value, expected in (("3.5", "0.0000"), (None, "3.5000")):
        port = _free_port()
        proc = _serve(tmp_path, port)
        try:
            assert proc.stdout is not None
            assert proc.stdout.readline().strip() == f"board 1: MC405 tcp 127.0.0.1:{port}"
            host = TrioHost(port)
            host.connect()
            assert host.cmd("?VR(5)") == expected
            if value is not None:
                host.cmd(f"VR(5) = {value}")
            host.close()
        finally:
            _stop(proc)
    assert (tmp_path / "MC405-board1.programs" / FILE_NAME).exists()

"""Parameter flash: APP/RDP/RDF archives, power-up flags, crash-safe writes, reset."""

import os
import random
import select
import signal
import time

import pytest

from maxk import MAXk
from maxk.personalities.maxk import flags as F
from maxk.personalities.maxk.parameters import ARCHIVED_FIELDS, ParameterArchive, snapshot

# Every archived parameter away from its factory value, on two axes.
SETUP = ("AX LMS; LF; LTH; MM; AC123456; DC234567; PN7; VL54321; VB123; UU2.5; SE15; PA1; "
         "ER4000,1000; ES12; HTH; HD3; HG4; HV2000; SVB0; SVP-; KP12.5; KI3; KD170; KU99; "
         "KV5; KA6; KF7; KO-8; "
         "AY SC; SS9; PR11; VL1000; AC5000; KP1; KD2;")


def saved_state(board: MAXk) -> list[dict]:
    return [snapshot(axis.config) for axis in board.board.axes]


def power_up(path, model="MAXk-4000") -> MAXk:
    board = MAXk(model, archive=path)
    board.advance(ticks=1)
    return board


def test_firmware_flags_read_all_ones_until_initialization_is_over(tmp_path):
    board = MAXk("MAXk-4000", archive=tmp_path / "flash.json")
    assert board.firmware_flags == 0xFFFF_FFFF
    board.advance(ticks=1)
    assert board.firmware_flags == F.FIRMWARE_RUNNING | F.FACTORY_DEFAULTS_LOADED


def test_app_saves_every_listed_parameter_and_power_up_restores_it(tmp_path):
    path = tmp_path / "flash.json"
    board = power_up(path)
    board.send(SETUP)
    assert not board.command_error, board.last_error
    before = saved_state(board)
    assert before[0] != snapshot(type(board.board.axes[0].config)())  # really changed
    changed = [n for n in ARCHIVED_FIELDS
               if before[0][n] != snapshot(type(board.board.axes[0].config)())[n]
               or before[1][n] != snapshot(type(board.board.axes[1].config)())[n]]
    assert set(changed) == set(ARCHIVED_FIELDS)  # the setup covers the whole list
    board.send("APP")
    assert not board.command_error
    again = power_up(path)
    assert again.firmware_flags == F.FIRMWARE_RUNNING | F.USER_DEFAULTS_LOADED
    assert saved_state(again) == before
    assert again.query("AX RC") == "123456"
    assert again.query("AX LM?") == "=f"
    assert again.query("AX PS?") == "=O"  # the axis type is not in the archive (2.14)


def test_rdf_and_rdp_switch_between_factory_and_saved_sets(tmp_path):
    board = power_up(tmp_path / "flash.json")
    board.send("RDP")
    assert board.command_error  # nothing saved yet
    assert "no parameters were saved" in str(board.last_error)
    board.send("IC; AX VL1234; AC4321; APP; VL999; RDF;")
    assert board.query("AX RC") == "2000000"
    assert board.board.axes[0].config.velocity == 200_000
    assert board.firmware_flags == F.FIRMWARE_RUNNING | F.FACTORY_DEFAULTS_LOADED
    board.send("RDP")
    assert board.board.axes[0].config.velocity == 1234
    assert board.firmware_flags == F.FIRMWARE_RUNNING | F.USER_DEFAULTS_LOADED


@pytest.mark.parametrize("damage", ["flip", "truncate", "empty", "garbage", "nested",
                                    "nested-object"])
def test_a_damaged_archive_loads_the_factory_set_with_the_checksum_bit(tmp_path, damage):
    path = tmp_path / "flash.json"
    board = power_up(path)
    board.send("AX VL1234; APP;")
    raw = bytearray(path.read_bytes())
    if damage == "flip":
        at = raw.index(b'"velocity": 1234') + len('"velocity": 1')
        raw[at] = ord("9")  # one digit: still valid JSON, wrong checksum
    elif damage == "truncate":
        raw = raw[: len(raw) // 2]
    elif damage == "empty":
        raw = bytearray()
    elif damage == "nested":  # thousands deep: the JSON reader's recursion gives up
        raw = bytearray(b"[" * 100_000 + b"]" * 100_000)
    elif damage == "nested-object":
        raw = bytearray(b'{"checksum": "0", "axes": ' + b'{"a": ' * 5000 + b"1"
                        + b"}" * 5001)
    else:
        raw = bytearray(os.urandom(200))
    path.write_bytes(bytes(raw))
    again = power_up(path)
    assert again.firmware_flags == (F.FIRMWARE_RUNNING | F.ARCHIVE_CHECKSUM_ERROR
                                    | F.FACTORY_DEFAULTS_LOADED)
    assert again.board.axes[0].config.velocity == 200_000
    assert "power-up" in str(again.last_error)
    again.send("RDP")
    assert again.command_error  # the bad archive is not loaded by RDP either
    again.send("IC; APP;")  # saving again repairs it
    assert power_up(path).firmware_flags == F.FIRMWARE_RUNNING | F.USER_DEFAULTS_LOADED


def test_an_archive_for_another_model_is_not_loaded(tmp_path):
    path = tmp_path / "flash.json"
    power_up(path).send("APP")
    assert power_up(path, "MAXk-8000").firmware_flags & F.ARCHIVE_CHECKSUM_ERROR


def test_a_failed_write_is_a_command_error_with_bit_13(tmp_path):
    blocker = tmp_path / "not-a-directory"
    blocker.write_text("")
    board = power_up(blocker / "flash.json")
    board.send("APP")
    assert board.command_error
    assert board.firmware_flags & F.ARCHIVE_PROGRAMMING_ERROR


def test_killing_a_process_in_the_middle_of_app_never_leaves_a_torn_archive(tmp_path):
    """A child saves parameter sets in a loop (each with its own VL); once it has saved
    at least one, it is killed at a random moment, many times. The archive is always
    one whole set, the newest child's (never an older one, never a mix), and the
    temporary files the kills leave are swept at the next start-up. Nothing here
    depends on how fast the machine is."""
    path = tmp_path / "flash.json"
    rng = random.Random(2026)
    for round_ in range(40):
        first = 1000 + round_ * 100_000
        ready_r, ready_w = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child: APP in a loop
            try:
                os.close(ready_r)
                board = MAXk("MAXk-4000", archive=path)
                velocity = first
                board.send(f"AX VL{velocity}; AY VL{velocity}; APP;")
                os.write(ready_w, b"saved")  # one whole set is on disk
                while True:
                    velocity += 1
                    board.send(f"AX VL{velocity}; AY VL{velocity}; APP;")
            finally:
                os._exit(0)
        os.close(ready_w)
        try:
            assert select.select([ready_r], [], [], 60)[0], "the child never saved"
            assert os.read(ready_r, 5) == b"saved"
        finally:
            os.close(ready_r)
            time.sleep(rng.uniform(0.0, 0.03))  # a random moment in the child's loop
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
        sets = ParameterArchive(path).load("MAXk-4000")  # raises if torn or corrupted
        assert sets is not None
        assert sets[0]["velocity"] == sets[1]["velocity"]  # one whole save, not a mix
        assert first <= sets[0]["velocity"] < first + 100_000  # this child's, the newest
        board = power_up(path)
        assert board.firmware_flags == F.FIRMWARE_RUNNING | F.USER_DEFAULTS_LOADED
        assert not list(tmp_path.glob(".flash.json.*.tmp"))  # swept at start-up


def test_reset_mid_move(tmp_path):
    path = tmp_path / "flash.json"
    board = power_up(path)
    board.send("AX VL5000; AC50000; APP; MR100000; GO; ID; AY PSM; CL1;")
    board.advance(1.0)
    moved = int(board.query("AX RP"))
    assert 0 < moved < 100_000
    stage = board.board.axes[0].steps_now(board.board)
    cc = int(board.query("CC"))
    board.reset()
    assert board.firmware_flags == 0xFFFF_FFFF  # initializing again
    board.advance(ticks=1)
    assert board.firmware_flags == F.FIRMWARE_RUNNING | F.USER_DEFAULTS_LOADED
    assert board.query("AX RV") == "0"  # stopped at once
    assert board.query("AX RP") == "0"  # counters start again where the stage stands
    assert board.board.axes[0].steps_now(board.board) == stage
    assert board.query("AX RQC") == "2559"
    assert board.query("AY PS?") == "=O"
    assert board.board.axes[0].config.velocity == 5000  # the archived set
    assert int(board.query("CC")) < cc
    board.advance(1.0)
    assert board.query("AX RP") == "0"
    assert not board.done("X")


def test_user_units_scale_operands_and_survive_the_archive(tmp_path):
    path = tmp_path / "flash.json"
    board = power_up(path)
    board.send("AX UU1000; VL2.5; AC50.5; MR1.5; GO; ID;")
    assert board.board.axes[0].config.velocity == 2500
    assert board.board.axes[0].config.acceleration == 50500
    assert board.run_until_done("X", timeout=5)
    assert board.query("AX RP") == "1500"  # reports stay in counts
    board.send("AX LP0.25;")
    assert board.query("AX RP") == "250"
    board.send("AX VL5000;")  # 5,000,000 counts/s: out of range once scaled
    assert board.command_error
    board.send("IC; AX UF; MR10.9; GO;")
    board.run_until_idle()
    assert board.query("AX RP") == "260"  # counts again, decimals truncate
    board.send("AX UU0.5; APP;")
    assert power_up(path).board.axes[0].config.user_units == 0.5


def test_er_with_uu_keeps_the_host_in_motor_steps():
    """Classic EPICS sends `ER e,m` then `UU e/m` so it can keep working in steps."""
    board = MAXk()
    board.send("AX PSE; ER4000,1000; UU4; VL1000; MR100; GO; ID;")
    assert board.run_until_done("X", timeout=5)
    assert board.query("AX RP") == "100"
    assert board.query("AX RE") == "400"
    assert board.board.axes[0].config.velocity == 1000


def test_the_repl_resets(tmp_path):
    from maxk.repl import ReplSession

    session = ReplSession(manual_time=True, archive=tmp_path / "flash.json")
    session.handle("AX VL4000; APP; JG4000;")
    session.handle(":advance 0.5 s")
    out = session.handle(":reset")
    assert out[0].startswith("reset: firmware flags 0x00010004")
    assert session.handle("AX RV") == ["0"]


def test_a_serial_break_resets_the_board():
    import serial

    import maxk  # noqa: F401  (registers maxk://)

    port = serial.serial_for_url("maxk://MAXk-4000?speed=1000", timeout=0)
    port.write(b"AX JG5000;\r")
    port.send_break()
    port.write(b"AX RV\r")
    time.sleep(0.05)
    assert port.read(100).strip().endswith(b"0")
    port.close()


def write_archive(path, sets, model="MAXk-4000"):
    from maxk.personalities.maxk.parameters import encode

    path.write_bytes(encode(model, sets))


@pytest.mark.parametrize("bad", [
    {"gains": [1, 2, 3]}, {"gains": "x"}, {"velocity": float("inf")}, {"acceleration": 0},
    {"encoder_ratio": [0, 1]}, {"user_units": float("nan")}, {"gains": {"kp": "nan"}},
    {"velocity": -5}, {"move_direction": 5}, {"limits_enabled": "false"},
    {"user_units": -2}, {"servo_polarity": 0},  # VB above VL loads (issue 40)
])
def test_values_the_commands_would_refuse_are_a_damaged_archive(tmp_path, bad):
    """A valid checksum over values no command accepts: factory set, bits 12 and 18;
    RDP refuses it and changes nothing on any axis."""
    path = tmp_path / "flash.json"
    good = snapshot(MAXk("MAXk-4000").board.axes[0].config)
    write_archive(path, [dict(good, velocity=5555), dict(good, **bad), good, good])
    board = power_up(path)
    assert board.firmware_flags == (F.FIRMWARE_RUNNING | F.ARCHIVE_CHECKSUM_ERROR
                                    | F.FACTORY_DEFAULTS_LOADED)
    assert board.board.axes[0].config.velocity == 200_000
    board.send("AX VL1234; AY VL1234; RDP;")
    assert board.command_error
    assert [a.config.velocity for a in board.board.axes[:2]] == [1234, 1234]


def test_restoring_parameters_keeps_the_encoder_reading_and_unarchived_settings(tmp_path):
    board = power_up(tmp_path / "flash.json")
    board.send("AX PSE; ER2,1; MR1000; GO; ID;")
    assert board.run_until_done("X", timeout=5)
    board.send("AX TN; ES5; APP; RDF;")
    assert board.send("AX RP; RE;") == ["500", "1000"]
    assert board.board.axes[0].config.slip_detect  # TN is not in the archive: it stays
    board.send("RDP")
    assert board.send("AX RP; RE;") == ["500", "1000"]
    board.reset()
    board.advance(ticks=1)
    assert board.send("AX RP; RE;") == ["0", "0"]


def test_two_processes_saving_to_one_archive_both_succeed(tmp_path):
    path = tmp_path / "flash.json"
    pids = []
    for _ in range(2):
        pid = os.fork()
        if pid == 0:
            code = 1
            try:
                board = MAXk("MAXk-4000", archive=path)
                for _ in range(100):
                    board.send("APP")
                code = 1 if board.command_error else 0
            finally:
                os._exit(code)
        pids.append(pid)
    assert [os.waitpid(pid, 0)[1] for pid in pids] == [0, 0]


def test_user_unit_ranges_follow_the_units_in_force_when_the_command_runs():
    board = MAXk()
    board.send("AX MR1000; GO; UU1000; VL0.5; ID;")  # UU waits behind the move
    assert board.run_until_done("X", timeout=5)
    assert not board.command_error, board.last_error
    assert board.board.axes[0].config.velocity == 500
    board.send("AX UF; VL99999999999;")
    assert board.command_error
    assert board.board.axes[0].config.velocity == 500
    board.send("IC; AX UU1; HV-1;")
    assert board.command_error
    board.send("IC; AX UU1; MR2.5; GO;")
    board.run_until_idle()
    assert board.query("AX RP") == "1003"  # nearest count, halves away from zero


def test_linear_moves_in_encoder_mode_take_encoder_counts():
    board = MAXk()
    board.send("AX PSE; ER2,1; AY PSE; ER2,1; AM; VL1000,1000; MT10,20; GO; ID;")
    assert board.run_until_done("X", "Y", timeout=5)
    assert board.query("AA RE").startswith("10,20,")
    assert board.query("AA RP").startswith("5,10,")


def test_the_repl_reset_does_not_repeat_old_errors(tmp_path):
    from maxk.repl import ReplSession

    session = ReplSession(manual_time=True, archive=tmp_path / "flash.json")
    assert session.handle("XX")[0].startswith("! command error")
    out = session.handle(":reset")
    assert len(out) == 1 and out[0].startswith("reset:")


def test_temporary_files_of_a_killed_app_are_swept_at_start_up_and_nothing_else(tmp_path):
    path = tmp_path / "flash.json"
    power_up(path).send("APP")
    leftover = tmp_path / ".flash.json.k1ll3d_x.tmp"  # what a kill during APP leaves
    leftover.write_bytes(b'{"half": ')
    keep = [tmp_path / name for name in (
        "flash.json.tmp", ".flash.json.short.tmp", ".flash.json.k1ll3d_x.tmp.bak",
        ".other.json.k1ll3d_x.tmp", ".flash.json.K1LL3D_X.tmp", "notes.txt")]
    for file in keep:
        file.write_text("not the board's")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.write_text("precious")
    link = tmp_path / ".flash.json.abcdefgh.tmp"  # the pattern, but a symlink
    link.symlink_to(elsewhere)
    busy = tmp_path / ".flash.json.writing_.tmp"  # another process is writing it now
    busy.write_bytes(b"in progress")
    import fcntl

    with open(busy, "rb") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        board = power_up(path)
        assert busy.exists()
    assert board.firmware_flags == F.FIRMWARE_RUNNING | F.USER_DEFAULTS_LOADED
    assert not leftover.exists()
    assert all(file.read_text() == "not the board's" for file in keep)
    assert link.is_symlink() and elsewhere.read_text() == "precious"
    power_up(path)  # nobody writes it any more: now it goes too
    assert not busy.exists()

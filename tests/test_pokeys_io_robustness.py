"""The PoKeys I/O against bad input: the console language with numbers no request can
carry, and every request byte of the table with out-of-range fields. Each gets a clear
`! ...` line or the device's silence/status byte: never a traceback, never half a change.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from maxk.commands.pokeys.packet import make_request
from maxk.commands.pokeys.table import ENTRIES
from maxk.commands.tables import TableError, unique_table
from maxk.controllers.contract import BuildOptions
from maxk.controllers.pokeys.controller import PoKeys, build

ROOT = Path(__file__).parent.parent
HUGE = ["1e308", "-1e308", "1e-320", "nan", "NaN", "inf", "-inf", str(2 ** 63), "9" * 250,
        "-" + "9" * 250, "0x10", "-1"]
LINES = ["pin {v} output", "pin 1 {v}", "out {v} on", "out 1 {v}", "analog 41 {v}",
         "analog {v} 1.0", "counter {v}", "pwm period {v}", "pwm {v} 10", "pwm 0 {v}",
         "pwm 0 {v}%", "encoder {v} on X", "encoder 0 on {v}", "encoder 0 set {v}",
         "key {v} 0 on", "key 0 {v} on", "kbd48 {v} on", "input {v} on"]


@pytest.mark.parametrize("template", LINES)
def test_console_numbers_out_of_any_range_answer_an_error_and_change_nothing(template):
    dev = PoKeys("PoKeys57CNC")
    console = dev.console()
    assert console.execute("pin 1 output") == []
    assert console.execute("pwm period 25000") == []
    before = (list(dev.device.io.functions), dev.device.io.pwm_period,
              list(dev.device.io.pwm_duty), dict(dev.world.analog))
    taken = []
    for value in HUGE:
        out = console.execute(template.format(v=value))
        assert all(isinstance(line, str) for line in out)
        assert len(out) <= 4 and all(len(line) < 400 for line in out), out
        if out:
            assert out[0].startswith("!"), (template, value, out)
        else:
            taken.append(value)
    assert set(taken) <= {"1e-320", "-1"}, taken  # a tiny voltage; a count of -1
    dev.world.analog.pop(41, None)
    after = (list(dev.device.io.functions), dev.device.io.pwm_period,
             list(dev.device.io.pwm_duty), dict(dev.world.analog))
    assert after == before


def test_every_request_with_fields_out_of_range_is_answered_or_silent():
    """Every command of the table, every [2], payload all 0xFF or all 0x00: a 64-byte
    reply with the request's ID or silence; the device still answers after it."""
    dev = PoKeys("PoKeys57CNC")
    session = dev.open_session()
    commands = sorted({e.command for e in ENTRIES})
    for command in commands:
        for sub in range(256):
            for fill in (0x00, 0xFF):
                frame = make_request(command, sub, fill, fill, fill, request_id=sub,
                                     payload=bytes([fill]) * 56)
                session.feed(frame)
                reply = session.read()
                assert reply == b"" or (len(reply) == 64 and reply[6] == sub), (command, sub)
        dev.reset()
    session.feed(make_request(0x00, request_id=7))
    assert session.read()[6] == 7


def test_every_io_request_of_the_table_is_answered_in_its_plain_form():
    """The get form of every I/O request answers (what a host calls first)."""
    dev = PoKeys("PoKeys57CNC")
    plain = {0xC0: 0, 0xCC: 0, 0x3A: 1, 0xCB: 0, 0xC4: 0, 0xC5: 0, 0xCE: 2, 0x1C: 0xFF,
             0xCD: 0, 0x83: 0, 0xDA: 2, 0xCA: 10, 0xD0: 1, 0xD1: 0x10, 0xDD: 0, 0x81: 0,
             0xDB: 0x31, 0xE5: 0x01, 0xDC: 0x21, 0x86: 0x31, 0x38: 0, 0xD8: 0, 0x1D: 0,
             0x30: 0, 0x40: 0, 0xC1: 0, 0xC2: 0, 0xC3: 0, 0xD7: 11, 0xC6: 0, 0xC7: 0}
    for entry in ENTRIES:
        if entry.handler.__module__.rsplit(".", 1)[-1] not in ("io_commands",
                                                                "peripheral_commands"):
            continue
        sub = entry.sub if entry.sub >= 0 else plain.get(entry.command)
        if sub is None:
            continue
        assert dev.request(entry.command, sub) is not None, entry.name


def test_a_request_listed_twice_is_an_error_at_import():
    with pytest.raises(TableError, match="listed twice"):
        unique_table(ENTRIES + ENTRIES[:1], lambda e: (e.command, e.sub), "PoKeys table")


def test_the_console_help_lists_every_request_with_source_and_confidence():
    lines = PoKeys().console().help("requests")
    assert lines is not None and len(lines) == len(ENTRIES)
    assert all(re.search(r"\[[CID]\] \S", line) for line in lines)


def test_saved_configuration_is_kept_in_the_archive_across_runs(tmp_path):
    archive = str(tmp_path / "pokeys.json")
    first = build("PoKeys57CNC", BuildOptions(1, archive))
    first.set_pin_function(1, 0x04)
    first.set_pwm(1, [100, 0, 0, 0, 0, 0], 1000)
    first.save_configuration()
    second = build("PoKeys57CNC", BuildOptions(1, archive))
    assert second.pin_functions()[0] == 0x04 and second.pwm() == (1, [100, 0, 0, 0, 0, 0],
                                                                   1000)
    Path(archive).write_text("{not json", encoding="utf-8")
    third = build("PoKeys57CNC", BuildOptions(1, archive))  # a damaged archive: defaults
    assert third.pin_functions()[0] == 0


def test_serve_gives_a_pokeys_one_port_for_tcp_and_udp():
    proc = subprocess.Popen([sys.executable, "-m", "maxk", "serve", "--model", "PoKeys57CNC",
                             "--port", "0"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, cwd=ROOT)
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()
        m = re.search(r"tcp 127\.0\.0\.1:(\d+), udp 127\.0\.0\.1:(\d+)", line)
        assert m is not None, line
        assert m[1] == m[2]
    finally:
        proc.terminate()
        proc.communicate(timeout=10)


def test_the_trace_has_the_outputs_pwm_duty_and_attached_encoders(tmp_path):
    dev = PoKeys("PoKeys57CNC")
    console = dev.console()
    for line in ("pin 1 output", "pwm period 1000", "pwm 0 25%", "encoder 0 on X",
                 "encoder 0 enable", "setup 1", "axis X internal position max 10 accel 0 "
                 "decel 0", "state running"):
        assert console.execute(line) == [], line
    path = tmp_path / "t.csv"
    assert console.repl_word("trace", str(path)) == [f"trace: {path}"]
    assert console.execute("move X 50") == [] and console.execute("out 1 on") == []
    dev.advance(0.01)
    console.repl_word("trace", "off")
    rows = path.read_text().splitlines()
    head = rows[0].split(",")
    last = dict(zip(head, rows[-1].split(","), strict=True))
    assert last["outputs"] == "00000000000001" and last["pwm0_duty"] == "25.00"
    assert last["encoder0"] == last["X_position"] == "50"
    assert dev.world_view().trace_values()[:2] == ["00000000000001", "25.00"]


@pytest.mark.parametrize(("model", "pin", "function", "taken"), [
    ("PoKeys57CNC", 7, 0x04, False), ("PoKeys57E", 7, 0x04, True),
    ("PoKeys56E", 7, 0x04, True), ("PoKeys57E", 46, 0x08, True),
    ("PoKeys57CNC", 46, 0x08, False), ("PoKeys57E", 3, 0x42, False),
    ("PoKeys57E", 1, 0x42, True), ("PoKeys57CNC", 19, 0x20, True),
    ("PoKeys57E", 19, 0x20, False)])
def test_each_models_pins_take_what_the_librarys_device_tables_say(model, pin, function,
                                                                    taken):
    dev = PoKeys(model)
    functions = [0] * 55
    functions[pin - 1] = function
    reply = dev.request(0xC0, 1, payload=bytes(functions))
    assert reply is not None and dev.last_refused == (not taken)
    assert (reply[8:] == bytes(56)) == (not taken)  # a refusal's payload is zero
    assert dev.pin_functions()[pin - 1] == (function if taken else 0)


@settings(max_examples=300, deadline=None)
@given(command=st.sampled_from(sorted({e.command for e in ENTRIES} - {0xB0})),
       head=st.binary(min_size=4, max_size=4), payload=st.binary(min_size=56, max_size=56))
def test_any_frame_of_a_known_command_is_answered_once_or_not_at_all(command, head, payload):
    """Random fields and payloads: one 64-byte reply with the request's ID, or silence;
    the device is never left unable to answer."""
    dev = PoKeys("PoKeys57CNC")
    session = dev.open_session()
    session.feed(make_request(command, *head, request_id=0x42, payload=payload))
    reply = session.read()
    assert reply == b"" or (len(reply) == 64 and reply[0] == 0xAA and reply[6] == 0x42)
    session.feed(make_request(0xCC, request_id=0x43))
    assert session.read()[6] == 0x43


def test_a_pokeys56e_has_the_io_but_no_pulse_engine_v2_extras():
    dev = PoKeys("PoKeys56E")
    dev.set_pin_function(1, 0x04)
    dev.set_output(1, True)
    assert dev.digital_inputs()[0] is True
    for sub in (0x37, 0x0A, 0x0B, 0x40, 0x41, 0x50, 0x51, 0x52, 0x53):
        reply = dev.request(0x85, sub)  # no such command on a v1 device
        assert reply is not None and reply[2] == 0xFF and dev.last_refused


LIBRARY_REQUESTS = [
    (0x00, 0x00), (0x03, 0x00), (0x04, 0x00), (0x04, 0x01), (0x04, 0x02), (0x06, 0x00),
    (0x06, 0x01), (0x07, None), (0x07, 0x0A), (0x1C, None), (0x1C, 0xFF), (0x1D, 0x00),
    (0x30, None), (0x38, 0x00), (0x39, 0x00), (0x3A, 0x01), (0x40, None), (0x4B, 0x00),
    (0x4B, 0x10), (0x50, 0xAA), (0x52, 0xAA), (0x76, None), (0x77, None), (0x81, 0x00),
    (0x81, 0x01), (0x82, 0x00), (0x82, 0x01), (0x82, 0x02), (0x82, 0x03), (0x82, 0x05),
    (0x82, 0x10), (0x82, 0x11), (0x82, 0x15), (0x82, 0x16), (0x82, 0x20), (0x83, 0x00),
    (0x83, 0x10), (0x84, 0x00), (0x85, 0x00), (0x85, 0x01), (0x85, 0x02), (0x85, 0x03),
    (0x85, 0x04), (0x85, 0x05), (0x85, 0x06), (0x85, 0x08), (0x85, 0x0A), (0x85, 0x0B),
    (0x85, 0x10), (0x85, 0x11), (0x85, 0x18), (0x85, 0x19), (0x85, 0x20), (0x85, 0x21),
    (0x85, 0x22), (0x85, 0x23), (0x85, 0x24), (0x85, 0x25), (0x85, 0x30), (0x85, 0x31),
    (0x85, 0x32), (0x85, 0x33), (0x85, 0x34), (0x85, 0x35), (0x85, 0x36), (0x85, 0x37),
    (0x85, 0x40), (0x85, 0x41), (0x85, 0x50), (0x85, 0x51), (0x85, 0x52), (0x85, 0x53),
    (0x85, 0xF0), (0x85, 0xFE), (0x85, 0xFF), (0x86, 0x01), (0x86, 0x10), (0x86, 0x20),
    (0x86, 0x31), (0x86, 0x32), (0x8F, 0x00), (0x8F, 0x01), (0x8F, 0xFF), (0xB0, 0x00),
    (0xBB, 0x00), (0xBB, 0x01), (0xBB, 0x02), (0xBB, 0x03), (0xC0, 0x00), (0xC0, 0x01),
    (0xC1, 0x00), (0xC1, 0x01), (0xC2, 0x00), (0xC2, 0x01), (0xC3, 0x00), (0xC3, 0x01),
    (0xC4, 0x00), (0xC4, 0x01), (0xC5, 0x00), (0xC5, 0x01), (0xC6, 0x00), (0xC6, 0x01),
    (0xC7, 0x00), (0xC7, 0x01), (0xCA, None), (0xCA, 0x01), (0xCA, 0x0A), (0xCA, 0x14),
    (0xCA, 0x32), (0xCB, 0x00), (0xCB, 0x01), (0xCC, 0x00), (0xCC, 0x01), (0xCD, 0x00),
    (0xCD, 0x01), (0xCD, 0x0A), (0xCD, 0x0B), (0xCE, None), (0xCE, 0x02), (0xD0, 0x00),
    (0xD0, 0x01), (0xD1, 0x00), (0xD1, 0x10), (0xD1, 0x20), (0xD1, 0x30), (0xD1, 0x31),
    (0xD1, 0x40), (0xD1, 0x50), (0xD1, 0x60), (0xD1, 0x80), (0xD1, 0x85), (0xD5, 0x00),
    (0xD5, 0x01), (0xD6, None), (0xD7, 0x01), (0xD7, 0x02), (0xD7, 0x03), (0xD7, 0x04),
    (0xD7, 0x0B), (0xD7, 0x0C), (0xD7, 0x0D), (0xD7, 0x0E), (0xD8, 0x00), (0xDA, 0x01),
    (0xDA, 0x02), (0xDB, None), (0xDB, 0x10), (0xDB, 0x11), (0xDB, 0x20), (0xDB, 0x21),
    (0xDB, 0x30), (0xDB, 0x31), (0xDC, None), (0xDC, 0x10), (0xDC, 0x11), (0xDC, 0x20),
    (0xDC, 0x21), (0xDC, 0x22), (0xDC, 0x23), (0xDD, 0x00), (0xDD, 0x10), (0xDD, 0x50),
    (0xDD, 0x55), (0xDD, 0x60), (0xDD, 0x70), (0xDE, 0x10), (0xDE, 0x20), (0xDE, 0x30),
    (0xE0, 0x00), (0xE0, 0x0A), (0xE5, 0x01), (0xE5, 0x10), (0xE5, 0x20),
]
"""(command, [2]) of every request a PoKeysLib function sends (None: [2] varies), as the
library's source has them (the shared reference's list of library requests)."""


def test_every_request_the_library_sends_gets_a_reply_of_its_layout():
    for model in ("PoKeys57CNC", "PoKeys57E"):
        dev = PoKeys(model)
        for command, sub in LIBRARY_REQUESTS:
            if command == 0xB0:
                continue  # the 8-frame fill: tests/test_pokeys_v2.py
            first = {0x85: 0x00, 0xD6: 0x01, 0x4B: 0x00, 0x07: 0x0A, 0x1C: 0xFF, 0xC0: 0,
                      0xCA: 10, 0xCE: 2, 0x30: 0, 0x40: 0, 0xDB: 0x02, 0xDC: 0x11,
                      0x76: 0, 0x77: 0}.get(command, 0) if sub is None else sub
            p2 = {0x76: 1, 0x50: 0x55, 0x52: 0x55, 0xD1: 1, 0xDD: 0x10}.get(command, 0)
            payload = bytes([0, 0, 0, 0, 1, 1, 1, 0, 0xEA, 0x07]) if command == 0x83 else b""
            p3 = 1 if command == 0x85 and first in (0xFE, 0xFF) else 0  # AX: one axis
            reply = dev.request(command, first, p2, p3, payload=payload)
            assert reply is not None and len(reply) == 64, (model, hex(command), first)


@pytest.mark.parametrize("damage", [
    {"functions": [2 ** 70 | 4]}, {"functions": "output"}, {"counter_options": [999] * 80},
    {"pwm_duty": [1e308]}, {"encoder_setup": [[1, 2]]}, {"lcd_setup": None},
    {"failsafe": "zz"}, {"matrix_config": 5}])
def test_a_tampered_archive_powers_up_without_a_traceback(tmp_path, damage):
    import json

    archive = tmp_path / "p.json"
    archive.write_text(json.dumps({"functions": [4] + [0] * 54, **damage}), encoding="utf-8")
    dev = build("PoKeys57CNC", BuildOptions(1, str(archive)))
    functions = dev.pin_functions()  # answers: every stored value fits its byte
    assert len(functions) == 55 and all(0 <= f <= 255 for f in functions)
    assert dev.request(0xC0, 0, 1) is not None and dev.pwm() is not None


def test_a_counter_counts_every_edge_of_an_input_that_follows_time_or_an_axis():
    from maxk.firmware_model.world import axis_position_source, time_source

    dev = PoKeys("PoKeys57CNC")
    dev.set_pin_function(3, 0x42)
    dev.set_input(3, time_source(lambda t: int(t * 100) % 2 == 1))  # 50 rising edges a s
    dev.advance(1.0)
    assert dev.counters([3]) == {3: 50}
    dev.set_pin_function(5, 0x42)
    dev.set_input(5, axis_position_source("X", lambda p: p % 100 >= 50))  # a mark / 100
    dev.setup(1)
    dev.configure_axis(0, internal=True, max_speed=10, accel=0.05, decel=0.05)
    dev.set_state("running")
    dev.move({0: 1000})
    assert dev.run_until_idle()
    assert dev.status().positions[0] == 1000 and dev.counters([5]) == {5: 10}

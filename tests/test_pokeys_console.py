"""The PoKeys controller for people and Python: the console language (REPL, scripts),
the Python API in virtual time, the REPL through the registry, the slot trace."""

from __future__ import annotations

import csv
from pathlib import Path

import pytest

from maxk.commands.pokeys import make_request
from maxk.controllers.contract import Console, Controller
from maxk.controllers.pokeys.controller import PoKeys, PoKeysError
from maxk.controllers.registry import build, kind_of
from maxk.repl import ReplSession
from maxk.script import parse_script, run_script


def console_of(model: str = "PoKeys57CNC") -> tuple[PoKeys, Console]:
    dev = build(model)
    assert isinstance(dev, PoKeys)
    return dev, dev.console()


def run(console: Console, *lines: str) -> list[str]:
    out: list[str] = []
    for line in lines:
        out += console.execute(line)
    return out


def test_registry_builds_every_model_behind_the_contract() -> None:
    for model in ("PoKeys56E", "pokeys57e", "PoKeys57CNC"):
        dev = build(model)
        assert isinstance(dev, PoKeys) and kind_of(model).name == "PoKeys"
        c: Controller = dev
        assert c.kind == "PoKeys" and tuple(c.transports) == ("tcp", "udp")
        assert c.packet_size == 64 and c.engine.update_rate_hz == 1000


def test_the_api_in_virtual_time() -> None:
    dev = PoKeys("PoKeys57CNC")
    dev.setup(3)
    dev.configure_axis(0, internal=True, max_speed=10, accel=0.05, decel=0.05)
    dev.configure_axis(1, max_speed=10)
    dev.set_state("running")
    dev.move({0: 1000})
    assert dev.fill([[0, 4]] * 300) == 128
    assert dev.run_until_idle(1.0)
    s = dev.status()
    assert s.positions[:2] == (1000, 512) and dev.slot == 283 and s.state_name == "RUNNING"
    assert dev.fill([[0, 300]] * 20, large=True) == 20  # 16-bit, multi-part, clipped
    dev.advance(0.020)
    assert dev.status().positions[1] == 512 + 20 * 125
    with pytest.raises(PoKeysError):
        dev.set_state(21)  # HOMING cannot be set: silence


def test_the_api_speaks_v1_to_a_56e() -> None:
    dev = PoKeys("PoKeys56E")
    dev.configure_axis(2, max_speed=20, switches=0x04)
    dev.set_home(2, -2000, -101)
    dev.home([2])
    assert dev.run_until_idle(2.0)
    assert dev.status().state_name == "HOME" and dev.status().positions[2] == 0
    dev.set_state("buffer")
    assert dev.fill([[30, -1, 2]] * 40) == 40
    dev.advance(0.040)
    assert dev.status().positions == (40 * 25, -40, 80)  # 25 pulses a slot at most
    assert dev.free_slots() == 128


def test_console_lines_and_replies() -> None:
    dev, con = console_of()
    assert run(con, "status") == ["state STOPPED, buffer 0/128", "no axes enabled (setup N)"]
    assert run(con, "setup 2", "axis X internal position max 10 accel 0.05 decel 0.05",
               "axis Y buffer", "state running", "move X 1000") == []
    assert run(con, "fill 0 5 x 200") == ["accepted 128 of 200, buffer 128/128"]
    dev.advance(0.1)
    assert run(con, "status") == ["state RUNNING, buffer 28/128", "X 250 RUNNING",
                                  "Y 500 RUNNING"]
    assert run(con, "set X 0", "pos") == ["X 0 Y 500"]  # the counter only: X moves on
    assert dev.run_until_idle(1.0) and run(con, "pos") == ["X 750 Y 640"]
    reply = run(con, "request 85 00 33")[0].split()  # [3]: the soft-limit bits now
    assert reply[:6] == ["aa", "85", "00", "00", "00", "00"] and reply[63] == "8d"
    # an unknown command: the device's refusal, status 0xFF in [2], the ID echoed (0x13)
    head = [0xAA, 0xF7, 0xFF, 0, 0, 0, 0x13]
    assert run(con, "request f7") == [bytes(head + [sum(head) & 0xFF] + [0] * 56).hex(" ")
                                      + "  (refused: status 255)"]


def test_console_errors_say_what_to_type() -> None:
    _, con = console_of()
    assert run(con, "jump") == ["! unknown word 'jump'; try help"]
    assert run(con, "state flying") == [
        "! state is one of stopped, running, jogging on the PoKeys57CNC"]
    assert run(con, "move Q 5") == ["! no axis 'Q': say X Y Z A B C U V or 1..8"]
    assert run(con, "fill") == ["! fill: say fill P1 [P2 ...] [x N] [16bit] [large]"]
    assert run(con, "probe finish") == ["no probe result"]
    _, con1 = console_of("PoKeys56E")
    assert run(con1, "probe Z -100") == ["! PEv2_ProbingStart: the PoKeys56E has pulse engine v1"]
    assert run(con1, "move A 5") == ["! no axis 'A' on this device (3 axes)"]
    assert run(con1, "move D 5") == ["! no axis 'D': say X Y Z or 1..3"]


def test_console_world_limits_and_new_errors() -> None:
    dev, con = console_of()
    run(con, "setup 1", "axis X internal position max 10 accel 0.05 switches lim+",
        "world X limits 1500 none", "state running", "move X 2000")
    assert dev.run_until_idle(2.0)
    assert con.new_errors() == ["! slot 250: a limit switch stopped the engine (X)"]
    assert con.new_errors() == []
    assert run(con, "status")[-1] == "switches: limit+ X"
    assert run(con, "world")[0].startswith("X limits 1500 none home -1333 -1234, stage at ")


def test_probe_and_home_from_the_console() -> None:
    dev, con = console_of()
    run(con, "setup 3", "axis Z buffer max 10 switches home homing 50 50",
        "input 1 when Z <= -1234", "state running", "probe Z -5000 speed 0.5 input 1")
    assert dev.run_until_idle(1.0)
    assert run(con, "probe finish") == ["probed: X 0 Y 0 Z -1235"]
    run(con, "world Z home -2000 -1503", "state stopped", "home Z")
    assert dev.run_until_idle(2.0)
    assert run(con, "status") == ["state HOME, buffer 0/128", "X 0 STOPPED", "Y 0 STOPPED",
                                  "Z 0 HOME"]
    assert run(con, "home finish running", "status")[0] == "state RUNNING, buffer 0/128"


def test_status_line_fits_80_columns_with_eight_far_axes() -> None:
    dev, con = console_of()
    run(con, "setup 8")
    for axis in "XYZABCUV":
        run(con, f"axis {axis} buffer")
    run(con, "set " + " ".join(f"{x} -1999999999" for x in "XYZABCUV"))
    line = con.status_line(80)
    assert line == "t=0.000s STOPPED buf 0/128 X-2G Y-2G Z-2G A-2G B-2G C-2G U-2G V-2G"
    run(con, "fill " + " ".join(["1"] * 8) + " x 5", "state running")
    dev.advance(0.001)
    line = con.status_line(80)
    assert len(line) <= 80 and line.endswith("U-2G~ V-2G~")
    assert con.status_line(200).endswith("U-1999999998~ V-1999999998~")


def test_help_words_summary_and_repl_words(tmp_path: Path) -> None:
    dev, con = console_of()
    assert "fill" in con.words() and con.summary("fill").startswith("offer N slots")
    assert con.help("move") == ["move X 1000 [Y -500 ...] [at F]",
                                "  internal-controller axes to positions (speed-mode axes: "
                                "pulses/s)"]
    assert con.help("GO") is None and con.prompt() == "PoKeys57CNC> "
    assert any(":slots N" in line for line in con.repl_help())
    assert con.repl_word("nonsense", "") is None
    run(con, "setup 2", "axis X buffer", "axis Y buffer", "fill 3 -1 x 3", "state running")
    assert con.repl_word("plan", "X") == [
        "X from slot 0 at 0: ends 0.003 s, +9 pulses",
        "  t0 0.000 s  0.003 s  dir +1  3000..3000 pulses/s"]
    assert con.repl_word("slots", "4") == [
        "slot 0: X+3 Y-1 RUNNING buf 2", "slot 1: X+3 Y-1 RUNNING buf 1",
        "slot 2: X+3 Y-1 RUNNING buf 0", "slot 3: X+0 Y+0 RUNNING buf 0"]
    assert con.repl_word("plan", "X") == ["X stands still"]
    requests = con.repl_word("requests", "")
    assert requests is not None and "0x85 0xff PK_PEv2_BufferFill [C] reference 6, 8" in requests
    assert con.after_reset() == [
        "reset: PoKeys57CNC powered up, pulse engine STOPPED, buffer empty"]


def test_slot_trace_csv_and_plot(tmp_path: Path) -> None:
    dev, con = console_of()
    csv_path, png = tmp_path / "slots.csv", tmp_path / "slots.png"
    assert con.repl_word("trace", str(csv_path)) == [f"trace: {csv_path}"]
    run(con, "setup 2", "axis X buffer", "axis Y buffer", "fill 5 -2 x 50", "state running")
    dev.advance(0.060)
    assert con.repl_word("trace", "off") == ["trace: 60 slots written"]
    rows = list(csv.reader(csv_path.read_text().splitlines()))
    assert rows[0][:8] == ["slot", "time_s", "engine_state", "buffer_fill", "X_pulses",
                           "X_dir", "X_position", "X_state"]
    assert rows[1][:8] == ["0", "0.000", "RUNNING", "49", "5", "0", "5", "2"]
    assert rows[50][:8] == ["49", "0.049", "RUNNING", "0", "5", "0", "250", "1"]
    assert rows[51][:8] == ["50", "0.050", "RUNNING", "0", "0", "0", "250", "1"]
    assert rows[50][9] == "1"  # Y's direction pin: negative
    pytest.importorskip("matplotlib")
    assert con.repl_word("plot", str(png)) == [f"plot: {png}"]
    assert png.stat().st_size > 1000


def test_the_repl_takes_a_pokeys_through_the_registry() -> None:
    session = ReplSession("PoKeys57CNC", manual_time=True)
    assert session.handle("setup 1") == []
    assert session.handle("axis X buffer") == []
    assert session.handle("fill 7 x 10") == ["accepted 10 of 10, buffer 10/128"]
    assert session.handle("state running") == []
    assert session.handle(":run 1 s") == ["idle at tick 10"]
    assert session.handle(":status")[1] == "X 70 READY"
    assert session.handle(":advance 5 ms") == ["tick 15"]
    assert session.handle(":reset") == [
        "reset: PoKeys57CNC powered up, pulse engine STOPPED, buffer empty"]
    assert session.handle("pos") == ["no axes enabled (setup N)"]
    assert "PoKeys's own words:" in session.handle("help")


def test_a_command_script_with_a_pokeys_board() -> None:
    script = parse_script(
        "@board PoKeys57CNC\n"
        "setup 1\naxis X buffer\nfill 2 x 100\n< accepted 100 of 100, buffer 100/128\n"
        "state running\n@wait until idle within 1 s\npos\n< X 200\n"
        "@expect X position 200\n")
    transcript = run_script(script)
    assert transcript.failures == []  # @expect speaks to the PoKeys's axes too
    assert transcript.board is not None and transcript.board.engine.tick == 100


def test_datagram_sessions_and_discovery() -> None:
    dev = PoKeys("PoKeys56E")
    udp = dev.open_datagram_session()
    udp.feed(b"")
    reply = udp.read()
    assert len(reply) == 14 and reply[1] << 8 | reply[2] == 27431
    status = make_request(0x80, 0x30, request_id=9)
    udp.feed(status[:63])  # a short datagram is ignored whole...
    assert udp.read() == b""
    udp.feed(status)  # ...and cannot misalign the next
    out = udp.read()
    assert len(out) == 64 and out[6] == 9 and tuple(out[8:12]) == (3, 25, 128, 1)
    tcp = dev.open_session()
    tcp.feed(status[:63])
    tcp.feed(status[63:])
    assert tcp.read()[6] == 9
    tcp.close()
    tcp.feed(status)
    assert tcp.read() == b""


def test_position_counters_wrap_at_32_bits_as_the_device_reports_them() -> None:
    """A speed-mode run of a day at 100 kHz passes 2^31 pulses: the status reply carries
    the device's 32-bit counters, wrapped (D), where packing used to fail the request; the
    motion keeps every pulse."""
    dev, console = console_of()
    assert run(console, "setup 3", "axis X internal speed max 3.4e38 accel 3.4e38 decel 1",
               "state running", "move X 100000") == []
    assert console.new_errors() == []
    dev.advance(1e5)
    pulses = dev.device.engine.positions()[0]
    assert pulses > 2**32
    wrapped = (pulses + 2**31) % 2**32 - 2**31
    assert run(console, "pos") == [f"X {wrapped} Y 0 Z 0"]
    assert console.new_errors() == []

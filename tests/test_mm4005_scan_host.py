"""The trajectory scan's Build, Execute and Readback over a real TCP socket to the server
`maxk serve` runs (in-process, virtual time), checked against an independent computation
of where each pulse must find the axes."""

from __future__ import annotations

import math

from tests.hosting import HostedBoards
from tests.mm4005_scan_host import ScanHost, circle


def test_scan_build_execute_readback_100_elements_2_axes() -> None:
    hosted = HostedBoards(models=("MM4005-2",))
    host = ScanHost(hosted.ports[0])
    try:
        traj = circle(100)
        assert host.build(traj, 0.05, 100) == "TB@ No error"
        host.move_to_start(traj, lambda: hosted.advance(0.1))
        assert host.query("TP") == "1TP2.0000,2TP0.0000"
        status = host.execute(lambda: hosted.advance(0.25), 2)
        assert status == "Success"
        back = host.readback(2)
        assert len(back) == 100
        for i, pairs in enumerate(back):
            # pulse i (0-based) fires at the start of element i+1: the axes are at point i,
            # theoretical exact to the printed digit, actual within one count (0.001)
            for a in range(2):
                th, tp = pairs[a]
                assert math.isclose(th, round(traj[a][i], 4), abs_tol=1.5e-4), (i, a, th)
                assert abs(tp - traj[a][i]) <= 0.0011, (i, a, tp)
        assert host.query("XC1") == "XC100"
        assert host.query("TB") == "TB@ No error"
    finally:
        host.sock.close()
        hosted.close()


def test_lf_hosts_are_answered_over_tcp() -> None:
    hosted = HostedBoards(models=("MM4005-2",))
    try:
        for end in (b"\n", b"\r\n", b"\r"):
            host = ScanHost(hosted.ports[0])
            host.sock.sendall(b"ve" + end + b"1tp,2TP" + end)
            data = b""
            while data.count(b"\r") < 3:
                data += host.sock.recv(4096)
            assert data == b"VE MM4005 Version 2.42\r1TP0.0000\r2TP0.0000\r"
            host.sock.close()
    finally:
        hosted.close()

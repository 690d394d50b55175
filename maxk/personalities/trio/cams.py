"""CAMBOX as its help page gives it: link options, pattern mode and multi-axis loading.

`cambox_from` turns a CAMBOX's arguments into a `link_kinds.Cambox` (refusing, before anything
is loaded, what the page does not allow); `next_pattern` steps a pattern-mode CAMBOX's
control block at the end of each shape, as the page's control-block table says.

Link options (bits of the 6th argument, the CAMBOX page of the TrioBASIC help):
bit 0 starts on the link axis's MARK, bit 8 on its MARKB, bit 9 on R_MARK (link pos is
the channel); bit 1 starts at the absolute link position `link pos`; bit 2 repeats both
ways until REP_OPTION bit 1 is set; bit 3 is pattern mode (the third argument is then the
control block); bit 7 starts the profile `offset start` into the link distance; bit 13
follows the link axis's DPOS (the model always follows the demand: an MC405 stepper's
MPOS is its DPOS); bit 5 follows only the link's forward movement, bit 14 only its
forward movement past the highest position it reached (`link_kinds.Follow`). The reserved
bits are refused (D).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from maxk.firmware_model.profiles import Motion, Phase, RampShape

from .link_kinds import Cambox, Follow
from .runs import Run

MARK_START, ABSOLUTE, REPEAT, PATTERN = 1, 2, 4, 8
OFFSET_START, MARKB_START, R_MARK_START, FOLLOW_DPOS = 128, 256, 512, 8192
FORWARD_ONLY, THRESHOLD = 32, 16384
MODELLED = MARK_START | ABSOLUTE | REPEAT | PATTERN | OFFSET_START | MARKB_START \
    | R_MARK_START | FOLLOW_DPOS | FORWARD_ONLY | THRESHOLD
MULTI_AXIS_FIELDS = 8  # TABLE values per axis in the multi-axis loading form
CONTROL_BLOCK = 7  # TABLE values of a pattern-mode control block


def cambox_from(args: Sequence[float], read_table: Callable[[int], float],
                read_run: Callable[[int, int], Sequence[float]]) -> Cambox:
    """A CAMBOX from its arguments; ValueError ('Parameter out of range') for anything
    the page does not allow or the model does not hold. The link axis is checked by
    the caller."""
    start, end, multiplier, distance, link_axis = args[:5]
    options = args[5] if len(args) > 5 else 0.0
    link_pos = args[6] if len(args) > 6 else 0.0
    offset = args[7] if len(args) > 7 else 0.0
    if options != int(options) or not 0 <= options < 1 << 15 or int(options) & ~MODELLED:
        raise ValueError("Parameter out of range")
    bits = int(options)
    if distance <= 0 or start != int(start) or end != int(end) or end <= start:
        raise ValueError("Parameter out of range")
    starts = [b for b in (MARK_START, ABSOLUTE, MARKB_START, R_MARK_START) if bits & b]
    if len(starts) > 1:
        raise ValueError("Parameter out of range")  # one start event (D)
    if bits & OFFSET_START and not 0 <= offset < distance:
        raise ValueError("Parameter out of range")
    values = np.array(read_run(int(start), int(end)), dtype=float)
    pattern = None
    if bits & PATTERN:
        pattern = _index(multiplier)
        block = [read_table(pattern + k) for k in range(CONTROL_BLOCK)]
        multiplier = read_table(_index(block[0]))
    if bits & FORWARD_ONLY and bits & THRESHOLD:
        raise ValueError("Parameter out of range")  # (D)
    follow = Follow("forward") if bits & FORWARD_ONLY else \
        Follow("threshold") if bits & THRESHOLD else None
    cam = Cambox(values, multiplier, distance, int(link_axis), None, 0.0,
                 repeat=bool(bits & REPEAT) and pattern is None,
                 offset=offset if bits & OFFSET_START else 0.0, pattern=pattern,
                 follow=follow, table_start=int(start))
    if bits & MARK_START:
        cam.wait = "MARK"
    elif bits & MARKB_START:
        cam.wait = "MARKB"
    elif bits & R_MARK_START:
        cam.channel = _index(link_pos)
        if cam.channel >= 8:
            raise ValueError("Parameter out of range")  # R_MARK channels 0..7 (C)
        cam.wait = f"R_MARK{cam.channel}"
    cam.start_pos = link_pos if bits & ABSOLUTE else None
    return cam


def retable(cams: Sequence[tuple[Cambox, float | None]], start: int, count: int,
            read_run: Callable[[int, int], Sequence[float]]) -> bool:
    """TABLE(start, ...) wrote `count` values: every CAMBOX whose profile reads one of
    them takes the TABLE as it is now (its link's DPOS given for one that runs, None for
    one buffered). A running CAMBOX reads its TABLE live (C: the TABLE_POINTER page loads
    new cam data into the locations already passed, for the next cycle, while it runs);
    the values are positions from the profile's start (C: CAMBOX page), so the position
    of the cycle the link is in follows the new values at once, and the cycles already
    done keep what they moved (D). True if one changed."""
    touched = False
    for cam, link_dpos in cams:
        first, last = cam.table_start, cam.table_start + len(cam.values) - 1
        if start > last or start + count - 1 < first:
            continue
        if link_dpos is not None and cam.repeat and cam.link_origin is not None:
            # the whole cycles done go into the origin: they keep what they moved
            link = np.array([link_dpos])
            if cam.follow is not None:
                link = cam.follow.effective(link)
            cycles = math.floor((float(link[0]) - cam.link_origin) / cam.distance)
            if cam.held:
                cycles = max(cycles, 0)
            cam.origin += cycles * cam.span
            cam.link_origin += cycles * cam.distance
        raw = np.asarray(read_run(first, last), dtype=float)
        cam.values = raw - float(raw[0])  # (offset by the first, as loaded)
        touched = True
    return touched


def _index(value: float) -> int:
    if value != int(value) or value < 0:
        raise ValueError("Parameter out of range")
    return int(value)


def next_pattern(cam: Cambox, read: Callable[[int], float],
                 write: Callable[[int, float], None]) -> bool:
    """One shape of a pattern-mode CAMBOX ended with the link moving forward: step the
    control block (force position, wrap and count repeats, chain to the next block) and
    take the next scale. False: the CAMBOX is done."""
    assert cam.pattern is not None
    cb = cam.pattern
    forced = read(cb + 1)
    if forced != -1:
        position = forced
        write(cb + 1, -1.0)
    else:
        position = read(cb) + 1
    if position > read(cb + 3):
        position = read(cb + 2)
        repeats = read(cb + 4) + 1
        write(cb + 4, repeats)
        wanted = read(cb + 5)
        if wanted != -1 and abs(repeats) >= wanted:
            following = read(cb + 6)
            if following == -1:
                return False
            cb = cam.pattern = _index(following)
            position = read(cb)
    write(cb, position)
    cam.origin += cam.span  # this shape's end is the next one's start (no drift)
    assert cam.link_origin is not None
    cam.link_origin += cam.distance
    cam.multiplier = read(_index(position))
    return True


def multi_axis(table_start: int, count: int, read: Callable[[int], float]
               ) -> list[list[float]]:
    """The multi-axis loading form CAMBOX(table start, axis count): each axis's eight
    arguments from consecutive TABLE values."""
    if count != int(count) or count < 1:
        raise ValueError("Parameter out of range")
    return [[read(table_start + MULTI_AXIS_FIELDS * k + j) for j in range(MULTI_AXIS_FIELDS)]
            for k in range(int(count))]


def cam_motion(args: Sequence[float], read_run: Callable[[int, int], Sequence[float]],
               speed: float, units: float) -> Motion:
    """CAM(start, end, multiplier, distance): the TABLE values start..end (offset by the
    first, times the multiplier, counts) followed in time, the whole profile taking
    distance / SPEED seconds (distance in the axis's user units, SPEED when it loads: I,
    the MC206 manual's CAM page as recalled): one constant-speed phase per TABLE
    interval, so every tick's position is the linear interpolation. It ends on the
    profile's last value rounded to a whole count (D)."""
    if len(args) != 4:
        raise ValueError("Syntax error")
    start, end, multiplier, distance = args
    if start != int(start) or end != int(end) or end <= start or not distance > 0 \
            or not speed > 0:
        raise ValueError("Parameter out of range")
    values = np.array(read_run(int(start), int(end)), dtype=float)
    return cam_profile(values, multiplier, distance * units / speed)


def cam_profile(values: np.ndarray, multiplier: float, duration: float) -> Motion:
    """The CAM's profile over `duration` seconds: one constant-speed phase per TABLE
    interval (cam_motion)."""
    counts = multiplier * (values - values[0])
    if not (np.all(np.isfinite(counts)) and np.max(np.abs(counts)) < 2.0 ** 53
            and np.isfinite(duration)):
        raise ValueError("Parameter out of range")
    step = duration / (len(counts) - 1)
    if not (step > 0 and np.isfinite(np.max(np.abs(np.diff(counts))) / step)):
        raise ValueError("Parameter out of range")  # (D: a speed no double holds)
    phases = []
    for i in range(len(counts) - 1):
        delta = float(counts[i + 1] - counts[i])
        phases.append(Phase(i * step, step, float(counts[i]), abs(delta) / step,
                            abs(delta) / step, 1 if delta >= 0 else -1, RampShape.LINEAR))
    final = round(float(counts[-1]))
    return Motion(phases, duration, final, duration, 1 if final >= 0 else -1)


def recam(run: Run, start: int, count: int,
          read_run: Callable[[int, int], Sequence[float]]) -> Motion | None:
    """TABLE(start, ...) wrote `count` values: a CAM that reads one of them takes the
    TABLE as it is now, over the same time (as CAMBOX's: the TABLE is read live, the
    values positions from the CAM's start, C: CAM and TABLE_POINTER pages); its new
    profile, or None if it reads none of them (or is being stopped)."""
    if run.table is None or run.cam is None or run.stopping or run.preset is None \
            or run.preset.end_time is None:
        return None
    last, multiplier = run.cam
    if start > last or start + count - 1 < run.table:
        return None
    values = np.array(read_run(run.table, last), dtype=float)
    try:
        profile = cam_profile(values, multiplier, run.preset.end_time)
    except ValueError:
        return None  # (a value no double holds: the CAM keeps its profile, D)
    run.preset = profile
    run.deltas[0] = (profile.final_offset,)
    return profile


def cam_pointer(run: Run, elapsed: float) -> float:
    """TABLE_POINTER of a running CAM `elapsed` seconds in: each TABLE interval takes an
    equal share of its time (cam_motion), so the index of the one it is in plus the share
    of it done (help TABLE_POINTER)."""
    assert run.table is not None and run.profile is not None
    intervals = len(run.profile.phases)
    step = run.profile.phases[0].duration  # (every interval the same: cam_motion)
    return run.table + min(max(elapsed / step, 0.0), float(intervals))


__all__ = ["cam_motion", "cam_pointer", "cambox_from", "multi_axis", "next_pattern", "recam",
           "retable"]

"""TIMER and SCOPE: outputs set for a time, and parameters sampled into TABLE, each on
its own servo cycles (their help pages). The runtime wakes for the next one
(`next_timer`) and runs them before the processes of the cycle (`run_timers`).

SCOPE_DELAY (its page), read at TRIGGER: above 0, the capture starts that many ms after
the TRIGGER; below 0, up to that many ms of samples from before the TRIGGER are stored
first. An armed scope samples every period while SCOPE_DELAY is negative, keeping the last
block (D: the page's pre-trigger needs samples from before it; SCOPE's example 5 sets the
delay after SCOPE). Fewer taken than asked: those are stored, and SCOPE_TRIGGER_POS says
where the trigger fell: the 1-based place of the trigger's sample in each block (I: the
page's example prints TABLE table_start - 1 + SCOPE_TRIGGER_POS), 0 after a delayed one
(D: its trigger came before the first sample). At most block - 1 samples from before: the
trigger's own is always stored (D); an automatic TRIGGER's later scans have none (D)."""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field

from ...personalities.trio.memory import TABLE_SIZE
from .interpreter import Interpreter, ProcessContext, Value, number_arg
from .lexer import TrioError
from .machine import TrioMachine
from .parser import Expr


@dataclass
class Scope:
    """SCOPE(ON, period, table_start, table_stop, p0 ...): what it samples, where to.
    Each parameter has its own block of (stop - start + 1) // n TABLE values: table_stop
    is the last index used (SCOPE_DELAY's examples: 10001..10800 holds 4 traces of 200
    from 10001, 10201, 10401 and 10601; 10001..12000, 1000 points on 2; SCOPE's example
    1: two parameters over 0..1000 fill 0..499 and 500..999)."""

    period: int  # servo cycles between samples
    start: int
    block: int  # samples each parameter has room for
    params: list[Expr]
    ctx: ProcessContext  # the axes BASE names when SCOPE was set
    next_tick: int | None = None  # the next sample (None: not triggered, or done)
    taken: int = 0  # samples stored since TRIGGER
    repeat: bool = False  # TRIGGER(1): starts again at the end of each scan
    early: deque[tuple[int, list[float]]] = field(default_factory=deque)  # samples
    # before TRIGGER, with their ticks
    early_tick: int = 0  # the next one's tick (taken while SCOPE_DELAY is negative)


class TimersAndScope:
    """TIMER and SCOPE handlers; the attributes are the runtime's own."""

    machine: TrioMachine
    interpreter: Interpreter | None
    scope: Scope | None
    scope_cycles: int
    scope_trigger_pos: int
    timers: dict[int, tuple[int, list[int], bool]]

    def cmd_timer(self, args: list[Value]) -> None:
        """TIMER(slot, output, pattern, time[, option]): outputs on (option 0) or off
        (option 1) now, back after `time` ms (TIMER's page); pattern 1 is the output
        alone, another number a bit array of outputs from `output` up. The time is
        rounded up to whole servo cycles (D, as WA); a slot set again while it runs
        starts over (D)."""
        slot, first, pattern, ms = (number_arg(a) for a in args[:4])
        option = number_arg(args[4]) if len(args) > 4 else 0.0
        period = self.machine.servo_period_us()
        if not (0 <= slot <= 127 and 0 <= first <= 255 and 0 <= pattern <= 65535
                and 0 <= ms <= 1e9 and option in (0, 1)) or \
                any(v != int(v) for v in (slot, first, pattern)):
            raise TrioError("Parameter out of range")
        outputs = [int(first) + k for k in range(16) if int(pattern) >> k & 1]
        if any(n > 255 for n in outputs):
            raise TrioError("Parameter out of range")
        start_level = option == 0
        for n in outputs:
            self.machine.set_output(n, start_level)
        ticks = -(-int(ms * 1000) // period)
        self.timers[int(slot)] = (self.machine.servo_tick() + ticks, outputs, not start_level)
        self.run_timers()

    def set_scope(self, args: list[float], params: list[Expr], ctx: ProcessContext) -> None:
        """SCOPE(OFF); SCOPE(ON, period): a new period; SCOPE(ON, period, start, stop,
        p0[, ... p7]): arm a capture of up to 8 parameters (SCOPE's page)."""
        if args[0] == 0:
            self.scope = None
            return
        period = args[1] if len(args) > 1 else 1.0
        if period != int(period) or not 1 <= period <= 1e6:
            raise TrioError("Parameter out of range")
        if len(args) == 2:
            if self.scope is None:
                raise TrioError("Parameter out of range")
            self.scope.period = int(period)
            return
        if len(args) != 4 or not 1 <= len(params) <= 8:
            raise TrioError("Syntax error")
        start, stop = args[2], args[3]
        if start != int(start) or stop != int(stop) or not 0 <= start <= stop < TABLE_SIZE:
            raise TrioError("Parameter out of range")
        block = int(stop - start + 1) // len(params)
        if block < 1:
            raise TrioError("Parameter out of range")
        self.scope = Scope(int(period), int(start), block, params,
                           ProcessContext(process=ctx.process, base=list(ctx.base)),
                           early=deque(maxlen=block - 1),
                           early_tick=self.machine.servo_tick())
        self.run_timers()  # (a sample before TRIGGER: from this cycle on, as TRIGGER's)

    def trigger(self, repeat: bool) -> None:
        """TRIGGER[(auto)]: the armed SCOPE samples from this servo cycle on (D: the
        first sample is taken on the trigger's own cycle)."""
        scope = self.scope
        if scope is None:
            return  # (disabled: TRIGGER starts nothing, the page's example 2)
        now = self.machine.servo_tick()
        scope.next_tick, scope.taken, scope.repeat = now, 0, repeat
        delay = self.machine.system_parameter("SCOPE_DELAY")  # ms
        samples = math.ceil(abs(delay) * 1000 / self.machine.servo_period_us())
        if delay > 0:  # the capture starts later
            scope.next_tick = now + samples
            self.scope_trigger_pos = 0
        else:  # the samples taken before, as many as it asks for and has
            before = [values for tick, values in scope.early if tick < now]
            wanted = math.ceil(samples / scope.period) if delay < 0 else 0
            kept = before[len(before) - min(wanted, len(before)):]
            for scope.taken, values in enumerate(kept, start=1):
                for i, value in enumerate(values):
                    self.machine.table_write(scope.start + i * scope.block + scope.taken - 1,
                                             [value])
            self.scope_trigger_pos = scope.taken + 1
        scope.early.clear()
        self.scope_cycles += 1
        self.run_timers()

    def scope_position(self) -> float:
        """SCOPE_POS: where in each parameter's block the capture stores its next sample,
        from 0 at TRIGGER: the samples stored so far, the block's size once it is full
        (I: SCOPE_DELAY's examples wait for SCOPE_POS = 200 and = 1000, the points each
        trace holds, to know the capture is complete)."""
        scope = self.scope
        return float(scope.taken) if scope is not None else 0.0

    def next_timer(self) -> int | None:
        """The tick the next TIMER ends or the SCOPE samples (None: neither)."""
        ticks = [end for end, _o, _l in self.timers.values()]
        if self.scope is not None and self.scope.next_tick is not None:
            ticks.append(self.scope.next_tick)
        elif self._early_due():
            assert self.scope is not None
            ticks.append(self.scope.early_tick)
        return min(ticks, default=None)

    def _early_due(self) -> bool:
        """An armed scope not triggered samples while SCOPE_DELAY is negative."""
        scope = self.scope
        return scope is not None and scope.next_tick is None and \
            scope.early.maxlen != 0 and self.machine.system_parameter("SCOPE_DELAY") < 0

    def _sample(self, now: int) -> None:
        scope = self.scope
        if scope is not None and self._early_due() and scope.early_tick <= now:
            assert self.interpreter is not None
            scope.early.append((now, [self.interpreter.number(p, scope.ctx)
                                      for p in scope.params]))
            scope.early_tick = now + scope.period
        if scope is None or scope.next_tick is None or scope.next_tick > now:
            return
        assert self.interpreter is not None
        values = [self.interpreter.number(p, scope.ctx) for p in scope.params]
        for i, value in enumerate(values):
            self.machine.table_write(scope.start + i * scope.block + scope.taken, [value])
        scope.taken += 1
        if scope.taken < scope.block:
            scope.next_tick = now + scope.period
        elif scope.repeat:
            scope.taken, scope.next_tick = 0, now + scope.period
            self.scope_cycles += 1
        else:
            scope.next_tick = None

    def run_timers(self) -> None:
        """End the TIMERs due by now (their outputs take their end level); take the
        SCOPE's sample due now."""
        now = self.machine.servo_tick()
        try:
            self._sample(now)
        except TrioError:
            self.scope = None  # a parameter it cannot read ends the capture (D)
        for slot, (end, outputs, level) in sorted(self.timers.items()):
            if end <= now:
                del self.timers[slot]
                for n in outputs:
                    self.machine.set_output(n, level)



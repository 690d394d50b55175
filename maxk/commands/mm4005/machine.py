"""What the MM4005 language needs from the machine below it.

Axes are numbered from 1 (the language has already checked the number). Positions,
velocities and limits are in the axis's user units. Methods that the firmware may refuse
raise maxk.personalities.mm4005.MM4005Error; the language stores the code for TE/TB.
Time belongs to the machine: the door advances it before feeding bytes in.
"""

from __future__ import annotations

from typing import Protocol

from maxk.personalities.mm4005 import AxisStatus, Trajectory, TrajectoryRun
from maxk.personalities.mm4005.io import GpioPort
from maxk.personalities.mm4005.programs import ProgramStore, Tasks, Variables
from maxk.personalities.mm4005.settings import AxisSettings
from maxk.personalities.mm4005.timed import PulseTrace, TimedTrajectory
from maxk.personalities.mm4005.trace_mode import AxisTrace, GlobalTrace


class MM4005Machine(Protocol):
    """An MM4005 controller's axes, trajectory store and time, as the language uses them."""

    @property
    def axis_count(self) -> int:
        """Installed axes (the all-axes replies list this many)."""
        ...

    @property
    def version(self) -> str:
        """VE text after 'VE ', e.g. 'MM4005 Version 2.42' (must contain MM4005)."""
        ...

    @property
    def tick(self) -> int:
        """Virtual time in ticks of ``tick_period`` seconds."""
        ...

    @property
    def tick_period(self) -> float: ...

    @property
    def trajectory_base_period(self) -> float:
        """Tbase of the MPN formula, seconds."""
        ...

    @property
    def trajectory(self) -> Trajectory:
        """The trajectory definition and pulse settings (personality state)."""
        ...

    def position(self, axis: int) -> float:
        """TP: actual position."""
        ...

    def theoretical_position(self, axis: int) -> float:
        """TH: where the profile generator says the axis is."""
        ...

    def target(self, axis: int) -> float:
        """DP: destination of the current or last motion."""
        ...

    def velocity(self, axis: int) -> float: ...

    def set_velocity(self, axis: int, value: float) -> None: ...

    def acceleration(self, axis: int) -> float: ...

    def set_acceleration(self, axis: int, value: float) -> None: ...

    def resolution(self, axis: int) -> float:
        """TU: the axis's step (encoder resolution), user units."""
        ...

    def loop_type(self, axis: int) -> int:
        """TC: 0 open loop, non-zero closed loop (EPICS: atoi(reply+3) != 0)."""
        ...

    def travel_limits(self, axis: int) -> tuple[float, float]:
        """(TL, TR): left and right software travel limits."""
        ...

    def set_travel_limits(self, axis: int, left: float, right: float) -> None: ...

    def home_preset(self, axis: int) -> float:
        """XH: the position the axis reads after a home search or DH."""
        ...

    def set_home_preset(self, axis: int, value: float) -> None: ...

    def define_home(self, axis: int, limits: tuple[float, float]) -> None:
        """DH: the current position becomes the home preset; the limits move along."""
        ...

    def set_power(self, axis: int, on: bool) -> None:
        """MO (True) / MF (False); motor power off also stops the axis."""
        ...

    def status(self, axis: int) -> AxisStatus:
        """MS bits for the axis."""
        ...

    def move_to(self, axis: int, position: float) -> None:
        """Start a point-to-point move at the axis's VA and AC."""
        ...

    def stop(self, axis: int) -> None:
        """ST: decelerate to a stop at AC."""
        ...

    def search_home(self, axis: int, mode: int) -> None:
        """OR: start a home search (mode as given to OR, 0 by default)."""
        ...

    def start_trajectory(self, run: TrajectoryRun) -> None:
        """ET accepted: run the path on the X and Y axes, pulses included."""
        ...

    def trajectory_element(self) -> int:
        """AT: the element under execution, 0 when no trajectory runs."""
        ...

    @property
    def timed(self) -> TimedTrajectory:
        """The time-based trajectory definition (NC/DC/UC/DT/DX/MB/ME/MN/GC)."""
        ...

    @property
    def pulse_trace(self) -> PulseTrace:
        """The last run's pulses (a bounded ring): NQ, TQ."""
        ...

    @property
    def settings(self) -> list[AxisSettings]:
        """Each axis's stored settings the motion does not read (index axis - 1)."""
        ...

    def verify_timed(self) -> None:
        """VC."""
        ...

    def input_level(self, bit: int) -> bool:
        """RB: the level of GPIO input bit 1..8, as the world around the controller sets it."""
        ...

    @property
    def gpio(self) -> GpioPort:
        """SB, RA: the outputs and analog inputs, on the world (personalities/mm4005/io.py)."""
        ...

    @property
    def global_trace(self) -> GlobalTrace:
        """GQ/SQ: the global trace acquisition into the buffer NQ/TQ read."""
        ...

    @property
    def axis_trace(self) -> AxisTrace:
        """TM/SP: one axis's trace into the memory TT and XN read."""
        ...

    def execute_timed(self, scale: float) -> None:
        """EC at a time scale."""
        ...

    def elements_done(self) -> int:
        """XC."""
        ...

    def desired_velocity(self, axis: int) -> float:
        """DV: the profile's velocity now, units/s."""
        ...

    def apply_gains(self, axis: int) -> None:
        """UF: the gains set take effect on the loop."""
        ...

    def take_errors(self) -> list[int]:
        """Axes whose following error turned their motor off since the last look."""
        ...

    def abort(self) -> None:
        """AB: every motion and trajectory stops at once."""
        ...

    @property
    def programs(self) -> ProgramStore:
        """The stored programs (EP ... QP, EX, XX) and their archive."""
        ...

    @property
    def tasks(self) -> Tasks:
        """The command lines held by a wait and the running program: resumed by the
        machine after each event tick (`Tasks.poll`)."""
        ...

    @property
    def variables(self) -> Variables:
        """The value variables $Y1..$Y120 (TY reads them; a command takes one in place
        of a value)."""
        ...

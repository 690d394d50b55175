"""Newport MM4005 personality: trajectory definition and ET verification (chapter 5.7),
pulses synchronized to a trajectory (6.1.2), the MS status byte and the error register.
Nothing here knows a wire format; maxk.commands.mm4005 is the language."""

from . import axis_rules
from .errors import ERROR_CODES, ErrorCode, ErrorRegister, MM4005Error
from .geometry import Arc, Line
from .pulses import PulsePlan, PulsePoint, PulsePoints, PulseSettings, maximum_pulse_number
from .status import AxisStatus
from .trajectory import Element, Trajectory, TrajectoryRun, VerifiedTrajectory

__all__ = ["ERROR_CODES", "Arc", "AxisStatus", "Element", "ErrorCode", "ErrorRegister", "Line",
           "MM4005Error", "PulsePlan", "PulsePoint", "PulsePoints", "PulseSettings", "Trajectory",
           "TrajectoryRun", "VerifiedTrajectory", "axis_rules", "maximum_pulse_number"]

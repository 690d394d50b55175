"""The Newport MM4005 command language: ``[xx]AA[nn]`` commands on CR-terminated lines,
echoing replies, the TE/TB error register (manual chapter 3), the trajectory and pulse
commands (5.7, 6.1.2). The session is what doors talk to."""

from .fake import FakeMM4005
from .machine import MM4005Machine
from .session import Interpreter, MM4005Session
from .spec import AxisRule, Command, CommandSpec, Operand
from .table import COMMANDS

__all__ = ["COMMANDS", "AxisRule", "Command", "CommandSpec", "FakeMM4005", "Interpreter",
           "MM4005Machine", "MM4005Session", "Operand"]

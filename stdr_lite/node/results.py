"""
How the simulation services answer: a standard Result, OK or a code with a reason.

A job raises Refusal to refuse (requests.py turns it into the response's result), so a refusal
is written once, where it is decided, and a refused call changes nothing.
"""

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from simulation_interfaces.msg import Result

# Requests are queued whole however many come at once: no burst loses one.
SERVICE_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
# StepSimulation answers once its steps are taken, so it is kept short; the SimulateSteps action
# takes more, up to a count that still ends (a day of sim time at 1000 Hz is 86.4 M steps).
MAX_SERVICE_STEPS = 10_000
MAX_ACTION_STEPS = 1_000_000_000


class Refusal(Exception):
    """A request refused with a standard result code."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


def result(code: int = Result.RESULT_OK, message: str = '') -> Result:
    """Return a simulation_interfaces Result: OK unless told otherwise."""
    return Result(result=code, error_message=message)

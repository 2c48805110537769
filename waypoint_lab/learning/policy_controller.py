"""
A policy learned in process, driving a robot of a live stdr_lite through ROS, unchanged.

PolicyController is the lab's runner (waypoint_lab/runner.py) with a learned policy as its
control law: from the robot's odometry and laser it builds the observation a WaypointsEnv
would give (task.observe) and asks the policy (any callable: observation -> (linear m/s,
angular rad/s)) for an action at the environment's rate, on odometry time. So it starts,
reports, aborts (a stall, a teleport) and answers in lockstep as waypoint_controller does, and
grade_lab grades it as any controller. The laser's rays are taken at the environment's angles
(the nearest ray of the scan to each): a scan of the same rays gives the same observation to
the bit. Each control tick waits for the scan of its period, so a run in lockstep is the same
run on any machine. As the executable policy_controller it drives with a trained policy file
(numpy_policy.py; the bundled one by default) through a waypoint file, as waypoint_controller
does.
"""

import numpy as np
from rclpy.time import Time
from sensor_msgs.msg import LaserScan
from simple_robot_control.validation import ConfigError
from stdr_lite.core.sensors import relative_angles
from waypoint_lab.learning.arena import laser_robot
from waypoint_lab.learning.numpy_policy import NumpyPolicy, PolicyFileError
from waypoint_lab.learning.task import observe, TaskSettings
from waypoint_lab.lifecycle import ControlLaw, RunRules
from waypoint_lab.parameters import POLICY_CONTROLLER_PARAMETERS
from waypoint_lab.runner import (CourseRunner, NOT_YET, READY, run_controller, run_rules,
                                 WAIT)


DESCRIPTION = ('policy_controller: drive a robot through a waypoint file with a learned policy '
               '(run with numpy alone), reporting on robot_status as the lab asks, for '
               'grade_lab as any controller. Exit code 0 when finished, 1 when aborted, 2 for '
               'bad input.')


def scan_at(scan: LaserScan, angles: np.ndarray) -> np.ndarray:
    """Return the scan's ranges at angles (the nearest ray to each); inf where none returned."""
    ranges = np.asarray(scan.ranges, dtype=float)
    if scan.angle_increment == 0.0 or not len(ranges):
        return np.full(angles.size, np.inf)
    index = np.rint((angles - scan.angle_min) / scan.angle_increment).astype(np.int64)
    index = np.clip(index, 0, len(ranges) - 1)
    picked = ranges[index]
    return np.where(np.isnan(picked) | (picked > scan.range_max), np.inf, picked)


class PolicyLaw:
    """A policy as the lab's control law: the observation from the latest ranges and the goal."""

    def __init__(self, policy, waypoints, max_range: float):
        self._policy, self._max_range = policy, max_range
        self._waypoints = np.asarray(waypoints, dtype=float).reshape(-1, 3)
        self._goal = self._waypoints[:1]
        self.ranges = None

    def aim(self, pose: tuple, index: int) -> None:
        self._goal = self._waypoints[index:index + 1]

    def command(self, pose: tuple, dt: float) -> tuple[float, float]:
        observation = observe(self.ranges[None, :], self._max_range,
                              np.asarray(pose, dtype=float)[None, :], self._goal)[0]
        return tuple(np.asarray(self._policy(observation), dtype=float).reshape(2))


class PolicyController(CourseRunner):
    """
    Drives the robot robot_name through waypoints ((x, y, theta radians) each) with policy.

    Without waypoints, they come from waypoint_file (or the parameter, or the bundled course);
    without a policy, the policy parameter's file is run. The task (goal set, laser rays,
    speeds) must be the one the policy learned on, rate_hz its control rate; robot is the robot
    file it learned with (its first laser's span and range are the observation's).
    """

    def __init__(self, policy=None, waypoints=None, task: TaskSettings = TaskSettings(),
                 robot: str = '', laser: str = 'laser_0', rate_hz: float = 10.0,
                 waypoint_file: str | None = None, **kwargs):
        spec = laser_robot(robot, task.laser_rays).lasers[0]
        self._angles = relative_angles(spec)
        self._scan_period_ns = round(1e9 / spec.frequency)
        self._policy, self._task, self._rate_hz = policy, task, rate_hz
        self._max_range = spec.max_range
        self._scan_stamp = None
        super().__init__('policy_controller', POLICY_CONTROLLER_PARAMETERS, waypoint_file,
                         waypoints, **kwargs)
        self._scan_topic = self.create_subscription(
            LaserScan, f'{self.params["robot_name"]}/{laser}', self._on_scan, 10).topic_name

    def build_law(self, params: dict, waypoints: list) -> tuple[ControlLaw, RunRules]:
        policy = self._policy
        if policy is None:
            try:
                policy = NumpyPolicy(params['policy'] or None)
            except PolicyFileError as error:
                raise ConfigError(str(error)) from None
        self._law = PolicyLaw(policy, [tuple(waypoint) for waypoint in waypoints],
                              self._max_range)
        task = self._task
        return self._law, run_rules(params, max_linear_speed=task.max_linear_speed,
                                    max_angular_speed=task.max_angular_speed,
                                    control_period_ns=round(1e9 / self._rate_hz))

    def inputs_ready(self, stamp_ns: int) -> str:
        """Act once a scan came, each time on the scan of the laser's period up to stamp_ns."""
        if self._scan_stamp is None:
            return NOT_YET
        return READY if self._scan_stamp > stamp_ns - self._scan_period_ns else WAIT

    def waiting_for(self) -> str:
        return f'a scan on {self._scan_topic}'

    def _on_scan(self, message):
        stamp = Time.from_msg(message.header.stamp).nanoseconds
        if self._scan_stamp is not None and stamp < self._scan_stamp:
            return
        self._scan_stamp = stamp
        self._law.ranges = scan_at(message, self._angles)
        self.answer_waiting()


def main(argv: list[str] | None = None) -> None:
    run_controller('policy_controller', DESCRIPTION, POLICY_CONTROLLER_PARAMETERS,
                   lambda waypoint_file: PolicyController(waypoint_file=waypoint_file), argv)


if __name__ == '__main__':
    main()

"""
A policy learned in process, driving a robot of a live stdr_lite through ROS, unchanged.

PolicyController is a node: from the robot's odometry and laser it builds the observation a
WaypointsEnv would give (task.observe), asks the policy (any callable: observation ->
(linear m/s, angular rad/s)) for an action at the environment's rate, sends it as cmd_vel, and
reports on robot_status as the lab asks (status.py's texts, interface.py's QoS), so that
grade_lab can grade it as it grades a student's controller. The laser's rays are taken at the
environment's angles (the nearest ray of the scan to each): a scan of the same rays gives the same
observation to the bit. As the executable policy_controller it drives with a trained policy
file (numpy_policy.py; the bundled one by default) through a waypoint file, as
waypoint_controller does.
"""

import sys
import time

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry, Path
import numpy as np
from rclpy.task import Future
from sensor_msgs.msg import LaserScan
from simple_robot_control.graph import deliver_before_exit, DISCOVERY_TIME
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.pose import pose_from_message
from simple_robot_control.validation import ConfigError
from std_msgs.msg import String
from stdr_lite.core.sensors import relative_angles
from waypoint_lab import status
from waypoint_lab.interface import course_message, load_course, status_qos
from waypoint_lab.learning.arena import laser_robot
from waypoint_lab.learning.numpy_policy import NumpyPolicy, PolicyFileError
from waypoint_lab.learning.task import Courses, observe, TaskSettings
from waypoint_lab.parameters import POLICY_CONTROLLER_PARAMETERS
from waypoint_lab.rules import COURSE_TOPIC, STATUS_TOPIC
from waypoint_lab.waypoints import Waypoint


DESCRIPTION = ('policy_controller: drive a robot through a waypoint file with a learned policy '
               '(run with numpy alone), reporting on robot_status as the lab asks, for '
               'grade_lab as any controller.')


def scan_at(scan: LaserScan, angles: np.ndarray) -> np.ndarray:
    """Return the scan's ranges at angles (the nearest ray to each); inf where none returned."""
    ranges = np.asarray(scan.ranges, dtype=float)
    if scan.angle_increment == 0.0 or not len(ranges):
        return np.full(angles.size, np.inf)
    index = np.rint((angles - scan.angle_min) / scan.angle_increment).astype(np.int64)
    index = np.clip(index, 0, len(ranges) - 1)
    picked = ranges[index]
    return np.where(np.isnan(picked) | (picked > scan.range_max), np.inf, picked)


class PolicyController(GuardedNode):
    """
    Drives the robot robot_name through waypoints ((x, y, theta radians) each) with policy.

    Without waypoints, they come from waypoint_file (or the parameter, or the bundled course);
    without a policy, the policy parameter's file is run. The task (goal set, laser rays,
    speeds) must be the one the policy learned on; robot is the robot file it learned with (its
    first laser's span and range are the observation's). finished completes with 0 on FINISHED.
    """

    def __init__(self, policy=None, waypoints=None, task: TaskSettings = TaskSettings(),
                 robot: str = '', laser: str = 'laser_0', rate_hz: float = 10.0,
                 waypoint_file: str | None = None, **kwargs):
        super().__init__('policy_controller', **kwargs)
        self.finished = Future()
        self._alive_since = time.monotonic()
        params = declare_parameters(self, POLICY_CONTROLLER_PARAMETERS)
        robot_name = params['robot_name']
        if waypoints is None:
            _, course = load_course(self, waypoint_file, params['waypoint_file'])
            waypoints = [tuple(waypoint) for waypoint in course]
        if policy is None:
            try:
                policy = NumpyPolicy(params['policy'] or None)
            except PolicyFileError as error:
                raise ConfigError(str(error)) from None
        self._policy, self._task = policy, task
        spec = laser_robot(robot, task.laser_rays).lasers[0]
        self._angles, self._max_range = relative_angles(spec), spec.max_range
        self._courses = Courses(np.asarray(waypoints, dtype=float)[None, :, :], task)
        self._pose = self._scan = None
        self._started = False
        self._command = self.create_publisher(Twist, f'{robot_name}/cmd_vel', 10)
        self._status = self.create_publisher(String, STATUS_TOPIC,
                                             status_qos(len(self._courses.waypoints[0])))
        # The course, as the lab's controller publishes it (latched), for recorders and plots.
        self._course = self.create_publisher(Path, COURSE_TOPIC, status_qos(0))
        self._course.publish(course_message([Waypoint(*waypoint) for waypoint in waypoints],
                                            'map'))
        self.create_subscription(Odometry, f'{robot_name}/odom', self._on_odometry, 10)
        self.create_subscription(LaserScan, f'{robot_name}/{laser}', self._on_scan, 10)
        self.create_timer(1.0 / rate_hz, self._act)

    def _on_odometry(self, message):
        self._pose = np.array(pose_from_message(message.pose.pose))

    def _on_scan(self, message):
        self._scan = message

    def _say(self, text):
        self._status.publish(String(data=text))
        self.get_logger().info(text)

    def _act(self):
        if self._pose is None or self._scan is None or self.finished.done():
            return
        poses = self._pose[None, :]
        if not self._started:
            self._started = True
            self._courses.start(poses)
            self._say(status.started(tuple(self._pose)))
        _, reached, finished = self._courses.update(poses, np.zeros(1, dtype=bool))
        if reached[0]:
            self._say(status.waypoint_reached(int(self._courses.next[0]), tuple(self._pose)))
        if finished[0]:
            self._command.publish(Twist())
            self._say(status.finished())
            self.finished.set_result(0)
            return
        ranges = scan_at(self._scan, self._angles)[None, :]
        observation = observe(ranges, self._max_range, poses, self._courses.goals)[0]
        linear, angular = np.clip(np.asarray(self._policy(observation), dtype=float),
                                  [-self._task.max_linear_speed, -self._task.max_angular_speed],
                                  [self._task.max_linear_speed, self._task.max_angular_speed])
        twist = Twist()
        twist.linear.x, twist.angular.z = float(linear), float(angular)
        self._command.publish(twist)

    def shut_down(self):
        """Stop the robot; let every reader of robot_status have the run's last words."""
        self._command.publish(Twist())
        deliver_before_exit(self, self._status, self._alive_since, DISCOVERY_TIME)


def main(argv=None):
    parser = build_parser('policy_controller', DESCRIPTION,
                          POLICY_CONTROLLER_PARAMETERS)
    parser.add_argument('waypoint_file', nargs='?', metavar='WAYPOINT_FILE',
                        help='waypoint file; the waypoint_file parameter is the alternative')
    sys.exit(run('policy_controller', parser,
                 lambda options: PolicyController(waypoint_file=options.waypoint_file), argv))


if __name__ == '__main__':
    main()

"""The waypoint_controller node: follows a waypoint file and reports on robot_status."""

import math
import sys

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from rclpy.clock import Clock, ClockType
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rclpy.time import Time
from std_msgs.msg import String

from stdr_lite.node_runtime import (build_parser, ConfigError, declare_parameters, EXIT_FAILED,
                                    EXIT_OK, ParameterSpec, require, run)
from stdr_lite.pose import yaw_from_quaternion
from stdr_lite.share import shared_file
from waypoint_controller.control_law import ControllerConfig, CourseFollower
from waypoint_controller.progress import ProgressMonitor
from waypoint_controller.schedule import ControlSchedule
from waypoint_controller.status import aborted, finished, started, waypoint_reached
from waypoint_controller.waypoints import load_waypoints, WaypointFileError

DEFAULT_COURSE = 'lab_tour.txt'
DEFAULTS = ControllerConfig()

PARAMETERS = (
    ParameterSpec('waypoint_file', '', 'waypoint file (x y theta triples: m, m, degrees); '
                  f'empty: the command-line argument, or else the bundled {DEFAULT_COURSE}'),
    ParameterSpec('distance_tolerance', DEFAULTS.distance_tolerance, 'goal set radius d [m]',
                  '> 0'),
    ParameterSpec('angle_tolerance_deg', math.degrees(DEFAULTS.angle_tolerance),
                  'goal set heading tolerance t [degrees, as in the lab]', '> 0'),
    ParameterSpec('max_linear_speed', DEFAULTS.max_linear_speed, 'speed limit [m/s]', '> 0'),
    ParameterSpec('max_angular_speed', DEFAULTS.max_angular_speed, 'turn-rate limit [rad/s]',
                  '> 0'),
    ParameterSpec('control_rate_hz', 20.0, 'control loop rate [Hz of odometry stamp time]',
                  '5 to 100'),
    ParameterSpec('stall_timeout', 10.0, 'abort when no progress towards the current waypoint '
                  'for this long [s of odometry stamp time]', '> 0'),
    ParameterSpec('heading_kp', DEFAULTS.heading_kp, 'heading PID proportional gain [1/s]',
                  '> 0'),
    ParameterSpec('heading_ki', DEFAULTS.heading_ki, 'heading PID integral gain [1/s^2]',
                  '>= 0'),
    ParameterSpec('heading_kd', DEFAULTS.heading_kd, 'heading PID derivative gain [-]', '>= 0'),
    ParameterSpec('distance_kp', DEFAULTS.distance_kp, 'distance PID proportional gain [1/s]',
                  '> 0'),
    ParameterSpec('distance_ki', DEFAULTS.distance_ki, 'distance PID integral gain [1/s^2]',
                  '>= 0'),
    ParameterSpec('distance_kd', DEFAULTS.distance_kd, 'distance PID derivative gain [-]',
                  '>= 0'),
)

DESCRIPTION = ('waypoint_controller: drive the robot through the waypoints of WAYPOINT_FILE '
               '(x y theta triples in m, m, degrees) and report STARTED, WAYPOINT n, FINISHED '
               'or ABORTED on robot_status. Exit code 0 when finished, 1 when aborted, 2 for '
               'bad input.')


def load_course(node, argument, parameter):
    """
    Return (path, waypoints) of the course from the argument, the parameter or the default.

    Giving both is an error, as is a bad file; giving neither picks the bundled course and
    logs that it did.
    """
    require(not (argument and parameter),
            f'waypoint file given twice: argument {argument!r} and parameter '
            f'waypoint_file {parameter!r}; give one')
    path = argument or parameter
    if not path:
        path = shared_file('waypoints', DEFAULT_COURSE)
        node.get_logger().info(f'no waypoint file given: using the bundled {DEFAULT_COURSE}')
    try:
        return path, load_waypoints(path)
    except WaypointFileError as error:
        raise ConfigError(str(error)) from None


def status_qos(waypoint_count):
    """Reliable, transient local, and deep enough to replay a whole run to a late subscriber."""
    return QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=waypoint_count + 2,
                      reliability=ReliabilityPolicy.RELIABLE,
                      durability=DurabilityPolicy.TRANSIENT_LOCAL)


class WaypointController(Node):
    """Reads odometry, commands velocities, and reports progress on robot_status."""

    def __init__(self, waypoint_file=None, **kwargs):
        super().__init__('waypoint_controller', **kwargs)
        self.finished = Future()
        params = declare_parameters(self, PARAMETERS)
        path, waypoints = load_course(self, waypoint_file, params['waypoint_file'])
        rate = params['control_rate_hz']
        require(5.0 <= rate <= 100.0, f'control_rate_hz must lie in [5, 100], got {rate}')
        require(params['stall_timeout'] > 0.0,
                f'stall_timeout must be positive, got {params["stall_timeout"]}')
        config = ControllerConfig(
            max_linear_speed=params['max_linear_speed'],
            max_angular_speed=params['max_angular_speed'],
            distance_tolerance=params['distance_tolerance'],
            angle_tolerance=math.radians(params['angle_tolerance_deg']),
            **{name: params[name] for name in ('heading_kp', 'heading_ki', 'heading_kd',
                                               'distance_kp', 'distance_ki', 'distance_kd')})
        try:
            self._follower = CourseFollower(waypoints, config)
        except ValueError as error:
            raise ConfigError(str(error)) from None
        self._progress = ProgressMonitor(params['stall_timeout'])
        self._schedule = ControlSchedule(round(1e9 / rate))
        self._pose = None
        self._stamp = None
        self._answered = None
        self._command = Twist()
        self._status_publisher = self.create_publisher(String, 'robot_status',
                                                       status_qos(len(waypoints)))
        self._cmd_publisher = self.create_publisher(Twist, '/robot0/cmd_vel', 10)
        self.create_subscription(Odometry, '/robot0/odom', self._on_odometry, 10)
        self._odometry_watch = self.create_timer(
            5.0, self._warn_while_waiting, clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info(f'following {len(waypoints)} waypoints from {path}')

    def _on_odometry(self, message):
        """
        Answer each new odometry stamp with exactly one cmd_vel.

        The command is recomputed once per control period of odometry time and held in
        between, so the commands depend only on the odometry, and a simulator in lockstep can
        count answers. A repeated stamp is answered only if its first answer had nobody to
        receive it.
        """
        if self.finished.done():
            return
        stamp = Time.from_msg(message.header.stamp).nanoseconds
        if stamp != self._stamp:
            self._stamp = stamp
            pose = message.pose.pose
            self._control_step(
                (pose.position.x, pose.position.y, yaw_from_quaternion(pose.orientation)),
                stamp)
        if self._answered != stamp and self._cmd_publisher.get_subscription_count() > 0:
            self._cmd_publisher.publish(self._command)
            self._answered = stamp

    def _control_step(self, pose, stamp):
        now = stamp * 1e-9
        first = self._pose is None
        self._pose = pose
        if first:
            self._report(started(pose))
            self._progress.restart(now)
        for index in self._follower.check(pose):
            self._report(waypoint_reached(index + 1, pose))
            self._progress.restart(now)
        if self._follower.finished:
            self._report(finished())
            self._stop(EXIT_OK)
            return
        distance, heading_error = self._follower.errors(pose)
        if self._progress.stalled(now, distance, heading_error):
            goal = self._follower.current
            number = self._follower.next_index + 1
            self.get_logger().error(
                f'waypoint {number} ({goal.x:g}, {goal.y:g}, {math.degrees(goal.theta):g} deg) '
                f'unreachable: no progress for {self._progress.timeout:g} s, still '
                f'{distance:.2f} m away')
            self._report(aborted(number, pose))
            self._stop(EXIT_FAILED)
            return
        elapsed = self._schedule.due(stamp)
        if elapsed is not None:
            step = self._follower.update(pose, elapsed * 1e-9)
            self._command = Twist()
            self._command.linear.x, self._command.angular.z = step.linear, step.angular

    def _warn_while_waiting(self):
        if self._pose is None:
            self.get_logger().warn('waiting for odometry on /robot0/odom: is stdr_lite running?')
        else:
            self._odometry_watch.cancel()

    def _report(self, text):
        self.get_logger().info(text)
        self._status_publisher.publish(String(data=text))

    def _stop(self, exit_code):
        self._command = Twist()
        if not self.finished.done():
            self.finished.set_result(exit_code)

    def shut_down(self):
        """Stop the robot and give late robot_status subscribers a moment to catch up."""
        self._stop(EXIT_OK)
        self._cmd_publisher.publish(self._command)
        self._status_publisher.wait_for_all_acked(Duration(seconds=1.0))


def main(argv=None):
    parser = build_parser('waypoint_controller', DESCRIPTION, PARAMETERS)
    parser.add_argument('waypoint_file', nargs='?', metavar='WAYPOINT_FILE',
                        help='waypoint file; the waypoint_file parameter is the alternative')
    sys.exit(run('waypoint_controller', parser,
                 lambda options: WaypointController(options.waypoint_file), argv))


if __name__ == '__main__':
    main()

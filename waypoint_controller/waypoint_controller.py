"""The waypoint_controller node: follows a waypoint file and reports on robot_status."""

import dataclasses
import math
import sys
import time

from nav_msgs.msg import OccupancyGrid, Odometry, Path
from rclpy.clock import Clock, ClockType
from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rclpy.time import Time
from simple_robot_control.exit_codes import EXIT_FAILED, EXIT_OK
from simple_robot_control.graph import (command_type_problem, deliver_before_exit,
                                        DISCOVERY_TIME, MISMATCH_PATIENCE, other_publishers,
                                        SETTLED_FOR)
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.occupancy_map import MapError, OccupancyMap
from simple_robot_control.parameters import accept_tuning, declare_parameters
from simple_robot_control.pose import pose_from_message
from simple_robot_control.validation import ConfigError
from simple_robot_control.velocity import VelocityPublisher
from std_msgs.msg import String
from waypoint_controller.continuity import jump_problem
from waypoint_controller.control_law import CourseFollower
from waypoint_controller.parameters import DEFAULTS, PARAMETERS
from waypoint_controller.schedule import ControlSchedule
from waypoint_controller.stall import StallDetector
from waypoint_lab.interface import course_message, load_course, status_qos
from waypoint_lab.rules import COURSE_TOPIC, STATUS_TOPIC
from waypoint_lab.status import aborted, finished, started, waypoint_reached

# Wall-clock seconds. Odometry is held this long after the node is made, which covers discovery
# nine times in ten (config/fastdds_quick_discovery.xml), to see who else commands the robot;
# the controller stays ready to yield for the whole discovery time, so a slow discovery costs
# at most a few seconds of two commanders rather than every run a wait. When /map has a
# publisher, odometry is held on until the map is in (at most MAP_WAIT), so the first plan
# already avoids the walls and a run does not depend on when the map happened to arrive.
# Silence this long is worth a warning. At the end of a run, readers known to the graph get
# what they need (see deliver_before_exit), unknown ones as long as discovery may take; when
# interrupted, a moment.
FIRST_ANSWER_AFTER = SETTLED_FOR
MAP_WAIT = 10.0
NEWCOMER_FOR = DISCOVERY_TIME
WATCH_PERIOD = 0.5
ODOMETRY_SILENCE = 3.0
EXIT_WAIT = DISCOVERY_TIME
INTERRUPTED_WAIT = 0.25

STOP = (0.0, 0.0)

_CONFIG_FIELDS = ('max_linear_speed', 'max_angular_speed', 'distance_tolerance', 'heading_kp',
                  'heading_ki', 'heading_kd', 'distance_kp', 'distance_ki', 'distance_kd')

DESCRIPTION = ('waypoint_controller: drive the robot through the waypoints of WAYPOINT_FILE '
               '(x y theta triples in m, m, degrees) and report STARTED, WAYPOINT n, FINISHED '
               'or ABORTED on robot_status. Exit code 0 when finished, 1 when aborted, 2 for '
               'bad input.')


def controller_config(values):
    """Return the ControllerConfig that parameter values (by name) describe."""
    return dataclasses.replace(
        DEFAULTS, angle_tolerance=math.radians(values['angle_tolerance_deg']),
        **{name: values[name] for name in _CONFIG_FIELDS})


class WaypointController(GuardedNode):
    """Reads odometry, commands velocities, and reports progress on robot_status."""

    def __init__(self, waypoint_file=None, **kwargs):
        super().__init__('waypoint_controller', **kwargs)
        # Discovery began with the node: its grace runs from now.
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._discovery = self.create_timer(FIRST_ANSWER_AFTER, self._end_grace, clock=steady)
        self.finished = Future()
        params = declare_parameters(self, PARAMETERS)
        path, waypoints = load_course(self, waypoint_file, params['waypoint_file'])
        self._tuned = {name: params[name] for name in _CONFIG_FIELDS + ('angle_tolerance_deg',)}
        try:
            self._follower = CourseFollower(waypoints, controller_config(self._tuned))
        except ValueError as error:
            raise ConfigError(str(error)) from None
        self._pending_config = None
        accept_tuning(self, PARAMETERS, self._on_tuning)
        self._stall = StallDetector(params['stall_timeout'])
        self._schedule = ControlSchedule(round(1e9 / params['control_rate_hz']))
        self._pose = None
        self._stamp = None
        self._answered = None
        self._command = STOP
        self._started_at = self._odometry_at = time.monotonic()
        self._mismatch_since = None
        self._held = None
        self._has_map = self._map_given_up = False
        self._status_publisher = self.create_publisher(String, STATUS_TOPIC,
                                                       status_qos(len(waypoints)))
        self._course_publisher = self.create_publisher(Path, COURSE_TOPIC, status_qos(0))
        self._course_publisher.publish(course_message(waypoints, 'map'))
        robot = params['robot_name']
        self._commands = VelocityPublisher(self, f'{robot}/cmd_vel', params['cmd_vel_stamped'])
        self._odom_topic = self.create_subscription(Odometry, f'{robot}/odom',
                                                    self._on_odometry, 10).topic_name
        self._robot_radius = params['robot_radius']
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(OccupancyGrid, '/map', self._on_map, latched)
        self.create_timer(WATCH_PERIOD, self._watch_odometry, clock=steady)
        # The wall check needs scipy, a sixth of a second to import: imported now, while
        # discovery runs, rather than before the node exists or once the map has come.
        from waypoint_controller.clearance import Clearance
        self._clearance = Clearance
        self.get_logger().info(f'following {len(waypoints)} waypoints from {path}')

    def _end_grace(self):
        """Discovery has had its grace: check that no one else commands the robot, then go."""
        self.destroy_timer(self._discovery)
        self._discovery = None
        self._check_alone()
        self._release_held()

    def _release_held(self):
        """Answer the odometry held since start, once the controller may."""
        if self._held is not None and self._may_start():
            held, self._held = self._held, None
            self._on_odometry(held)

    def _may_start(self):
        """Whether discovery has had its grace and the walls are known, or cannot be."""
        if self._discovery is not None:
            return False
        if self._has_map or self._map_given_up or self.count_publishers('/map') == 0:
            return True
        waited = time.monotonic() - self._started_at
        if waited < MAP_WAIT:
            return False
        self._map_given_up = True
        self.get_logger().warn(f'/map has a publisher but no map came in {waited:.0f} s: '
                               'driving without regard to walls until it does')
        return True

    def _check_alone(self):
        """
        Refuse to drive a robot that another node already commands.

        Odometry is held at start (FIRST_ANSWER_AFTER), so that a controller, a move_robot or a
        teleop already publishing on the same cmd_vel is usually seen before the first answer;
        the check is repeated while the controller is a newcomer (NEWCOMER_FOR), in case
        discovery was slow. Only the newcomer refuses: a controller past that keeps its robot.
        """
        others = other_publishers(self, self._commands.topic_name)
        if not others or self.finished.done():
            return
        self._command = STOP
        self._commands.publish(*self._command)
        self.finished.set_exception(ConfigError(
            f'{", ".join(others)} already publishes on {self._commands.topic_name}: '
            'one robot takes commands from one node; stop it or give robot_name'))

    def _on_map(self, message):
        """Keep the robot's plans off the walls of the map from now on, if it is a map."""
        try:
            grid = OccupancyMap.from_grid_message(message)
        except MapError as error:
            self.get_logger().warn(f'ignoring {error}; planning without regard to walls',
                                   throttle_duration_sec=10.0)
            self._map_given_up = True
            self._release_held()
            return
        self._follower.avoid(self._clearance(grid, self._robot_radius).is_free)
        self.get_logger().info(f'planning around the walls of /map ({grid.width} x '
                               f'{grid.height} cells of {grid.resolution:g} m)')
        self._has_map = True
        self._release_held()

    def _on_tuning(self, changes):
        """Keep tuned values for the next control tick, where they take effect together."""
        self._tuned.update(changes)
        self._pending_config = controller_config(self._tuned)

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
        self._odometry_at = time.monotonic()
        if self._stamp is None and not self._may_start():
            self._held = message
            return
        stamp = Time.from_msg(message.header.stamp).nanoseconds
        pose = pose_from_message(message.pose.pose)
        if not all(map(math.isfinite, pose)):
            self.get_logger().warn(f'ignoring odometry on {self._odom_topic} whose pose is not '
                                   'finite', throttle_duration_sec=5.0)
            return
        if self._stamp is not None and stamp < self._stamp:
            self._world_changed(pose, f'odometry time went back from {self._stamp * 1e-9:.3f} s '
                                f'to {stamp * 1e-9:.3f} s: the simulator restarted')
            return
        if stamp != self._stamp:
            if self._pose is not None:
                limits = self._follower.config
                jump = jump_problem(self._pose, pose, (stamp - self._stamp) * 1e-9,
                                    limits.max_linear_speed, limits.max_angular_speed)
                if jump is not None:
                    self._world_changed(pose, f'the robot {jump}: it was moved (a teleport, or '
                                        'a reset of the simulation)')
                    return
            self._stamp = stamp
            self._control_step(pose, stamp)
        if self._answered != stamp and self._commands.publisher.get_subscription_count() > 0:
            self._commands.publish(*self._command)
            self._answered = stamp

    def _control_step(self, pose, stamp):
        now = stamp * 1e-9
        first = self._pose is None
        self._pose = pose
        if first:
            self._report(started(pose))
            self._stall.restart(now)
        for index in self._follower.check(pose):
            self._report(waypoint_reached(index + 1, pose))
            self._stall.restart(now)
        if self._follower.finished:
            self._report(finished())
            self._stop(EXIT_OK)
            return
        distance, heading_error = self._follower.errors(pose)
        if self._stall.stalled(now, distance, heading_error):
            goal = self._follower.current
            number = self._follower.next_index + 1
            self.get_logger().error(
                f'waypoint {number} ({goal.x:g}, {goal.y:g}, {math.degrees(goal.theta):g} deg) '
                f'unreachable: no progress for {self._stall.timeout:g} s, still '
                f'{distance:.3g} m away')
            self._report(aborted(number, pose))
            self._stop(EXIT_FAILED)
            return
        elapsed = self._schedule.due(stamp)
        if elapsed is not None:
            if self._pending_config is not None:
                self._follower.reconfigure(self._pending_config)
                self._pending_config = None
            step = self._follower.update(pose, elapsed * 1e-9)
            self._command = (step.linear, step.angular)

    def _world_changed(self, pose, what):
        """
        Stop at once when the world changed under the run, rather than act on one that is gone.

        A restarted simulator, a teleport or a reset make the run no longer one run: it ends
        ABORTED with exit code 1, and the user starts it again.
        """
        self.get_logger().error(f'{self._odom_topic}: {what}; stopping the robot: this run is '
                                'over (start the controller again for a new one)')
        self._report(aborted(self._follower.next_index + 1, pose))
        self._stop(EXIT_FAILED)
        self._commands.publish(*self._command)

    def _robot_gone(self):
        """Stop when the odometry has lost its publisher: the robot was deleted, or the world."""
        self.get_logger().error(
            f'no odometry on {self._odom_topic} for {ODOMETRY_SILENCE:g} s and it has no '
            'publisher any more: the robot was deleted or the simulator stopped; this run is '
            'over')
        self._report(aborted(self._follower.next_index + 1, self._pose))
        self._stop(EXIT_FAILED)

    def _watch_odometry(self):
        self._release_held()
        if self._discovery is None and time.monotonic() - self._started_at < NEWCOMER_FOR:
            self._check_alone()
        if self._discovery is None and not self.finished.done():
            self._check_command_type()
        silence = time.monotonic() - self._odometry_at
        if self.finished.done() or silence < ODOMETRY_SILENCE:
            return
        if self._pose is not None and self.count_publishers(self._odom_topic) == 0:
            self._robot_gone()
            return
        self.get_logger().warn(f'no odometry on {self._odom_topic} for {silence:.0f} s: is '
                               'stdr_lite running?', throttle_duration_sec=5.0)

    def _check_command_type(self):
        """End the run once cmd_vel's readers have taken another message type for long."""
        mismatch = command_type_problem(self, self._commands.publisher, 'cmd_vel_stamped')
        if mismatch is None:
            self._mismatch_since = None
            return
        now = time.monotonic()
        self._mismatch_since = self._mismatch_since or now
        if now - self._mismatch_since >= MISMATCH_PATIENCE:
            self._command = STOP
            self.finished.set_exception(ConfigError(mismatch))

    def _report(self, text):
        self.get_logger().info(text)
        self._status_publisher.publish(String(data=text))

    def _stop(self, exit_code):
        self._command = STOP
        if not self.finished.done():
            self.finished.set_result(exit_code)

    def shut_down(self):
        """
        Stop the robot, then let every robot_status reader receive the whole run.

        A run that ended by itself waits (EXIT_WAIT at most) for readers still being
        discovered; an interrupted one only flushes what is matched, to exit promptly.
        """
        ended = self.finished.done()
        self._stop(EXIT_OK)
        # Fast DDS sends from a thread of its own: wait until the simulator has the stop, or
        # the process would end with the command still queued.
        self._commands.publish(*self._command)
        self._commands.publisher.wait_for_all_acked(Duration(seconds=INTERRUPTED_WAIT))
        if ended:
            deliver_before_exit(self, self._status_publisher, self._started_at, EXIT_WAIT)
        else:
            self._status_publisher.wait_for_all_acked(Duration(seconds=INTERRUPTED_WAIT))


def main(argv=None):
    parser = build_parser('waypoint_controller', DESCRIPTION, PARAMETERS)
    parser.add_argument('waypoint_file', nargs='?', metavar='WAYPOINT_FILE',
                        help='waypoint file; the waypoint_file parameter is the alternative')
    sys.exit(run('waypoint_controller', parser,
                 lambda options: WaypointController(options.waypoint_file), argv))


if __name__ == '__main__':
    main()

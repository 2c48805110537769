"""
The lab's run on ROS, for any control law: what every controller of the lab does the same way.

CourseRunner is a node that follows a course with a control law (lifecycle.py): it reads the
robot's odometry, waits until it may start (start.py: discovery has had its grace, the map is in
when the law plans around walls), answers every odometry stamp with exactly one cmd_vel (so a
simulator in lockstep can count the answers), reports STARTED, WAYPOINT n, FINISHED and ABORTED
on robot_status (reliable, transient local), publishes the course, ends the run on a stall, a
teleport, a restarted simulator or a deleted robot, refuses to drive a robot another node
already commands, and at the end stops the robot and delivers every status before it exits. A
controller subclasses it and gives build_law(); waypoint_controller and policy_controller are
two such.
"""

import argparse
from collections.abc import Callable, Sequence
import math
import os
import sys
import time

from nav_msgs.msg import OccupancyGrid, Odometry, Path
from rclpy.clock import Clock, ClockType
from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rclpy.time import Time
from simple_robot_control.exit_codes import EXIT_OK
from simple_robot_control.graph import (command_type_problem, deliver_before_exit,
                                        DISCOVERY_TIME, MISMATCH_PATIENCE, other_publishers,
                                        SETTLED_FOR)
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.occupancy_map import MapError, OccupancyMap
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.pose import pose_from_message
from simple_robot_control.validation import ConfigError
from simple_robot_control.velocity import VelocityPublisher
from std_msgs.msg import String
from waypoint_lab.interface import course_message, load_course, status_qos
from waypoint_lab.lifecycle import (ControlLaw, FunctionLaw, Outcome, Pose, RunLifecycle,
                                    RunRules, STOP)
from waypoint_lab.parameters import RUNNER_PARAMETERS
from waypoint_lab.rules import COURSE_TOPIC, STATUS_TOPIC
from waypoint_lab.start import StartConditions
from waypoint_lab.waypoints import Waypoint

# Wall-clock seconds. Odometry is held this long after the node is made (start.py), which
# covers discovery nine times in ten (config/fastdds_quick_discovery.xml), to see who else
# commands the robot; the runner stays ready to yield for the whole discovery time, so a slow
# discovery costs at most a few seconds of two commanders rather than every run a wait.
# Silence this long is worth a warning. At the end of a run, readers known to the graph get
# what they need (see deliver_before_exit), unknown ones as long as discovery may take; when
# interrupted, a moment.
FIRST_ANSWER_AFTER = SETTLED_FOR
NEWCOMER_FOR = DISCOVERY_TIME
WATCH_PERIOD = 0.5
ODOMETRY_SILENCE = 3.0
EXIT_WAIT = DISCOVERY_TIME
INTERRUPTED_WAIT = 0.25
# What inputs_ready() says of a law's inputs beyond the pose.
READY, WAIT, NOT_YET = 'ready', 'wait', 'not yet'


def run_rules(params: dict, **overrides) -> RunRules:
    """Return the run's rules from the runner's parameter values (RUNNER_PARAMETERS)."""
    values = {'distance_tolerance': params['distance_tolerance'],
              'angle_tolerance': math.radians(params['angle_tolerance_deg']),
              'stall_timeout': params['stall_timeout']}
    for name in ('max_linear_speed', 'max_angular_speed'):
        if name in params:
            values[name] = params[name]
    if 'control_rate_hz' in params:
        values['control_period_ns'] = round(1e9 / params['control_rate_hz'])
    return RunRules(**{**values, **overrides})


class CourseRunner(GuardedNode):
    """
    A controller of the lab: the course, the statuses and the run's life; the law is build_law's.

    parameters is the node's table (RUNNER_PARAMETERS and its own); waypoint_file is the
    command line's course, if any. finished completes with the exit code (0 FINISHED, 1
    ABORTED) or a ConfigError (another node commands the robot; cmd_vel read as another type).
    """

    def __init__(self, node_name: str, parameters: Sequence, waypoint_file: str | None = None,
                 waypoints: Sequence[Waypoint] | None = None, **kwargs):
        super().__init__(node_name, **kwargs)
        # Discovery began with the node: its grace runs from now.
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._discovery = self.create_timer(FIRST_ANSWER_AFTER, self._end_grace, clock=steady)
        self.finished = Future()
        self.params = params = declare_parameters(self, parameters)
        if waypoints is None:
            path, waypoints = load_course(self, waypoint_file, params['waypoint_file'])
        else:
            path, waypoints = 'the caller', [Waypoint(*waypoint) for waypoint in waypoints]
        self.waypoints = waypoints
        law, rules = self.build_law(params, waypoints)
        try:
            self.lifecycle = RunLifecycle(waypoints, law, rules)
        except ValueError as error:
            raise ConfigError(str(error)) from None
        self._pose = self._stamp = self._answered = None
        self._command = STOP
        self._started_at = self._odometry_at = time.monotonic()
        self._mismatch_since = self._waiting = self._unready_since = None
        # The latest map's stamp (0: a map of no time, as a map server's).
        self.map_stamp_ns = 0
        self._status_publisher = self.create_publisher(String, STATUS_TOPIC,
                                                       status_qos(len(waypoints)))
        self._course_publisher = self.create_publisher(Path, COURSE_TOPIC, status_qos(0))
        self._course_publisher.publish(course_message(waypoints, 'map'))
        robot = params['robot_name']
        self._commands = VelocityPublisher(self, f'{robot}/cmd_vel',
                                           params.get('cmd_vel_stamped', False))
        self._odom_topic = self.create_subscription(Odometry, f'{robot}/odom',
                                                    self._on_odometry, 10).topic_name
        # A planner may take a mapper's growing map in place of the simulator's.
        self._map_topic = params.get('map_topic', '/map')
        uses_map = self.plans_around_walls()
        self._start = StartConditions(
            self._map_topic, (lambda: self.count_publishers(self._map_topic)) if uses_map
            else None, self.get_logger().warn)
        if uses_map:
            latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                                 durability=DurabilityPolicy.TRANSIENT_LOCAL)
            self.create_subscription(OccupancyGrid, self._map_topic, self._on_map, latched)
        self.create_timer(WATCH_PERIOD, self._watch_odometry, clock=steady)
        self.get_logger().info(f'following {len(waypoints)} waypoints from {path}')

    def build_law(self, params: dict, waypoints: list) -> tuple[ControlLaw, RunRules]:
        """Return the control law for the course and the run's rules (a subclass's to give)."""
        raise NotImplementedError

    def plans_around_walls(self) -> bool:
        """Whether the law takes the map (use_map): the run then waits for /map at start."""
        return False

    def use_map(self, grid: OccupancyMap) -> None:
        """Give the law the walls of the map (called for each that comes; map_stamp_ns its)."""

    def inputs_ready(self, stamp_ns: int) -> str:
        """
        Say whether the law has what it needs, beyond the pose, to answer at stamp_ns.

        READY: the run takes the pose. WAIT: the answer waits for the inputs (answer_waiting()
        once they come), so that in lockstep the robot never outruns them. NOT_YET: the
        law has had no input at all: the stamp is answered with a stop and the run starts
        later (in lockstep the simulator steps on until the first input comes).
        """
        return READY

    def waiting_for(self) -> str:
        """Say what inputs_ready() waits for, for a warning when it waits long."""
        return ''

    def answer_waiting(self) -> None:
        """Answer the odometry held for the law's inputs, now that they may have come."""
        if self._waiting is not None:
            waiting, self._waiting = self._waiting, None
            self._on_odometry(waiting)

    def _end_grace(self):
        """Discovery has had its grace: check that no one else commands the robot, then go."""
        self.destroy_timer(self._discovery)
        self._discovery = None
        self._start.discovered()
        self._check_alone()
        self._release_held()

    def _release_held(self):
        """Answer the odometry held since start, once the runner may."""
        held = self._start.release()
        if held is not None:
            self._on_odometry(held)

    def _check_alone(self):
        """
        Refuse to drive a robot that another node already commands.

        Odometry is held at start (FIRST_ANSWER_AFTER), so that a controller, a move_robot or a
        teleop already publishing on the same cmd_vel is usually seen before the first answer;
        the check is repeated while the runner is a newcomer (NEWCOMER_FOR), in case discovery
        was slow. Only the newcomer refuses: a runner past that keeps its robot.
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
        """Keep the law's plans off the walls of the map from now on, if it is a map."""
        try:
            grid = OccupancyMap.from_grid_message(message, self._map_topic)
        except MapError as error:
            self.get_logger().warn(f'ignoring {error}; planning without regard to walls',
                                   throttle_duration_sec=10.0)
            self._start.map_unreadable()
            self._release_held()
            return
        self.map_stamp_ns = Time.from_msg(message.header.stamp).nanoseconds
        self.use_map(grid)
        if not self._start.has_map:
            self.get_logger().info(f'planning around the walls of {self._map_topic} '
                                   f'({grid.width} x {grid.height} cells of '
                                   f'{grid.resolution:g} m)')
        self._start.map_came()
        self._release_held()

    def _on_odometry(self, message):
        """
        Answer each new odometry stamp with exactly one cmd_vel.

        A repeated stamp is answered only if its first answer had nobody to receive it. Held
        while the runner may not start yet, or while the law's inputs for it are not in.
        """
        if self.finished.done():
            return
        self._odometry_at = time.monotonic()
        if not self.lifecycle.started and not self._start.may_start():
            self._start.hold(message)
            return
        stamp = Time.from_msg(message.header.stamp).nanoseconds
        pose = pose_from_message(message.pose.pose)
        if not all(map(math.isfinite, pose)):
            self.get_logger().warn(f'ignoring odometry on {self._odom_topic} whose pose is not '
                                   'finite', throttle_duration_sec=5.0)
            return
        readiness = READY if stamp == self._stamp else self.inputs_ready(stamp)
        self._unready_since = (None if readiness == READY
                               else self._unready_since or time.monotonic())
        if readiness == WAIT:
            self._waiting = message
            return
        if readiness == READY and stamp != self._stamp:
            self._stamp, self._pose = stamp, pose
            self._take(self.lifecycle.observe(stamp, pose))
        if self._answered != stamp and self._commands.publisher.get_subscription_count() > 0:
            self._commands.publish(*self._command)
            self._answered = stamp

    def _take(self, outcome: Outcome):
        """Report the outcome's statuses, hold its command, end the run if it ended."""
        for text in outcome.statuses:
            self._report(text)
        if outcome.command is not None:
            self._command = outcome.command
        if outcome.problem:
            self.get_logger().error(f'{self._odom_topic}: {outcome.problem}; stopping the '
                                    'robot: this run is over (start the controller again for '
                                    'a new one)')
        if outcome.exit_code is not None:
            self._stop(outcome.exit_code)

    def _robot_gone(self):
        """Stop when the odometry has lost its publisher: the robot was deleted, or the world."""
        self._take(self.lifecycle.abort(self._pose, (
            f'no odometry for {ODOMETRY_SILENCE:g} s and it has no publisher any more: the '
            'robot was deleted or the simulator stopped')))

    def _watch_odometry(self):
        self._release_held()
        if self._discovery is None and time.monotonic() - self._started_at < NEWCOMER_FOR:
            self._check_alone()
        if self._discovery is None and not self.finished.done():
            self._check_command_type()
        silence = time.monotonic() - self._odometry_at
        if self.finished.done():
            return
        unready = 0.0 if self._unready_since is None else time.monotonic() - self._unready_since
        if unready >= ODOMETRY_SILENCE:
            self.get_logger().warn(f'waiting {unready:.0f} s for {self.waiting_for()}',
                                   throttle_duration_sec=5.0)
            return
        if silence < ODOMETRY_SILENCE:
            return
        if self.lifecycle.started and self.count_publishers(self._odom_topic) == 0:
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

    def shut_down(self) -> None:
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


class FunctionController(CourseRunner):
    """A plain function law(pose, waypoint, dt) -> (linear, angular) as a controller of the lab."""

    def __init__(self, law: Callable[[Pose, Waypoint, float], tuple[float, float]],
                 waypoint_file: str | None = None, waypoints: Sequence | None = None,
                 node_name: str = 'my_controller', **kwargs):
        self._function = law
        super().__init__(node_name, RUNNER_PARAMETERS, waypoint_file, waypoints, **kwargs)

    def build_law(self, params: dict, waypoints: list) -> tuple[ControlLaw, RunRules]:
        return FunctionLaw(waypoints, self._function), run_rules(params)


def course_parser(name: str, description: str, parameters: Sequence) -> argparse.ArgumentParser:
    """Return a controller's command-line parser: its ROS parameters, and the waypoint file."""
    parser = build_parser(name, description, parameters)
    parser.add_argument('waypoint_file', nargs='?', metavar='WAYPOINT_FILE',
                        help='waypoint file; the waypoint_file parameter is the alternative')
    return parser


def run_controller(name: str, description: str, parameters: Sequence,
                   make_node: Callable[[str | None], CourseRunner],
                   argv: list[str] | None = None) -> None:
    """Run a controller of the lab from its command line (make_node(waypoint_file)); exit."""
    sys.exit(run(name, course_parser(name, description, parameters),
                 lambda options: make_node(options.waypoint_file), argv))


def drive(law: Callable[[Pose, Waypoint, float], tuple[float, float]],
          argv: list[str] | None = None) -> None:
    """
    Run a script's own control law as a controller of the lab, as waypoint_controller runs.

    The script's command line is the controller's: a waypoint file, then --ros-args (robot_name,
    tolerances, speed limits, control_rate_hz, stall_timeout); it exits 0 on FINISHED, 1 on
    ABORTED, 2 for bad input.
    """
    argv = list(sys.argv if argv is None else argv)
    name = os.path.splitext(os.path.basename(argv[0]))[0] or 'my_controller'
    run_controller(name, f'{name}: drive the robot through the waypoints of WAYPOINT_FILE with '
                   'a control law of your own, reporting on robot_status as the lab asks.',
                   RUNNER_PARAMETERS, lambda waypoint_file: FunctionController(
                       law, waypoint_file, node_name=_node_name(name)), argv)


def _node_name(name):
    """Return a script's name as a valid ROS node name."""
    cleaned = ''.join(character if character.isascii() and character.isalnum() else '_'
                      for character in name)
    return cleaned if cleaned[:1].isalpha() else f'my_{cleaned}'

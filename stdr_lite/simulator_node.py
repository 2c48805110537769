"""The stdr_lite node: steps the world at a fixed rate and speaks STDR's topics."""

from collections import deque
import functools
import math
import sys
import time

from geometry_msgs.msg import Twist
from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosgraph_msgs.msg import Clock as ClockMsg

from stdr_lite.commands import CommandBuffer
from stdr_lite.kinematics import INTEGRATORS
from stdr_lite.node_runtime import (build_parser, ConfigError, declare_parameters,
                                    ParameterSpec, require, run)
from stdr_lite.occupancy_map import load_map, MapError
from stdr_lite.share import shared_file
from stdr_lite.world import PlacementError, World

NANOSECONDS = 1_000_000_000
# In lockstep, odometry that has gone unanswered this long is published again (same stamp), so
# a controller that started after it was first sent still gets it.
LOCKSTEP_REPEAT_AFTER = 0.5
LATENCY_SAMPLES = 100_000

PARAMETERS = (
    ParameterSpec('map_yaml', '', 'map_server YAML file of the world; empty for the bundled '
                  'lab_room (20 m x 15 m)'),
    ParameterSpec('rate_hz', 50.0, 'simulation steps per simulated second; dt = 1/rate_hz',
                  '> 0'),
    ParameterSpec('integrator', 'euler', "'euler' (the lab's equation 2) or 'arc' (exact "
                  'constant-velocity arc)', 'euler | arc'),
    ParameterSpec('real_time_factor', 1.0, 'simulated seconds per wall-clock second; 0 steps '
                  'as fast as the CPU allows', '>= 0'),
    ParameterSpec('lockstep', False, 'advance only once every robot has answered its latest '
                  'odometry with a cmd_vel, so sim time never runs ahead of the controller; '
                  'real_time_factor is then an upper bound'),
    ParameterSpec('robot_name', 'robot0', 'robot name: topics are /<name>/cmd_vel and '
                  '/<name>/odom'),
    ParameterSpec('robot_radius', 0.2, 'radius of the circular footprint [m]', '> 0'),
    ParameterSpec('initial_pose', [1.0, 2.0, 0.0], 'start pose [x m, y m, theta rad] in the '
                  'map frame', 'off walls, on the map'),
    ParameterSpec('max_linear_speed', 2.0, 'commands beyond this linear speed are clamped '
                  '[m/s]', '> 0'),
    ParameterSpec('max_angular_speed', math.pi, 'commands beyond this angular speed are '
                  'clamped [rad/s]', '> 0'),
    ParameterSpec('cmd_vel_timeout', 0.0, 'stop a robot whose last command is older than '
                  'this [s of sim time]; 0 holds the last command forever (STDR)', '>= 0'),
    ParameterSpec('map_frame_id', 'map', 'frame of /map'),
    ParameterSpec('odom_frame_id', 'odom', 'frame of the odometry pose (REP-105); it '
                  'coincides with the map frame'),
    ParameterSpec('base_frame_id', 'base_link', 'child frame of the odometry (REP-105)'),
)

DESCRIPTION = ('stdr_lite: a small STDR-equivalent simulator. Subscribes /<robot>/cmd_vel '
               '(geometry_msgs/Twist); publishes /<robot>/odom (nav_msgs/Odometry), /map '
               '(nav_msgs/OccupancyGrid, transient local) and /clock.')


class StdrLite(Node):
    """
    Unicycle robots in a map_server world, stepped at a fixed rate.

    Free-running, a steady-clock timer steps the world every dt / real_time_factor wall seconds
    whether or not anyone listens. In lockstep, step k + 1 waits until each robot's cmd_vel has
    answered odometry k, so the outcome depends on the commands alone, never on machine load.
    """

    def __init__(self, **kwargs):
        super().__init__('stdr_lite', **kwargs)
        self.finished = Future()
        params = declare_parameters(self, PARAMETERS)
        self._validate(params)
        self._dt_ns = round(NANOSECONDS / params['rate_hz'])
        self._step_count = 0
        self._world = self._build_world(params)
        self._commands = CommandBuffer(self._world.robot_count, params['max_linear_speed'],
                                       params['max_angular_speed'], params['cmd_vel_timeout'])
        self._frames = (params['odom_frame_id'], params['base_frame_id'])
        self._applied = (np.zeros(self._world.robot_count), np.zeros(self._world.robot_count))
        self._robot_names = [params['robot_name']]
        self._odom_publishers = [self.create_publisher(Odometry, f'/{name}/odom', 10)
                                 for name in self._robot_names]
        self._cmd_subscriptions = [
            self.create_subscription(Twist, f'/{name}/cmd_vel',
                                     functools.partial(self._on_cmd_vel, index), 10)
            for index, name in enumerate(self._robot_names)]
        self._clock_publisher = self.create_publisher(ClockMsg, '/clock', 10)
        self._clock_message = ClockMsg()
        self._odometry_messages = [Odometry() for _ in self._robot_names]
        for message in self._odometry_messages:
            message.header.frame_id, message.child_frame_id = self._frames
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self._map_publisher = self.create_publisher(OccupancyGrid, '/map', latched)
        self._map_publisher.publish(self._map_message(params['map_frame_id']))
        self._lockstep = params['lockstep']
        self._unanswered = set()
        self._published_at = self._repeated_at = 0.0
        self.answer_latencies = deque(maxlen=LATENCY_SAMPLES)
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        paced = params['real_time_factor'] > 0.0
        if paced or not self._lockstep:
            wall_period = 0.0
            if paced:
                wall_period = self._dt_ns / NANOSECONDS / params['real_time_factor']
            self.create_timer(wall_period, self._on_tick, clock=steady)
        self._step_on_answer = self._lockstep and not paced
        if self._lockstep:
            self._odometry_subscribers = 0
            self.create_timer(0.05, self._repeat_unanswered_state, clock=steady)
            self._publish_state()
            self._await_answers()
        self.get_logger().info(
            f'{self._map_name} {self._world.map.width}x{self._world.map.height} cells, '
            f'robot {self._robot_names[0]} at {tuple(params["initial_pose"])}, '
            f'{params["rate_hz"]:g} Hz {params["integrator"]}, '
            f'real_time_factor {params["real_time_factor"]:g}'
            + (', lockstep' if self._lockstep else ''))

    @staticmethod
    def _validate(params):
        require(params['rate_hz'] > 0.0, f'rate_hz must be positive, got {params["rate_hz"]}')
        require(params['integrator'] in INTEGRATORS,
                f'integrator must be one of {", ".join(INTEGRATORS)}, '
                f'got {params["integrator"]!r}')
        require(params['real_time_factor'] >= 0.0,
                f'real_time_factor must be >= 0, got {params["real_time_factor"]}')
        for name in ('robot_radius', 'max_linear_speed', 'max_angular_speed'):
            require(params[name] > 0.0, f'{name} must be positive, got {params[name]}')
        require(params['cmd_vel_timeout'] >= 0.0,
                f'cmd_vel_timeout must be >= 0, got {params["cmd_vel_timeout"]}')
        require(len(params['initial_pose']) == 3,
                f'initial_pose must be [x, y, theta], got {params["initial_pose"]}')
        require(params['robot_name'].isidentifier(),
                f'robot_name must be a plain name such as robot0, got {params["robot_name"]!r}')

    def _build_world(self, params):
        map_yaml = params['map_yaml'] or shared_file('maps', 'lab_room.yaml')
        try:
            occupancy_map = load_map(map_yaml)
        except MapError as error:
            raise ConfigError(str(error)) from None
        self._map_name = map_yaml
        world = World(occupancy_map, params['robot_radius'], params['integrator'])
        try:
            world.add_robot(params['initial_pose'], params['robot_radius'])
        except PlacementError as error:
            raise ConfigError(f'initial_pose in {map_yaml}: {error}') from None
        return world

    def _map_message(self, frame_id):
        occupancy_map = self._world.map
        message = OccupancyGrid()
        message.header.frame_id = frame_id
        message.info.resolution = occupancy_map.resolution
        message.info.width = occupancy_map.width
        message.info.height = occupancy_map.height
        origin_x, origin_y, yaw = occupancy_map.origin
        message.info.origin.position.x = origin_x
        message.info.origin.position.y = origin_y
        message.info.origin.orientation.z = math.sin(0.5 * yaw)
        message.info.origin.orientation.w = math.cos(0.5 * yaw)
        message.data = occupancy_map.cells.ravel().tolist()
        return message

    @property
    def sim_time(self):
        """Return the simulated seconds since start."""
        return self._step_count * self._dt_ns / NANOSECONDS

    def _on_cmd_vel(self, index, message):
        linear, angular = message.linear.x, message.angular.z
        if self._commands.exceeds_limits(linear, angular):
            self.get_logger().warn(
                f'{self._robot_names[index]}: command ({linear:g} m/s, {angular:g} rad/s) '
                'clamped to max_linear_speed/max_angular_speed', throttle_duration_sec=5.0)
        if not self._commands.update(index, linear, angular, self.sim_time):
            self.get_logger().warn(
                f'{self._robot_names[index]}: ignored cmd_vel with a non-finite component '
                f'({linear}, {angular}); keeping the last valid command',
                throttle_duration_sec=5.0)
        if index in self._unanswered:
            self._unanswered.discard(index)
            self.answer_latencies.append(time.monotonic() - self._published_at)
            if not self._unanswered and self._step_on_answer:
                self._step()

    def _on_tick(self):
        if not self._unanswered:
            self._step()

    def _step(self):
        linear, angular = self._commands.current(self.sim_time)
        self._applied = self._world.step(linear, angular, self._dt_ns / NANOSECONDS)
        self._step_count += 1
        self._publish_state()
        if self._lockstep:
            self._await_answers()

    def _publish_state(self):
        """Publish /clock (when anyone listens) and every robot's odometry for this step."""
        seconds, nanoseconds = divmod(self._step_count * self._dt_ns, NANOSECONDS)
        if self._clock_publisher.get_subscription_count():
            self._clock_message.clock.sec, self._clock_message.clock.nanosec = (seconds,
                                                                                nanoseconds)
            self._clock_publisher.publish(self._clock_message)
        applied_linear, applied_angular = self._applied
        for index, publisher in enumerate(self._odom_publishers):
            message = self._odometry_messages[index]
            message.header.stamp.sec, message.header.stamp.nanosec = seconds, nanoseconds
            x, y, theta = self._world.poses[index].tolist()
            message.pose.pose.position.x, message.pose.pose.position.y = x, y
            message.pose.pose.orientation.z = math.sin(0.5 * theta)
            message.pose.pose.orientation.w = math.cos(0.5 * theta)
            message.twist.twist.linear.x = float(applied_linear[index])
            message.twist.twist.angular.z = float(applied_angular[index])
            publisher.publish(message)

    def _await_answers(self):
        self._unanswered = set(range(self._world.robot_count))
        self._published_at = self._repeated_at = time.monotonic()

    def _repeat_unanswered_state(self):
        """Repeat unanswered odometry when a subscriber joins or after a long silence."""
        subscribers = sum(publisher.get_subscription_count()
                          for publisher in self._odom_publishers)
        joined, self._odometry_subscribers = (subscribers > self._odometry_subscribers,
                                              subscribers)
        silent = time.monotonic() - self._repeated_at > LOCKSTEP_REPEAT_AFTER
        if self._unanswered and (joined or silent):
            self._publish_state()
            self._repeated_at = time.monotonic()

    def shut_down(self):
        """Log how long the controller took to answer, when in lockstep."""
        if self._lockstep and self.answer_latencies:
            median, p99 = np.percentile(self.answer_latencies, (50, 99)) * 1e3
            self.get_logger().info(
                f'lockstep: {self._step_count} steps, cmd_vel answered odometry after '
                f'{median:.2f} ms (median), {p99:.2f} ms (99th percentile)')


def main(argv=None):
    parser = build_parser('stdr_lite', DESCRIPTION, PARAMETERS)
    sys.exit(run('stdr_lite', parser, lambda options: StdrLite(), argv))


if __name__ == '__main__':
    main()

"""The stdr_lite node: steps the world at a fixed rate and speaks STDR's topics."""

import functools
import math
import sys

from geometry_msgs.msg import Twist
from nav_msgs.msg import OccupancyGrid, Odometry
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rclpy.time import Time
from rosgraph_msgs.msg import Clock as ClockMsg

from stdr_lite.commands import CommandBuffer
from stdr_lite.kinematics import INTEGRATORS
from stdr_lite.node_runtime import (build_parser, ConfigError, declare_parameters,
                                    ParameterSpec, require, run)
from stdr_lite.occupancy_map import load_map, MapError
from stdr_lite.share import shared_file
from stdr_lite.world import PlacementError, World

NANOSECONDS = 1_000_000_000

PARAMETERS = (
    ParameterSpec('map_yaml', '', 'map_server YAML file of the world; empty for the bundled '
                  'lab_room (20 m x 15 m)'),
    ParameterSpec('rate_hz', 50.0, 'simulation steps per simulated second; dt = 1/rate_hz',
                  '> 0'),
    ParameterSpec('integrator', 'euler', "'euler' (the lab's equation 2) or 'arc' (exact "
                  'constant-velocity arc)', 'euler | arc'),
    ParameterSpec('real_time_factor', 1.0, 'simulated seconds per wall-clock second; 0 steps '
                  'as fast as the CPU allows', '>= 0'),
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
    """Unicycle robots in a map_server world, stepped at a fixed rate."""

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
        self._robot_names = [params['robot_name']]
        self._odom_publishers = [self.create_publisher(Odometry, f'/{name}/odom', 10)
                                 for name in self._robot_names]
        self._cmd_subscriptions = [
            self.create_subscription(Twist, f'/{name}/cmd_vel',
                                     functools.partial(self._on_cmd_vel, index), 10)
            for index, name in enumerate(self._robot_names)]
        self._clock_publisher = self.create_publisher(ClockMsg, '/clock', 10)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self._map_publisher = self.create_publisher(OccupancyGrid, '/map', latched)
        self._map_publisher.publish(self._map_message(params['map_frame_id']))
        wall_period = 0.0
        if params['real_time_factor'] > 0.0:
            wall_period = self._dt_ns / NANOSECONDS / params['real_time_factor']
        self._timer = self.create_timer(wall_period, self._step,
                                        clock=Clock(clock_type=ClockType.STEADY_TIME))
        self.get_logger().info(
            f'{self._map_name} {self._world.map.width}x{self._world.map.height} cells, '
            f'robot {self._robot_names[0]} at {tuple(params["initial_pose"])}, '
            f'{params["rate_hz"]:g} Hz {params["integrator"]}, '
            f'real_time_factor {params["real_time_factor"]:g}')

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

    def _step(self):
        linear, angular = self._commands.current(self.sim_time)
        applied_linear, applied_angular = self._world.step(linear, angular,
                                                           self._dt_ns / NANOSECONDS)
        self._step_count += 1
        stamp = Time(nanoseconds=self._step_count * self._dt_ns).to_msg()
        self._clock_publisher.publish(ClockMsg(clock=stamp))
        for index, publisher in enumerate(self._odom_publishers):
            publisher.publish(self._odometry(index, stamp, applied_linear[index],
                                             applied_angular[index]))

    def _odometry(self, index, stamp, linear, angular):
        x, y, theta = self._world.poses[index]
        message = Odometry()
        message.header.stamp = stamp
        message.header.frame_id, message.child_frame_id = self._frames
        message.pose.pose.position.x = float(x)
        message.pose.pose.position.y = float(y)
        message.pose.pose.orientation.z = math.sin(0.5 * theta)
        message.pose.pose.orientation.w = math.cos(0.5 * theta)
        message.twist.twist.linear.x = float(linear)
        message.twist.twist.angular.z = float(angular)
        return message

    def shut_down(self):
        """Nothing to release: the simulator owns no hardware."""


def main(argv=None):
    parser = build_parser('stdr_lite', DESCRIPTION, PARAMETERS)
    sys.exit(run('stdr_lite', parser, lambda options: StdrLite(), argv))


if __name__ == '__main__':
    main()

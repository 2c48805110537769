"""The stdr_lite node: steps the world at a fixed rate and speaks STDR's topics."""

from collections import deque
from dataclasses import dataclass, field, replace
import functools
import math
import sys
import time

from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosgraph_msgs.msg import Clock as ClockMsg
from sensor_msgs.msg import LaserScan, Range
from std_msgs.msg import String

from stdr_lite.commands import CommandBuffer
from stdr_lite.kinematics import INTEGRATORS
from stdr_lite.node_runtime import (build_parser, ConfigError, declare_parameters,
                                    ParameterSpec, require, run)
from stdr_lite.occupancy_map import load_map, MapError
from stdr_lite.pose import yaw_from_quaternion
from stdr_lite.robot_description import (load_robot_list, load_robot_or_default,
                                         robot_entry, RobotEntry, RobotFileError)
from stdr_lite.sensors import RangeFinder, read_sensors
from stdr_lite.share import shared_file
from stdr_lite.world import PlacementError, World
import yaml

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
    ParameterSpec('robot_description', '', 'STDR robot YAML (footprint, sensors) of the '
                  'robots; empty for the bundled lab robot'),
    ParameterSpec('robots_file', '', 'YAML robot list {robots: [{name, description, pose}]}; '
                  'empty: one robot, robot_name at initial_pose'),
    ParameterSpec('robot_name', 'robot0', 'name of the one robot when there is no robots_file: '
                  'topics are /<name>/cmd_vel, /<name>/odom, ...'),
    ParameterSpec('robot_radius', 0.0, 'footprint radius of that robot [m]; 0 takes the '
                  'one in robot_description', '>= 0'),
    ParameterSpec('initial_pose', [1.0, 2.0, 0.0], 'start pose of that robot [x m, y m, theta '
                  'rad] in the map frame', 'off walls, on the map'),
    ParameterSpec('max_linear_speed', 2.0, 'commands beyond this linear speed are clamped '
                  '[m/s]', '> 0'),
    ParameterSpec('max_angular_speed', math.pi, 'commands beyond this angular speed are '
                  'clamped [rad/s]', '> 0'),
    ParameterSpec('cmd_vel_timeout', 0.0, 'stop a robot whose last command is older than '
                  'this [s of sim time]; 0 holds the last command forever (STDR)', '>= 0'),
    ParameterSpec('sensor_seed', 0, 'seed of the sensor noise, so that runs repeat'),
    ParameterSpec('map_frame_id', 'map', 'frame of /map'),
    ParameterSpec('odom_frame_id', 'odom', 'frame of the odometry pose (REP-105); it '
                  'coincides with the map frame'),
    ParameterSpec('base_frame_id', 'base_link', 'child frame of the odometry (REP-105), '
                  'prefixed with the robot name'),
)

DESCRIPTION = ('stdr_lite: a small STDR-equivalent simulator. For each robot, subscribes '
               '/<robot>/cmd_vel (geometry_msgs/Twist) and /<robot>/initialpose; publishes '
               '/<robot>/odom (nav_msgs/Odometry), /<robot>/laser_J (sensor_msgs/LaserScan) and '
               '/<robot>/sonar_J (sensor_msgs/Range). Also /map (transient local) and /clock; '
               'robots come and go on ~/add_robot and ~/remove_robot (std_msgs/String).')

# Footprints up to this radius can be added while running, besides those in the start list.
LARGEST_ADDED_RADIUS = 0.5


@dataclass
class _Sensor:
    spec: object
    publisher: object
    message: object
    next_due_ns: int = 0


@dataclass
class _Robot:
    """A robot's ROS plumbing; its state lives in the World, at the robot's index."""

    name: str
    description: object
    odometry: Odometry
    odom_publisher: object
    subscriptions: list
    sensors: list = field(default_factory=list)


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
        self._frames = (params['odom_frame_id'], params['base_frame_id'])
        self._default_description = self._load_description(params['robot_description'])
        entries = self._robot_entries(params)
        self._world = self._build_world(params, entries)
        self._finder = RangeFinder(self._world.map)
        self._noise = np.random.default_rng(params['sensor_seed'])
        self._commands = CommandBuffer(0, params['max_linear_speed'],
                                       params['max_angular_speed'], params['cmd_vel_timeout'])
        self._robots = []
        self._indices = {}
        self._applied = (np.zeros(0), np.zeros(0))
        for entry in entries:
            try:
                self._add(entry)
            except PlacementError as error:
                raise ConfigError(f'{entry.name} in {self._map_name}: {error}') from None
        self.create_subscription(String, '~/add_robot', self._on_add_robot, 10)
        self.create_subscription(String, '~/remove_robot', self._on_remove_robot, 10)
        self._clock_publisher = self.create_publisher(ClockMsg, '/clock', 10)
        self._clock_message = ClockMsg()
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
        robots = ', '.join(f'{robot.name} at {tuple(pose)}' for robot, pose in zip(
            self._robots, self._world.poses.round(3).tolist()))
        self.get_logger().info(
            f'{self._map_name} {self._world.map.width}x{self._world.map.height} cells, '
            f'{robots}, {params["rate_hz"]:g} Hz {params["integrator"]}, '
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
        for name in ('max_linear_speed', 'max_angular_speed'):
            require(params[name] > 0.0, f'{name} must be positive, got {params[name]}')
        require(params['robot_radius'] >= 0.0,
                f'robot_radius must be >= 0, got {params["robot_radius"]}')
        require(params['cmd_vel_timeout'] >= 0.0,
                f'cmd_vel_timeout must be >= 0, got {params["cmd_vel_timeout"]}')
        require(len(params['initial_pose']) == 3,
                f'initial_pose must be [x, y, theta], got {params["initial_pose"]}')
        require(params['robot_name'].isidentifier(),
                f'robot_name must be a plain name such as robot0, got {params["robot_name"]!r}')

    @staticmethod
    def _load_description(path):
        try:
            return load_robot_or_default(path)
        except RobotFileError as error:
            raise ConfigError(str(error)) from None

    def _robot_entries(self, params):
        single = {name: params[name] for name in ('robot_name', 'robot_radius', 'initial_pose')}
        if not params['robots_file']:
            description = self._default_description
            if single['robot_radius'] > 0.0:
                description = replace(description, radius=single['robot_radius'])
            return [RobotEntry(single['robot_name'], description,
                               tuple(single['initial_pose']))]
        changed = [spec.name for spec in PARAMETERS
                   if spec.name in single and single[spec.name] != spec.default]
        require(not changed, f'robots_file lists the robots; drop {", ".join(changed)}')
        try:
            return load_robot_list(params['robots_file'], self._default_description)
        except RobotFileError as error:
            raise ConfigError(str(error)) from None

    def _build_world(self, params, entries):
        map_yaml = params['map_yaml'] or shared_file('maps', 'lab_room.yaml')
        try:
            occupancy_map = load_map(map_yaml)
        except MapError as error:
            raise ConfigError(str(error)) from None
        self._map_name = map_yaml
        largest = max([LARGEST_ADDED_RADIUS] + [entry.description.radius for entry in entries])
        return World(occupancy_map, largest, params['integrator'])

    def _add(self, entry):
        """Place a robot and give it topics; PlacementError leaves everything unchanged."""
        self._world.add_robot(entry.pose, entry.description.radius)
        self._commands.add_robot()
        self._applied = tuple(np.append(values, 0.0) for values in self._applied)
        name = entry.name
        odometry = Odometry()
        odometry.header.frame_id = self._frames[0]
        odometry.child_frame_id = f'{name}/{self._frames[1]}'
        robot = _Robot(name, entry.description, odometry,
                       self.create_publisher(Odometry, f'/{name}/odom', 10), [
                           self.create_subscription(Twist, f'/{name}/cmd_vel', functools.partial(
                               self._on_cmd_vel, name), 10),
                           self.create_subscription(
                               PoseWithCovarianceStamped, f'/{name}/initialpose',
                               functools.partial(self._on_initial_pose, name), 10)])
        for spec in entry.description.lasers:
            robot.sensors.append(_Sensor(spec, self.create_publisher(
                LaserScan, f'/{name}/{spec.frame_id}', 10), laser_message(name, spec)))
        for spec in entry.description.sonars:
            robot.sensors.append(_Sensor(spec, self.create_publisher(
                Range, f'/{name}/{spec.frame_id}', 10), sonar_message(name, spec)))
        for sensor in robot.sensors:
            sensor.next_due_ns = self._step_count * self._dt_ns + _period_ns(sensor.spec)
        self._robots.append(robot)
        self._indices = {robot.name: index for index, robot in enumerate(self._robots)}

    def _remove(self, name):
        index = self._indices[name]
        robot = self._robots.pop(index)
        for subscription in robot.subscriptions:
            self.destroy_subscription(subscription)
        for publisher in [robot.odom_publisher] + [sensor.publisher for sensor in robot.sensors]:
            self.destroy_publisher(publisher)
        self._world.remove_robot(index)
        self._commands.remove_robot(index)
        self._applied = tuple(np.delete(values, index) for values in self._applied)
        self._indices = {robot.name: index for index, robot in enumerate(self._robots)}
        if name in self._unanswered:
            self._answered(name)

    def _on_add_robot(self, message):
        try:
            item = yaml.safe_load(message.data)
            default_name = next(f'robot{k}' for k in range(len(self._robots) + 1)
                                if f'robot{k}' not in self._indices)
            entry = robot_entry(item, default_name, self._default_description, 'add_robot')
            if entry.name in self._indices:
                raise PlacementError(f'a robot named {entry.name} exists already')
            self._add(entry)
        except (yaml.YAMLError, RobotFileError, PlacementError) as error:
            reason = str(error).splitlines()[0]
            self.get_logger().warn(f'add_robot {message.data!r} refused: {reason}')
            return
        self.get_logger().info(f'added {entry.name} at {entry.pose}')

    def _on_remove_robot(self, message):
        name = message.data.strip()
        if name not in self._indices:
            self.get_logger().warn(f'remove_robot: no robot named {name!r}')
            return
        self._remove(name)
        self.get_logger().info(f'removed {name}')

    def _on_initial_pose(self, name, message):
        pose = message.pose.pose
        target = (pose.position.x, pose.position.y, yaw_from_quaternion(pose.orientation))
        try:
            self._world.move_robot(self._indices[name], target)
        except PlacementError as error:
            self.get_logger().warn(f'{name}: move to ({target[0]:g}, {target[1]:g}, '
                                   f'{target[2]:g}) refused: {error}')
            return
        self.get_logger().info(f'{name} moved to ({target[0]:g}, {target[1]:g}, '
                               f'{target[2]:g})')

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

    def _on_cmd_vel(self, name, message):
        index = self._indices.get(name)
        if index is None:
            return
        linear, angular = message.linear.x, message.angular.z
        if self._commands.exceeds_limits(linear, angular):
            self.get_logger().warn(
                f'{name}: command ({linear:g} m/s, {angular:g} rad/s) '
                'clamped to max_linear_speed/max_angular_speed', throttle_duration_sec=5.0)
        if not self._commands.update(index, linear, angular, self.sim_time):
            self.get_logger().warn(
                f'{name}: ignored cmd_vel with a non-finite component '
                f'({linear}, {angular}); keeping the last valid command',
                throttle_duration_sec=5.0)
        if name in self._unanswered:
            self._answered(name)

    def _answered(self, name):
        self._unanswered.discard(name)
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
        self._publish_sensors()
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
        for index, robot in enumerate(self._robots):
            message = robot.odometry
            message.header.stamp.sec, message.header.stamp.nanosec = seconds, nanoseconds
            x, y, theta = self._world.poses[index].tolist()
            message.pose.pose.position.x, message.pose.pose.position.y = x, y
            message.pose.pose.orientation.z = math.sin(0.5 * theta)
            message.pose.pose.orientation.w = math.cos(0.5 * theta)
            message.twist.twist.linear.x = float(applied_linear[index])
            message.twist.twist.angular.z = float(applied_angular[index])
            robot.odom_publisher.publish(message)

    def _publish_sensors(self):
        """Read and publish the sensors that are due and that someone listens to."""
        now_ns = self._step_count * self._dt_ns
        due = []
        for index, robot in enumerate(self._robots):
            for sensor in robot.sensors:
                if now_ns < sensor.next_due_ns:
                    continue
                period_ns = _period_ns(sensor.spec)
                sensor.next_due_ns += period_ns * (1 + (now_ns - sensor.next_due_ns)
                                                   // period_ns)
                if sensor.publisher.get_subscription_count():
                    due.append((index, sensor))
        if not due:
            return
        readings = read_sensors(self._finder, self._world.poses, self._world.radii,
                                [(index, sensor.spec) for index, sensor in due], self._noise)
        seconds, nanoseconds = divmod(now_ns, NANOSECONDS)
        for (_, sensor), reading in zip(due, readings):
            message = sensor.message
            message.header.stamp.sec, message.header.stamp.nanosec = seconds, nanoseconds
            if isinstance(message, LaserScan):
                message.ranges = reading.astype(np.float32).tolist()
            else:
                message.range = reading
            sensor.publisher.publish(message)

    def _await_answers(self):
        self._unanswered = set(self._indices)
        self._published_at = self._repeated_at = time.monotonic()

    def _repeat_unanswered_state(self):
        """Repeat unanswered odometry when a subscriber joins or after a long silence."""
        subscribers = sum(robot.odom_publisher.get_subscription_count()
                          for robot in self._robots)
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


def _period_ns(spec):
    return round(NANOSECONDS / spec.frequency)


def laser_message(robot_name, spec):
    """Return a LaserScan with all but the stamp and the ranges filled in from the spec."""
    message = LaserScan()
    message.header.frame_id = f'{robot_name}/{spec.frame_id}'
    message.angle_min, message.angle_max = spec.min_angle, spec.max_angle
    message.angle_increment = ((spec.max_angle - spec.min_angle) / (spec.num_rays - 1)
                               if spec.num_rays > 1 else 0.0)
    message.scan_time = 1.0 / spec.frequency
    message.range_min, message.range_max = spec.min_range, spec.max_range
    return message


def sonar_message(robot_name, spec):
    """Return a Range (ultrasound) with all but the stamp and the range filled in."""
    message = Range()
    message.header.frame_id = f'{robot_name}/{spec.frame_id}'
    message.radiation_type = Range.ULTRASOUND
    message.field_of_view = spec.cone_angle
    message.min_range, message.max_range = spec.min_range, spec.max_range
    message.variance = spec.noise.std ** 2
    return message


def main(argv=None):
    parser = build_parser('stdr_lite', DESCRIPTION, PARAMETERS)
    sys.exit(run('stdr_lite', parser, lambda options: StdrLite(), argv))


if __name__ == '__main__':
    main()

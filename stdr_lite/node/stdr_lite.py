"""The stdr_lite node: the simulation core on STDR's topics, stepped by timers or by answers."""

from collections import deque
import sys
import time

from nav_msgs.msg import OccupancyGrid
import numpy as np
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rosgraph_msgs.msg import Clock as ClockMsg
from simple_robot_control.node_runtime import build_parser, declare_parameters, run
from simple_robot_control.pose import pose_from_message
from std_msgs.msg import String
from stdr_lite.core.robot_description import robot_entry, RobotFileError
from stdr_lite.core.simulation import CommandOutcome, RequestError
from stdr_lite.core.world import PlacementError
from stdr_lite.node.frames import FramePublisher
from stdr_lite.node.health import HealthWatch
from stdr_lite.node.messages import map_message, set_stamp
from stdr_lite.node.parameters import build_simulation, frames, PARAMETERS
from stdr_lite.node.robot_topics import RobotTopics
import yaml

# In lockstep, odometry that has gone unanswered this long is published again (same stamp), so
# a controller that started after it was first sent still gets it.
LOCKSTEP_REPEAT_AFTER = 0.5
LATENCY_SAMPLES = 100_000

DESCRIPTION = ('stdr_lite: a small STDR-equivalent simulator. For each robot, subscribes '
               '/<robot>/cmd_vel (geometry_msgs/Twist) and /<robot>/initialpose; publishes '
               '/<robot>/odom (nav_msgs/Odometry), /<robot>/laser_J (sensor_msgs/LaserScan) and '
               '/<robot>/sonar_J (sensor_msgs/Range). Also /map (transient local) and /clock; '
               'robots come and go on ~/add_robot and ~/remove_robot (std_msgs/String).')


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
        self._frames = frames(params)
        self.simulation, self._default_description = build_simulation(params)
        self._stamped = params['cmd_vel_stamped']
        self._frame_publisher = FramePublisher(self, self._frames)
        self._topics = {}
        for name in self.simulation.names:
            self._add_topics(name)
        self._frame_publisher.publish_fixed(self.simulation)
        self.create_subscription(String, '~/add_robot', self._on_add_robot, 10)
        self.create_subscription(String, '~/remove_robot', self._on_remove_robot, 10)
        self._clock_publisher = self.create_publisher(ClockMsg, '/clock', 10)
        self._clock_message = ClockMsg()
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_publisher(OccupancyGrid, '/map', latched).publish(
            map_message(self.simulation.occupancy_map, self._frames.map_frame))
        self._lockstep = params['lockstep']
        self._published_at = self._repeated_at = 0.0
        self._odometry_subscribers = 0
        self.answer_latencies = deque(maxlen=LATENCY_SAMPLES)
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        paced = params['real_time_factor'] > 0.0
        if paced or not self._lockstep:
            period = self.simulation.dt / params['real_time_factor'] if paced else 0.0
            self.create_timer(period, self._on_tick, clock=steady)
        self._step_on_answer = self._lockstep and not paced
        # In lockstep the controller sets the pace by design: only free-running can lag.
        HealthWatch(self, self.simulation, self._topics,
                    0.0 if self._lockstep else params['real_time_factor'])
        if self._lockstep:
            self.create_timer(0.05, self._repeat_unanswered_state, clock=steady)
            self.simulation.odometry_due()
            self._publish_state()
            self._await_answers()
        names = self.simulation.names
        robots = (', '.join(f'{name} at {tuple(round(v, 3) for v in self.simulation.pose(name))}'
                            for name in names) if len(names) <= 5 else f'{len(names)} robots')
        self.get_logger().info(
            f'{self.simulation.occupancy_map.source} {self.simulation.occupancy_map.width}x'
            f'{self.simulation.occupancy_map.height} cells, {robots}, {params["rate_hz"]:g} Hz '
            f'{params["integrator"]}, real_time_factor {params["real_time_factor"]:g}'
            + (', lockstep' if self._lockstep else ''))

    @property
    def sim_time(self):
        """Return the simulated seconds since start."""
        return self.simulation.sim_time

    def _add_topics(self, name):
        self._topics[name] = RobotTopics(self, self.simulation.robot(name), self._frames,
                                         self._stamped, self._on_cmd_vel, self._on_initial_pose)

    def _on_add_robot(self, message):
        try:
            entry = robot_entry(yaml.safe_load(message.data), self.simulation.default_name(),
                                self._default_description, 'add_robot')
            self.simulation.add_robot(entry)
        except (yaml.YAMLError, RobotFileError, PlacementError, RequestError) as error:
            reason = str(error).splitlines()[0]
            self.get_logger().warn(f'add_robot {message.data!r} refused: {reason}')
            return
        self._add_topics(entry.name)
        self._frame_publisher.publish_fixed(self.simulation)
        self.get_logger().info(f'added {entry.name} at {entry.pose}')

    def _on_remove_robot(self, message):
        name = message.data.strip()
        if name not in self.simulation:
            self.get_logger().warn(f'remove_robot: no robot named {name!r}')
            return
        self.simulation.remove_robot(name)
        self._topics.pop(name).destroy()
        self._frame_publisher.publish_fixed(self.simulation)
        self.get_logger().info(f'removed {name}')
        self._step_if_answered()

    def _on_initial_pose(self, name, message):
        target = pose_from_message(message.pose.pose)
        where = ', '.join(f'{value:g}' for value in target)
        try:
            self.simulation.teleport(name, target)
        except PlacementError as error:
            self.get_logger().warn(f'{name}: move to ({where}) refused: {error}')
            return
        self.get_logger().info(f'{name} moved to ({where})')

    def _on_cmd_vel(self, name, linear, angular):
        if name not in self.simulation:
            return
        outcome = self.simulation.command(name, linear, angular)
        if outcome is not CommandOutcome.APPLIED:
            self.get_logger().warn(f'{name}: command ({linear:g} m/s, {angular:g} rad/s) '
                                   f'{outcome.value}', throttle_duration_sec=5.0)
        if self.simulation.answer(name):
            self.answer_latencies.append(time.monotonic() - self._published_at)
            self._step_if_answered()

    def _step_if_answered(self):
        """Unpaced lockstep: run to the next published odometry once all have answered."""
        if self._step_on_answer and not self.simulation.awaiting_answers:
            while not self._step():
                pass

    def _on_tick(self):
        if not self.simulation.awaiting_answers:
            self._step()

    def _step(self):
        """Advance one step and publish what falls due; return whether odometry went out."""
        self.simulation.step()
        if self._clock_publisher.get_subscription_count():
            set_stamp(self._clock_message.clock, self.simulation.time_ns)
            self._clock_publisher.publish(self._clock_message)
        published = self.simulation.odometry_due()
        if published:
            self._publish_state()
            if self._lockstep:
                self._await_answers()
        self._publish_sensors()
        return published

    def _publish_state(self):
        """Publish every robot's odometry, its ground truth and the moving TF frames."""
        now_ns = self.simulation.time_ns
        for name, topics in self._topics.items():
            topics.publish_odometry(now_ns, self.simulation.odometry(name),
                                    self.simulation.ground_truth(name))
        self._frame_publisher.publish_moving(self.simulation, now_ns)

    def _publish_sensors(self):
        """Read and publish the sensors that are due and that someone listens to."""
        jobs = [(name, spec) for name, spec in self.simulation.due_sensors()
                if self._topics[name].listened(spec)]
        if not jobs:
            return
        now_ns = self.simulation.time_ns
        for (name, spec), reading in zip(jobs, self.simulation.read_sensors(jobs)):
            self._topics[name].publish_reading(spec, now_ns, reading)

    def _await_answers(self):
        self.simulation.expect_answers()
        self._published_at = self._repeated_at = time.monotonic()

    def _repeat_unanswered_state(self):
        """Repeat unanswered odometry when a subscriber joins or after a long silence."""
        subscribers = sum(topics.odom_publisher.get_subscription_count()
                          for topics in self._topics.values())
        joined, self._odometry_subscribers = (subscribers > self._odometry_subscribers,
                                              subscribers)
        silent = time.monotonic() - self._repeated_at > LOCKSTEP_REPEAT_AFTER
        if self.simulation.awaiting_answers and (joined or silent):
            self._publish_state()
            self._repeated_at = time.monotonic()

    def shut_down(self):
        """Log how long the controller took to answer, when in lockstep."""
        if self._lockstep and self.answer_latencies:
            median, p99 = np.percentile(self.answer_latencies, (50, 99)) * 1e3
            self.get_logger().info(
                f'lockstep: {self.simulation.step_count} steps, cmd_vel answered odometry '
                f'after {median:.2f} ms (median), {p99:.2f} ms (99th percentile)')


def main(argv=None):
    parser = build_parser('stdr_lite', DESCRIPTION, PARAMETERS)
    sys.exit(run('stdr_lite', parser, lambda options: StdrLite(), argv))


if __name__ == '__main__':
    main()

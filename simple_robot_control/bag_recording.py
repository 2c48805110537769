"""
Topics recorded into a rosbag2 bag in MCAP as they appear in the graph, on behalf of a node.

Topics are matched by pattern against the graph, looked at twice a second, so robots spawned
later are recorded too; each is subscribed with what its publishers offer (reliable and
transient local only when all of them are), so a transient-local topic's history is received,
as ros2 bag does. record_run is a node of its own around it; course_monitor records its run
with it.
"""

from collections import Counter
from fnmatch import fnmatchcase
import importlib

from rclpy.clock import Clock, ClockType
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from simple_robot_control.bag import BagError, BagWriter
from simple_robot_control.input_files import output_problem
from simple_robot_control.node_runtime import ConfigError

GRAPH_PERIOD = 0.5
DEPTH = 1000
# What makes a run: the controller's reports and course, every robot's odometry and ground
# truth, the frames, the map and the time.
RUN_TOPICS = ('/robot_status', '/waypoints', '/tf', '/tf_static', '/map', '/clock', '*/odom',
              '*/ground_truth')


def offered(profile):
    """Return a publisher's QoS profile as rosbag2 writes it (bag version 9)."""
    def duration(value):
        seconds, nanoseconds = divmod(value.nanoseconds, 10 ** 9)
        return {'sec': seconds, 'nsec': nanoseconds}
    return {'history': profile.history.name.lower(), 'depth': profile.depth,
            'reliability': profile.reliability.name.lower(),
            'durability': profile.durability.name.lower(),
            'deadline': duration(profile.deadline), 'lifespan': duration(profile.lifespan),
            'liveliness': profile.liveliness.name.lower(),
            'liveliness_lease_duration': duration(profile.liveliness_lease_duration),
            'avoid_ros_namespace_conventions': profile.avoid_ros_namespace_conventions}


def message_class(type_name):
    """Return the Python class of a pkg/msg/Type, or None if it is not installed."""
    package, kind, name = type_name.split('/')
    try:
        return getattr(importlib.import_module(f'{package}.{kind}'), name)
    except (ImportError, AttributeError):
        return None


class BagRecording:
    """Records every topic matching the patterns into the bag at path, for node."""

    def __init__(self, node, path, patterns=RUN_TOPICS, inputs=()):
        problem = output_problem(path, inputs=inputs)
        if problem is not None:
            raise ConfigError(f'bag {path}: {problem}')
        try:
            self.bag = BagWriter(path)
        except BagError as error:
            raise ConfigError(str(error)) from None
        self._node = node
        self._patterns = tuple(patterns)
        self._recorded = {}
        self.received = Counter()
        self._skipped = set()
        node.create_timer(GRAPH_PERIOD, self._follow_graph,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._follow_graph()

    @property
    def topics(self):
        """Return the topics being recorded."""
        return sorted(self._recorded)

    def _follow_graph(self):
        node = self._node
        for topic, types in node.get_topic_names_and_types():
            if topic in self._recorded or topic in self._skipped or not any(
                    fnmatchcase(topic, pattern) for pattern in self._patterns):
                continue
            publishers = node.get_publishers_info_by_topic(topic)
            if publishers:
                self._record(topic, types, publishers)

    def _record(self, topic, types, publishers):
        kind = message_class(types[0]) if len(types) == 1 else None
        if kind is None:
            self._skipped.add(topic)
            self._node.get_logger().warn(
                f'{topic}: not recorded: its type {" or ".join(types)} is not installed or not '
                'one type')
            return
        profiles = [info.qos_profile for info in publishers]
        try:
            channel = self.bag.add_topic(topic, types[0], [offered(p) for p in profiles])
        except BagError as error:
            self._skipped.add(topic)
            self._node.get_logger().warn(f'{topic}: not recorded: {error}')
            return
        qos = QoSProfile(depth=DEPTH, reliability=(
            ReliabilityPolicy.RELIABLE if all(p.reliability == ReliabilityPolicy.RELIABLE
                                              for p in profiles)
            else ReliabilityPolicy.BEST_EFFORT), durability=(
            DurabilityPolicy.TRANSIENT_LOCAL if all(
                p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in profiles)
            else DurabilityPolicy.VOLATILE))
        clock = self._node.get_clock()

        def write(data):
            self.bag.write(channel, clock.now().nanoseconds, data)
            self.received[topic] += 1
        self._recorded[topic] = self._node.create_subscription(kind, topic, write, qos, raw=True)

    def close(self):
        """Finish the bag, so that an interrupted recording is complete and indexed."""
        self.bag.close()
        self._node.get_logger().info(f'{self.bag.path}: {self.bag.message_count} messages of '
                                     f'{len(self._recorded)} topics')

"""
record_run: record a run's topics, or any, into a rosbag2 bag in MCAP until Ctrl-C.

The PyPI route to ROS 2 has no `ros2 bag`; this writes what Jazzy's `ros2 bag record -s mcap`
writes (see bag.py), for ros2 bag, Foxglove, rosbags and plot_run. Topics are matched by
pattern against the graph, looked at twice a second, so robots spawned later are recorded
too; each is subscribed with what its publishers offer (reliable and transient local only
when all of them are), so a transient-local topic's history is received, as ros2 bag does.
"""

from fnmatch import fnmatchcase
import importlib
import sys

from rclpy.clock import Clock, ClockType
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from simple_robot_control.bag import BagError, BagWriter
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.input_files import output_problem
from simple_robot_control.node_runtime import build_parser, ConfigError, run
from simple_robot_control.parameters import declare_parameters, ParameterSpec

GRAPH_PERIOD = 0.5
DEPTH = 1000
# What makes a run: the controller's reports, every robot's odometry and ground truth, the
# frames, the map and the time.
RUN_TOPICS = ('/robot_status', '/tf', '/tf_static', '/map', '/clock', '*/odom',
              '*/ground_truth')

PARAMETERS = (
    ParameterSpec('bag', 'run.mcap', 'the bag to write, an .mcap file (replaced if it exists)'),
    ParameterSpec('topics', RUN_TOPICS, 'the topics to record: full names or patterns (* and ?, '
                  "as in shell globs; '*/laser_*' adds every robot's lasers)"),
)

DESCRIPTION = ('record_run: record the topics of a run (robot_status, odometry, ground truth, '
               'TF, map, clock; or those given) into a rosbag2 bag in MCAP that ros2 bag, '
               'Foxglove and plot_run read. Stops on Ctrl-C, leaving the bag complete.')


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


class RunRecorder(GuardedNode):
    """Subscribes to every topic matching the patterns as it appears, and writes the bag."""

    def __init__(self, bag=None, topics=None, **kwargs):
        super().__init__('record_run', **kwargs)
        # Recording ends only when asked to (Ctrl-C): nothing sets this.
        self.finished = Future()
        params = declare_parameters(self, PARAMETERS)
        path = bag or params['bag']
        problem = output_problem(path)
        if problem is not None:
            raise ConfigError(f'bag {path}: {problem}')
        self._patterns = tuple(topics or params['topics'])
        try:
            self.bag = BagWriter(path)
        except BagError as error:
            raise ConfigError(str(error)) from None
        self._recorded = {}
        self._skipped = set()
        self.create_timer(GRAPH_PERIOD, self._follow_graph,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._follow_graph()

    @property
    def topics(self):
        """Return the topics being recorded."""
        return sorted(self._recorded)

    def _follow_graph(self):
        for topic, types in self.get_topic_names_and_types():
            if topic in self._recorded or topic in self._skipped or not any(
                    fnmatchcase(topic, pattern) for pattern in self._patterns):
                continue
            publishers = self.get_publishers_info_by_topic(topic)
            if publishers:
                self._record(topic, types, publishers)

    def _record(self, topic, types, publishers):
        kind = message_class(types[0]) if len(types) == 1 else None
        if kind is None:
            self._skipped.add(topic)
            self.get_logger().warn(f'{topic}: not recorded: its type '
                                   f'{" or ".join(types)} is not installed or not one type')
            return
        profiles = [info.qos_profile for info in publishers]
        try:
            channel = self.bag.add_topic(topic, types[0], [offered(p) for p in profiles])
        except BagError as error:
            self._skipped.add(topic)
            self.get_logger().warn(f'{topic}: not recorded: {error}')
            return
        qos = QoSProfile(depth=DEPTH, reliability=(
            ReliabilityPolicy.RELIABLE if all(p.reliability == ReliabilityPolicy.RELIABLE
                                              for p in profiles)
            else ReliabilityPolicy.BEST_EFFORT), durability=(
            DurabilityPolicy.TRANSIENT_LOCAL if all(
                p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in profiles)
            else DurabilityPolicy.VOLATILE))
        clock = self.get_clock()
        self._recorded[topic] = self.create_subscription(
            kind, topic, lambda data: self.bag.write(channel, clock.now().nanoseconds, data),
            qos, raw=True)

    def shut_down(self):
        """Finish the bag, so that an interrupted recording is complete and indexed."""
        self.bag.close()
        self.get_logger().info(f'{self.bag.path}: {self.bag.message_count} messages of '
                               f'{len(self._recorded)} topics')


def main(argv=None):
    parser = build_parser('record_run', DESCRIPTION, PARAMETERS)
    sys.exit(run('record_run', parser, lambda options: RunRecorder(), argv))


if __name__ == '__main__':
    main()

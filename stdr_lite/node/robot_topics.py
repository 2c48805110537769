"""One simulated robot's topics: what it hears and what it says, with reused messages."""

from collections.abc import Iterator

from geometry_msgs.msg import PoseWithCovarianceStamped, Twist, TwistStamped
from nav_msgs.msg import Odometry
import numpy as np
from rclpy.event_handler import PublisherEventCallbacks
from simple_robot_control.graph import type_name
from std_msgs.msg import Bool
try:
    from stdr_msgs.srv import MoveRobot
except ImportError:  # a ROS 2 machine where interfaces/stdr_msgs was not built
    MoveRobot = None
from stdr_lite.core.odometry import OdometryReading
from stdr_lite.core.robot_description import LaserSpec, SonarSpec
from stdr_lite.node.messages import fill_odometry, fill_reading, sensor_message, set_stamp

GROUND_TRUTH = 'ground_truth'
# Whether the robot's last step was refused (a wall, a robot or an obstacle in its way).
STALL = 'stall'
# A reliable publisher keeps this many messages for a reader that has not acknowledged them: a
# recorder judging a run from the truth and the stall flag (grade_lab) loses none while it lags
# up to 2 s of sim time behind at 50 Hz (a lockstep run is as fast as its controller answers).
# Sensors keep rclpy's usual 10.
JUDGED_DEPTH = 100


class RobotTopics:
    """
    The publishers and subscriptions of one robot, named as STDR names them.

    Topics are relative (<robot>/odom, <robot>/cmd_vel, ...), so they sit under the node's
    namespace and can be remapped; <robot> is the robot's topic namespace (its name unless it
    was spawned with another), which prefixes its frames too. Messages are built once and
    refilled at every publish. on_command(name, twist) gets every command's Twist, plain or
    stamped. The ground truth, the stall flag and the sensors, which cost only when someone
    listens, keep count of their readers from the middleware's matched events rather than
    asking the graph at every message; on_truth_reader(name) is called when the ground truth
    gains one, so a late reader gets the current truth at once (in lockstep the next may be
    long in coming).

    Every endpoint costs the node more the more it has (a large swarm's start is dominated by
    their number), so with on_demand the ground truth, the stall flag and the sensors get their
    publishers only once the graph shows a reader of their topic (see wanted and make_wanted).
    """

    def __init__(self, node, robot, frames, stamped, on_command, on_initial_pose,
                 on_truth_reader, on_demand=False):
        name, prefix = robot.name, robot.namespace
        self.name = name
        self._node = node
        self._odometry = Odometry()
        self._odometry.header.frame_id = frames.odom(prefix)
        self._odometry.child_frame_id = frames.base(prefix)
        self._ground_truth = Odometry()
        self._ground_truth.header.frame_id = frames.map_frame
        self._ground_truth.child_frame_id = frames.base(prefix)
        self.odom_publisher = node.create_publisher(Odometry, f'{prefix}/odom', 10)
        self._readers = {}
        self._on_truth_reader = on_truth_reader
        self._ground_truth_publisher = self._stall_publisher = None
        self._stall = Bool()
        self._prefix, self._frames = prefix, frames
        self._on_command = on_command
        self._command = self._command_subscription(TwistStamped if stamped else Twist)
        # A supervised simulator (on_initial_pose None) lets nothing move a robot. STDR's own
        # teleport, /robotN/replace, where its stdr_msgs are built (interfaces/).
        self._pose_subscription = self._replace = None
        if on_initial_pose is not None:
            self._pose_subscription = node.create_subscription(
                PoseWithCovarianceStamped, f'{prefix}/initialpose',
                lambda message: on_initial_pose(name, message), 10)
        if on_initial_pose is not None and MoveRobot is not None:
            self._replace = node.create_service(
                MoveRobot, f'{prefix}/replace',
                lambda request, response: (on_initial_pose(name, request), response)[1])
        self.cmd_vel_topic = self._command.topic_name
        self._sensors = {}
        self._optional = {node.resolve_topic_name(f'{prefix}/{key}'): item for key, item in [
            (GROUND_TRUTH, GROUND_TRUTH), (STALL, STALL),
            *((sensor.spec.frame_id, sensor.spec) for sensor in robot.sensors)]}
        self._unmade = [] if on_demand else list(self._optional.values())
        if not on_demand:
            self._make(self._unmade.pop(0))

    def _command_subscription(self, kind):
        """Subscribe to the robot's cmd_vel as kind (Twist or TwistStamped)."""
        self.command_type = type_name(kind)
        name = self.name
        if kind is TwistStamped:
            return self._node.create_subscription(
                TwistStamped, f'{self._prefix}/cmd_vel',
                lambda message: self._on_command(name, message.twist), 10)
        return self._node.create_subscription(
            Twist, f'{self._prefix}/cmd_vel', lambda message: self._on_command(name, message), 10)

    def stop_reading_commands(self) -> None:
        """
        Take the cmd_vel subscription away, to subscribe anew with another type soon.

        The middleware lets the topic go only once the executor has let the old subscription
        go: a subscription of another type made at once would be refused.
        """
        self._node.destroy_subscription(self._command)
        self._command = None

    def read_commands_as(self, kind: type) -> None:
        """Read the robot's cmd_vel as kind from now on, after stop_reading_commands."""
        if self._command is None:
            self._command = self._command_subscription(kind)

    @property
    def complete(self) -> bool:
        """Whether every publisher due is made (see make_sensor_topic)."""
        return not self._unmade

    def wanted(self, topic: str) -> None:
        """Queue the publisher of topic (its full name) if it is one of ours not yet made."""
        item = self._optional.get(topic)
        if item is not None and item not in self._unmade and not self._made(item):
            self._unmade.append(item)

    @property
    def unmade_topics(self) -> list[str]:
        """Return the full names of the optional topics with no publisher and none due."""
        return [topic for topic, item in self._optional.items()
                if item not in self._unmade and not self._made(item)]

    def _made(self, item):
        if item == GROUND_TRUTH:
            return self._ground_truth_publisher is not None
        if item == STALL:
            return self._stall_publisher is not None
        return item.frame_id in self._sensors

    def make_sensor_topic(self) -> None:
        """
        Make one more publisher that is due, if any is left.

        Endpoints cost a fraction of a millisecond each, and a robot may have a hundred
        sensors: a spawn makes them one at a time, between steps. A sensor without its
        publisher yet is read by no one.
        """
        if self._unmade:
            self._make(self._unmade.pop(0))

    def _make(self, item):
        if item == GROUND_TRUTH:
            name = self.name
            self._ground_truth_publisher = self._counted_publisher(
                Odometry, f'{self._prefix}/{GROUND_TRUTH}', GROUND_TRUTH,
                lambda: self._on_truth_reader(name), JUDGED_DEPTH)
            return
        if item == STALL:
            self._stall_publisher = self._counted_publisher(
                Bool, f'{self._prefix}/{STALL}', STALL, depth=JUDGED_DEPTH)
            return
        message = sensor_message(self._frames.sensor(self._prefix, item), item)
        publisher = self._counted_publisher(type(message), f'{self._prefix}/{item.frame_id}',
                                            item.frame_id)
        self._sensors[item.frame_id] = (publisher, message)

    def _counted_publisher(self, kind, topic, key, on_new_reader=None, depth=10):
        """Create a publisher whose matched readers are counted in self._readers[key]."""
        self._readers[key] = 0

        def matched(status):
            self._readers[key] = status.current_count
            if on_new_reader is not None and status.current_count_change > 0:
                on_new_reader()
        return self._node.create_publisher(
            kind, topic, depth, event_callbacks=PublisherEventCallbacks(matched=matched))

    def publish_odometry(self, time_ns: int, reading: OdometryReading) -> None:
        fill_odometry(self._odometry, time_ns, reading)
        self.odom_publisher.publish(self._odometry)

    @property
    def ground_truth_listened(self) -> bool:
        """Whether anyone subscribes to the ground truth, so it is worth publishing."""
        return self._readers.get(GROUND_TRUTH, 0) > 0

    def publish_ground_truth(self, time_ns: int, reading: OdometryReading) -> None:
        fill_odometry(self._ground_truth, time_ns, reading)
        self._ground_truth_publisher.publish(self._ground_truth)

    @property
    def stall_listened(self) -> bool:
        """Whether anyone subscribes to the stall flag."""
        return self._readers.get(STALL, 0) > 0

    def publish_stall(self, stalled: bool) -> None:
        self._stall.data = stalled
        self._stall_publisher.publish(self._stall)

    def listened(self, spec: LaserSpec | SonarSpec) -> bool:
        """Whether anyone subscribes to this sensor's topic."""
        return self._readers.get(spec.frame_id, 0) > 0

    def any_listened(self) -> bool:
        """Whether anyone subscribes to any of the robot's sensors."""
        return any(self._readers[frame_id] for frame_id in self._sensors)

    def publish_reading(self, spec: LaserSpec | SonarSpec, time_ns: int,
                        reading: np.ndarray | float) -> None:
        publisher, message = self._sensors[spec.frame_id]
        set_stamp(message.header.stamp, time_ns)
        fill_reading(message, reading)
        publisher.publish(message)

    def dismantle(self) -> Iterator[None]:
        """
        Take the robot's topics off the graph, one at a time, yielding after each (a generator).

        Withdrawing an endpoint costs more the more the node has (rmw sends the whole list
        again): between steps, one at a time, a large swarm's robot goes without a stall.
        """
        for subscription in (self._command, self._pose_subscription):
            if subscription is not None:
                self._node.destroy_subscription(subscription)
            yield
        if self._replace is not None:
            self._node.destroy_service(self._replace)
            yield
        publishers = [self.odom_publisher, self._ground_truth_publisher, self._stall_publisher]
        publishers += [publisher for publisher, _ in self._sensors.values()]
        for publisher in filter(None, publishers):
            self._node.destroy_publisher(publisher)
            yield
        self._unmade = []

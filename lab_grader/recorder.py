"""
The grader's node in a course's domain.

It records the run's bag (at most MAX_BAG_BYTES of it), keeps every robot_status message with
its send time (at most status_limit of them), a mapping submission's last map (none larger than
the world's geometry could be), and reads the graph for who publishes where. What it holds of a
run is so bounded whatever the submission sends, but for the one message being received.
"""

from collections.abc import Iterable
import time

from courseworks.courses import submitted_map_topic
from courseworks.names import MAPPING
from lab_grader.publishers import Publisher
from nav_msgs.msg import OccupancyGrid
from rclpy.logging import LoggingSeverity
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from simple_robot_control.bag_recording import BagRecording
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.occupancy_map import load_map, MapError, MAX_CELLS, OccupancyMap
from std_msgs.msg import String
from stdr_lite.core.loading import map_file
from waypoint_lab.course import Course
from waypoint_lab.rules import COURSE_TOPIC, STATUS_TOPIC
from waypoint_lab.status import parse_status

# Everything the run is judged by is kept, however far behind the recorder falls (a lockstep
# simulator runs as fast as the controller answers): nothing is dropped from the queue. Reliable
# readers match the simulator's publishers and the lab's status publisher (rclpy's default,
# reliable and volatile) alike, transient-local ones too.
JUDGED_QOS = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE)
STATUS_HISTORY = QoSProfile(history=HistoryPolicy.KEEP_ALL, reliability=ReliabilityPolicy.RELIABLE,
                            durability=DurabilityPolicy.TRANSIENT_LOCAL)
# A submitted map: the last matters, and one at a time is taken in.
MAP_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                     reliability=ReliabilityPolicy.RELIABLE)
MAP_HISTORY = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                         reliability=ReliabilityPolicy.RELIABLE,
                         durability=DurabilityPolicy.TRANSIENT_LOCAL)
# What a map's message may hold beyond its cells (header, frame, geometry).
MAP_HEADER_BYTES = 4096
FINER = 4
MAX_BAG_BYTES = 512 << 20
# The simulator's topics, which nothing else may publish on during a run.
SIMULATOR_TOPICS = ('/clock', '/map', '/tf', '/tf_static')
ROBOT_TOPICS = ('odom', 'ground_truth', 'stall')


def status_limit(course: Course) -> int:
    """Return the most robot_status messages a run may send: ten times an honest run's, +100."""
    return 10 * (len(course.waypoints) + 2) + 100


class GradingRecorder(GuardedNode):
    """Records the run's topics into its bag, keeps robot_status, and watches the publishers."""

    def __init__(self, context, bag, robot_name, course):
        # Each course's recorder is a node of this process: one rosout publisher per name.
        super().__init__('grade_lab_recorder', context=context, enable_rosout=False)
        # What goes wrong (a bag the disk refuses) is said once, by the course's verdict.
        self.get_logger().set_level(LoggingSeverity.FATAL)
        robot = f'/{robot_name}'
        self.recording = BagRecording(self, bag, (f'/{COURSE_TOPIC}', '/map'), send_times=True,
                                      course=course.waypoint_file.name, max_bytes=MAX_BAG_BYTES)
        self.simulator_topics = {f'{robot}/ground_truth': 'nav_msgs/msg/Odometry',
                                 f'{robot}/stall': 'std_msgs/msg/Bool'}
        self.watched = SIMULATOR_TOPICS + tuple(f'{robot}/{name}' for name in ROBOT_TOPICS)
        # The truth over ROS is the bag's, and tells how far behind the recorder is.
        self.truth_sent = self.truth_heard_at = 0
        for topic, type_name in self.simulator_topics.items():
            self.recording.record_now(topic, type_name, JUDGED_QOS,
                                      self._on_truth if 'ground_truth' in topic else None)
        self.ended_at = None
        self.status_heard_at = 0.0
        self.statuses = []
        self.status_limit = status_limit(course)
        # A transient-local status publisher (the lab's controller's) replays to the second
        # subscription what the first missed while the publisher's side of the match lagged.
        self.recording.record_now(f'/{STATUS_TOPIC}', 'std_msgs/msg/String', JUDGED_QOS,
                                  self._on_status, STATUS_HISTORY)
        # A mapping submission's map: the last one is judged (kept serialised until then).
        self._last_map = self._map_refused = None
        self._map_topic = submitted_map_topic(course)
        if course.task == MAPPING:
            world = load_map(map_file(course.map_file))
            # A map up to 4 times finer than the world's is judged too (on_world_cells).
            self._map_limit = (min(FINER * FINER * world.width * world.height, MAX_CELLS)
                               + MAP_HEADER_BYTES)
            self._world_size = f'{world.width}x{world.height}'
            self.recording.record_now(self._map_topic, 'nav_msgs/msg/OccupancyGrid',
                                      MAP_QOS, self._on_map, MAP_HISTORY, self._map_fits)

    def _map_fits(self, data):
        return len(data) <= self._map_limit

    def _on_map(self, data, _):
        if self._map_fits(data):
            self._last_map, self._map_refused = data, None
        else:
            self._last_map, self._map_refused = None, (
                f'{len(data):,} bytes on {self._map_topic}, more than a map of the '
                f"world's {self._world_size} cells at {FINER} times finer takes: refused as it "
                'came')

    @property
    def bag_truncated(self) -> str:
        """Say why the bag stopped short of the run ('' when it did not)."""
        return self.recording.bag.truncated

    def submitted_map(self) -> OccupancyMap | str | None:
        """Return the last map the submission published, a line saying why it is none, or None."""
        if self._map_refused:
            return self._map_refused
        if self._last_map is None:
            return None
        try:
            return OccupancyMap.from_grid_message(
                deserialize_message(self._last_map, OccupancyGrid), self._map_topic)
        except MapError as error:
            return str(error)

    @property
    def simulator_matched(self) -> bool:
        """Whether the simulator's topics recorded in the bag have their publisher matched."""
        return all(self.recording.subscription(topic).get_publisher_count()
                   for topic in self.simulator_topics)

    @property
    def status_publishers(self) -> int:
        return self.recording.subscription(f'/{STATUS_TOPIC}').get_publisher_count()

    @property
    def sent_statuses(self) -> int:
        """Count the statuses sent: heard, or numbered by their publisher (one may outrun us)."""
        return max(len(self.statuses),
                   self.recording.highest_sequence.get(f'/{STATUS_TOPIC}', 0))

    def take_waiting_statuses(self) -> int:
        """Take every status that waits in the subscription now (see BagRecording)."""
        return self.recording.take_waiting(f'/{STATUS_TOPIC}')

    @property
    def flooded(self) -> bool:
        return self.sent_statuses > self.status_limit

    def _on_truth(self, _, sent):
        self.truth_sent, self.truth_heard_at = sent or 0, time.monotonic()

    def _on_status(self, data, sent):
        self.status_heard_at = time.monotonic()
        if self.flooded:
            return
        text = deserialize_message(data, String).data
        self.statuses.append((sent or time.time_ns(), text))
        status = parse_status(text)
        if status is not None and status.ends_run and self.ended_at is None:
            self.ended_at = time.monotonic()

    def publishers(self, topics: Iterable[str]) -> list[Publisher]:
        """Return every publisher the graph shows on topics."""
        return [Publisher(topic, f'{info.node_namespace.rstrip("/")}/{info.node_name}',
                          bytes(info.endpoint_gid))
                for topic in topics for info in self.get_publishers_info_by_topic(topic)]

    def others(self) -> list[str]:
        """Return the nodes of the graph, this one aside."""
        return [f'{namespace.rstrip("/")}/{name}'
                for name, namespace in self.get_node_names_and_namespaces()
                if name != self.get_name()]

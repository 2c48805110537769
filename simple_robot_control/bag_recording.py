"""
Topics recorded into a rosbag2 bag in MCAP as they appear in the graph, on behalf of a node.

Topics are matched by pattern against the graph, looked at twice a second, so robots spawned
later are recorded too (hidden ones, an action's, left out, as ros2 bag record does); each is
subscribed with what its publishers offer (reliable and transient local only when all of them
are), so a transient-local topic's history is received, as ros2 bag does. A message's log time
is when it was received (by the node's clock); with send_times, its publish time is when it was
sent (the middleware's source timestamp, wall time), as rosbag2 writes it, whichever executor
spins the node (rclpy's EventsExecutor gives it only to a callback that asks for it, and
differently: see _make_subscription).
record_run is a node of its own around it; course_monitor and grade_lab record runs with it.
A bag the disk stops taking (full) ends the recording with one line, never the node's run.
"""

from collections import Counter
from collections.abc import Callable
from fnmatch import fnmatchcase
import hashlib
import importlib
import inspect
import time

from rclpy.clock import Clock, ClockType
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.subscription import Subscription
from rclpy.topic_or_service_is_hidden import topic_or_service_is_hidden
from simple_robot_control.bag import BagError, BagWriter, RUN_METADATA
from simple_robot_control.input_files import output_problem
from simple_robot_control.validation import ConfigError

GRAPH_PERIOD = 0.5
DEPTH = 1000
# One look at the graph subscribes to new topics for at most this long (s), then lets the
# executor run (a Ctrl-C's ending among them) and goes on CATCH_UP_PERIOD later: a swarm's
# thousands of topics once held the node's start for seconds, and a Ctrl-C then left no bag.
GRAPH_WORK = 0.05
CATCH_UP_PERIOD = 0.005


def offered(profile: QoSProfile) -> dict:
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


def message_class(type_name: str) -> type | None:
    """Return the Python class of a pkg/msg/Type, or None if it is not installed."""
    package, kind, name = type_name.split('/')
    try:
        return getattr(importlib.import_module(f'{package}.{kind}'), name)
    except (ImportError, AttributeError):
        return None


def subscription_qos(profiles: list[QoSProfile], depth: int = DEPTH
                     ) -> tuple[QoSProfile, bool]:
    """
    Return the QoS to subscribe with to publishers offering profiles, and whether it latches.

    Reliable and transient local only when every publisher is, as ros2 bag subscribes.
    """
    reliable = all(p.reliability == ReliabilityPolicy.RELIABLE for p in profiles)
    latched = all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in profiles)
    return QoSProfile(depth=depth, reliability=(
        ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT),
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE
    ), latched


class BagRecording:
    """
    Records every topic matching the patterns into the bag at path, for node.

    course, if given, is the name of the run's waypoint file, kept in the bag's metadata.
    """

    def __init__(self, node, path, patterns, inputs=(), send_times=False,
                 course='', max_bytes=None):
        problem = output_problem(path, inputs=inputs)
        if problem is not None:
            raise ConfigError(f'bag {path}: {problem}')
        try:
            self.bag = BagWriter(path, max_bytes)
            if course:
                self.bag.add_metadata(RUN_METADATA, {'course': course})
        except BagError as error:
            raise ConfigError(str(error)) from None
        self._node = node
        self._patterns = tuple(patterns)
        self._recorded = {}
        self.received = Counter()
        # With send_times: per topic, the highest sequence number of a message its publishers
        # sent, which counts what they sent, heard or not.
        self.highest_sequence = {}
        self._skipped = set()
        self._closed = False
        self._reported = False
        self._send_times = send_times
        # Per topic recorded with history: its second subscription, None until it is made.
        self._late, self._history = {}, {}
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        node.create_timer(GRAPH_PERIOD, self._follow_graph, clock=steady)
        # The first look too is the executor's: the node is made at once.
        self._catch_up = node.create_timer(CATCH_UP_PERIOD, self._follow_graph, clock=steady)

    @property
    def topics(self) -> list[str]:
        """Return the topics being recorded."""
        return sorted(self._recorded)

    def _follow_graph(self):
        node = self._node
        self._catch_up.cancel()
        if self._closed:
            return
        self._ask_history()
        deadline = time.monotonic() + GRAPH_WORK
        for topic, types in node.get_topic_names_and_types():
            # Hidden topics (an action's feedback and status) are left out, as ros2 bag
            # record leaves them out unless asked.
            if topic in self._recorded or topic in self._skipped or topic_or_service_is_hidden(
                    topic) or not any(fnmatchcase(topic, pattern) for pattern in self._patterns):
                continue
            if time.monotonic() > deadline:
                self._catch_up.reset()
                return
            publishers = node.get_publishers_info_by_topic(topic)
            if publishers:
                self._record(topic, types, publishers)

    def record_now(self, topic: str, type_name: str, qos: QoSProfile,
                   then: Callable | None = None, history: int | None = None,
                   keep: Callable | None = None) -> None:
        """
        Record topic at once, as type_name with qos, before any publisher of it is known.

        Following the graph, a topic is recorded only once its publisher shows, and what that
        publisher sends before the subscription matches is lost unless it is transient local.
        A topic subscribed to in advance misses nothing a matching publisher sends once
        matched; its channel says it was offered qos. With history (a transient-local profile),
        a second subscription asks transient-local publishers for what they sent before the
        match, and a message both bring (the same send time and bytes) is recorded once.
        then(data, sent), if given, also gets each serialised message, once it is recorded (or
        the recording has stopped), and the wall time it was sent at (nanoseconds; None without
        send_times). keep(data), if given, says which messages the bag keeps (then gets all).
        """
        try:
            channel = self.bag.add_topic(topic, type_name, [offered(qos)])
        except BagError as error:
            self._stop(error)
            return
        seen = set() if history is not None else None
        self._subscribe(topic, message_class(type_name), channel, qos, then, seen, keep)
        if history is not None:
            # Made once a transient-local publisher shows (_ask_history): a volatile one, the
            # usual kind, never matches it, and both sides would warn of it.
            self._late[topic] = None
            self._history[topic] = (message_class(type_name), channel, history, then, seen, keep)
            self._ask_history()

    def _ask_history(self):
        """Make the history subscriptions whose topic has a transient-local publisher now."""
        for topic, made in self._late.items():
            if made is None and any(
                    info.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL
                    for info in self._node.get_publishers_info_by_topic(topic)):
                self._late[topic] = self._make_subscription(topic, *self._history.pop(topic),
                                                            history_only=True)

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
            if self.bag.failure is not None:
                self._stop(error)
                return
            self._skipped.add(topic)
            self._node.get_logger().warn(f'{topic}: not recorded: {error}')
            return
        self._subscribe(topic, kind, channel, subscription_qos(profiles)[0])

    def _subscribe(self, topic, kind, channel, qos, then=None, seen=None, keep=None):
        self._recorded[topic] = self._make_subscription(topic, kind, channel, qos, then, seen,
                                                        keep)

    def _make_subscription(self, topic, kind, channel, qos, then, seen, keep=None,
                           history_only=False):
        clock = self._node.get_clock()

        def write(data, info=None):
            sent = info and info['source_timestamp']
            if info:
                # How many its publisher has sent, heard or not (a reader keeps no more than
                # its queue of a publisher that outruns it).
                self.highest_sequence[topic] = max(self.highest_sequence.get(topic, 0),
                                                   info.get('publication_sequence_number', 0))
            if seen is not None:
                # A digest, not the bytes: every message of a topic is remembered.
                key = (sent, hashlib.blake2b(data, digest_size=16).digest())
                if key in seen:
                    return
                seen.add(key)
            if not self._closed and (keep is None or keep(data)):
                try:
                    self.bag.write(channel, clock.now().nanoseconds, data, sent)
                    self.received[topic] += 1
                except BagError as error:
                    self._stop(error)
            # Once the recording has stopped (a full disk), then still gets every message.
            if then is not None:
                then(data, sent)

        def write_with_send_time(data, info=None):
            if info is None:
                data, info = data
            write(data, info)
        # rclpy passes the MessageInfo to a callback whose signature needs two arguments: its
        # Python executors as the second, its EventsExecutor (7.1) with the message in a tuple.
        write_with_send_time.__signature__ = inspect.signature(lambda data, info: None)
        # A subscription for the history matches transient-local publishers only: rclpy's
        # warning about every volatile one (the usual status publisher) would say nothing.
        events = SubscriptionEventCallbacks(incompatible_qos=lambda _: None) if (
            history_only) else None
        return self._node.create_subscription(
            kind, topic, write_with_send_time if self._send_times else write, qos, raw=True,
            event_callbacks=events)

    def subscription(self, topic: str) -> Subscription | None:
        """Return the subscription recording topic, or None while it is not recorded."""
        return self._recorded.get(topic)

    def take_waiting(self, topic: str) -> int:
        """
        Take now every message of topic that waits in its subscription; return how many.

        As the executor takes them, through the same callback, for a reader that must hold
        all that was sent before it judges: a starved executor may leave a reliable
        publisher's acknowledged messages waiting in the reader for seconds. rclpy 7.1 has no
        public take (test/node/test_rclpy_limits.py fails once it has): the handle's is used.
        """
        subscription = self._recorded.get(topic)
        taken = 0
        while subscription is not None:
            with subscription.handle:
                message = subscription.handle.take_message(subscription.msg_type,
                                                           subscription.raw)
            if message is None:
                return taken
            subscription.callback(*(message if self._send_times else message[:1]))
            taken += 1
        return taken

    @property
    def failed(self) -> bool:
        """Whether the disk stopped taking the bag, which then ended early."""
        return self.bag.failure is not None

    def _stop(self, error):
        """End the recording at a write the disk refused: one line, and the node goes on."""
        self._closed = True
        if not self._reported:
            self._reported = True
            self._node.get_logger().error(
                f'{error}; recording stopped after {self.bag.message_count} messages (the bag '
                'keeps what reached the disk, up to its last complete chunk)')

    def finish_seconds(self) -> float:
        """Return how long finishing the bag may take now (for a Ctrl-C's ending)."""
        return 0.0 if self._closed else self.bag.finish_seconds()

    def close(self) -> None:
        """Finish the bag, so that an interrupted recording is complete and indexed."""
        if self._closed:
            return
        self._closed = True
        try:
            self.bag.close()
        except BagError as error:
            self._stop(error)
            return
        self._node.get_logger().info(f'{self.bag.path}: {self.bag.message_count} messages of '
                                     f'{len(self._recorded)} topics')

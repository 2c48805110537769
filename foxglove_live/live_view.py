"""
A run's topics served live to Foxglove over its WebSocket protocol, on one port.

Foxglove's own server library (foxglove-sdk) speaks the protocol. This follows the graph as the
bag recorder does and offers every topic matching the patterns as a channel with the ros2msg
schema the bag writer writes (bag.message_definition) and the CDR bytes as they come off the
wire: the file and the socket carry the same thing. A topic is subscribed in ROS only while a
client subscribes to its channel (Foxglove asks for what its panels show), so what nobody
watches costs nothing. A transient-local topic (the map, /tf_static, the course) keeps its last
messages for a client that subscribes once it is subscribed already, as ROS gives them to a late
subscriber; the SDK sends a channel's messages to every client watching it, so those kept
messages are sent again at most once every REPLAY_PERIOD, however many clients come (200 idle
clients arriving would otherwise queue 20,000 copies of the map). A topic with no publisher
left (a deleted robot's) is withdrawn; hidden topics (an action's, as `ros2 topic list` hides
them) are not offered.

Clients may publish (Foxglove's Teleop panel) on the command topics: see live_commands.py.
The SDK keeps at most BACKLOG messages for each client and drops the oldest when one
falls behind, so a slow or vanished client never holds up the node, let alone the simulator,
nor another client (bench/live_view.py: 200 idle clients, a reading client's share). What a
client held is freed when it leaves; the C library keeps freed memory for reuse, so it is handed
back to the system (malloc_trim) once clients have left.

The SDK calls the listener from its own threads: those only note what changed, under a lock,
and a timer of the node's acts on it within WORK_PERIOD (rclpy's EventsExecutor takes no guard
condition): everything ROS is done by the node's executor.
"""

from collections import Counter, deque
import ctypes
import ctypes.util
from fnmatch import fnmatchcase
import ipaddress
import logging
import re
import threading
import time

import foxglove
from foxglove.websocket import Capability, StatusLevel
from foxglove_live.live_commands import CommandChannels
from rclpy.clock import Clock, ClockType
from rclpy.topic_or_service_is_hidden import topic_or_service_is_hidden
from simple_robot_control.bag import BagError, message_definition
from simple_robot_control.bag_recording import message_class, subscription_qos
from simple_robot_control.validation import ConfigError

GRAPH_PERIOD = 0.5
# How soon a client's subscription or command is acted on (s).
WORK_PERIOD = 0.02
# Messages queued for each client before the oldest are dropped (the SDK's default).
BACKLOG = 1024
# Messages of a transient-local topic kept for clients that subscribe later.
KEEP = 100
# A transient-local topic's kept messages are sent again at most this often (s).
REPLAY_PERIOD = 1.0
# Memory is handed back to the system this long after a client left (s).
RELEASE_AFTER = 1.0
# A line of the SDK's (a client's bad frame, a full outbox) is repeated at most this often.
REPEAT_AFTER = 10.0


class _Topic:
    """A ROS topic offered as a channel: subscribed while watched, its latched messages kept."""

    def __init__(self, channel, kind, qos, latched):
        self.channel = channel
        self.kind = kind
        self.qos = qos
        self.kept = deque(maxlen=min(qos.depth, KEEP)) if latched else None
        self.subscription = None
        self.replayed_at = -REPLAY_PERIOD


class LiveView:
    """
    Serves the topics matching patterns to Foxglove clients on host:port, on behalf of node.

    Clients may publish on the topics matching commands (see live_commands.py); each
    client gets at most backlog messages queued.
    """

    def __init__(self, node, patterns, host='127.0.0.1', port=8765, commands=('*/cmd_vel',),
                 backlog=BACKLOG):
        self._node = node
        self._patterns = tuple(patterns)
        self.commands = CommandChannels(node, commands, self._report)
        self._context = foxglove.Context()
        self._topics, self._by_channel, self._skipped = {}, {}, set()
        self._lock = threading.Lock()
        # Written by the SDK's threads, read by the executor, under the lock.
        self._watchers, self._replays = Counter(), set()
        self._left_at = None
        self._log = _SdkLog(node.get_logger(), backlog)
        self._changed = True
        try:
            self.server = foxglove.start_server(
                name=node.get_fully_qualified_name(), host=host, port=port,
                capabilities=[Capability.ClientPublish], supported_encodings=['cdr'],
                server_listener=_Listener(self), context=self._context,
                message_backlog_size=backlog)
        except RuntimeError as error:
            raise ConfigError(f'cannot serve Foxglove on {host}:{port}: {error}') from None
        self.port = self.server.port
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        node.create_timer(GRAPH_PERIOD, self._follow_graph, clock=steady)
        node.create_timer(WORK_PERIOD, self._work, clock=steady)
        self._follow_graph()

    def _follow_graph(self):
        node = self._node
        present = set()
        for topic, types in node.get_topic_names_and_types():
            if topic_or_service_is_hidden(topic) or not any(
                    fnmatchcase(topic, pattern) for pattern in self._patterns):
                continue
            publishers = node.get_publishers_info_by_topic(topic)
            if not publishers:
                continue
            present.add(topic)
            if topic not in self._topics and topic not in self._skipped:
                self._offer(topic, types, publishers)
        for topic in set(self._topics) - present:
            self._withdraw(topic)
        self._changed = True

    def _offer(self, topic, types, publishers):
        kind = message_class(types[0]) if len(types) == 1 else None
        try:
            if kind is None:
                raise BagError(f'its type {" or ".join(types)} is not installed or not one type')
            schema = foxglove.Schema(name=types[0], encoding='ros2msg',
                                     data=message_definition(types[0]).encode())
        except BagError as error:
            self._skipped.add(topic)
            self._node.get_logger().warn(f'{topic}: not offered to Foxglove: {error}')
            return
        qos, latched = subscription_qos([info.qos_profile for info in publishers])
        channel = foxglove.Channel(topic, schema=schema, message_encoding='cdr',
                                   context=self._context)
        self._topics[topic] = _Topic(channel, kind, qos, latched)
        self._by_channel[channel.id()] = topic

    def _withdraw(self, topic):
        entry = self._topics.pop(topic)
        del self._by_channel[entry.channel.id()]
        if entry.subscription is not None:
            self._node.destroy_subscription(entry.subscription)
        entry.channel.close()

    def _work(self):
        """Act on the commands received, then subscribe what clients watch, replay kept ones."""
        self.commands.work()
        if not self._changed:
            return
        now = time.monotonic()
        with self._lock:
            self._changed = False
            watched = {channel for channel, count in self._watchers.items() if count > 0}
            replays, self._replays = self._replays, set()
            left_at = self._left_at
        for channel_id, topic in self._by_channel.items():
            entry = self._topics[topic]
            if channel_id in watched and entry.subscription is None:
                # A new subscription gets a transient-local topic's history from ROS itself.
                entry.subscription = self._node.create_subscription(
                    entry.kind, topic, self._forwarder(entry), entry.qos, raw=True)
                entry.replayed_at = now
            elif channel_id not in watched and entry.subscription is not None:
                self._node.destroy_subscription(entry.subscription)
                entry.subscription = None
                if entry.kept is not None:
                    entry.kept.clear()
            elif channel_id in replays and entry.kept:
                if now - entry.replayed_at < REPLAY_PERIOD:
                    self._later(replay=channel_id)
                    continue
                entry.replayed_at = now
                for data in list(entry.kept):
                    entry.channel.log(data)
        if left_at is not None:
            if now - left_at < RELEASE_AFTER:
                self._later()
            else:
                with self._lock:
                    self._left_at = None
                release_freed_memory()

    def _later(self, replay=None):
        """Have the next _work look again (at a replay or a release not yet due)."""
        with self._lock:
            if replay is not None:
                self._replays.add(replay)
            self._changed = True

    def _forwarder(self, entry):
        def forward(data):
            if entry.kept is not None:
                entry.kept.append(data)
            entry.channel.log(data)
        return forward

    # Called by the SDK's threads (see _Listener): they note, the executor acts.

    def watched(self, channel_id: int, change: int) -> None:
        with self._lock:
            self._watchers[channel_id] += change
            if change > 0:
                self._replays.add(channel_id)
            else:
                self._left_at = time.monotonic()
            self._changed = True

    def _report(self, text):
        """Tell every client (Foxglove shows a status) and the log."""
        self.server.publish_status(text, StatusLevel.Error)
        self._node.get_logger().warn(text)

    def close(self) -> None:
        """Stop serving: clients are disconnected."""
        self.server.stop()
        self._log.close()


class _SdkLog(logging.Handler):
    """
    The SDK's log lines (it logs through Python's logging) as the node's, each seldom.

    A client's malformed frame or unknown channel id, a full outbox: the SDK answers the client
    and logs a line each time; a flood of them becomes a line every REPEAT_AFTER seconds.
    """

    def __init__(self, logger, backlog):
        super().__init__(logging.INFO)
        self._ros = logger
        self._backlog = backlog
        self._said = {}
        self._sdk = logging.getLogger('foxglove')
        self._sdk.setLevel(logging.INFO)
        self._sdk.propagate = False
        self._sdk.addHandler(self)

    def emit(self, record):
        text = record.getMessage()
        if record.levelno < logging.WARNING and 'outbox' not in text:
            return
        kind = re.sub(r'\d+', '#', text)[:80]
        now = time.monotonic()
        if now - self._said.get(kind, -REPEAT_AFTER) < REPEAT_AFTER:
            return
        self._said[kind] = now
        if 'outbox' in text:
            text += (f': a client is falling behind, its oldest messages are dropped (at most '
                     f'{self._backlog} wait)')
        self._ros.warn(f'Foxglove: {text}')

    def close(self):
        self._sdk.removeHandler(self)
        super().close()


class _Listener(foxglove.websocket.ServerListener):
    """The SDK's view of a LiveView."""

    def __init__(self, view):
        self._view = view

    def on_subscribe(self, client, channel):
        self._view.watched(channel.id, +1)

    def on_unsubscribe(self, client, channel):
        self._view.watched(channel.id, -1)

    def on_client_advertise(self, client, channel):
        self._view.commands.advertised(client.id, channel)

    def on_client_unadvertise(self, client, client_channel_id):
        self._view.commands.unadvertised(client.id, client_channel_id)

    def on_message_data(self, client, client_channel_id, data):
        self._view.commands.received(client.id, client_channel_id, data)


def _c_library_trim():
    """Return glibc's malloc_trim, or None where the C library has none (musl, macOS)."""
    try:
        return ctypes.CDLL(ctypes.util.find_library('c')).malloc_trim
    except (AttributeError, OSError, TypeError):
        return None


_MALLOC_TRIM = _c_library_trim()


def release_freed_memory() -> None:
    """
    Hand the memory freed by the C library back to the system.

    glibc keeps what was freed for later allocations: after 200 clients left, foxglove_live
    kept 380 MB it no longer used, 120 MB once trimmed (measured with bench/live_view.py).
    """
    if _MALLOC_TRIM is not None:
        _MALLOC_TRIM(0)


def is_loopback(host: str) -> bool:
    """Whether host names this machine's loopback (localhost, 127.0.0.0/8, ::1)."""
    if host == 'localhost':
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def exposure_line(host: str, port: int) -> str | None:
    """Return the line warning that host:port is open to the network, or None for loopback."""
    if is_loopback(host):
        return None
    return (f'Foxglove is served on {host}:{port}: open to the network, with no authentication; '
            'anyone who reaches this port may watch the run and drive the robots')

"""
Commands from Foxglove clients (the Teleop panel) published into ROS, checked and bounded.

A client may advertise channels on the topics matching the command patterns only, as
geometry_msgs Twist or TwistStamped in CDR, and only on a topic something in ROS subscribes to
with that type (a robot that exists: stdr_lite subscribes to each robot's cmd_vel). A client
holds at most PER_CLIENT such channels and the server PER_SERVER in all. A topic's ROS
publisher is made for its first accepted channel and destroyed with its last (the SDK
unadvertises a client's channels when it leaves), so a controller started after someone drove a
robot from Foxglove finds no publisher of ours left on its cmd_vel. Any other advertisement is
refused with a status the client shows and a log line (once per client and kind of refusal); a
message that is malformed, oversized or not finite is dropped, with a line once per channel and
kind.

The SDK calls in from its own threads: those note what came under a lock; work(), run by the
node's executor, decides and publishes.
"""

from collections import Counter, deque
from fnmatch import fnmatchcase
import math
import threading

from foxglove.websocket import ClientChannel
from geometry_msgs.msg import Twist, TwistStamped
from rclpy.serialization import deserialize_message

COMMAND_TYPES = {'geometry_msgs/msg/Twist': Twist, 'geometry_msgs/Twist': Twist,
                 'geometry_msgs/msg/TwistStamped': TwistStamped,
                 'geometry_msgs/TwistStamped': TwistStamped}
# Each command type's full name, as the graph lists a subscriber's.
TYPE_NAMES = {kind: name for name, kind in COMMAND_TYPES.items() if '/msg/' in name}
# A Twist is 52 bytes in CDR, a TwistStamped with a long frame id a few hundred.
MAX_COMMAND_BYTES = 1024
# Commands waiting for the executor; a flood beyond this loses its oldest.
INBOX = 256
# Command channels one client may hold (a Teleop panel advertises one), and all clients.
PER_CLIENT = 16
PER_SERVER = 256
# Refusals remembered (each said once); beyond this, further ones go unsaid.
REFUSALS_KEPT = 4096


class CommandChannels:
    """
    The command channels Foxglove clients advertise, on behalf of node.

    report(text) tells every client and the log that an advertisement was refused.
    """

    def __init__(self, node, patterns, report):
        self._node = node
        self._patterns = tuple(patterns)
        self._report = report
        self._lock = threading.Lock()
        # Under the lock: channels claimed (advertised, not yet let go) by key and by client,
        # the changes and commands waiting for the executor, the refusals said.
        self._claimed = {}
        self._per_client = Counter()
        self._changes = deque()
        self._inbox = deque(maxlen=INBOX)
        self._said = set()
        # The executor's alone: the accepted channels' topics, publishers and their users.
        self._accepted = {}
        self._publishers = {}
        self._users = Counter()

    # Called by the SDK's threads.

    def advertised(self, client_id: int, channel: ClientChannel) -> None:
        """Claim a client's new channel within the bounds, or refuse it at once."""
        key = (client_id, channel.id)
        problem = self._shape_problem(channel)
        with self._lock:
            if problem is None and key not in self._claimed:
                if self._per_client[client_id] >= PER_CLIENT:
                    problem = f'a client may publish on {PER_CLIENT} channels at most'
                elif len(self._claimed) >= PER_SERVER:
                    problem = f'clients may publish on {PER_SERVER} channels at most in all'
            if problem is None:
                if key not in self._claimed:
                    self._per_client[client_id] += 1
                self._claimed[key] = channel.topic
                self._changes.append((key, channel.topic, COMMAND_TYPES[channel.schema_name]))
        if problem is not None:
            self._refuse(client_id, channel.topic, problem)

    def _shape_problem(self, channel):
        if not any(fnmatchcase(channel.topic, pattern) for pattern in self._patterns):
            return f'only {", ".join(self._patterns)} take messages from Foxglove'
        if channel.schema_name not in COMMAND_TYPES:
            return f'{channel.schema_name} is no geometry_msgs/msg/Twist or TwistStamped'
        if channel.encoding != 'cdr':
            return f'its encoding {channel.encoding} is not cdr'
        return None

    def unadvertised(self, client_id: int, channel_id: int) -> None:
        """Let a channel go: the client took it back, or left."""
        key = (client_id, channel_id)
        with self._lock:
            if self._claimed.pop(key, None) is None:
                return
            self._per_client[client_id] -= 1
            if not self._per_client[client_id]:
                del self._per_client[client_id]
            self._changes.append((key, None, None))

    def received(self, client_id: int, channel_id: int, data: bytes) -> None:
        """Queue a client's message for the executor, or drop it with one line."""
        key = (client_id, channel_id)
        if key not in self._claimed:
            self._refuse_once(key, 'refused', 'a message on a channel it may not publish on')
        elif len(data) > MAX_COMMAND_BYTES:
            self._refuse_once(key, 'oversized', f'a message of {len(data)} bytes (at most '
                              f'{MAX_COMMAND_BYTES})')
        else:
            with self._lock:
                self._inbox.append((key, bytes(data)))

    # Run by the node's executor.

    def work(self) -> None:
        """Decide the channels advertised, then publish the commands received, in order."""
        with self._lock:
            changes = list(self._changes)
            self._changes.clear()
            commands = list(self._inbox)
            self._inbox.clear()
        for key, topic, kind in changes:
            self._let_go(key)
            if topic is not None:
                self._accept(key, topic, kind)
        for key, data in commands:
            self._publish(key, data)

    def _accept(self, key, topic, kind):
        name = TYPE_NAMES[kind]
        if not any(info.topic_type == name
                   for info in self._node.get_subscriptions_info_by_topic(topic)):
            self.unadvertised(*key)
            self._refuse(key[0], topic, f'nothing subscribes to it as {name} (no such robot)')
            return
        self._accepted[key] = (topic, kind)
        if not self._users[topic, kind]:
            self._publishers[topic, kind] = self._node.create_publisher(kind, topic, 10)
        self._users[topic, kind] += 1

    def _let_go(self, key):
        accepted = self._accepted.pop(key, None)
        if accepted is None:
            return
        self._users[accepted] -= 1
        if not self._users[accepted]:
            del self._users[accepted]
            self._node.destroy_publisher(self._publishers.pop(accepted))

    def _publish(self, key, data):
        topic, kind = self._accepted.get(key, (None, None))
        if topic is None:
            return  # let go, or refused, while the message waited
        try:
            message = deserialize_message(data, kind)
        except Exception:  # noqa: B902  rclpy raises its RMWError, or others, on bad CDR
            self._refuse_once(key, 'malformed', f'a message on {topic} that is no '
                              f'{kind.__name__} in CDR')
            return
        twist = message.twist if kind is TwistStamped else message
        values = (twist.linear.x, twist.linear.y, twist.linear.z,
                  twist.angular.x, twist.angular.y, twist.angular.z)
        if not all(map(math.isfinite, values)):
            self._refuse_once(key, 'not finite', f'a command on {topic} that is not finite')
            return
        self._publishers[topic, kind].publish(message)

    def publishers(self) -> int:
        """Return how many ROS publishers clients' channels hold now."""
        return len(self._publishers)

    def claimed(self) -> int:
        """Return how many channels clients hold now, accepted or being decided."""
        with self._lock:
            return len(self._claimed)

    def _refuse(self, client_id, topic, problem):
        """Tell a channel's refusal once for each client and problem (3000 ghosts: one line)."""
        if self._first((client_id, problem)):
            self._report(f'Foxglove client {client_id}: cannot publish on {topic}: {problem} '
                         '(and any more like it)')

    def _refuse_once(self, key, kind, what):
        """Log one line for the first message of a kind that a client channel has dropped."""
        if self._first((key, kind)):
            self._node.get_logger().warn(f'Foxglove client {key[0]}: dropped {what} (and any '
                                         'more like it)')

    def _first(self, refusal):
        with self._lock:
            if refusal in self._said or len(self._said) >= REFUSALS_KEPT:
                return False
            self._said.add(refusal)
            return True

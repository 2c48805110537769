"""
The message type of each robot's cmd_vel follows its publishers, or their mix is named.

Twist and TwistStamped endpoints never match: a teleop or a Nav2 sending the other type than
the simulator reads would drive nothing, silently. Given the whole graph's topic types (see
graph_watch), a robot's cmd_vel that shows another type has its publishers looked at. When
they all send the other of the two velocity types, the robot's subscription is made anew with
theirs; when they disagree, or send some third type, the simulator warns, naming each
publisher and its type.
"""

from geometry_msgs.msg import Twist, TwistStamped
from rclpy.clock import Clock, ClockType
from simple_robot_control.graph import endpoint_node, type_name

# The old subscription must be gone from the executor before one of another type is made.
RESUBSCRIBE_AFTER = 0.1
WARN_EVERY = 10.0
COMMAND_TYPES = {type_name(kind): kind for kind in (Twist, TwistStamped)}


class CommandTypeWatch:
    """Keeps each robot's cmd_vel subscription of the type its publishers send."""

    def __init__(self, node, topics):
        self._node = node
        self._topics = topics
        self._pending = {}
        self._resubscribe = node.create_timer(RESUBSCRIBE_AFTER, self._subscribe_anew,
                                              clock=Clock(clock_type=ClockType.STEADY_TIME))
        self._resubscribe.cancel()

    def check(self, names_and_types: list[tuple[str, list[str]]]) -> None:
        """Look at every robot's cmd_vel whose graph shows a type the robot does not read."""
        by_topic = {topics.cmd_vel_topic: topics for name, topics in self._topics.items()
                    if name not in self._pending}
        for topic, types in names_and_types:
            topics = by_topic.get(topic)
            if topics is not None and any(kind != topics.command_type for kind in types):
                self._settle(topics)

    def _subscribe_anew(self):
        self._resubscribe.cancel()
        for name, kind in self._pending.items():
            if name in self._topics:
                self._topics[name].read_commands_as(kind)
        self._pending.clear()

    def _settle(self, topics):
        """Follow the publishers' type if they agree on one we can read; else say why not."""
        publishers = sorted({(info.topic_type, endpoint_node(info)) for info in
                             self._node.get_publishers_info_by_topic(topics.cmd_vel_topic)})
        kinds = {kind for kind, _ in publishers}
        if not kinds or kinds == {topics.command_type}:
            return
        logger = self._node.get_logger()
        named = ', '.join(f'{name} sends {kind}' for kind, name in publishers)
        if len(kinds) == 1 and kinds <= set(COMMAND_TYPES):
            kind = kinds.pop()
            topics.stop_reading_commands()
            self._pending[topics.name] = COMMAND_TYPES[kind]
            self._resubscribe.reset()
            logger.info(f'{topics.cmd_vel_topic}: now read as {kind}, the type of its '
                        f'publishers ({named})')
            return
        logger.warn(f'{topics.cmd_vel_topic}: its publishers disagree or send a type no robot '
                    f'reads ({named}); it is read as {topics.command_type}, so only those '
                    'commands drive the robot', throttle_duration_sec=WARN_EVERY)

"""
What the simulator learns from the graph, read once a second in one call.

A single get_topic_names_and_types() costs little however many robots there are, where asking
about each robot's topics would not. It serves the cmd_vel type following (command_types), and
the publishers made on demand: a robot's ground truth or sensor whose topic shows a reader and
no publisher of ours gets its publisher, one per tick of a short timer so that a viewer
subscribing to a thousand sensors never holds the loop for long.
"""

from rclpy.clock import Clock, ClockType
from stdr_lite.node.command_types import CommandTypeWatch

CHECK_PERIOD = 1.0
MAKE_PERIOD = 0.01


class GraphWatch:
    """Reads the graph once a second for the cmd_vel types and the on-demand publishers."""

    def __init__(self, node, topics):
        self._node = node
        self._topics = topics
        self._command_types = CommandTypeWatch(node, topics)
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        node.create_timer(CHECK_PERIOD, self.check, clock=steady)
        self._maker = node.create_timer(MAKE_PERIOD, self._make_one, clock=steady)
        self._maker.cancel()

    def check(self) -> None:
        """Read the graph; follow cmd_vel types and queue the publishers that readers await."""
        names_and_types = self._node.get_topic_names_and_types()
        self._command_types.check(names_and_types)
        unmade = {topic: topics for topics in self._topics.values()
                  for topic in topics.unmade_topics}
        for topic, _ in names_and_types:
            topics = unmade.get(topic)
            if topics is not None and self._node.count_subscribers(topic):
                topics.wanted(topic)
                self._maker.reset()

    def _make_one(self):
        """Make one publisher that a reader waits for; stop once none is left."""
        for topics in self._topics.values():
            if not topics.complete:
                topics.make_sensor_topic()
                return
        self._maker.cancel()

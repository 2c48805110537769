"""
Warnings a running simulator owes its user: falling behind, and commands that would mix.

(Commands of a type the robot does not read are command_types.py's.)
"""

import time

from rclpy.clock import Clock, ClockType
from simple_robot_control.graph import endpoint_node, UNNAMED

CHECK_PERIOD = 1.0
# A free-running simulator achieving less than this share of its real_time_factor is behind.
BEHIND = 0.9
WARN_EVERY = 10.0
# cmd_vel topics whose publishers are counted per check, so a large swarm costs little: a
# lookup costs more the larger the graph (0.5 to 1.6 ms with 1000 robots' topics).
TOPICS_PER_CHECK = 10
# A publisher's node is named once discovery has its name, within a second or two however busy
# the machine: the warning waits for the names this long, then names what it can.
NAMES_PATIENCE = 5.0


class HealthWatch:
    """Checks, once a second of wall time, the pace and the publishers of every cmd_vel."""

    def __init__(self, node, simulation, topics, real_time_factor, playing):
        self._node = node
        self._playing = playing
        self._simulation = simulation
        self._topics = topics
        self._target = real_time_factor
        # The pace is measured from the first check on: before it the node was still starting.
        self._since = None
        self._next_topic = 0
        # Since when each cmd_vel topic has had several publishers, one of them not yet named.
        self._unnamed_since = {}
        node.create_timer(CHECK_PERIOD, self.check,
                          clock=Clock(clock_type=ClockType.STEADY_TIME))

    def check(self) -> None:
        self._check_pace()
        self._check_publishers()

    def _check_pace(self):
        """Warn with the achieved factor when a paced, free-running simulation lags."""
        now, sim_time = time.monotonic(), self._simulation.sim_time
        since, self._since = self._since, (now, sim_time)
        if since is None:
            return
        achieved = (sim_time - since[1]) / max(now - since[0], 1e-9)
        if self._target > 0.0 and self._playing() and achieved < BEHIND * self._target:
            count = len(self._simulation.names)
            remedy = ('lower rate_hz or the robot count, or use lockstep' if count
                      else 'lower rate_hz or real_time_factor')
            self._node.get_logger().warn(
                f'running at {achieved:.2f}x real time, behind real_time_factor '
                f'{self._target:g} with {count or "no"} entities: this machine cannot keep up; '
                f'{remedy}', throttle_duration_sec=WARN_EVERY)

    def _check_publishers(self):
        """Warn when a robot's cmd_vel has publishers in more than one node."""
        names = list(self._topics)
        if not names:
            return
        start = self._next_topic % len(names)
        chosen = (names[start:] + names[:start])[:TOPICS_PER_CHECK]
        self._next_topic = start + len(chosen)
        for name in chosen:
            topics = self._topics[name]
            infos = self._node.get_publishers_info_by_topic(topics.cmd_vel_topic)
            publishers = sorted(map(endpoint_node, infos))
            if len(publishers) > 1 and UNNAMED in publishers:
                first = self._unnamed_since.setdefault(topics.cmd_vel_topic, time.monotonic())
                if time.monotonic() - first < NAMES_PATIENCE:
                    continue
            else:
                self._unnamed_since.pop(topics.cmd_vel_topic, None)
            if len(publishers) > 1:
                self._node.get_logger().warn(
                    f'{topics.cmd_vel_topic} has {len(publishers)} publishers '
                    f'({", ".join(publishers)}): their commands mix; stop all but one',
                    throttle_duration_sec=WARN_EVERY)

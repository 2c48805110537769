"""What nodes ask of the ROS graph: who else publishes, and whether every reader has caught up."""

import time

from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.topic_endpoint_info import TopicEndpointInfo

# Participants on this host find each other within this much wall time. Measured here with
# Fast DDS's default transports (shared memory and UDP): usually 0.05 to 0.2 s, but about one
# time in ten the quick exchange is missed and a peer appears only with its next periodic
# announcement, up to 3 s later (3.06 s seen; our Fast DDS profile, which processes started
# without it do not have, bounds it to about 0.4 s). A node younger than this may not see
# every peer.
DISCOVERY_TIME = 4.0
SETTLED_FOR = 0.25
# A reader of cmd_vel of the other message type may be about to follow ours: stdr_lite takes
# its publishers' type within a second of seeing them, which a slow discovery may delay by 3 s.
# Only a mismatch lasting this long counts.
MISMATCH_PATIENCE = 5.0
POLL_PERIOD = 0.02


UNNAMED = 'a node not yet named'


def endpoint_node(info: TopicEndpointInfo) -> str:
    """Return the full name of an endpoint's node, or UNNAMED while discovery is under way."""
    if info.node_name == '_NODE_NAME_UNKNOWN_':
        return UNNAMED
    return f'{info.node_namespace.rstrip("/")}/{info.node_name}'


def other_publishers(node: Node, topic: str, own: int = 1) -> list[str]:
    """
    Return the full names of the publishers on topic (resolved) besides node's own.

    Two nodes may bear one name (two controllers started alike), so own publishers are
    discounted by number rather than every publisher named like node left out. A publisher
    whose node is seen before its name (discovery under way) is 'a node not yet named'.
    """
    me = f'{node.get_namespace().rstrip("/")}/{node.get_name()}'
    names = sorted(map(endpoint_node, node.get_publishers_info_by_topic(topic)))
    for _ in range(own):
        if me in names:
            names.remove(me)
    return names


def type_name(message_type: type) -> str:
    """Return a message class's ROS type name, such as geometry_msgs/msg/Twist."""
    return f'{message_type.__module__.split(".")[0]}/msg/{message_type.__name__}'


def command_type_problem(node: Node, publisher: Publisher, parameter: str) -> str | None:
    """
    Say so when the topic's readers take another message type than the publisher sends.

    Endpoints of different types never match, so the commands would reach no one, silently:
    a reader of another type, and none of ours, is a configuration to fix (parameter names
    the switch between the two types). None while any reader of our type is matched.
    """
    if publisher.get_subscription_count():
        return None
    ours = type_name(publisher.msg_type)
    others = sorted({(info.topic_type, endpoint_node(info))
                     for info in node.get_subscriptions_info_by_topic(publisher.topic_name)
                     if info.topic_type != ours})
    if not others:
        return None
    kind, reader = others[0]
    return (f'{publisher.topic_name} is read as {kind} by {reader}, but this node sends {ours}: '
            f'both must use one type (the parameter {parameter})')


def deliver_before_exit(node: Node, publisher: Publisher, alive_since: float,
                        budget: float) -> None:
    """
    Wait, at most budget seconds of wall time, until every reader has every message.

    wait_for_all_acked covers only the readers matched so far, so the wait lasts until every
    reader the graph knows is matched (a matter of milliseconds). A node younger than the
    discovery time may not know every reader yet: while it knows of none, one may still be on
    its way, so it waits for the discovery time; once it knows some, for them all, steady for
    a moment. Discovery runs in the middleware's own threads: nothing needs to spin meanwhile.
    """
    deadline = time.monotonic() + budget
    topic = publisher.topic_name
    count, steady_since = publisher.get_subscription_count(), time.monotonic()
    while time.monotonic() < deadline:
        now = time.monotonic()
        current = publisher.get_subscription_count()
        if current != count:
            count, steady_since = current, now
        known = node.count_subscribers(topic)
        settled = now >= alive_since + DISCOVERY_TIME or (
            known > 0 and now - steady_since >= SETTLED_FOR)
        if current >= known and settled:
            break
        time.sleep(POLL_PERIOD)
    remaining = deadline - time.monotonic()
    if remaining > 0.0:
        publisher.wait_for_all_acked(Duration(seconds=remaining))

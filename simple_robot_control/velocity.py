"""Velocity commands as a robot's cmd_vel takes them: Twist, or TwistStamped as Nav2 sends."""

from geometry_msgs.msg import Twist, TwistStamped


class VelocityPublisher:
    """
    Publishes (linear m/s, angular rad/s) on a cmd_vel topic as Twist or TwistStamped.

    A stamped command carries the node's clock time; every other field is zero.
    """

    def __init__(self, node, topic, stamped):
        self._node = node
        self._stamped = stamped
        # One message, refilled at every publish: building one costs as much as sending it.
        self._message = TwistStamped() if stamped else Twist()
        self._twist = self._message.twist if stamped else self._message
        self.publisher = node.create_publisher(type(self._message), topic, 10)

    @property
    def topic_name(self) -> str:
        return self.publisher.topic_name

    def publish(self, linear: float, angular: float) -> None:
        self._twist.linear.x, self._twist.angular.z = float(linear), float(angular)
        if self._stamped:
            self._message.header.stamp = self._node.get_clock().now().to_msg()
        self.publisher.publish(self._message)

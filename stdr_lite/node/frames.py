"""
The robots on the TF tree (REP-105), and the markers that show them in RViz.

For every robot r: map -> r/odom -> r/base_link on /tf with each odometry, and
r/base_link -> r/<sensor> on /tf_static from its description. map -> r/odom is what makes the
chain end at the true pose, as a perfect localiser would publish it: the identity while the
odometry is exact.
"""

from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from stdr_lite.node.messages import robot_markers, transform
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

# tf2_ros's own choices: a deep volatile queue for /tf, the latest message latched for
# /tf_static (so that message holds every static transform of the node).
TF_QOS = QoSProfile(depth=100)
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


class FramePublisher:
    """Publishes the TF tree of a simulation's robots and their markers."""

    def __init__(self, node, frames):
        self._frames = frames
        self._dynamic = node.create_publisher(TFMessage, '/tf', TF_QOS)
        self._static = node.create_publisher(TFMessage, '/tf_static', LATCHED)
        self._markers = node.create_publisher(MarkerArray, '~/robot_markers', LATCHED)

    def publish_moving(self, simulation, time_ns):
        """Publish map -> r/odom -> r/base_link for every robot, when anyone listens."""
        if not self._dynamic.get_subscription_count():
            return
        frames = self._frames
        transforms = []
        for name in simulation.names:
            transforms.append(transform(time_ns, frames.map_frame, frames.odom(name),
                                        simulation.map_to_odom(name)))
            transforms.append(transform(time_ns, frames.odom(name), frames.base(name),
                                        simulation.odometry(name).pose))
        self._dynamic.publish(TFMessage(transforms=transforms))

    def publish_fixed(self, simulation):
        """Publish the sensor mounts and the markers of the robots there are now."""
        frames, time_ns = self._frames, simulation.time_ns
        transforms, markers = [], [Marker(action=Marker.DELETEALL)]
        for index, name in enumerate(simulation.names):
            robot = simulation.robot(name)
            for sensor in robot.sensors:
                transforms.append(transform(time_ns, frames.base(name),
                                            frames.sensor(name, sensor.spec), sensor.spec.pose))
            markers += robot_markers(name, robot.description.radius, frames.base(name),
                                     3 * index)
        self._static.publish(TFMessage(transforms=transforms))
        self._markers.publish(MarkerArray(markers=markers))

"""One simulated robot's topics: what it hears and what it says, with reused messages."""

import functools

from geometry_msgs.msg import PoseWithCovarianceStamped, Twist
from nav_msgs.msg import Odometry
from simple_robot_control.pose import set_pose
from stdr_lite.node.messages import fill_reading, sensor_message, set_stamp


class RobotTopics:
    """
    The publishers and subscriptions of one robot, named as STDR names them.

    Topics are relative (<robot>/odom, <robot>/cmd_vel, ...), so they sit under the node's
    namespace and can be remapped. Messages are built once and refilled at every publish.
    """

    def __init__(self, node, robot, frames, on_command, on_initial_pose):
        name = robot.name
        self.name = name
        self._node = node
        self._odometry = Odometry()
        self._odometry.header.frame_id = frames.odom_frame
        self._odometry.child_frame_id = f'{name}/{frames.base_frame}'
        self.odom_publisher = node.create_publisher(Odometry, f'{name}/odom', 10)
        self._subscriptions = [
            node.create_subscription(Twist, f'{name}/cmd_vel',
                                     functools.partial(on_command, name), 10),
            node.create_subscription(PoseWithCovarianceStamped, f'{name}/initialpose',
                                     functools.partial(on_initial_pose, name), 10)]
        self.cmd_vel_topic = self._subscriptions[0].topic_name
        self._sensors = {}
        for sensor in robot.sensors:
            message = sensor_message(name, sensor.spec)
            publisher = node.create_publisher(type(message), f'{name}/{sensor.spec.frame_id}',
                                              10)
            self._sensors[sensor.spec.frame_id] = (publisher, message)

    def publish_odometry(self, time_ns, pose, velocity):
        """Publish the pose and the velocity applied in the last step, stamped time_ns."""
        message = self._odometry
        set_stamp(message.header.stamp, time_ns)
        set_pose(message.pose.pose, *pose)
        message.twist.twist.linear.x, message.twist.twist.angular.z = velocity
        self.odom_publisher.publish(message)

    def listened(self, spec):
        """Whether anyone subscribes to this sensor's topic."""
        return self._sensors[spec.frame_id][0].get_subscription_count() > 0

    def publish_reading(self, spec, time_ns, reading):
        publisher, message = self._sensors[spec.frame_id]
        set_stamp(message.header.stamp, time_ns)
        fill_reading(message, reading)
        publisher.publish(message)

    def destroy(self):
        """Take the robot's topics off the graph."""
        for subscription in self._subscriptions:
            self._node.destroy_subscription(subscription)
        for publisher, _ in [(self.odom_publisher, None)] + list(self._sensors.values()):
            self._node.destroy_publisher(publisher)

#!/usr/bin/env python3
"""Give each robot of a swarm one constant twist, so that they all drive circles."""

import sys

from geometry_msgs.msg import Twist
import rclpy
from rclpy.executors import ExternalShutdownException

DISCOVERY_TIMEOUT = 10.0


def main(robot_count=10):
    rclpy.init()
    node = rclpy.create_node('swarm_driver')
    try:
        for index in range(robot_count):
            publisher = node.create_publisher(Twist, f'/robot{index}/cmd_vel', 10)
            waited = 0.0
            while publisher.get_subscription_count() == 0 and waited < DISCOVERY_TIMEOUT:
                rclpy.spin_once(node, timeout_sec=0.05)
                waited += 0.05
            command = Twist()
            command.linear.x = 0.3
            command.angular.z = 0.3 if index % 2 else -0.3
            publisher.publish(command)
        rclpy.spin_once(node, timeout_sec=0.5)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())

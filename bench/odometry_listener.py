"""
A process of its own that listens to every robot's odometry, as RViz or a fleet would.

`python -m bench.odometry_listener N` subscribes to /robot0/odom ... /robot<N-1>/odom until
interrupted; bench.realtime runs it.
"""

import sys

from bench.round_trip import serve
from nav_msgs.msg import Odometry
from rclpy.node import Node


class OdometryListener(Node):
    """Takes every robot's odometry and does nothing with it."""

    def __init__(self, robot_count):
        super().__init__('odometry_listener')
        for index in range(robot_count):
            self.create_subscription(Odometry, f'/robot{index}/odom', lambda _: None, 10)


def main(argv=None):
    robot_count = int((sys.argv if argv is None else argv)[1])
    return serve(lambda: OdometryListener(robot_count))


if __name__ == '__main__':
    sys.exit(main())

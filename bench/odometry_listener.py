"""
A process of its own that listens to every robot's odometry, as RViz or a fleet would.

`python -m bench.odometry_listener N` subscribes to /robot0/odom ... /robot<N-1>/odom until
interrupted; bench.realtime runs it.
"""

import argparse
import sys

from bench.round_trip import HelperNode, serve
from nav_msgs.msg import Odometry


class OdometryListener(HelperNode):
    """Takes every robot's odometry and does nothing with it."""

    def __init__(self, robot_count):
        super().__init__('odometry_listener')
        for index in range(robot_count):
            self.create_subscription(Odometry, f'/robot{index}/odom', lambda _: None, 10)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog='odometry_listener', description='listen to every robot odometry: a helper process '
        'that bench.realtime starts, not a benchmark (run python -m bench.realtime [--smoke])')
    parser.add_argument('robot_count', type=int)
    return serve(parser, lambda options: OdometryListener(options.robot_count), argv)


if __name__ == '__main__':
    sys.exit(main())

"""
The occupancy_mapper node: the mapping coursework's reference answer, the laser into a map.

It builds the world's occupancy grid from the robot's laser alone (mapper.py: log-odds, rays
compiled), each scan placed at the robot's odometry pose of the scan's stamp, on the geometry
the task gives: nav_msgs/MapMetaData on /map_metadata (stdr_lite's map_visible:=false), or the
info of /map where the world's map is shown (its cells are never read). The map goes out as a
nav_msgs/OccupancyGrid on map_topic (transient local, as map servers and SLAM nodes publish
theirs) every publish_every scans and once more on exit; planner_controller with the same
map_topic plans on it as it grows.
"""

import array
from collections import deque
import sys

from builtin_interfaces.msg import Time as TimeMsg
from coursework_answers.parameters import OCCUPANCY_MAPPER_PARAMETERS
from nav_msgs.msg import MapMetaData, OccupancyGrid, Odometry
import numpy as np
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rclpy.time import Time
from sensor_msgs.msg import LaserScan
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.pose import compose, pose_from_message, yaw_from_quaternion

DESCRIPTION = ("occupancy_mapper: build the occupancy grid of the world from the robot's "
               'laser and odometry, on the geometry of /map_metadata, and publish it as '
               "nav_msgs/OccupancyGrid on map_topic (the mapping coursework's reference "
               'answer). Runs until Ctrl-C; exit code 2 for bad input.')
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
# Odometry poses kept to place scans by their stamp (50 Hz odometry: two seconds), and scans
# held until the odometry of their stamp comes.
POSES_KEPT = 100
SCANS_HELD = 10


class OccupancyMapper(GuardedNode):
    """Maps the laser of robot_name into an OccupancyGrid on map_topic (see the module)."""

    def __init__(self, **kwargs):
        super().__init__('occupancy_mapper', **kwargs)
        self.finished = Future()
        self.params = params = declare_parameters(self, OCCUPANCY_MAPPER_PARAMETERS)
        self.mapper = None
        self.scans = 0
        self._message = OccupancyGrid()
        self._poses = deque(maxlen=POSES_KEPT)
        self._held = deque(maxlen=SCANS_HELD)
        self._publisher = self.create_publisher(OccupancyGrid, params['map_topic'], LATCHED)
        robot = params['robot_name']
        self.create_subscription(MapMetaData, '/map_metadata', self._on_geometry, LATCHED)
        self.create_subscription(OccupancyGrid, '/map', lambda grid: self._on_geometry(
            grid.info), LATCHED)
        self.create_subscription(Odometry, f'{robot}/odom', self._on_odometry, 50)
        self.create_subscription(LaserScan, f'{robot}/{params["laser"]}', self._on_scan, 10)

    def _on_geometry(self, info):
        """Make the grid on the first geometry given; a map along x only (the courseworks')."""
        if self.mapper is not None:
            return
        from coursework_answers.mapper import LogOddsMapper
        yaw = yaw_from_quaternion(info.origin.orientation)
        if not (0 < info.width * info.height <= 16_000_000 and info.resolution > 0.0
                and abs(yaw) < 1e-9):
            self.get_logger().warn(f'ignoring a map geometry of {info.width}x{info.height} '
                                   f'cells of {info.resolution:g} m, yaw {yaw:g}: not one a '
                                   'coursework maps')
            return
        self.mapper = LogOddsMapper((info.height, info.width), info.resolution,
                                    (info.origin.position.x, info.origin.position.y))
        self._message.header.frame_id = 'map'
        self._message.info = info
        self.get_logger().info(f'mapping {info.width} x {info.height} cells of '
                               f'{info.resolution:g} m onto {self._publisher.topic_name}')
        # The unknown map at once: a planner waiting for a map may start (in lockstep no scan
        # comes before it does).
        self.publish_map()

    def _on_odometry(self, message):
        self._poses.append((Time.from_msg(message.header.stamp).nanoseconds,
                            pose_from_message(message.pose.pose)))
        while self._held and self._held[0][0] <= self._poses[-1][0]:
            self._add(*self._held.popleft())

    def _on_scan(self, scan):
        stamp = Time.from_msg(scan.header.stamp).nanoseconds
        if self._poses and self._poses[-1][0] >= stamp:
            self._add(stamp, scan)
        else:
            self._held.append((stamp, scan))

    def _add(self, stamp, scan):
        """Add a scan at the robot's pose of its stamp (the latest before it, if not seen)."""
        if self.mapper is None:
            return
        pose = next((pose for when, pose in reversed(self._poses) if when <= stamp), None)
        if pose is None:
            return
        self.mapper.add_scan(compose(pose, self.params['laser_pose']), scan.angle_min,
                             scan.angle_increment, np.asarray(scan.ranges, dtype=float),
                             scan.range_max)
        self.scans += 1
        if self.scans % self.params['publish_every'] == 0:
            self.publish_map(scan.header.stamp)

    def publish_map(self, stamp: TimeMsg | None = None) -> None:
        """Publish the map as it stands (nothing before the geometry is known)."""
        if self.mapper is None:
            return
        message = self._message
        if stamp is not None:
            message.header.stamp = stamp
        message.data = array.array('b', self.mapper.cells().tobytes())
        self._publisher.publish(message)

    def shut_down(self) -> None:
        """Publish the last map, for whoever reads it after the run."""
        self.publish_map()


def main(argv: list[str] | None = None) -> None:
    parser = build_parser('occupancy_mapper', DESCRIPTION, OCCUPANCY_MAPPER_PARAMETERS)
    sys.exit(run('occupancy_mapper', parser, lambda options: OccupancyMapper(), argv))


if __name__ == '__main__':
    main()

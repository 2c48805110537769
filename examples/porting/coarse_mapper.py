"""
A coarse occupancy mapper written the STDR way, ported from ROS 1 (rospy) to ROS 2 (rclpy).

    python3 coarse_mapper.py [--ros-args -p robot:=robot0]

doc/porting.md shows the ROS 1 original and what changed. At start it asks static_map for the
world's size, as STDR-era mappers do, then counts, for each cell of 0.25 m, the laser's rays
that ended in it (a wall) and that crossed it (free space), each scan placed at the odometry
pose of its stamp (the latest pose is not it: odometry comes five times as often, and a turn
of a tenth of a radian moves a wall 4 m away by 0.4 m), and publishes the grid on
/coursework_map every ten scans.
"""

from collections import deque
import math

from nav_msgs.msg import OccupancyGrid, Odometry
from nav_msgs.srv import GetMap
import numpy as np
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from sensor_msgs.msg import LaserScan

CELL = 0.25
MAX_POSE_GAP_NS = 30_000_000
# ROS 1's latched publisher is a transient-local, reliable one in ROS 2.
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


class CoarseMapper(Node):

    def __init__(self):
        super().__init__('coarse_mapper')
        robot = self.declare_parameter('robot', 'robot0').value
        # rospy.wait_for_service + ServiceProxy become a client and a future spun to its end.
        client = self.create_client(GetMap, '/static_map')
        while not client.wait_for_service(timeout_sec=1.0):
            self.get_logger().info('waiting for static_map')
        future = client.call_async(GetMap.Request())
        rclpy.spin_until_future_complete(self, future)
        info = future.result().map.info
        self.origin = (info.origin.position.x, info.origin.position.y)
        self.columns = math.ceil(info.width * info.resolution / CELL)
        self.rows = math.ceil(info.height * info.resolution / CELL)
        self.hits = np.zeros((self.rows, self.columns), dtype=np.int32)
        self.passes = np.zeros((self.rows, self.columns), dtype=np.int32)
        # (stamp in ns, pose): a minute of odometry, as a scan may be counted well after it came.
        self.poses = deque(maxlen=3000)
        self.scans = 0
        self.publisher = self.create_publisher(OccupancyGrid, '/coursework_map', LATCHED)
        self.create_subscription(Odometry, f'/{robot}/odom', self.on_odometry, 100)
        # Deep enough to miss no scan while a burst is counted (in lockstep the simulator runs as
        # fast as the controller answers, not as fast as this mapper).
        self.create_subscription(LaserScan, f'/{robot}/laser_0', self.on_scan, 100)

    def on_odometry(self, message):
        orientation = message.pose.pose.orientation
        self.poses.append((stamp_ns(message), (
            message.pose.pose.position.x, message.pose.pose.position.y,
            2.0 * math.atan2(orientation.z, orientation.w))))

    def count(self, counts, xs, ys):
        """Add one to the cell of each point (x, y) that lies on the grid."""
        rows = np.floor((ys - self.origin[1]) / CELL).astype(int)
        columns = np.floor((xs - self.origin[0]) / CELL).astype(int)
        inside = (rows >= 0) & (rows < self.rows) & (columns >= 0) & (columns < self.columns)
        np.add.at(counts, (rows[inside], columns[inside]), 1)

    def on_scan(self, scan):
        if not self.poses:
            return
        stamp = stamp_ns(scan)
        when, (x, y, theta) = min(self.poses, key=lambda entry: abs(entry[0] - stamp))
        if abs(when - stamp) > MAX_POSE_GAP_NS:
            return  # no odometry of its time: placed anywhere, it would draw false walls
        ranges = np.asarray(scan.ranges, dtype=float)
        angles = theta + scan.angle_min + np.arange(len(ranges)) * scan.angle_increment
        # REP-117: +inf is no return within range_max (free all along), -inf too close to tell.
        reach = np.where(np.isposinf(ranges), scan.range_max, ranges)
        usable = np.isfinite(reach) & (reach >= scan.range_min)
        reach, angles, wall = reach[usable], angles[usable], np.isfinite(ranges[usable])
        # Every half cell along a ray is free, but where it ended on a wall.
        along = np.arange(0.0, scan.range_max, CELL / 2)
        crossed = along[np.newaxis, :] < reach[:, np.newaxis]
        cosines, sines = np.cos(angles)[:, np.newaxis], np.sin(angles)[:, np.newaxis]
        self.count(self.passes, (x + along * cosines)[crossed], (y + along * sines)[crossed])
        self.count(self.hits, x + reach[wall] * cosines[wall, 0],
                   y + reach[wall] * sines[wall, 0])
        self.scans += 1
        if self.scans % 10 == 0:
            self.publish()

    def publish(self):
        grid = OccupancyGrid()
        grid.header.frame_id = 'map'
        grid.header.stamp = self.get_clock().now().to_msg()
        grid.info.resolution = CELL
        grid.info.width, grid.info.height = self.columns, self.rows
        grid.info.origin.position.x, grid.info.origin.position.y = self.origin
        grid.info.origin.orientation.w = 1.0
        cells = np.full((self.rows, self.columns), -1, dtype=np.int8)
        cells[self.passes > 0] = 0
        cells[self.hits > 0] = 100
        # rospy took any sequence for an int8[] field; rclpy takes a list (or an array.array).
        grid.data = cells.ravel().tolist()
        self.publisher.publish(grid)


def stamp_ns(message):
    return message.header.stamp.sec * 1_000_000_000 + message.header.stamp.nanosec


def main():
    rclpy.init()
    try:
        rclpy.spin(CoarseMapper())
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()

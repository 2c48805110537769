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
        self.poses = deque(maxlen=200)  # (stamp in ns, pose): four seconds of odometry
        self.scans = 0
        self.publisher = self.create_publisher(OccupancyGrid, '/coursework_map', LATCHED)
        self.create_subscription(Odometry, f'/{robot}/odom', self.on_odometry, 10)
        self.create_subscription(LaserScan, f'/{robot}/laser_0', self.on_scan, 10)

    def on_odometry(self, message):
        orientation = message.pose.pose.orientation
        self.poses.append((stamp_ns(message), (
            message.pose.pose.position.x, message.pose.pose.position.y,
            2.0 * math.atan2(orientation.z, orientation.w))))

    def cell(self, x, y):
        return (math.floor((y - self.origin[1]) / CELL),
                math.floor((x - self.origin[0]) / CELL))

    def on_scan(self, scan):
        if not self.poses:
            return
        stamp = stamp_ns(scan)
        _, (x, y, theta) = min(self.poses, key=lambda entry: abs(entry[0] - stamp))
        for index in range(0, len(scan.ranges), 4):
            distance = scan.ranges[index]
            if not scan.range_min <= distance <= scan.range_max:
                continue
            angle = theta + scan.angle_min + index * scan.angle_increment
            wall = distance < scan.range_max
            # Every half cell along the ray is free, but the last: a wall where the ray ended.
            steps = int(distance / (CELL / 2))
            for step in range(steps):
                row, column = self.cell(x + step * CELL / 2 * math.cos(angle),
                                        y + step * CELL / 2 * math.sin(angle))
                if 0 <= row < self.rows and 0 <= column < self.columns:
                    self.passes[row, column] += 1
            if wall:
                row, column = self.cell(x + distance * math.cos(angle),
                                        y + distance * math.sin(angle))
                if 0 <= row < self.rows and 0 <= column < self.columns:
                    self.hits[row, column] += 1
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

"""
A mapping submission that copies the world's map rather than building it, for grade_lab's tests.

    python3 map_copier.py [--huge]

The task hides /map; this finds the bundled map file of /map_metadata's size, publishes its
cells on /coursework_map as a map built from the laser would be, and ends a second later,
having driven nowhere. With --huge it publishes a map of 4000 x 4000 unknown cells instead
(16 MB, far more than the world's), as a submission sending the grader more than it can use.
"""

import array
import sys

from nav_msgs.msg import MapMetaData, OccupancyGrid
import rclpy
from rclpy.duration import Duration
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import bundled_files

HUGE = 4000
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


class MapCopier(Node):
    def __init__(self, huge):
        super().__init__('map_copier')
        self.huge = huge
        self.done = Future()
        self.publisher = self.create_publisher(OccupancyGrid, '/coursework_map', LATCHED)
        self.create_subscription(MapMetaData, '/map_metadata', self.copy, LATCHED)

    def copy(self, info):
        if self.huge:
            info.width = info.height = HUGE
            message = OccupancyGrid(info=info)
            message.header.frame_id = 'map'
            message.data = array.array('b', bytes(HUGE * HUGE))
            self.publisher.publish(message)
            # Delivered before this process ends, however loaded the machine (2 s once was not).
            self.publisher.wait_for_all_acked(Duration(seconds=30))
            print(f'published a map of {HUGE}x{HUGE} cells', flush=True)
            self.create_timer(1.0, lambda: self.done.set_result(True))
            return
        for path in bundled_files('maps').values():
            world = load_map(path)
            if (world.width, world.height) == (info.width, info.height):
                message = OccupancyGrid(info=info)
                message.header.frame_id = 'map'
                message.data = array.array('b', world.cells.tobytes())
                self.publisher.publish(message)
                print(f'copied {path}', flush=True)
                self.create_timer(1.0, lambda: self.done.set_result(True))
                return


def main():
    rclpy.init()
    node = MapCopier('--huge' in sys.argv)
    try:
        rclpy.spin_until_future_complete(node, node.done)
    except KeyboardInterrupt:
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    main()

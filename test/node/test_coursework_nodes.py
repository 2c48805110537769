"""The courseworks' reference nodes in-process: the mapper's map, built from the laser alone."""

from coursework_answers.occupancy_mapper import OccupancyMapper
from courseworks.grids import Grid
from courseworks.mapping import judge_map, seen_along
from nav_msgs.msg import OccupancyGrid
import numpy as np
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from ros_helpers import overrides, spin_until
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.loading import map_file, robot_file
from stdr_lite.core.robot_description import load_robot
from stdr_lite.node.stdr_lite import StdrLite

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
START = (1.0, 1.0, 0.0)


def test_the_mapper_maps_the_hidden_world_from_the_laser_alone(ros_context, executor):
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        map_yaml=map_file('simple_walls'), robot_description=robot_file('small_laser_robot'),
        initial_pose=list(START), map_visible=False, real_time_factor=0.0))
    mapper = OccupancyMapper(context=ros_context, parameter_overrides=overrides(
        publish_every=5))
    reader = Node('reader', context=ros_context)
    maps = []
    reader.create_subscription(OccupancyGrid, '/coursework_map', maps.append, LATCHED)
    for node in (simulator, mapper, reader):
        executor.add_node(node)
    spin_until(executor, lambda: mapper.scans >= 10 and maps and maps[-1].header.stamp.sec,
               what='a map of ten scans')
    grid = Grid.from_map(load_map(map_file('simple_walls')))
    last = maps[-1]
    assert (last.info.width, last.info.height) == (grid.shape[1], grid.shape[0])
    cells = np.asarray(last.data, dtype=np.int8).reshape(grid.shape)
    laser = load_robot(robot_file('small_laser_robot')).lasers[0]
    judgement = judge_map(seen_along(grid, [START], laser), cells)
    assert judgement.passed, judgement
    # Nothing of the world beyond the laser's 4.09 m is known.
    far = grid.cell_of(12.0, 10.0)
    assert cells[far] == -1 and maps[0].data[grid.shape[1] * 20 + 20] == -1

"""STDR's kinds of robot on the node: full-turn lasers, polygon footprints, omni robots."""

import math

from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
import pygame
import pytest
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from ros_helpers import (overrides, pose_stamped, ServiceCaller, simulator_and_client, spin_until,
                         wait_for_subscribers)
from sensor_msgs.msg import LaserScan
from simple_robot_control.share import shared_file
from simulation_interfaces.msg import Bounds, Result
from simulation_interfaces.srv import GetEntityBounds, GetEntityInfo, SpawnEntity
from stdr_lite.node.stdr_lite import StdrLite
from stdr_lite.viewer.scene import ROBOT
from stdr_lite.viewer.stdr_viewer import StdrViewer
from visualization_msgs.msg import Marker, MarkerArray

LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)
TURTLEBOT = shared_file('robots', 'turtlebot3_burger.xml')
# An omni-directional robot in STDR's XML, its kinematics included by name as STDR's are.
OMNI_ROBOT = """<robot><robot_specifications>
  <footprint><footprint_specifications><radius>0.2</radius></footprint_specifications></footprint>
  <kinematic><filename>kinematic_models/omni.xml</filename></kinematic>
</robot_specifications></robot>"""
OMNI_MODEL = """<kinematic><kinematic_specifications><kinematic_model>omni</kinematic_model>
</kinematic_specifications></kinematic>"""


@pytest.fixture
def turtle(ros_context, executor):
    """Give (simulator, client node): a TurtleBot3-like robot0 at (1, 2, 0) in the lab room."""
    return simulator_and_client(ros_context, executor, robot_description=TURTLEBOT,
                                real_time_factor=5.0)


def test_a_full_turn_laser_reads_the_wall_behind_at_index_180(turtle, executor):
    _, client = turtle
    scans = []
    client.create_subscription(LaserScan, '/robot0/scan', scans.append, 10)
    spin_until(executor, lambda: scans, what='a scan')
    scan = scans[-1]
    assert (len(scan.ranges), scan.angle_min, scan.header.frame_id) == (360, 0.0, 'robot0/scan')
    assert scan.angle_min + 180 * scan.angle_increment == pytest.approx(math.pi)
    # The room's wall face is at x = 0.35 m; the laser sits 0.032 m behind the robot's centre.
    assert scan.ranges[180] == pytest.approx(1.0 - 0.032 - 0.35, abs=0.08)
    assert math.isinf(scan.ranges[0]) and scan.range_max == pytest.approx(3.5)


def test_a_polygon_robot_shows_its_outline_and_reports_its_hull(turtle, executor, ros_context):
    simulator, client = turtle
    markers = []
    client.create_subscription(MarkerArray, '/stdr_lite/robot_markers', markers.append, LATCHED)
    viewer = StdrViewer(surface=pygame.Surface((800, 600)), context=ros_context)
    executor.add_node(viewer)
    spin_until(executor, lambda: markers, what='the markers')
    outline, = [marker for marker in markers[-1].markers if marker.ns == 'footprint']
    assert outline.type == Marker.LINE_STRIP
    assert [(point.x, point.y) for point in outline.points] == [
        (-0.105, -0.105), (0.041, -0.105), (0.041, 0.105), (-0.105, 0.105), (-0.105, -0.105)]
    call = ServiceCaller(executor, client)
    bounds = call(GetEntityBounds, 'get_entity_bounds', entity='robot0').bounds
    assert bounds.type == Bounds.TYPE_CONVEX_HULL
    assert [(point.x, point.y) for point in bounds.points] == [
        (-0.105, -0.105), (0.041, -0.105), (0.041, 0.105), (-0.105, 0.105)]
    info = call(GetEntityInfo, 'get_entity_info', entity='robot0').info
    assert 'robot of 4 corners' in info.description and 'with scan' in info.description
    spin_until(executor, lambda: viewer.scene.look('robot0').points and
               'robot0' in viewer.scene.robots, what="the viewer's outline of robot0")
    viewer.view.centre, viewer.view.scale = (1.0, 2.0), 1000.0
    pixels = pygame.surfarray.array3d(viewer.render_frame())
    # 8 cm behind the centre is inside the outline; 8 cm ahead, outside it (inside its circle).
    for ahead, inside in ((-0.08, True), (0.08, False)):
        column, row = (round(value) for value in viewer.view.to_screen(1.0 + ahead, 2.0 + 0.09))
        assert (tuple(pixels[column, row]) == ROBOT) == inside


def test_an_omni_robot_follows_linear_y(ros_context, executor, tmp_path):
    (tmp_path / 'kinematic_models').mkdir()
    (tmp_path / 'kinematic_models' / 'omni.xml').write_text(OMNI_MODEL)
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        real_time_factor=5.0, resource_paths=[str(tmp_path)]))
    client = Node('client', context=ros_context)
    for node in (simulator, client):
        executor.add_node(node)
    call = ServiceCaller(executor, client)
    answer = call(SpawnEntity, 'spawn_entity', name='crab', resource_string=OMNI_ROBOT,
                  initial_pose=pose_stamped(5.0, 5.0, 0.0))
    assert answer.result.result == Result.RESULT_OK, answer.result.error_message
    odometry = []
    client.create_subscription(Odometry, '/crab/odom', odometry.append, 10)
    driver = client.create_publisher(Twist, '/crab/cmd_vel', 10)
    wait_for_subscribers(executor, driver)
    command = Twist()
    command.linear.y = 0.5
    driver.publish(command)
    spin_until(executor, lambda: odometry and odometry[-1].pose.pose.position.y > 5.5,
               what='the robot sliding to its left')
    last = odometry[-1]
    assert last.pose.pose.position.x == pytest.approx(5.0)
    assert last.twist.twist.linear.y == 0.5 and last.twist.twist.linear.x == 0.0

"""stdr_viewer rendered offscreen: the picture shows the robots where they are."""

import math
import os

from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
from PIL import Image
import pytest
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from ros_helpers import overrides, pose_stamped, ServiceCaller, spin_for, spin_until
from sensor_msgs.msg import LaserScan
from simple_robot_control.validation import ConfigError
from simulation_interfaces.msg import EntityState
from simulation_interfaces.srv import SetEntityState, SpawnEntity
from std_msgs.msg import String
from stdr_lite.node.stdr_lite import StdrLite
from stdr_lite.viewer.pygame_quiet import pygame
from stdr_lite.viewer.scene import LASER, MOVING_OBSTACLE, OBSTACLE, ROBOT, SONAR, View, WALL
from stdr_lite.viewer.stdr_viewer import mount_of, StdrViewer
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

os.environ['SDL_VIDEODRIVER'] = 'dummy'
ROBOTS = {'robot0': (3.0, 7.5, 0.0), 'scout': (10.0, 10.0, math.pi / 2)}


def colour_count(pixels, colour):
    return int(np.all(pixels == colour, axis=2).sum())


def test_viewer_shows_robots_sensors_and_walls(ros_context, executor, tmp_path):
    robots = tmp_path / 'robots.yaml'
    robots.write_text('robots:\n' + ''.join(f'  - {{name: {name}, pose: {list(pose)}}}\n'
                                            for name, pose in ROBOTS.items()))
    executor.add_node(StdrLite(context=ros_context,
                               parameter_overrides=overrides(robots_file=str(robots))))
    viewer = StdrViewer(surface=pygame.Surface((800, 600)), context=ros_context)
    executor.add_node(viewer)
    scene = viewer.scene
    spin_until(executor, lambda: scene.cells is not None and set(scene.robots) == set(ROBOTS)
               and all(robot.lasers and len(robot.sonars) == 5
                       for robot in scene.robots.values()), timeout=20.0,
               what='the map, both robots and their sensors')
    frame = viewer.render_frame()
    picture = tmp_path / 'viewer.png'
    pygame.image.save(frame, str(picture))
    with Image.open(picture) as image:
        assert image.size == (800, 600)
        pixels = np.asarray(image.convert('RGB')).transpose(1, 0, 2)
    for x, y, _ in ROBOTS.values():
        column, row = (round(value) for value in viewer.view.to_screen(x - 0.1, y - 0.1))
        assert tuple(pixels[column, row]) == ROBOT
    assert colour_count(pixels, LASER) > 200
    assert colour_count(pixels, SONAR) > 50
    assert colour_count(pixels, WALL) > 2000


def test_zoom_keeps_the_point_under_the_cursor():
    view = View((800, 600), centre=(5.0, 5.0), scale=40.0)
    anchor = view.to_world(600, 100)
    view.zoom(2.0, (600, 100))
    assert view.scale == 80.0
    assert view.to_world(600, 100) == pytest.approx(anchor)


def test_dragging_moves_the_world_with_the_mouse():
    view = View((800, 600), centre=(5.0, 5.0), scale=40.0)
    before = view.to_screen(7.0, 3.0)
    view.pan(40, -20)
    assert view.to_screen(7.0, 3.0) == pytest.approx((before[0] + 40, before[1] - 20))


def test_fit_shows_the_whole_extent():
    view = View((800, 600))
    view.fit((0.0, 0.0, 20.0, 15.0))
    for corner in ((0.0, 0.0), (20.0, 15.0)):
        column, row = view.to_screen(*corner)
        assert 0 <= column <= 800 and 0 <= row <= 600


def test_each_robot_is_drawn_with_its_own_description(ros_context, executor, tmp_path):
    (tmp_path / 'big.yaml').write_text(
        'footprint: {radius: 0.5}\nsensors:\n  lasers:\n    - {frame_id: front, pose: {x: 0.3, '
        'y: 0.1, theta: 0.5}, min_angle: -1, max_angle: 1, min_range: 0.1, max_range: 4, '
        'num_rays: 50, frequency: 10}\n')
    robots = tmp_path / 'robots.yaml'
    robots.write_text('robots:\n  - {name: small, pose: [3.0, 3.0, 0.0]}\n'
                      '  - {name: big, description: big.yaml, pose: [10.0, 10.0, 0.0]}\n')
    executor.add_node(StdrLite(context=ros_context,
                               parameter_overrides=overrides(robots_file=str(robots))))
    viewer = StdrViewer(surface=pygame.Surface((800, 600)), context=ros_context)
    executor.add_node(viewer)
    scene = viewer.scene
    spin_until(executor, lambda: scene.look('big').radius == 0.5
               and 'front' in scene.look('big').mounts and 'sonar_4' in scene.look('small').mounts,
               what="each robot's look from its markers and /tf_static")
    assert scene.look('big').mounts == {'front': pytest.approx((0.3, 0.1, 0.5))}
    assert scene.look('small').radius == 0.2
    spin_until(executor, lambda: {'small', 'big'} <= set(scene.robots)
               and scene.cells is not None, what='both robots and the map')
    pixels = pygame.surfarray.array3d(viewer.render_frame())
    for name, x, y in (('small', 3.0, 3.0), ('big', 10.0, 10.0)):
        column, row = (round(value) for value in viewer.view.to_screen(x, y + 0.35))
        inside = tuple(pixels[column, row]) == ROBOT
        assert inside == (name == 'big')


def test_obstacles_are_drawn_where_they_are(ros_context, executor):
    executor.add_node(StdrLite(context=ros_context,
                               parameter_overrides=overrides(real_time_factor=5.0)))
    viewer = StdrViewer(surface=pygame.Surface((800, 600)), context=ros_context)
    executor.add_node(viewer)
    call = ServiceCaller(executor, viewer)
    call(SpawnEntity, 'spawn_entity', name='rock', uri='obstacle',
         initial_pose=pose_stamped(6.0, 6.0))
    call(SpawnEntity, 'spawn_entity', name='ball', uri='moving_obstacle',
         initial_pose=pose_stamped(12.0, 6.0))
    moving = EntityState(pose=pose_stamped(12.0, 6.0).pose)
    moving.twist.linear.y = 1.0
    call(SetEntityState, 'set_entity_state', entity='ball', state=moving)
    scene = viewer.scene
    spin_until(executor, lambda: scene.cells is not None and len(scene.obstacles) == 2 and any(
        obstacle.y > 7.0 for obstacle in scene.obstacles.values()), what='the ball rolling')
    pixels = pygame.surfarray.array3d(viewer.render_frame())
    for obstacle in scene.obstacles.values():
        column, row = (round(value) for value in viewer.view.to_screen(obstacle.x, obstacle.y))
        assert tuple(pixels[column, row]) == (MOVING_OBSTACLE if obstacle.moving else OBSTACLE)
    assert sorted(obstacle.moving for obstacle in scene.obstacles.values()) == [False, True]


class Vandal(Node):
    """Publishes one malformed message of every kind the viewer reads."""

    def __init__(self, context):
        super().__init__('vandal', context=context)
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.topics = {
            '/map': self.create_publisher(OccupancyGrid, '/map', latched),
            '/tf_static': self.create_publisher(TFMessage, '/tf_static', latched),
            'markers': self.create_publisher(MarkerArray, '/stdr_lite/robot_markers', latched),
            'obstacles': self.create_publisher(MarkerArray, '/stdr_lite/obstacle_markers',
                                               latched),
            'status': self.create_publisher(String, 'robot_status', latched),
            'odom': self.create_publisher(Odometry, '/wreck/odom', 10),
            'laser': self.create_publisher(LaserScan, '/wreck/laser_0', 10)}

    def publish_everything(self):
        grid = OccupancyGrid()
        grid.info.width, grid.info.height, grid.info.resolution = 100, 100, 0.05
        self.topics['/map'].publish(grid)
        mount = TransformStamped()
        mount.header.frame_id, mount.child_frame_id = 'wreck/base_link', 'wreck/laser_0'
        mount.transform.translation.x = math.nan
        self.topics['/tf_static'].publish(TFMessage(transforms=[mount]))
        footprint = Marker(ns='footprint', action=Marker.ADD)
        footprint.header.frame_id, footprint.scale.x = 'wreck/base_link', math.inf
        self.topics['markers'].publish(MarkerArray(markers=[footprint]))
        rock = Marker(ns='static_obstacle', action=Marker.ADD)
        rock.pose.position.x, rock.scale.x = math.nan, 0.5
        self.topics['obstacles'].publish(MarkerArray(markers=[rock]))
        self.topics['status'].publish(String(data='x' * 1_000_000))
        odometry = Odometry()
        odometry.pose.pose.position.x = math.nan
        self.topics['odom'].publish(odometry)
        scan = LaserScan(angle_min=math.nan, ranges=[1.0] * 10)
        self.topics['laser'].publish(scan)


def test_malformed_messages_leave_the_viewer_drawing(ros_context, executor):
    executor.add_node(StdrLite(context=ros_context,
                               parameter_overrides=overrides(real_time_factor=5.0)))
    viewer = StdrViewer(surface=pygame.Surface((800, 600)), context=ros_context)
    vandal = Vandal(ros_context)
    for node in (viewer, vandal):
        executor.add_node(node)
    scene = viewer.scene
    spin_until(executor, lambda: scene.cells is not None and 'robot0' in scene.robots
               and all(topic.get_subscription_count() for topic in vandal.topics.values()),
               what='the simulator seen and every topic matched')
    vandal.publish_everything()
    spin_until(executor, lambda: scene.status.endswith('...'), what='the long status')
    spin_for(executor, 0.5)
    assert scene.cells.shape == (300, 400)
    assert 'wreck' not in scene.robots and not scene.obstacles
    assert math.isfinite(scene.look('wreck').radius)
    assert len(scene.status) < 200
    frame = pygame.surfarray.array3d(viewer.render_frame())
    column, row = (round(value) for value in viewer.view.to_screen(0.9, 1.9))
    assert tuple(frame[column, row]) == ROBOT


def test_the_screenshot_goes_exactly_where_asked_and_over_no_folder(ros_context, tmp_path):
    with pytest.raises(ConfigError, match='is a folder, not a file'):
        StdrViewer(surface=pygame.Surface((200, 150)), context=ros_context,
                   parameter_overrides=overrides(screenshot=str(tmp_path)))
    picture = tmp_path / 'last_frame'
    viewer = StdrViewer(surface=pygame.Surface((200, 150)), context=ros_context,
                        parameter_overrides=overrides(screenshot=str(picture)))
    viewer.shut_down()
    viewer.destroy_node()
    assert picture.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'


@pytest.mark.parametrize('parent, child, mount', [
    ('robot0/base_link', 'robot0/laser_0', ('robot0', 'laser_0')),
    ('team/scout/base_link', 'team/scout/sonar_1', ('team/scout', 'sonar_1')),
    ('robot0', 'robot0_laser_0', ('robot0', 'laser_0')),
    ('map', 'map_static', ('', '')),
    ('map', 'robot0/odom', ('', '')),
])
def test_sensor_mounts_are_found_in_either_tree(parent, child, mount):
    """REP-105's <robot>/<base> -> <robot>/<sensor>, or STDR's <robot> -> <robot>_<sensor>."""
    assert mount_of(parent, child) == mount

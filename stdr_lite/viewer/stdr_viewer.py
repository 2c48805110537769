"""
stdr_viewer: watch a simulation live, in a window of its own (pygame).

It only subscribes, so it works with any simulator that publishes STDR's topics: /map, and for
each robot /<robot>/odom, /<robot>/laser_J (LaserScan), /<robot>/sonar_J (Range); plus
robot_status. Robots are found by looking at the ROS graph once a second.
"""

from collections import deque
import functools
import math
import os
import re
import sys
import time

from nav_msgs.msg import OccupancyGrid, Odometry
import numpy as np
from rclpy.clock import Clock, ClockType
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from sensor_msgs.msg import LaserScan, Range
from simple_robot_control.exit_codes import EXIT_OK
from simple_robot_control.guarded_node import GuardedNode
from simple_robot_control.input_files import output_problem
from simple_robot_control.node_runtime import build_parser, run
from simple_robot_control.occupancy_map import MapError, OccupancyMap
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.pose import pose_from_message, yaw_from_quaternion
from simple_robot_control.share import BUNDLED_ROBOT, shared_file
from simple_robot_control.validation import Bounds, ConfigError, describe
from std_msgs.msg import String
from stdr_lite.core.robot_description import load_robot, RobotFileError
from stdr_lite.node.parameters import search_path, STDR_STATIC_FRAME
from stdr_lite.viewer.parameters import PARAMETERS
from stdr_lite.viewer.pygame_quiet import pygame
from stdr_lite.viewer.scene import (LaserReading, ObstacleView, Painter, RobotLook, Scene,
                                    SonarReading, View)
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker, MarkerArray

DISCOVERY_PERIOD = 1.0
# What the view takes from the graph: anything else is left out with a warning, so a bad
# message from any node can neither crash the viewer nor stop it drawing.
FAR = 1e6
RADIUS = Bounds(0.0, 5.0, low_open=True)
MAX_RAYS = 100_000
MAX_CORNERS = 64
STATUS_SHOWN = 120
ZOOM_STEP = 1.2
FRAME_TIMES = 30
# Where a window can be shown: an X or Wayland display, or an SDL video driver chosen by hand.
DISPLAY_VARIABLES = ('DISPLAY', 'WAYLAND_DISPLAY', 'SDL_VIDEODRIVER')
TOPIC_KINDS = {'nav_msgs/msg/Odometry': 'odom', 'sensor_msgs/msg/LaserScan': 'laser',
               'sensor_msgs/msg/Range': 'sonar'}
# The marker namespaces of obstacle bodies on /stdr_lite/obstacle_markers, and whether each
# kind can move.
OBSTACLE_MARKERS = {'static_obstacle': False, 'moving_obstacle': True}
# /<robot>/<topic>, where <robot> may be a nested namespace (team_a/scout).
ROBOT_TOPIC = re.compile(r'^/((?:[A-Za-z_]\w*/)*[A-Za-z_]\w*)/([A-Za-z_]\w*)$')


DESCRIPTION = ('stdr_viewer: a live view of a stdr_lite (or STDR) world: the map, each robot '
               'with its name, heading and trail, laser fans in red, sonar cones in green, and '
               'the latest robot_status. Mouse wheel or +/- zooms, dragging pans, f fits the '
               'map, q or closing the window quits.')


def sane(*values) -> bool:
    """Whether every value is a finite number of sane size (within FAR) for the view."""
    return all(math.isfinite(value) and abs(value) <= FAR for value in values)


def mount_of(parent: str, child: str) -> tuple[str, str]:
    """Return (robot, sensor frame) of a sensor's mount transform, or ('', '') for another."""
    robot, _, frame = child.rpartition('/')
    if robot and parent.startswith(f'{robot}/'):
        return robot, frame
    stdr_mount = parent and '/' not in parent and child.startswith(f'{parent}_')
    if stdr_mount and child != STDR_STATIC_FRAME:
        return parent, child[len(parent) + 1:]
    return '', ''


def _outline(points) -> tuple:
    """Return the corners of a closed line strip, or () unless 3 to MAX_CORNERS sane ones."""
    if not 3 <= len(points) <= MAX_CORNERS + 1:
        return ()
    corners = tuple((point.x, point.y) for point in points)
    if corners[-1] == corners[0]:
        corners = corners[:-1]
    if len(corners) < 3 or not all(sane(*corner) for corner in corners):
        return ()
    return corners


class StdrViewer(GuardedNode):
    """Fills a Scene from topics and paints it at a steady rate."""

    def __init__(self, surface=None, **kwargs):
        super().__init__('stdr_viewer', **kwargs)
        self.finished = Future()
        params = declare_parameters(self, PARAMETERS)
        size = (params['width'], params['height'])
        try:
            description = load_robot(params['robot_description'] or shared_file(*BUNDLED_ROBOT),
                                     search_path(params))
        except RobotFileError as error:
            raise ConfigError(str(error)) from None
        self._screenshot = params['screenshot']
        if self._screenshot:
            problem = output_problem(self._screenshot, inputs=[params['robot_description']])
            if problem is not None:
                raise ConfigError(f'screenshot {self._screenshot}: {problem}')
        pygame.font.init()
        self._window = surface is None
        self.surface = self._open_window(size) if surface is None else surface
        self.scene = Scene(default_look=RobotLook(description.radius, {
            spec.frame_id: spec.pose for spec in description.lasers + description.sonars},
            description.points))
        self.view = View(self.surface.get_size())
        self._painter = Painter(pygame.font.Font(None, 22))
        self._subscribed = {}
        self._frame_times = deque(maxlen=FRAME_TIMES)
        self._scene_shown = False
        self._subscribe_world()
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self.create_timer(DISCOVERY_PERIOD, self.discover_robots, clock=steady)
        self.create_timer(1.0 / params['fps'], self._on_frame, clock=steady)
        self.discover_robots()

    def _open_window(self, size):
        """Open the window, or draw offscreen (saying so) where there is no display."""
        if not any(os.environ.get(name) for name in DISPLAY_VARIABLES):
            # SDL would look for a display it cannot have and say only 'XDG_RUNTIME_DIR'.
            os.environ['SDL_VIDEODRIVER'] = 'dummy'
            self.get_logger().warn(
                'no display here (DISPLAY is not set): drawing offscreen, no window; '
                '-p screenshot:=view.png saves the last frame on exit (ssh -X, or a '
                'desktop, shows the window)')
        pygame.display.init()
        surface = pygame.display.set_mode(size, pygame.RESIZABLE)
        pygame.display.set_caption('stdr_viewer')
        return surface

    def _subscribe_world(self):
        """Subscribe to what holds for the whole world: map, mounts, markers, statuses."""
        latched = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(OccupancyGrid, '/map', self._on_map, latched)
        self.create_subscription(TFMessage, '/tf_static', self._on_static_frames, latched)
        self.create_subscription(MarkerArray, '/stdr_lite/robot_markers', self._on_markers,
                                 latched)
        self.create_subscription(MarkerArray, '/stdr_lite/obstacle_markers',
                                 self._on_obstacle_markers, latched)
        everything = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                                reliability=ReliabilityPolicy.RELIABLE,
                                durability=DurabilityPolicy.TRANSIENT_LOCAL)
        self.create_subscription(String, 'robot_status', self._on_status, everything)

    def discover_robots(self) -> None:
        """Subscribe to the topics of robots that appeared; forget those that went away."""
        present = set()
        for topic, types in self.get_topic_names_and_types():
            match = ROBOT_TOPIC.match(topic)
            kind = next((TOPIC_KINDS[name] for name in types if name in TOPIC_KINDS), None)
            if not match or kind is None or (kind == 'odom' and match.group(2) != 'odom'):
                continue
            present.add(topic)
            if topic not in self._subscribed:
                self._subscribed[topic] = self._subscribe(kind, topic, *match.groups())
        for topic in set(self._subscribed) - present:
            self.destroy_subscription(self._subscribed.pop(topic))
            robot, name = ROBOT_TOPIC.match(topic).groups()
            if name == 'odom':
                self.scene.robots.pop(robot, None)

    def _subscribe(self, kind, topic, robot, name):
        if kind == 'odom':
            return self.create_subscription(
                Odometry, topic, functools.partial(self._on_odometry, robot), 10)
        if kind == 'laser':
            return self.create_subscription(
                LaserScan, topic, functools.partial(self._on_laser, robot, name), 10)
        return self.create_subscription(
            Range, topic, functools.partial(self._on_sonar, robot, name), 10)

    def _on_map(self, message):
        try:
            grid = OccupancyMap.from_grid_message(message)
        except MapError as error:
            self._ignore(f'{error}')
            return
        self.scene.set_map(grid.cells, grid.resolution, grid.origin[:2])
        self.view.fit(self.scene.extent())

    def _ignore(self, what):
        """Say, now and then, that a message from the graph was left out, and why."""
        self.get_logger().warn(f'ignoring {what}', throttle_duration_sec=5.0)

    def _on_static_frames(self, message):
        """
        Take each robot's sensor mounts from its static transforms.

        They are <robot>/... -> <robot>/<sensor> in REP-105's tree, <robot> -> <robot>_<sensor>
        in STDR's. A /tf_static message holds every static transform of its publisher, so the
        mounts it gives a robot replace whatever the robot had.
        """
        mounts = {}
        for transform in message.transforms:
            robot, frame = mount_of(transform.header.frame_id, transform.child_frame_id)
            if robot:
                offset = transform.transform
                mount = (offset.translation.x, offset.translation.y,
                         yaw_from_quaternion(offset.rotation))
                if not sane(*mount):
                    self._ignore(f'the mount of {describe(transform.child_frame_id)} on '
                                 '/tf_static: not finite, or beyond 100 m')
                    continue
                mounts.setdefault(robot, {})[frame] = mount
        for robot, robot_mounts in mounts.items():
            self.scene.own_look(robot).mounts = robot_mounts

    def _on_markers(self, message):
        """Take each robot's footprint from its marker: a disc, or a polygon's outline."""
        for marker in message.markers:
            if marker.ns == 'footprint' and marker.action == Marker.ADD:
                # The robot's body frame: <robot>/base_link (REP-105) or <robot> (STDR).
                robot = marker.header.frame_id.rpartition('/')[0] or marker.header.frame_id
                if marker.type == Marker.LINE_STRIP:
                    points = _outline(marker.points)
                    radius = max((math.hypot(*point) for point in points), default=0.0)
                    if not (points and RADIUS.contains(radius)):
                        self._ignore(f'the footprint marker of {describe(robot)}: its outline '
                                     f'must have 3 to {MAX_CORNERS} corners within '
                                     f'{RADIUS.text()} m')
                        continue
                else:
                    radius, points = 0.5 * marker.scale.x, ()
                    if not RADIUS.contains(radius):
                        self._ignore(f'the footprint marker of {describe(robot)}: its radius '
                                     f'must be {RADIUS.text()} m')
                        continue
                look = self.scene.own_look(robot)
                look.radius, look.points = radius, points

    def _on_obstacle_markers(self, message):
        """Take every obstacle from its body marker; each message holds all of them."""
        obstacles = {}
        for marker in message.markers:
            if marker.ns in OBSTACLE_MARKERS and marker.action == Marker.ADD:
                x, y, radius = marker.pose.position.x, marker.pose.position.y, 0.5 * marker.scale.x
                if not (sane(x, y) and RADIUS.contains(radius)):
                    self._ignore(f'obstacle marker {marker.id}: its pose is not finite or its '
                                 f'radius not {RADIUS.text()} m')
                    continue
                obstacles[marker.id] = ObstacleView(x, y, radius, OBSTACLE_MARKERS[marker.ns])
        self.scene.obstacles = obstacles

    def _on_status(self, message):
        text = ' '.join(message.data.split())
        self.scene.status = 'robot_status: ' + (
            text if len(text) <= STATUS_SHOWN else text[:STATUS_SHOWN] + '...')

    def _on_odometry(self, robot, message):
        pose = pose_from_message(message.pose.pose)
        if not sane(*pose):
            self._ignore(f'odometry of {robot}: not finite, or beyond {FAR:g} m')
            return
        self.scene.move(robot, pose)

    def _on_laser(self, robot, frame_id, message):
        shape = (message.angle_min, message.angle_increment, message.range_max)
        if not (sane(*shape) and 0 < len(message.ranges) <= MAX_RAYS):
            self._ignore(f'scan {robot}/{frame_id}: its angles or range are not finite, or it '
                         f'has no rays or more than {MAX_RAYS}')
            return
        self.scene.robot(robot).lasers[frame_id] = LaserReading(
            *shape, np.asarray(message.ranges, dtype=float))

    def _on_sonar(self, robot, frame_id, message):
        cone = (message.field_of_view, message.min_range, message.max_range)
        if not sane(*cone) or math.isnan(message.range):
            self._ignore(f'range {robot}/{frame_id}: not finite, or beyond {FAR:g} m')
            return
        self.scene.robot(robot).sonars[frame_id] = SonarReading(*cone, message.range)

    def render_frame(self) -> pygame.Surface:
        """Paint the scene onto the surface and return it."""
        times = self._frame_times
        times.append(time.monotonic())
        rate = (len(times) - 1) / (times[-1] - times[0]) if times[-1] > times[0] else 0.0
        self._painter.draw(self.surface, self.scene, self.view,
                           f'{len(self.scene.robots)} robots, {rate:.0f} fps, '
                           f'{self.view.scale:.0f} px/m')
        return self.surface

    def _on_frame(self):
        if self.finished.done():
            return
        if self._window:
            for event in pygame.event.get():
                self._handle(event)
        self.render_frame()
        if not self._scene_shown and self.scene.cells is not None and self.scene.robots:
            # Said once, so that a script waiting for a picture of the run knows there is one.
            self._scene_shown = True
            self.get_logger().info(f'showing the map and {len(self.scene.robots)} robots')
        if self._window:
            pygame.display.flip()

    def _handle(self, event):
        if event.type == pygame.QUIT or (event.type == pygame.KEYDOWN
                                         and event.key in (pygame.K_q, pygame.K_ESCAPE)):
            self.finished.set_result(EXIT_OK)
        elif event.type == pygame.MOUSEWHEEL:
            self.view.zoom(ZOOM_STEP ** event.y, pygame.mouse.get_pos())
        elif event.type == pygame.MOUSEMOTION and event.buttons[0]:
            self.view.pan(*event.rel)
        elif event.type == pygame.KEYDOWN and event.unicode in ('+', '=', '-'):
            factor = 1.0 / ZOOM_STEP if event.unicode == '-' else ZOOM_STEP
            self.view.zoom(factor, (self.view.size[0] / 2, self.view.size[1] / 2))
        elif event.type == pygame.KEYDOWN and event.unicode == 'f':
            self.view.fit(self.scene.extent())
        elif event.type == pygame.VIDEORESIZE:
            self.view.size = event.size

    def shut_down(self) -> None:
        """Save the last frame when asked to, and close the window."""
        if self._screenshot:
            try:
                with open(self._screenshot, 'wb') as stream:
                    pygame.image.save(self.render_frame(), stream, 'frame.png')
            except (OSError, pygame.error) as error:
                self.get_logger().error(f'{self._screenshot}: cannot write the screenshot: '
                                        f'{error}')
            else:
                self.get_logger().info(f'wrote {self._screenshot}')
        if self._window:
            pygame.display.quit()


def main(argv: list[str] | None = None) -> None:
    parser = build_parser('stdr_viewer', DESCRIPTION, PARAMETERS)
    sys.exit(run('stdr_viewer', parser, lambda options: StdrViewer(), argv))


if __name__ == '__main__':
    main()

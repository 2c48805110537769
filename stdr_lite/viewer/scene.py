"""
What stdr_viewer draws, and how: a scene (map, robots, sensor readings, status) and a view.

No ROS here: the viewer node fills the scene from topics, and draw() paints it onto any
pygame Surface, a window or an offscreen one alike. Colours follow the lab text's figure:
black walls, blue robots, red laser fans, green sonar cones; obstacles grey, orange if moving.
"""

from collections import deque
from dataclasses import dataclass, field
import math

import numpy as np
from stdr_lite.core.sensors import sensor_origin
from stdr_lite.viewer.pygame_quiet import pygame

BACKGROUND = (200, 200, 200)
WALL, FREE, UNKNOWN = (0, 0, 0), (255, 255, 255), (205, 205, 205)
ROBOT = (30, 80, 220)
LASER = (230, 30, 30)
LASER_FILL = (255, 215, 215)
SONAR = (30, 170, 60)
SONAR_FILL = (205, 240, 210)
TRAIL = (120, 150, 240)
OBSTACLE = (110, 110, 110)
MOVING_OBSTACLE = (235, 140, 30)
TEXT = (20, 20, 20)
TRAIL_LENGTH = 2000
ARC_POINTS = 12
CENTRE = (0.0, 0.0, 0.0)


@dataclass
class LaserReading:
    angle_min: float
    angle_increment: float
    range_max: float
    ranges: np.ndarray


@dataclass
class SonarReading:
    field_of_view: float
    min_range: float
    max_range: float
    distance: float


@dataclass
class RobotLook:
    """
    A robot's footprint and sensor mounts (sensor frame -> pose on the robot).

    The footprint is a disc of radius, or the polygon of points (its corners in the robot's
    frame) when there are any; radius is then the farthest corner's distance.
    """

    radius: float = 0.2
    mounts: dict = field(default_factory=dict)
    points: tuple = ()


@dataclass
class RobotView:
    """The latest of everything known about where one robot is and what it senses."""

    pose: tuple = (0.0, 0.0, 0.0)
    trail: deque = field(default_factory=lambda: deque(maxlen=TRAIL_LENGTH))
    lasers: dict = field(default_factory=dict)
    sonars: dict = field(default_factory=dict)


@dataclass
class ObstacleView:
    """An obstacle where the simulator last showed it."""

    x: float
    y: float
    radius: float
    moving: bool


@dataclass
class Scene:
    """The map as grey levels (row 0 at the bottom), every robot and every obstacle, by name."""

    resolution: float = 0.05
    origin: tuple = (0.0, 0.0)
    cells: np.ndarray = None
    robots: dict = field(default_factory=dict)
    status: str = ''
    default_look: RobotLook = field(default_factory=RobotLook)
    looks: dict = field(default_factory=dict)
    obstacles: dict = field(default_factory=dict)

    def set_map(self, cells: np.ndarray, resolution: float, origin: tuple) -> None:
        self.cells, self.resolution, self.origin = cells, resolution, origin

    def robot(self, name: str) -> RobotView:
        return self.robots.setdefault(name, RobotView())

    def look(self, name: str) -> RobotLook:
        """
        Return the robot's look: as the simulator told it (markers, /tf_static), if it did.

        Otherwise the default look, from a description file.
        """
        return self.looks.get(name, self.default_look)

    def own_look(self, name: str) -> RobotLook:
        """Return the robot's look to fill in, starting from the default one."""
        if name not in self.looks:
            default = self.default_look
            self.looks[name] = RobotLook(default.radius, dict(default.mounts), default.points)
        return self.looks[name]

    def move(self, name: str, pose: tuple) -> None:
        robot = self.robot(name)
        robot.pose = pose
        if not robot.trail or math.dist(robot.trail[-1], pose[:2]) > 0.01:
            robot.trail.append(pose[:2])

    def extent(self) -> tuple[float, float, float, float]:
        """Return (min x, min y, max x, max y) of the map, or of the robots without a map."""
        if self.cells is not None:
            height, width = self.cells.shape
            return (self.origin[0], self.origin[1], self.origin[0] + width * self.resolution,
                    self.origin[1] + height * self.resolution)
        points = [robot.pose[:2] for robot in self.robots.values()] or [(0.0, 0.0)]
        (low_x, low_y), (high_x, high_y) = np.min(points, axis=0), np.max(points, axis=0)
        return low_x - 2.0, low_y - 2.0, high_x + 2.0, high_y + 2.0


class View:
    """Where the camera looks (centre, in metres) and its zoom (pixels per metre)."""

    def __init__(self, size, centre=(0.0, 0.0), scale=40.0):
        self.size = size
        self.centre = centre
        self.scale = scale

    def fit(self, extent: tuple[float, float, float, float]) -> None:
        low_x, low_y, high_x, high_y = extent
        self.centre = (0.5 * (low_x + high_x), 0.5 * (low_y + high_y))
        self.scale = 0.95 * min(self.size[0] / (high_x - low_x),
                                self.size[1] / (high_y - low_y))

    def to_screen(self, x: float, y: float) -> tuple[float, float]:
        return (self.size[0] / 2 + (x - self.centre[0]) * self.scale,
                self.size[1] / 2 - (y - self.centre[1]) * self.scale)

    def to_world(self, column: float, row: float) -> tuple[float, float]:
        return (self.centre[0] + (column - self.size[0] / 2) / self.scale,
                self.centre[1] - (row - self.size[1] / 2) / self.scale)

    def zoom(self, factor: float, about: tuple[float, float]) -> None:
        """Zoom by factor keeping the world point under the screen point about in place."""
        anchor = self.to_world(*about)
        self.scale = min(max(self.scale * factor, 2.0), 2000.0)
        moved = self.to_world(*about)
        self.centre = (self.centre[0] + anchor[0] - moved[0],
                       self.centre[1] + anchor[1] - moved[1])

    def pan(self, columns: float, rows: float) -> None:
        self.centre = (self.centre[0] - columns / self.scale, self.centre[1] + rows / self.scale)


class Painter:
    """Draws a scene; keeps the map picture scaled for the current zoom between frames."""

    def __init__(self, font):
        self._font = font
        self._map_picture = None
        self._scaled = (None, None)

    def draw(self, surface: pygame.Surface, scene: Scene, view: View,
             extra_text: str = '') -> None:
        """
        Paint the scene onto surface.

        Layers go bottom up: map, obstacles, sensor fills, sensor outlines, trails, robots,
        text; so a robot is never hidden under another robot's fan.
        """
        surface.fill(BACKGROUND)
        self._draw_map(surface, scene, view)
        for obstacle in scene.obstacles.values():
            pygame.draw.circle(surface, MOVING_OBSTACLE if obstacle.moving else OBSTACLE,
                               view.to_screen(obstacle.x, obstacle.y),
                               max(2, round(obstacle.radius * view.scale)))
        shapes = [(colours, points) for name, robot in scene.robots.items()
                  for colours, points in self._sensor_shapes(robot, scene.look(name), view)]
        for (fill, _), points in shapes:
            pygame.draw.polygon(surface, fill, points)
        for (_, outline), points in shapes:
            pygame.draw.polygon(surface, outline, points, 1)
        for robot in scene.robots.values():
            if len(robot.trail) > 1:
                pygame.draw.lines(surface, TRAIL, False,
                                  [view.to_screen(x, y) for x, y in robot.trail], 2)
        for name, robot in scene.robots.items():
            self._draw_robot(surface, name, robot, scene.look(name), view)
        lines = [scene.status or 'robot_status: (nothing yet)', extra_text]
        for number, line in enumerate(line for line in lines if line):
            surface.blit(self._font.render(line, True, TEXT, BACKGROUND), (8, 8 + 20 * number))

    def _sensor_shapes(self, robot, look, view):
        """Yield ((fill, outline), screen polygon) for each laser fan and sonar cone."""
        for frame_id, reading in robot.lasers.items():
            x, y, heading = sensor_origin(robot.pose, look.mounts.get(frame_id, CENTRE))
            ranges = np.where(np.isfinite(reading.ranges) & (reading.ranges > 0),
                              reading.ranges, reading.range_max)
            angles = (heading + reading.angle_min
                      + reading.angle_increment * np.arange(ranges.size))
            ends = zip(x + ranges * np.cos(angles), y + ranges * np.sin(angles))
            points = [view.to_screen(x, y)] + [view.to_screen(*end) for end in ends]
            if len(points) > 2:
                yield (LASER_FILL, LASER), points
        for frame_id, reading in robot.sonars.items():
            x, y, heading = sensor_origin(robot.pose, look.mounts.get(frame_id, CENTRE))
            reach = min(max(reading.distance, reading.min_range), reading.max_range)
            angles = heading + np.linspace(-0.5, 0.5, ARC_POINTS) * reading.field_of_view
            arc = zip(x + reach * np.cos(angles), y + reach * np.sin(angles))
            yield (SONAR_FILL, SONAR), [view.to_screen(x, y)] + [view.to_screen(*point)
                                                                 for point in arc]

    def _draw_map(self, surface, scene, view):
        if scene.cells is None:
            return
        if self._map_picture is None or self._map_picture[0] is not scene.cells:
            shades = np.where(scene.cells[..., None] > 50, WALL,
                              np.where(scene.cells[..., None] < 0, UNKNOWN, FREE))
            picture = pygame.surfarray.make_surface(
                np.ascontiguousarray(shades[::-1].transpose(1, 0, 2)).astype(np.uint8))
            self._map_picture = (scene.cells, picture)
            self._scaled = (None, None)
        height, width = scene.cells.shape
        size = (max(1, round(width * scene.resolution * view.scale)),
                max(1, round(height * scene.resolution * view.scale)))
        if self._scaled[0] != size:
            self._scaled = (size, pygame.transform.scale(self._map_picture[1], size))
        top_left = view.to_screen(scene.origin[0], scene.origin[1] + height * scene.resolution)
        surface.blit(self._scaled[1], (round(top_left[0]), round(top_left[1])))

    def _draw_robot(self, surface, name, robot, look, view):
        x, y, theta = robot.pose
        radius = look.radius
        centre = view.to_screen(x, y)
        pixels = max(2, round(radius * view.scale))
        if look.points:
            cos_theta, sin_theta = math.cos(theta), math.sin(theta)
            pygame.draw.polygon(surface, ROBOT, [
                view.to_screen(x + cos_theta * px - sin_theta * py,
                               y + sin_theta * px + cos_theta * py) for px, py in look.points])
        else:
            pygame.draw.circle(surface, ROBOT, centre, pixels)
        nose = view.to_screen(x + radius * math.cos(theta), y + radius * math.sin(theta))
        pygame.draw.line(surface, FREE, centre, nose, 2)
        label = self._font.render(name, True, ROBOT)
        surface.blit(label, (centre[0] + pixels + 2, centre[1] - pixels - 14))

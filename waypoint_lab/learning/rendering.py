"""
Pictures of an arena, as stdr_viewer draws a world: its scene and painter, without ROS.

rgb_array paints offscreen into an array (height x width x 3); human opens a pygame window
and paints into it. The courses' goals are drawn over the scene: a circle of the goal set's
radius and a heading arrow each, the current goal in orange, the others in grey.
"""

import math
import os

import numpy as np
from stdr_lite.viewer.pygame_quiet import pygame
from stdr_lite.viewer.scene import LaserReading, Painter, RobotLook, Scene, View

SIZE = (600, 450)
CURRENT_GOAL = (235, 140, 30)
OTHER_GOAL = (150, 150, 150)


class ArenaPicture:
    """Draws an arena; mode is 'rgb_array' (an array) or 'human' (a window)."""

    def __init__(self, arena, mode: str):
        if mode == 'rgb_array' and 'DISPLAY' not in os.environ:
            os.environ.setdefault('SDL_VIDEODRIVER', 'dummy')
        pygame.display.init()
        pygame.font.init()
        self.arena, self.mode = arena, mode
        self.surface = (pygame.display.set_mode(SIZE) if mode == 'human'
                        else pygame.Surface(SIZE))
        if mode == 'human':
            pygame.display.set_caption('stdr_lite: waypoints')
        grid = arena.simulation.occupancy_map
        self.scene = Scene(default_look=RobotLook(arena.simulation.robot(arena.names[0]).radius,
                                                  {arena.laser.frame_id: arena.laser.pose}))
        self.scene.set_map(grid.cells, grid.resolution, grid.origin[:2])
        self.view = View(SIZE)
        self.view.fit(self.scene.extent())
        self.painter = Painter(pygame.font.Font(None, 20))

    def draw(self, ranges: np.ndarray, status: str) -> np.ndarray | None:
        """Paint the arena now, its robots' lasers reading ranges; return the frame or None."""
        laser = self.arena.laser
        increment = (laser.max_angle - laser.min_angle) / max(laser.num_rays - 1, 1)
        for name, pose, scan in zip(self.arena.names, self.arena.poses, ranges):
            self.scene.move(name, tuple(pose))
            self.scene.robot(name).lasers[laser.frame_id] = LaserReading(
                laser.min_angle, increment, laser.max_range, scan)
        self.scene.status = status
        self.painter.draw(self.surface, self.scene, self.view)
        self._draw_goals()
        if self.mode == 'human':
            pygame.event.pump()
            pygame.display.flip()
            return None
        return np.transpose(pygame.surfarray.array3d(self.surface), (1, 0, 2)).copy()

    def _draw_goals(self):
        courses, task = self.arena.courses, self.arena.task
        radius = max(2, round(task.distance_tolerance * self.view.scale))
        for robot, waypoints in enumerate(courses.waypoints):
            for number, (x, y, theta) in enumerate(waypoints):
                colour = CURRENT_GOAL if number == courses.next[robot] else OTHER_GOAL
                centre = self.view.to_screen(x, y)
                tip = self.view.to_screen(x + 0.4 * math.cos(theta), y + 0.4 * math.sin(theta))
                pygame.draw.circle(self.surface, colour, centre, radius, 2)
                pygame.draw.line(self.surface, colour, centre, tip, 2)

    def close(self) -> None:
        if self.mode == 'human':
            pygame.display.quit()

"""
The reference planner: a route of waypoints through a map, clear of its walls. No ROS here.

The shortest path on the map grown by the robot's radius (courseworks.grids: scipy's Dijkstra
on the 8-connected grid) is pulled taut: from each corner kept, the path runs straight to the
farthest later cell the robot sees clear (a ray through the grown walls, courseworks.rays),
so the route is a few straight legs a waypoint controller drives one by one. Each waypoint
faces along its leg; the last takes the goal's heading.
"""

import math

from courseworks.grids import Grid, inflate, shortest_path
from courseworks.rays import trace
import numpy as np


def plan_route(grid: Grid, radius: float, start: tuple[float, float, float],
               goal: tuple[float, float, float]) -> list[tuple[float, float, float]] | None:
    """
    Return waypoints (x, y, theta) from start to goal clear of grid's walls, None if none.

    radius is the clearance to keep: the robot's radius and a margin for the controller's
    error (a route at the radius alone grazes door jambs).
    """
    grown = inflate(grid, radius)
    free = ~grown
    first, last = grid.cell_of(*start[:2]), grid.cell_of(*goal[:2])
    if first is None or last is None or not free[last]:
        return None
    free[first] = True
    cells = shortest_path(free, first, last, grid.resolution)
    if not cells:
        return None
    points = [start[:2]] + [grid.centre_of(*cell) for cell in cells[1:-1]] + [goal[:2]]
    crossed = np.zeros(grown.shape, dtype=np.int32)
    corners = [points[0]]
    here = 0
    while here < len(points) - 1:
        ahead = here + 1
        while ahead + 1 < len(points) and _clear(grown, grid, points[here], points[ahead + 1],
                                                 crossed):
            ahead += 1
        corners.append(points[ahead])
        here = ahead
    route = [(x, y, math.atan2(y - y0, x - x0))
             for (x0, y0), (x, y) in zip(corners, corners[1:])]
    route[-1] = (goal[0], goal[1], goal[2])
    return route


def _clear(grown, grid, point, to, crossed):
    """
    Whether the straight segment from point to to crosses no grown wall.

    crossed is scratch for the ray's counts, allocated once per route: only whether the ray
    ran its whole length matters (it stops at the first wall).
    """
    x, y = ((point[0] - grid.origin[0]) / grid.resolution,
            (point[1] - grid.origin[1]) / grid.resolution)
    length = math.hypot(to[0] - point[0], to[1] - point[1]) / grid.resolution
    angle = math.atan2(to[1] - point[1], to[0] - point[0])
    return trace(grown, x, y, angle, length, crossed, crossed)[0] >= length

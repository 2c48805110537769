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

# How much more a cell within the margin costs to cross than one beyond it.
MARGIN_COST = 5.0


def plan_route(grid: Grid, radius: float, start: tuple[float, float, float],
               goal: tuple[float, float, float],
               margin: float = 0.0) -> list[tuple[float, float, float]] | None:
    """
    Return waypoints (x, y, theta) from start to goal clear of grid's walls, None if none.

    radius is the robot's: no route brings its centre closer to a wall. margin is clearance
    kept beyond it where there is room (for the controller's error: a route at the radius
    alone grazes door jambs): cells within it cost MARGIN_COST times as much to cross, and the
    route's straight legs keep it. A robot that stands within radius of a wall (pushed there)
    may leave through the cells around it.
    """
    grown = inflate(grid, radius)
    kept = inflate(grid, radius + margin) if margin else grown
    free = ~grown
    first, last = grid.cell_of(*start[:2]), grid.cell_of(*goal[:2])
    if first is None or last is None or not free[last]:
        return None
    free |= grid.within(start[:2], 2.0 * radius) & ~grid.walls
    cost = np.where(kept & ~grown, MARGIN_COST, 1.0)
    cells = shortest_path(free, first, last, grid.resolution, cost)
    if not cells:
        return None
    points = [start[:2]] + [grid.centre_of(*cell) for cell in cells[1:-1]] + [goal[:2]]
    crossed = np.zeros(grown.shape, dtype=np.int32)
    corners = [points[0]]
    here = 0
    while here < len(points) - 1:
        ahead = here + 1
        while ahead + 1 < len(points) and _clear(kept, grid, points[here], points[ahead + 1],
                                                 crossed):
            ahead += 1
        corners.append(points[ahead])
        here = ahead
    route = [(x, y, math.atan2(y - y0, x - x0))
             for (x0, y0), (x, y) in zip(corners, corners[1:])]
    route[-1] = (goal[0], goal[1], goal[2])
    return route


def route_clear(grid: Grid, radius: float, route: list[tuple[float, float, float]]) -> bool:
    """Whether each leg between route's corners keeps radius off grid's walls (a new map's)."""
    grown = inflate(grid, radius)
    crossed = np.zeros(grown.shape, dtype=np.int32)
    return all(_clear(grown, grid, point[:2], to[:2], crossed)
               for point, to in zip(route, route[1:]))


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

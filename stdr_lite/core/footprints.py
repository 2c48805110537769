"""
Footprints as polygons: their checks and their geometry against points, boxes and rays.

A robot's footprint is a circle or a simple polygon (convex or not) given by its corners in the
robot's frame. No ROS here.
"""

import math

import numpy as np
import shapely
from shapely.geometry.polygon import orient


def polygon_problem(points: list) -> str | None:
    """Say why corners make no simple polygon (no area, or edges that cross), or None."""
    edges = list(zip(points, points[1:] + points[:1]))
    count = len(edges)
    for first in range(count):
        for second in range(first + 1, count):
            if second == first + 1 or (first == 0 and second == count - 1):
                continue
            if _segments_cross(*edges[first], *edges[second]):
                return f'edges {first} and {second} cross: give the corners in order round it'
    area = 0.5 * sum(x1 * y2 - x2 * y1
                     for (x1, y1), (x2, y2) in zip(points, points[1:] + points[:1]))
    if abs(area) < 1e-9:
        return 'the corners enclose no area'
    return None


def _segments_cross(a, b, c, d):
    def side(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    first, second = side(a, b, c), side(a, b, d)
    third, fourth = side(c, d, a), side(c, d, b)
    return first * second <= 0.0 and third * fourth <= 0.0 and not (
        first == second == 0.0)


def placed(points: tuple, pose: tuple) -> np.ndarray:
    """Return the polygon's corners at pose (x, y, theta), as an (n, 2) array in the world."""
    corners = np.asarray(points, dtype=float)
    cos_theta, sin_theta = math.cos(pose[2]), math.sin(pose[2])
    return np.column_stack([pose[0] + cos_theta * corners[:, 0] - sin_theta * corners[:, 1],
                            pose[1] + sin_theta * corners[:, 0] + cos_theta * corners[:, 1]])


def convex_hull(points: tuple) -> list[tuple[float, float]]:
    """Return the corners of the polygon's convex hull, counter-clockwise, none repeated."""
    hull = orient(shapely.convex_hull(shapely.MultiPoint(points)))
    return [(float(x), float(y)) for x, y in shapely.get_coordinates(hull)[:-1]]

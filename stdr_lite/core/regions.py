"""
Whether a circular footprint overlaps a region: a sphere, an axis-aligned box or a convex hull.

The world is planar, so regions are taken in x and y: a sphere is its circle, a box its
rectangle, a hull the convex polygon of its points. A region from a request is checked once
(finite numbers, a bounded count of points) and its hull computed once, however many entities
it is then tried against.
"""

import math
from typing import Callable

import numpy as np

MAX_HULL_POINTS = 1000


def region_test(kind: str, points: list) -> Callable[[tuple, float], bool]:
    """
    Return overlaps(centre, radius) for a region, or raise ValueError saying what is wrong.

    kind is 'sphere' (points: its centre, then (radius, _, _)), 'box' (two opposite corners)
    or 'hull' (at least three points, not all on one line); points are (x, y, z) triples.
    """
    problem = count_problem(len(points))
    if problem is not None:
        raise ValueError(problem)
    if not all(math.isfinite(value) for point in points for value in point):
        raise ValueError('the bounds hold a value that is not finite')
    if kind == 'sphere' and len(points) == 2:
        centre, radius = points[0][:2], points[1][0]
        if radius < 0.0:
            raise ValueError(f'a sphere radius must be >= 0, got {radius:g}')
        return lambda middle, size: overlaps_circle(middle, size, centre, radius)
    if kind == 'box' and len(points) == 2:
        return lambda middle, size: overlaps_box(middle, size, points[0], points[1])
    if kind == 'hull' and len(points) >= 3:
        hull = convex_hull(points)
        return lambda middle, size: overlaps_hull(middle, size, hull)
    raise ValueError(f'bounds of kind {kind} with {len(points)} points define no volume')


def count_problem(count: int) -> str | None:
    """Say why a region of count points is refused (more than any region takes), or None."""
    if count > MAX_HULL_POINTS:
        return f'bounds of {count:,} points; a convex hull takes at most {MAX_HULL_POINTS:,}'
    return None


def overlaps_circle(centre: tuple, radius: float, other_centre: tuple,
                    other_radius: float) -> bool:
    """Whether two circles overlap (touching counts)."""
    return math.dist(centre, other_centre) <= radius + other_radius


def overlaps_box(centre: tuple, radius: float, corner: tuple, opposite: tuple) -> bool:
    """Whether a circle overlaps the axis-aligned rectangle with these two opposite corners."""
    low = np.minimum(corner[:2], opposite[:2])
    high = np.maximum(corner[:2], opposite[:2])
    nearest = np.clip(centre[:2], low, high)
    return math.dist(nearest, centre[:2]) <= radius


def convex_hull(points: list) -> list:
    """
    Return the corners of the convex hull of points, counter-clockwise, in x and y.

    Raises ValueError unless there are three points not all on one line.
    """
    hull = _convex_hull([tuple(point[:2]) for point in points])
    if len(hull) < 3:
        raise ValueError('a convex hull needs three points not all on one line')
    return hull


def overlaps_hull(centre: tuple, radius: float, hull: list) -> bool:
    """
    Whether a circle overlaps a convex hull (its corners counter-clockwise: convex_hull()).

    The circle overlaps when its centre is inside the hull or within radius of an edge.
    """
    x, y = centre[:2]
    inside = True
    for (x1, y1), (x2, y2) in zip(hull, hull[1:] + hull[:1]):
        if (x2 - x1) * (y - y1) - (y2 - y1) * (x - x1) < 0.0:
            inside = False
        if _distance_to_segment((x, y), (x1, y1), (x2, y2)) <= radius:
            return True
    return inside


def _distance_to_segment(point, start, end):
    dx, dy = end[0] - start[0], end[1] - start[1]
    length_squared = dx * dx + dy * dy
    along = 0.0 if length_squared == 0.0 else max(0.0, min(1.0, (
        (point[0] - start[0]) * dx + (point[1] - start[1]) * dy) / length_squared))
    return math.dist(point, (start[0] + along * dx, start[1] + along * dy))


def _convex_hull(points):
    """Return the hull's corners counter-clockwise (Andrew's monotone chain)."""
    points = sorted(set(points))
    if len(points) < 3:
        return points

    def turn(origin, first, second):
        return ((first[0] - origin[0]) * (second[1] - origin[1])
                - (first[1] - origin[1]) * (second[0] - origin[0]))

    lower, upper = [], []
    for point in points:
        while len(lower) >= 2 and turn(lower[-2], lower[-1], point) <= 0.0:
            lower.pop()
        lower.append(point)
    for point in reversed(points):
        while len(upper) >= 2 and turn(upper[-2], upper[-1], point) <= 0.0:
            upper.pop()
        upper.append(point)
    return lower[:-1] + upper[:-1]

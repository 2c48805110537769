"""
Contact between bodies: circles (obstacles, round robots) and polygons (robots with corners).

A step offends when it brings two footprints into overlap, or deeper into it: bodies never
pass through each other, and bodies in contact may still part. How deep two footprints overlap
is measured for each pair of shapes: for two circles, the sum of their radii less the distance
of their centres (negative while apart); where a polygon takes part, shapely measures it: a
circle's radius less its centre's signed distance to the polygon's boundary, or two polygons'
common area (zero while apart). Only the sign and the change of a pair's depth matter. Pairs
are found by their circumscribed circles first, so polygons cost only when bodies are close.
No ROS here.
"""

import numpy as np
from scipy.spatial import cKDTree
import shapely
from stdr_lite.core.footprints import placed

# Up to this many bodies every pair is looked at; beyond, a k-d tree finds the close ones.
FEW_BODIES = 8


class Picked:
    """The shapes of the bodies picked by index, each looked up only when asked for."""

    def __init__(self, shapes: list, picked: np.ndarray):
        self._shapes, self._picked = shapes, picked

    def __getitem__(self, index: int):
        return self._shapes[self._picked[index]]


def depths(first_poses: np.ndarray, first_radii: np.ndarray, first_shapes,
           second_poses: np.ndarray, second_radii: np.ndarray, second_shapes,
           polygonal: np.ndarray | None = None) -> np.ndarray:
    """
    Return how deep each pair of bodies overlaps: positive only when it does.

    Each body is a pose, a radius (its circumscribed circle's, for a polygon) and a shape:
    None for a circle, else its corners in its own frame. polygonal, if given, says of each
    pair whether a polygon takes part; the shapes (a list, or Picked) are looked up only for
    the pairs whose circles overlap and that hold a polygon: a crowd of thousands of round
    bodies pressed together costs numpy's work alone.
    """
    depth = first_radii + second_radii - np.hypot(first_poses[:, 0] - second_poses[:, 0],
                                                  first_poses[:, 1] - second_poses[:, 1])
    weighed = depth > 0.0
    if polygonal is not None:
        weighed &= polygonal
    for index in np.flatnonzero(weighed).tolist():
        first, second = first_shapes[index], second_shapes[index]
        if first is not None or second is not None:
            depth[index] = _polygon_depth(first_poses[index], first_radii[index], first,
                                          second_poses[index], second_radii[index], second)
    return depth


def _polygon_depth(first_pose, first_radius, first, second_pose, second_radius, second):
    if first is None:
        first_pose, first_radius, first, second_pose, second_radius, second = (
            second_pose, second_radius, second, first_pose, first_radius, first)
    polygon = shapely.Polygon(placed(first, first_pose))
    if second is not None:
        return shapely.intersection(polygon, shapely.Polygon(placed(second, second_pose))).area
    centre = shapely.Point(second_pose[0], second_pose[1])
    distance = shapely.distance(centre, polygon.exterior)
    return second_radius + (distance if shapely.contains(polygon, centre) else -distance)


def overlapped(pose: tuple, radius: float, shape, poses: np.ndarray, radii: np.ndarray,
               shapes: list, ignore: int | None = None) -> int | None:
    """Return the index of a body that a body at pose would overlap, or None."""
    close = np.flatnonzero(np.hypot(poses[:, 0] - pose[0], poses[:, 1] - pose[1])
                           < radii + radius)
    close = close[close != ignore] if ignore is not None else close
    if close.size == 0:
        return None
    count = close.size
    depth = depths(np.tile(np.asarray(pose, dtype=float), (count, 1)), np.full(count, radius),
                   [shape] * count, poses[close], radii[close], Picked(shapes, close))
    hits = close[depth > 0.0]
    return int(hits[np.argmax(depth[depth > 0.0])]) if hits.size else None


def moving_into_others(start: np.ndarray, end: np.ndarray, radii: np.ndarray, shapes: list,
                       polygonal: np.ndarray, moving: np.ndarray) -> np.ndarray:
    """
    Return which bodies' steps (start to end poses) would bring them into another, or deeper.

    polygonal says which bodies' shapes are polygons (the others are circles).

    Only bodies that move (moving) can be at fault. Rejecting a step can make another body's
    step the offending one, so the check repeats until no step offends; a body is at fault
    only if its own motion closes the gap.
    """
    count = len(radii)
    rejected = np.zeros(count, dtype=bool)
    if not moving.any() or count < 2:
        return rejected
    if count <= FEW_BODIES:
        pairs = np.column_stack(np.triu_indices(count, 1))
    else:
        longest = float(np.max(np.hypot(*(end[:, :2] - start[:, :2]).T)))
        reach = 2.0 * float(np.max(radii)) + 2.0 * longest
        pairs = cKDTree(start[:, :2]).query_pairs(reach, output_type='ndarray')
    pairs = np.concatenate([pairs, pairs[:, ::-1]])
    mover, other = pairs[moving[pairs[:, 0]]].T

    # Each depth after the mover's step, with the other body where it stands and where it
    # would go, and the same before: only pairs that could come into contact need weighing.
    def depth(mover_poses, other_poses):
        return depths(mover_poses[mover], radii[mover], Picked(shapes, mover),
                      other_poses[other], radii[other], Picked(shapes, other),
                      polygonal[mover] | polygonal[other])

    after_still, after_moved = depth(end, start), depth(end, end)
    close = np.flatnonzero(np.maximum(after_still, after_moved) > 0.0)
    mover, other = mover[close], other[close]
    after_still, after_moved = after_still[close], after_moved[close]
    before_still, before_moved = depth(start, start), depth(start, end)
    while mover.size:
        other_moved = moving[other] & ~rejected[other]
        after = np.where(other_moved, after_moved, after_still)
        before = np.where(other_moved, before_moved, before_still)
        offending = (after > 0.0) & (after > before)
        if not offending.any():
            break
        rejected[mover[offending]] = True
        # A rejected body stays put: its pairs can offend no more.
        keep = ~rejected[mover]
        mover, other = mover[keep], other[keep]
        after_still, after_moved = after_still[keep], after_moved[keep]
        before_still, before_moved = before_still[keep], before_moved[keep]
    return rejected

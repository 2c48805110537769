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

import math

from numba import njit
import numpy as np
import shapely
from stdr_lite.core.footprints import placed


class Picked:
    """The shapes of the bodies picked by index, each looked up only when asked for."""

    def __init__(self, shapes: list, picked: np.ndarray):
        self._shapes, self._picked = shapes, picked

    def __getitem__(self, index: int):
        return self._shapes[self._picked[index]]


def depths(first_poses: np.ndarray, first_radii: np.ndarray, first_shapes: list,
           second_poses: np.ndarray, second_radii: np.ndarray, second_shapes: list,
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


def overlapped(pose: tuple, radius: float, shape: np.ndarray | None, poses: np.ndarray,
               radii: np.ndarray,
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
    only if its own motion closes the gap. Compiled (numba) but for the depths of the pairs
    where a polygon takes part, which shapely measures.
    """
    if not moving.any() or len(radii) < 2:
        return np.zeros(len(radii), dtype=bool)
    mover, other, weighed = _close_pairs(start, end, radii, moving)
    if polygonal.any():
        pairs = np.flatnonzero((polygonal[mover] | polygonal[other])
                               & (weighed.max(axis=1) > 0.0))
        for column, (mover_poses, other_poses) in enumerate(((end, start), (end, end),
                                                             (start, start), (start, end))):
            weighed[pairs, column] = depths(
                mover_poses[mover[pairs]], radii[mover[pairs]], Picked(shapes, mover[pairs]),
                other_poses[other[pairs]], radii[other[pairs]], Picked(shapes, other[pairs]))
    return _rejections(mover, other, weighed, moving)


@njit(cache=True)
def _grown(array, size):
    """Return array with room for size rows, keeping its contents."""
    if size <= array.shape[0]:
        return array
    larger = np.empty((max(size, 2 * array.shape[0]),) + array.shape[1:], dtype=array.dtype)
    larger[:array.shape[0]] = array
    return larger


@njit(cache=True)
def _circle_depth(first, second, radius):
    return radius - math.hypot(first[0] - second[0], first[1] - second[1])


@njit(cache=True)
def _close_pairs(start, end, radii, moving):
    """
    Return the pairs (mover, other) that could come into contact, with their circles' depths.

    Sweep and prune along x finds the bodies within reach of each other (the two largest
    radii and the two longest steps); each pair is kept in the orders whose first body moves
    and whose depth, after the step, is positive with the other where it stands or where it
    goes. The depths' columns: after the step with the other still, and moved; before the
    step, with the other still, and moved.
    """
    count = radii.size
    longest = 0.0
    for body in range(count):
        longest = max(longest, math.hypot(end[body, 0] - start[body, 0],
                                          end[body, 1] - start[body, 1]))
    reach = 2.0 * radii.max() + 2.0 * longest
    order = np.argsort(start[:, 0], kind='mergesort')
    mover = np.empty(64, dtype=np.int64)
    other = np.empty(64, dtype=np.int64)
    weighed = np.empty((64, 4))
    found = 0
    for rank in range(count):
        first = order[rank]
        for later in range(rank + 1, count):
            second = order[later]
            if start[second, 0] - start[first, 0] > reach:
                break
            if abs(start[second, 1] - start[first, 1]) > reach:
                continue
            for one, two in ((first, second), (second, first)):
                if not moving[one]:
                    continue
                radius = radii[one] + radii[two]
                still = _circle_depth(end[one], start[two], radius)
                moved = _circle_depth(end[one], end[two], radius)
                if max(still, moved) <= 0.0:
                    continue
                mover, other = _grown(mover, found + 1), _grown(other, found + 1)
                weighed = _grown(weighed, found + 1)
                mover[found], other[found] = one, two
                weighed[found, 0], weighed[found, 1] = still, moved
                weighed[found, 2] = _circle_depth(start[one], start[two], radius)
                weighed[found, 3] = _circle_depth(start[one], end[two], radius)
                found += 1
    return mover[:found], other[:found], weighed[:found]


@njit(cache=True)
def _rejections(mover, other, weighed, moving):
    """
    Reject, round by round, every step that brings its body into another or deeper.

    In a round each pair weighs the other body where it will be (moved unless its step is
    rejected or it does not move); every offending mover of the round is rejected at once,
    and the rounds go on until none offends.
    """
    rejected = np.zeros(moving.size, dtype=np.bool_)
    offends = np.zeros(moving.size, dtype=np.bool_)
    while True:
        any_offends = False
        for pair in range(mover.size):
            one, two = mover[pair], other[pair]
            if rejected[one]:
                continue
            other_moves = moving[two] and not rejected[two]
            after = weighed[pair, 1] if other_moves else weighed[pair, 0]
            before = weighed[pair, 3] if other_moves else weighed[pair, 2]
            if after > 0.0 and after > before:
                offends[one] = any_offends = True
        if not any_offends:
            return rejected
        rejected |= offends

"""
Rays cast one at a time in compiled code (numba): walls by sphere tracing, bodies exactly.

A laser of 64 rays costs a few microseconds, so a learning loop can read it thousands of
times a second, and a hundred robots' lasers together a fraction of a millisecond. The walls
are met as sensors.py describes: each ray strides by the clearance of the cell it is in (never
less than half a cell) and, once it has crept along a wall for GRAZING_STRIDES strides,
marches on in half-cell steps. Bodies are circles and polygon edges, met exactly; each sensor
looks only at the bodies within its reach. The functions are compiled once and the machine
code is cached beside this file (or in numba's user cache), so later runs load it at once.
"""

import math

from numba import njit
import numpy as np

GRAZING_STRIDES = 4


@njit(cache=True)
def _clearance_at(clearance, column, row, column_rate, row_rate, along):
    """Return the clearance of the cell along metres on a ray; -1 in walls and off the map."""
    height, width = clearance.shape
    at_column = min(max(column + along * column_rate, 0.0), width - 1.0)
    at_row = min(max(row + along * row_rate, 0.0), height - 1.0)
    return clearance[int(at_row), int(at_column)]


@njit(cache=True)
def _wall_distance(clearance, resolution, diagonal, column, row, column_rate, row_rate,
                   max_range):
    """Return the distance along one ray to the first wall, or inf beyond max_range."""
    half_cell = 0.5 * resolution
    travelled = 0.0
    slow_strides = 0
    while True:
        here = _clearance_at(clearance, column, row, column_rate, row_rate, travelled)
        if here < 0.0:
            return travelled
        start = travelled
        travelled = start + max(here, half_cell)
        slow_strides = slow_strides + 1 if here <= half_cell else 0
        if travelled > max_range:
            return math.inf
        if slow_strides >= GRAZING_STRIDES:
            break
    # Grazing: half-cell steps from where the strides left it, as far as the map reaches.
    start = travelled
    reach = min(max_range - start, diagonal) + resolution
    step = 0
    while step * half_cell < reach:
        along = start + step * half_cell
        if along > max_range + half_cell:
            return math.inf
        if _clearance_at(clearance, column, row, column_rate, row_rate, along) < 0.0:
            return along
        step += 1
    return math.inf


@njit(cache=True)
def _circle_distance(x, y, cos_angle, sin_angle, centre_x, centre_y, radius):
    """Return the distance along a ray to a circle ahead of it, or inf."""
    dx, dy = centre_x - x, centre_y - y
    along = dx * cos_angle + dy * sin_angle
    half_chord_squared = radius * radius - (dx * dx + dy * dy - along * along)
    if not half_chord_squared >= 0.0:
        return math.inf
    entry = along - math.sqrt(half_chord_squared)
    return entry if entry >= 0.0 else math.inf


@njit(cache=True)
def _edge_distance(x, y, cos_angle, sin_angle, start_x, start_y, end_x, end_y):
    """Return the distance along a ray to a segment it crosses ahead, or inf."""
    edge_x, edge_y = end_x - start_x, end_y - start_y
    offset_x, offset_y = start_x - x, start_y - y
    denominator = cos_angle * edge_y - sin_angle * edge_x
    if denominator == 0.0:
        return math.inf
    along = (offset_x * edge_y - offset_y * edge_x) / denominator
    where = (offset_x * sin_angle - offset_y * cos_angle) / denominator
    return along if along >= 0.0 and 0.0 <= where <= 1.0 else math.inf


@njit(cache=True)
def _segment_distance(x, y, start_x, start_y, end_x, end_y):
    """Return the distance from (x, y) to the nearest point of a segment."""
    edge_x, edge_y = end_x - start_x, end_y - start_y
    length_squared = edge_x * edge_x + edge_y * edge_y
    where = 0.0
    if length_squared > 0.0:
        where = min(max(((x - start_x) * edge_x + (y - start_y) * edge_y) / length_squared,
                        0.0), 1.0)
    return math.hypot(start_x + where * edge_x - x, start_y + where * edge_y - y)


@njit(cache=True)
def _cast_group(clearance, resolution, origin, diagonal, x, y, max_range, owner, base_angle,
                angles, circles, edges, edge_owners, near_circles, near_edges, out):
    """Cast one sensor's rays from (x, y), at base_angle plus each of angles, into out."""
    origin_x, origin_y, cos_yaw, sin_yaw = origin[0], origin[1], origin[2], origin[3]
    circle_count = 0
    for index in range(circles.shape[0]):
        reach = max_range + circles[index, 2]
        if (index != owner and abs(circles[index, 0] - x) <= reach
                and abs(circles[index, 1] - y) <= reach):
            near_circles[circle_count] = index
            circle_count += 1
    edge_count = 0
    for index in range(edges.shape[0]):
        if edge_owners[index] != owner and _segment_distance(
                x, y, edges[index, 0], edges[index, 1], edges[index, 2],
                edges[index, 3]) <= max_range:
            near_edges[edge_count] = index
            edge_count += 1
    dx, dy = x - origin_x, y - origin_y
    column = (cos_yaw * dx + sin_yaw * dy) / resolution + 1.0
    row = (-sin_yaw * dx + cos_yaw * dy) / resolution + 1.0
    for ray in range(angles.size):
        angle = base_angle + angles[ray]
        cos_angle, sin_angle = math.cos(angle), math.sin(angle)
        nearest = _wall_distance(clearance, resolution, diagonal, column, row,
                                 (cos_yaw * cos_angle + sin_yaw * sin_angle) / resolution,
                                 (-sin_yaw * cos_angle + cos_yaw * sin_angle) / resolution,
                                 max_range)
        for near in range(circle_count):
            index = near_circles[near]
            nearest = min(nearest, _circle_distance(x, y, cos_angle, sin_angle,
                                                    circles[index, 0], circles[index, 1],
                                                    circles[index, 2]))
        for near in range(edge_count):
            index = near_edges[near]
            nearest = min(nearest, _edge_distance(x, y, cos_angle, sin_angle,
                                                  edges[index, 0], edges[index, 1],
                                                  edges[index, 2], edges[index, 3]))
        out[ray] = nearest if nearest <= max_range else math.inf


@njit(cache=True)
def cast_mounted(clearance: np.ndarray, resolution: float, origin: np.ndarray, diagonal: float,
                 poses: np.ndarray, robots: np.ndarray, mounts: np.ndarray,
                 group_starts: np.ndarray, relative: np.ndarray, group_range: np.ndarray,
                 circles: np.ndarray, edges: np.ndarray, edge_owners: np.ndarray) -> np.ndarray:
    """
    Return the distance along each sensor's ray to the first wall or body, inf beyond range.

    Sensor g holds rays group_starts[g] to group_starts[g + 1]; it is mounted at mounts[g]
    (x, y, theta in its body's frame) on body robots[g], whose pose is a row of poses, and its
    rays point at relative angles from its own heading. clearance is the padded grid of
    sensors.RangeFinder, origin its (x, y, cos yaw, sin yaw); circles are (x, y, radius) rows,
    a NaN radius meeting nothing; edges are (start x, start y, end x, end y) rows. A sensor
    ignores its own body's circle and edges.
    """
    distances = np.empty(relative.size)
    near_circles = np.empty(circles.shape[0], dtype=np.int64)
    near_edges = np.empty(edges.shape[0], dtype=np.int64)
    for group in range(group_starts.size - 1):
        robot = robots[group]
        x, y, theta = poses[robot, 0], poses[robot, 1], poses[robot, 2]
        cos_theta, sin_theta = math.cos(theta), math.sin(theta)
        mount_x, mount_y = mounts[group, 0], mounts[group, 1]
        first, last = group_starts[group], group_starts[group + 1]
        _cast_group(clearance, resolution, origin, diagonal,
                    x + cos_theta * mount_x - sin_theta * mount_y,
                    y + sin_theta * mount_x + cos_theta * mount_y, group_range[group], robot,
                    theta + mounts[group, 2], relative[first:last], circles, edges,
                    edge_owners, near_circles, near_edges, distances[first:last])
    return distances

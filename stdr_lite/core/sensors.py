"""
Range sensors, vectorized: every ray of every laser and sonar in one batch.

Walls are found by sphere tracing on a clearance field: each ray advances by the distance to
the nearest occupied cell (never less than half a cell), so it crosses open space in a few
strides and stops within half a cell past the boundary of the first occupied cell it enters.
Other bodies are met exactly: circles, and the edges of polygonal robots. Readings follow
REP-117: no return within max_range is +inf, a return closer than min_range is -inf.
"""

import functools
import math

import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.collision import wall_distances
from stdr_lite.core.footprints import placed
from stdr_lite.core.robot_description import LaserSpec, SonarSpec

GRAZING_STRIDES = 4
SONAR_RAYS = 9
MARCH_POINTS_PER_BATCH = 1 << 22


class RangeFinder:
    """Casts rays against the walls of an occupancy map and against circles."""

    def __init__(self, occupancy_map: OccupancyMap, distances: np.ndarray | None = None):
        """Prepare the casts; distances are the map's wall_distances, if already known."""
        self.resolution = occupancy_map.resolution
        origin_x, origin_y, yaw = occupancy_map.origin
        self._origin = (origin_x, origin_y)
        self._cos_yaw, self._sin_yaw = math.cos(yaw), math.sin(yaw)
        self._height, self._width = occupancy_map.occupied.shape
        self._diagonal = float(np.hypot(*occupancy_map.extent))
        # Centre-to-centre distance to the nearest occupied cell (or the map's edge), less one
        # cell diagonal: no point of this cell is closer than that to any point of an occupied
        # cell.
        if distances is None:
            distances = wall_distances(occupancy_map.occupied)
        # A border of -1 stands for everything outside the map: indices are clipped onto it.
        # Filled in place, term by term: a map of 16 M cells holds several such arrays at once.
        self._clearance = np.full((self._height + 2, self._width + 2), -1.0)
        inside = self._clearance[1:-1, 1:-1]
        np.subtract(distances, math.sqrt(2.0), out=inside)
        np.maximum(inside, 0.0, out=inside)
        inside *= self.resolution
        inside[occupancy_map.occupied] = -1.0

    def cast(self, x: ArrayLike, y: ArrayLike, angle: ArrayLike, max_range: ArrayLike,
             circles: tuple | None = None, edges: tuple | None = None) -> np.ndarray:
        """
        Return the distance along each ray to the first wall or body, inf beyond max_range.

        x, y, angle and max_range broadcast to one value per ray; circles is (cx, cy, radius)
        arrays plus, per ray, the index of a circle to ignore (the robot carrying the sensor),
        or None; edges is (start_x, start_y, end_x, end_y, owner) arrays of polygon edges
        plus, per ray, the owner whose edges it ignores, or None.
        """
        x, y, angle, max_range = (np.array(value, dtype=float).ravel() for value in
                                  np.broadcast_arrays(x, y, angle, max_range))
        distance = self._cast_at_walls(x, y, np.cos(angle), np.sin(angle), max_range)
        if circles is not None:
            distance = np.minimum(distance, _cast_at_circles(x, y, angle, *circles))
        if edges is not None:
            distance = np.minimum(distance, _cast_at_edges(x, y, angle, *edges))
        return np.where(distance <= max_range, distance, np.inf)

    def _cast_at_walls(self, x, y, cos_angle, sin_angle, max_range):
        # Rays in the padded grid's cell coordinates: a point t metres along a ray lies in
        # cell (column + t * column_rate, row + t * row_rate), truncated.
        map_x, map_y = self._to_map_frame(x, y)
        column, row = map_x / self.resolution + 1.0, map_y / self.resolution + 1.0
        column_rate = (self._cos_yaw * cos_angle + self._sin_yaw * sin_angle) / self.resolution
        row_rate = (-self._sin_yaw * cos_angle + self._cos_yaw * sin_angle) / self.resolution
        rays = (column, row, column_rate, row_rate)
        travelled = np.zeros_like(x)
        result = np.full_like(x, np.inf)
        slow_strides = np.zeros(x.size, dtype=np.int64)
        active = np.arange(x.size)
        grazing = []
        half_cell = 0.5 * self.resolution
        while active.size:
            step = travelled[active]
            clearance = self._clearance_along(*(part[active] for part in rays), step)
            hit = clearance < 0.0
            result[active[hit]] = step[hit]
            travelled[active] = step + np.maximum(clearance, half_cell)
            slow_strides[active] = np.where(clearance <= half_cell, slow_strides[active] + 1, 0)
            going = ~hit & (travelled[active] <= max_range[active])
            grazes = going & (slow_strides[active] >= GRAZING_STRIDES)
            grazing.append(active[grazes])
            active = active[going & ~grazes]
        grazing = np.concatenate(grazing)
        if grazing.size:
            result[grazing] = self._march(*(part[grazing] for part in rays),
                                          travelled[grazing], max_range[grazing])
        return result

    def _march(self, column, row, column_rate, row_rate, start, max_range):
        """
        Finish rays that graze a wall in one batch of half-cell steps.

        Sphere tracing would take one loop pass per half cell for them, each pass costing the
        same fixed overhead however few rays remain. Whether a ray grazes depends on its own
        strides only, so a reading never depends on which other rays were cast with it.
        """
        # No ray stays on the map for longer than its diagonal, and rays go in batches, so
        # memory stays bounded whatever the ranges and the number of grazing rays.
        reach = min(float(np.max(max_range - start)), self._diagonal)
        offsets = np.arange(0.0, reach + self.resolution, 0.5 * self.resolution)
        result = np.empty(column.size)
        batch = max(1, MARCH_POINTS_PER_BATCH // offsets.size)
        for first in range(0, column.size, batch):
            rays = slice(first, first + batch)
            along = start[rays, None] + offsets[None, :]
            blocked = self._clearance_along(column[rays, None], row[rays, None],
                                            column_rate[rays, None], row_rate[rays, None],
                                            along) < 0.0
            blocked &= along <= max_range[rays, None] + 0.5 * self.resolution
            hit = np.argmax(blocked, axis=1)
            chosen = np.arange(hit.size)
            result[rays] = np.where(blocked[chosen, hit], along[chosen, hit], np.inf)
        return result

    def _clearance_along(self, column, row, column_rate, row_rate, distance):
        """Clearance of the cells distance along rays; -1 in occupied cells and off the map."""
        columns = np.clip(column + distance * column_rate, 0.0, self._width + 1.0)
        rows = np.clip(row + distance * row_rate, 0.0, self._height + 1.0)
        return self._clearance[rows.astype(np.intp), columns.astype(np.intp)]

    def _to_map_frame(self, x, y):
        dx, dy = x - self._origin[0], y - self._origin[1]
        return (self._cos_yaw * dx + self._sin_yaw * dy,
                -self._sin_yaw * dx + self._cos_yaw * dy)


def _cast_at_circles(x, y, angle, centre_x, centre_y, radius, ignored):
    """Return the distance along each ray to the nearest circle ahead (inf if none)."""
    if len(radius) == 0:
        return np.full(x.shape, np.inf)
    dx = np.asarray(centre_x)[None, :] - x[:, None]
    dy = np.asarray(centre_y)[None, :] - y[:, None]
    along = dx * np.cos(angle)[:, None] + dy * np.sin(angle)[:, None]
    squared_gap = dx ** 2 + dy ** 2 - along ** 2
    half_chord_squared = np.asarray(radius)[None, :] ** 2 - squared_gap
    entry = along - np.sqrt(np.maximum(half_chord_squared, 0.0))
    usable = (half_chord_squared >= 0.0) & (entry >= 0.0)
    if ignored is not None:
        usable[np.arange(x.size), np.asarray(ignored)] = False
    return np.min(np.where(usable, entry, np.inf), axis=1)


def _cast_at_edges(x, y, angle, start_x, start_y, end_x, end_y, owner, ignored):
    """Return the distance along each ray to the nearest edge ahead (inf if none)."""
    if len(owner) == 0:
        return np.full(x.shape, np.inf)
    direction_x, direction_y = np.cos(angle)[:, None], np.sin(angle)[:, None]
    edge_x, edge_y = (end_x - start_x)[None, :], (end_y - start_y)[None, :]
    offset_x, offset_y = start_x[None, :] - x[:, None], start_y[None, :] - y[:, None]
    denominator = direction_x * edge_y - direction_y * edge_x
    with np.errstate(divide='ignore', invalid='ignore'):
        along = (offset_x * edge_y - offset_y * edge_x) / denominator
        where = (offset_x * direction_y - offset_y * direction_x) / denominator
    usable = (denominator != 0.0) & (along >= 0.0) & (where >= 0.0) & (where <= 1.0)
    usable &= np.asarray(owner)[None, :] != np.asarray(ignored)[:, None]
    return np.min(np.where(usable, along, np.inf), axis=1)


def sensor_origin(robot_pose: tuple, sensor_pose: tuple) -> tuple[float, float, float]:
    """Return the world pose (x, y, heading) of a sensor mounted at sensor_pose on a robot."""
    x, y, theta = robot_pose
    offset_x, offset_y, offset_theta = sensor_pose
    cos_theta, sin_theta = math.cos(theta), math.sin(theta)
    return (x + cos_theta * offset_x - sin_theta * offset_y,
            y + sin_theta * offset_x + cos_theta * offset_y, theta + offset_theta)


@functools.lru_cache(maxsize=256)
def relative_angles(spec: LaserSpec | SonarSpec) -> np.ndarray:
    """
    Return the ray angles of a sensor relative to it (read-only, cached per description).

    A laser's rays run from min_angle to max_angle inclusive; a sonar cone is sampled by
    SONAR_RAYS rays across its cone_angle.
    """
    if isinstance(spec, LaserSpec):
        angles = (np.array([spec.min_angle]) if spec.num_rays == 1
                  else np.linspace(spec.min_angle, spec.max_angle, spec.num_rays))
    else:
        angles = np.linspace(-0.5 * spec.cone_angle, 0.5 * spec.cone_angle, SONAR_RAYS)
    angles.flags.writeable = False
    return angles


def apply_noise_and_limits(distances: ArrayLike, means: np.ndarray, stds: np.ndarray,
                           min_ranges: np.ndarray, max_ranges: np.ndarray,
                           rng: np.random.Generator) -> np.ndarray:
    """
    Add Gaussian noise (per reading mean and std) to returns, then mark REP-117 limits.

    Every argument but rng has one value per reading; readings with no return stay +inf.
    """
    distances = np.array(distances, dtype=float)
    returned = np.isfinite(distances)
    distances[returned] += means[returned] + stds[returned] * rng.standard_normal(
        int(returned.sum()))
    distances[returned & (distances > max_ranges)] = np.inf
    distances[returned & (distances < min_ranges)] = -np.inf
    return distances


def read_sensors(finder: RangeFinder, poses: np.ndarray, radii: np.ndarray, shapes: list,
                 jobs: list, rng: np.random.Generator) -> list:
    """
    Read several sensors at once; jobs are (robot index, LaserSpec or SonarSpec) pairs.

    Every body is an obstacle to every sensor but its own robot's: a circle of its radius, or
    the polygon of its shape (corners in its frame; None for a circle). Returns, per job, the
    laser's ranges or the sonar's single range (the nearest return across its cone), noise and
    REP-117 limits applied.
    """
    if not jobs:
        return []
    origins = np.array([sensor_origin(poses[index], spec.pose) for index, spec in jobs])
    relative = [relative_angles(spec) for _, spec in jobs]
    sizes = np.array([angles.size for angles in relative])
    starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    specs = [spec for _, spec in jobs]
    per_job = {name: np.array([getattr(spec, name) for spec in specs])
               for name in ('min_range', 'max_range')}
    owners = np.repeat([index for index, _ in jobs], sizes)
    polygonal = np.array([shape is not None for shape in shapes], dtype=bool)
    # A polygon is met by its edges, not its circle: a NaN radius meets no ray.
    circle_radii = np.where(polygonal, np.nan, radii)
    edges = None
    if polygonal.any():
        corners = [placed(shapes[index], poses[index]) for index in np.flatnonzero(polygonal)]
        ends = [np.roll(points, -1, axis=0) for points in corners]
        edges = (*np.concatenate(corners).T, *np.concatenate(ends).T,
                 np.repeat(np.flatnonzero(polygonal), [len(points) for points in corners]),
                 owners)
    distances = finder.cast(
        np.repeat(origins[:, 0], sizes), np.repeat(origins[:, 1], sizes),
        np.repeat(origins[:, 2], sizes) + np.concatenate(relative),
        np.repeat(per_job['max_range'], sizes),
        circles=(poses[:, 0], poses[:, 1], circle_radii, owners), edges=edges)
    is_laser = np.array([isinstance(spec, LaserSpec) for spec in specs])
    nearest = np.minimum.reduceat(distances, starts)
    means = np.array([spec.noise.mean for spec in specs])
    stds = np.array([spec.noise.std for spec in specs])
    laser_rays = np.repeat(is_laser, sizes)
    laser_values = apply_noise_and_limits(
        distances[laser_rays], *(np.repeat(values, sizes)[laser_rays] for values in (
            means, stds, per_job['min_range'], per_job['max_range'])), rng)
    sonar_values = apply_noise_and_limits(
        nearest[~is_laser], means[~is_laser], stds[~is_laser],
        per_job['min_range'][~is_laser], per_job['max_range'][~is_laser], rng)
    laser_chunks = iter(np.split(laser_values, np.cumsum(sizes[is_laser])[:-1]))
    sonar_readings = iter(sonar_values.tolist())
    return [next(laser_chunks) if laser else next(sonar_readings) for laser in is_laser]

"""
Range sensors, vectorized: every ray of every laser and sonar in one batch.

Walls are found by sphere tracing on a clearance field: each ray advances by the distance to
the nearest occupied cell (never less than half a cell), so it crosses open space in a few
strides and stops within half a cell past the boundary of the first occupied cell it enters.
Other robots are circles, met exactly. Readings follow REP-117: no return within max_range is
+inf, a return closer than min_range is -inf.
"""

import math

import numpy as np
from scipy.ndimage import distance_transform_edt

from stdr_lite.robot_description import LaserSpec

MAX_STRIDES = 400
SONAR_RAYS = 9


class RangeFinder:
    """Casts rays against the walls of an occupancy map and against circles."""

    def __init__(self, occupancy_map):
        self.resolution = occupancy_map.resolution
        origin_x, origin_y, yaw = occupancy_map.origin
        self._origin = (origin_x, origin_y)
        self._cos_yaw, self._sin_yaw = math.cos(yaw), math.sin(yaw)
        self._height, self._width = occupancy_map.occupied.shape
        # Centre-to-centre distance to the nearest occupied cell, less one cell diagonal:
        # no point of this cell is closer than that to any point of an occupied cell.
        cells = distance_transform_edt(~occupancy_map.occupied)
        self._clearance = np.where(occupancy_map.occupied, -1.0,
                                   np.maximum(cells - math.sqrt(2.0), 0.0) * self.resolution)

    def cast(self, x, y, angle, max_range, circles=None):
        """
        Return the distance along each ray to the first wall or circle, inf beyond max_range.

        x, y, angle and max_range broadcast to one value per ray; circles is (cx, cy, radius)
        arrays plus, per ray, the index of a circle to ignore (the robot carrying the sensor),
        or None.
        """
        x, y, angle, max_range = (np.array(value, dtype=float).ravel() for value in
                                  np.broadcast_arrays(x, y, angle, max_range))
        distance = self._cast_at_walls(x, y, np.cos(angle), np.sin(angle), max_range)
        if circles is not None:
            distance = np.minimum(distance, _cast_at_circles(x, y, angle, *circles))
        return np.where(distance <= max_range, distance, np.inf)

    def _cast_at_walls(self, x, y, cos_angle, sin_angle, max_range):
        travelled = np.zeros_like(x)
        result = np.full_like(x, np.inf)
        active = np.arange(x.size)
        half_cell = 0.5 * self.resolution
        for _ in range(MAX_STRIDES):
            if active.size == 0:
                break
            step = travelled[active]
            map_x, map_y = self._to_map_frame(x[active] + step * cos_angle[active],
                                              y[active] + step * sin_angle[active])
            cols = np.floor(map_x / self.resolution).astype(np.int64)
            rows = np.floor(map_y / self.resolution).astype(np.int64)
            inside = (rows >= 0) & (rows < self._height) & (cols >= 0) & (cols < self._width)
            clearance = np.full(active.size, -1.0)
            clearance[inside] = self._clearance[rows[inside], cols[inside]]
            hit = clearance < 0.0
            result[active[hit]] = step[hit]
            travelled[active] = step + np.maximum(clearance, half_cell)
            active = active[~hit & (travelled[active] <= max_range[active])]
        return result

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


def sensor_origin(robot_pose, sensor_pose):
    """Return the world pose (x, y, heading) of a sensor mounted at sensor_pose on a robot."""
    x, y, theta = robot_pose
    offset_x, offset_y, offset_theta = sensor_pose
    cos_theta, sin_theta = math.cos(theta), math.sin(theta)
    return (x + cos_theta * offset_x - sin_theta * offset_y,
            y + sin_theta * offset_x + cos_theta * offset_y, theta + offset_theta)


def laser_angles(spec):
    """Return the ray angles relative to the laser, min_angle to max_angle inclusive."""
    if spec.num_rays == 1:
        return np.array([spec.min_angle])
    return np.linspace(spec.min_angle, spec.max_angle, spec.num_rays)


def sonar_angles(spec):
    """Return the angles of the rays that sample a sonar cone, relative to the sonar."""
    return np.linspace(-0.5 * spec.cone_angle, 0.5 * spec.cone_angle, SONAR_RAYS)


def apply_noise_and_limits(distances, spec, rng):
    """Add the described Gaussian noise to returns, then mark REP-117 out-of-range values."""
    distances = np.array(distances, dtype=float)
    returned = np.isfinite(distances)
    if spec.noise.mean or spec.noise.std:
        distances[returned] += rng.normal(spec.noise.mean, spec.noise.std, returned.sum())
    distances[returned & (distances > spec.max_range)] = np.inf
    distances[returned & (distances < spec.min_range)] = -np.inf
    return distances


def read_sensors(finder, poses, radii, jobs, rng):
    """
    Read several sensors at once; jobs are (robot index, LaserSpec or SonarSpec) pairs.

    Every robot is an obstacle to every sensor but its own. Returns, per job, the laser's
    ranges or the sonar's single range (the nearest return across its cone), noise and
    REP-117 limits applied.
    """
    origins, angles, reaches, owners, sizes = [], [], [], [], []
    for index, spec in jobs:
        x, y, heading = sensor_origin(poses[index], spec.pose)
        relative = laser_angles(spec) if isinstance(spec, LaserSpec) else sonar_angles(spec)
        origins.append(np.broadcast_to([x, y], (relative.size, 2)))
        angles.append(heading + relative)
        reaches.append(np.full(relative.size, spec.max_range))
        owners.append(np.full(relative.size, index))
        sizes.append(relative.size)
    if not jobs:
        return []
    origins = np.concatenate(origins)
    owners = np.concatenate(owners)
    distances = finder.cast(origins[:, 0], origins[:, 1], np.concatenate(angles),
                            np.concatenate(reaches),
                            circles=(poses[:, 0], poses[:, 1], radii, owners))
    readings = []
    for (_, spec), chunk in zip(jobs, np.split(distances, np.cumsum(sizes)[:-1])):
        if isinstance(spec, LaserSpec):
            readings.append(apply_noise_and_limits(chunk, spec, rng))
        else:
            readings.append(float(apply_noise_and_limits([chunk.min()], spec, rng)[0]))
    return readings

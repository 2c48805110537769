"""
Range sensors: every ray of every laser and sonar in one call of the compiled caster.

Walls are found by sphere tracing on a clearance field: each ray advances by the distance to
the nearest occupied cell (never less than half a cell), so it crosses open space in a few
strides and stops within half a cell past the boundary of the first occupied cell it enters
(raycast.py). Other bodies are met exactly: circles, and the edges of polygonal robots.
Readings follow REP-117: no return within max_range is +inf, a return closer than min_range is
-inf.
"""

import functools
import math

from numba import njit
import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.collision import wall_distances
from stdr_lite.core.footprints import placed
from stdr_lite.core.raycast import cast_mounted
from stdr_lite.core.robot_description import LaserSpec, SonarSpec

SONAR_RAYS = 9
_NO_CIRCLES = np.zeros((0, 3))
_NOTHING = np.zeros(0)
_NO_EDGES = (np.zeros((0, 4)), np.zeros(0, dtype=np.int64))


class RangeFinder:
    """Casts rays against the walls of an occupancy map and against bodies (raycast.py)."""

    def __init__(self, occupancy_map: OccupancyMap, distances: np.ndarray | None = None):
        """Prepare the casts; distances are the map's wall_distances, if already known."""
        self.resolution = occupancy_map.resolution
        origin_x, origin_y, yaw = occupancy_map.origin
        self._origin = np.array([origin_x, origin_y, math.cos(yaw), math.sin(yaw)])
        height, width = occupancy_map.occupied.shape
        self._diagonal = float(np.hypot(*occupancy_map.extent))
        # Centre-to-centre distance to the nearest occupied cell (or the map's edge), less one
        # cell diagonal: no point of this cell is closer than that to any point of an occupied
        # cell.
        if distances is None:
            distances = wall_distances(occupancy_map.occupied)
        # A border of -1 stands for everything outside the map: indices are clipped onto it.
        # Filled in place, term by term: a map of 16 M cells holds several such arrays at once.
        self._clearance = np.full((height + 2, width + 2), -1.0)
        inside = self._clearance[1:-1, 1:-1]
        np.subtract(distances, math.sqrt(2.0), out=inside)
        np.maximum(inside, 0.0, out=inside)
        inside *= self.resolution
        inside[occupancy_map.occupied] = -1.0

    def cast_mounted(self, poses: np.ndarray, robots: np.ndarray, mounts: np.ndarray,
                     group_starts: np.ndarray, relative: np.ndarray, max_range: np.ndarray,
                     circles: np.ndarray, edges: np.ndarray,
                     edge_owners: np.ndarray) -> np.ndarray:
        """Cast the rays of sensors mounted on bodies (raycast.cast_mounted says how)."""
        return cast_mounted(self._clearance, self.resolution, self._origin, self._diagonal,
                            np.ascontiguousarray(poses, dtype=float), robots, mounts,
                            group_starts, relative, max_range, circles, edges, edge_owners)


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


def apply_noise_and_limits(distances: ArrayLike, min_ranges: np.ndarray,
                           max_ranges: np.ndarray, means: np.ndarray, stds: np.ndarray,
                           rng: np.random.Generator) -> np.ndarray:
    """
    Add Gaussian noise (per reading mean and std) to returns, then mark REP-117 limits.

    Every argument but rng has one value per reading; readings with no return stay +inf.
    """
    distances = np.array(distances, dtype=float)
    count = _returns(distances)
    _add_noise_and_limits(distances, min_ranges, max_ranges, means, stds,
                          rng.standard_normal(count) if count else _NOTHING)
    return distances


@njit(cache=True)
def _returns(distances):
    """Return how many readings have a return (are finite)."""
    count = 0
    for distance in distances:
        count += math.isfinite(distance)
    return count


@njit(cache=True)
def _add_noise_and_limits(distances, min_ranges, max_ranges, means, stds, draws):
    """Add each return its noise (the draws in order, if any), then mark the limits, in place."""
    drawn = 0
    for reading in range(distances.size):
        if not math.isfinite(distances[reading]):
            continue
        if draws.size:
            distances[reading] += means[reading] + stds[reading] * draws[drawn]
            drawn += 1
        if distances[reading] > max_ranges[reading]:
            distances[reading] = math.inf
        elif distances[reading] < min_ranges[reading]:
            distances[reading] = -math.inf


class ReadingPlan:
    """
    What reading a fixed list of sensors takes, worked out once: their rays, ranges and noise.

    jobs are (robot index, LaserSpec or SonarSpec) pairs. A loop reading the same sensors
    every step (a learning environment, the node between changes of its robots) spends its
    time casting rays, not arranging them.
    """

    def __init__(self, jobs: tuple):
        self.robots = np.array([index for index, _ in jobs], dtype=np.int64)
        specs = [spec for _, spec in jobs]
        relative = [relative_angles(spec) for spec in specs]
        self.sizes = np.array([angles.size for angles in relative])
        self.group_starts = np.concatenate([[0], np.cumsum(self.sizes)])
        self.relative = np.concatenate(relative)
        self.mounts = np.array([spec.pose for spec in specs], dtype=float).reshape(-1, 3)
        self.is_laser = np.array([isinstance(spec, LaserSpec) for spec in specs])
        self.laser_rays = np.repeat(self.is_laser, self.sizes)
        per_job = {name: np.array([value(spec) for spec in specs], dtype=float) for name, value
                   in (('min_range', lambda spec: spec.min_range),
                       ('max_range', lambda spec: spec.max_range),
                       ('mean', lambda spec: spec.noise.mean),
                       ('std', lambda spec: spec.noise.std))}
        self.max_range = per_job['max_range']
        self._laser_limits = [np.repeat(values, self.sizes)[self.laser_rays]
                              for values in per_job.values()]
        self._sonar_limits = [values[~self.is_laser] for values in per_job.values()]
        self._laser_splits = np.cumsum(self.sizes[self.is_laser])[:-1]

    def distances(self, finder: RangeFinder, poses: np.ndarray, radii: np.ndarray,
                  shapes: list, bodies: bool = True) -> np.ndarray:
        """
        Return every ray's distance to the first wall or body (inf beyond its range).

        Without bodies, rays meet the walls only.
        """
        circles, edges, edge_owners = _NO_CIRCLES, *_NO_EDGES
        if bodies and len(poses) > 1:
            polygonal = np.array([shape is not None for shape in shapes], dtype=bool)
            # A polygon is met by its edges, not its circle: a NaN radius meets no ray.
            circles = np.empty((len(poses), 3))
            circles[:, :2] = poses[:, :2]
            circles[:, 2] = radii
            if polygonal.any():
                circles[polygonal, 2] = np.nan
                corners = [placed(shapes[index], poses[index])
                           for index in np.flatnonzero(polygonal)]
                edges = np.concatenate([np.column_stack([points, np.roll(points, -1, axis=0)])
                                        for points in corners])
                edge_owners = np.repeat(np.flatnonzero(polygonal),
                                        [len(points) for points in corners])
        return finder.cast_mounted(poses, self.robots, self.mounts, self.group_starts,
                                   self.relative, self.max_range, circles, edges, edge_owners)

    def read_lasers(self, finder: RangeFinder, poses: np.ndarray, radii: np.ndarray,
                    shapes: list, rng: np.random.Generator, bodies: bool = True) -> np.ndarray:
        """Return the ranges of lasers of one ray count as rows of an array, as read() would."""
        distances = self.distances(finder, poses, radii, shapes, bodies)
        return apply_noise_and_limits(distances, *self._laser_limits, rng).reshape(
            len(self.sizes), -1)

    def read(self, finder: RangeFinder, poses: np.ndarray, radii: np.ndarray, shapes: list,
             rng: np.random.Generator, bodies: bool = True) -> list:
        """Return, per job, the laser's ranges or the sonar's single range, noise applied."""
        distances = self.distances(finder, poses, radii, shapes, bodies)
        laser_values = sonar_values = _NOTHING
        if self.is_laser.any():
            laser_values = apply_noise_and_limits(distances[self.laser_rays],
                                                  *self._laser_limits, rng)
        if not self.is_laser.all():
            nearest = np.minimum.reduceat(distances, self.group_starts[:-1])
            sonar_values = apply_noise_and_limits(nearest[~self.is_laser], *self._sonar_limits,
                                                  rng)
        laser_chunks = iter(np.split(laser_values, self._laser_splits)
                            if len(self._laser_splits) else [laser_values])
        sonar_readings = iter(sonar_values.tolist())
        return [next(laser_chunks) if laser else next(sonar_readings) for laser in self.is_laser]


@functools.lru_cache(maxsize=64)
def reading_plan(jobs: tuple) -> ReadingPlan:
    """Return the plan for reading these sensors, made once for each list of them."""
    return ReadingPlan(jobs)


def read_sensors(finder: RangeFinder, poses: np.ndarray, radii: np.ndarray, shapes: list,
                 jobs: list, rng: np.random.Generator, bodies: bool = True) -> list:
    """
    Read several sensors at once; jobs are (robot index, LaserSpec or SonarSpec) pairs.

    Every body is an obstacle to every sensor but its own robot's: a circle of its radius, or
    the polygon of its shape (corners in its frame; None for a circle). Returns, per job, the
    laser's ranges or the sonar's single range (the nearest return across its cone), noise and
    REP-117 limits applied. Without bodies, sensors see the walls only.
    """
    if not jobs:
        return []
    return reading_plan(tuple(jobs)).read(finder, poses, radii, shapes, rng, bodies)

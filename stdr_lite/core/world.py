"""The simulated world: robot poses in one map, stepped together with numpy."""

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.collision import FootprintChecker
from stdr_lite.core.kinematics import INTEGRATORS, wrap_angle

# Sampling the path at a quarter cell bounds the depth by which a footprint could clip a
# corner between two samples to spacing**2 / (8 * radius): 0.1 mm for the defaults.
SAMPLES_PER_CELL = 4
PATH_POINTS_PER_BATCH = 1 << 16


class PlacementError(ValueError):
    """A pose where a robot cannot stand: off the map, touching a wall or another robot."""

    def __init__(self, message, overlapped=None):
        super().__init__(message)
        self.overlapped = overlapped


class World:
    """
    Poses (x, y, theta) and circular footprints of robots, all stepped at once.

    A step whose footprint would touch an occupied cell or leave the map anywhere along its
    path is rejected whole: the robot keeps x, y and theta and reports zero applied velocity.
    Rotation in place never moves the footprint, so it is always allowed.
    """

    def __init__(self, occupancy_map: OccupancyMap, max_radius: float, integrator: str = 'euler'):
        if integrator not in INTEGRATORS:
            raise ValueError(f'integrator must be one of {", ".join(INTEGRATORS)}, '
                             f'got {integrator!r}')
        self.map = occupancy_map
        self.checker = FootprintChecker(occupancy_map, max_radius)
        self._advance = INTEGRATORS[integrator]
        self._sample_spacing = occupancy_map.resolution / SAMPLES_PER_CELL
        self.poses = np.empty((0, 3))
        self.radii = np.empty(0)

    @property
    def robot_count(self) -> int:
        return len(self.radii)

    def check_placement(self, pose: tuple, radius: float, ignore: int | None = None) -> None:
        """
        Raise PlacementError unless a robot of this radius can stand at pose.

        It must be on the map, clear of walls and clear of every robot but the one numbered
        ignore (the robot being moved).
        """
        x, y, theta = (float(value) for value in pose)
        if not all(math.isfinite(value) for value in (x, y, theta)):
            raise PlacementError(f'pose ({x}, {y}, {theta}) is not finite')
        if radius > self.checker.max_radius:
            raise PlacementError(f'radius {radius} m exceeds the largest supported '
                                 f'{self.checker.max_radius} m')
        map_x, map_y = self.checker.to_map_frame(x, y)
        extent_x, extent_y = self.map.extent
        if not (0.0 <= map_x < extent_x and 0.0 <= map_y < extent_y):
            raise PlacementError(f'position ({x:g}, {y:g}) is off the map')
        if self.checker.touches(x, y, radius):
            raise PlacementError(f'a footprint of radius {radius:g} m at ({x:g}, {y:g}) '
                                 'touches a wall or the map edge')
        gaps = np.hypot(self.poses[:, 0] - x, self.poses[:, 1] - y) - self.radii - radius
        if ignore is not None:
            gaps[ignore] = np.inf
        if np.any(gaps < 0.0):
            other = int(np.argmin(gaps))
            raise PlacementError(f'a footprint of radius {radius:g} m at ({x:g}, {y:g}) '
                                 f'overlaps robot {other}', overlapped=other)

    def add_robot(self, pose: tuple, radius: float) -> int:
        """Place a robot and return its index."""
        self.check_placement(pose, radius)
        self.poses = np.vstack([self.poses, np.asarray(pose, dtype=float)])
        self.radii = np.append(self.radii, float(radius))
        return self.robot_count - 1

    def move_robot(self, index: int, pose: tuple) -> None:
        """Teleport robot index to pose, or raise PlacementError and leave it where it is."""
        self.check_placement(pose, self.radii[index], ignore=index)
        self.poses[index] = np.asarray(pose, dtype=float)

    def remove_robot(self, index: int) -> None:
        """Take robot index out of the world; the robots after it move down one index."""
        self.poses = np.delete(self.poses, index, axis=0)
        self.radii = np.delete(self.radii, index)

    def step(self, linear: ArrayLike, angular: ArrayLike, dt: float,
             travel_headings: ArrayLike | None = None) -> tuple[np.ndarray, np.ndarray]:
        """
        Advance every body by dt under its (linear, angular) velocity.

        A robot drives at linear along its heading while turning at angular (a unicycle). A
        body with a travel heading (NaN for none) slides at linear along that fixed world
        direction while spinning at angular on the spot, as a moving obstacle does.
        Returns the velocities actually applied, which are zero for a blocked body.
        """
        linear = np.asarray(linear, dtype=float)
        angular = np.asarray(angular, dtype=float)
        x, y, theta = self.poses.T
        heading, turn = theta, angular
        if travel_headings is not None:
            sliding = ~np.isnan(np.asarray(travel_headings, dtype=float))
            heading = np.where(sliding, travel_headings, theta)
            turn = np.where(sliding, 0.0, angular)
        moves = ~self._blocked(x, y, heading, linear, turn, dt)
        new_x, new_y, new_theta = self._advance(x, y, heading, linear, turn, dt)
        if travel_headings is not None:
            new_theta = np.where(sliding, wrap_angle(theta + angular * dt), new_theta)
        new_poses = np.column_stack([new_x, new_y, new_theta])
        moves &= ~self._moving_into_robots(new_poses, moves & (linear != 0.0), dt)
        self.poses = np.where(moves[:, None], new_poses, self.poses)
        return np.where(moves, linear, 0.0), np.where(moves, angular, 0.0)

    def _moving_into_robots(self, new_poses, translating, dt):
        """
        Which robots' steps would bring their footprint into another's, or deeper into it.

        Only pairs close enough to touch within a step are examined (a k-d tree finds them).
        Rejecting a step can make another robot's step the offending one, so the check repeats
        until no step offends; a robot is at fault only if its own motion closes the gap.
        """
        rejected = np.zeros(self.robot_count, dtype=bool)
        if not translating.any() or self.robot_count < 2:
            return rejected
        longest = float(np.max(np.hypot(*(new_poses[:, :2] - self.poses[:, :2]).T)))
        reach = 2.0 * float(np.max(self.radii)) + 2.0 * longest
        pairs = cKDTree(self.poses[:, :2]).query_pairs(reach, output_type='ndarray')
        if pairs.size == 0:
            return rejected
        pairs = np.concatenate([pairs, pairs[:, ::-1]])
        mover, other = pairs[:, 0], pairs[:, 1]
        pairs_moving = translating[mover]
        mover, other = mover[pairs_moving], other[pairs_moving]
        contact = self.radii[mover] + self.radii[other]
        while True:
            moved = translating & ~rejected
            positions = np.where(moved[:, None], new_poses[:, :2], self.poses[:, :2])
            before = np.hypot(*(self.poses[mover, :2] - positions[other]).T)
            after = np.hypot(*(new_poses[mover, :2] - positions[other]).T)
            offending = moved[mover] & (after < contact) & (after < before)
            if not offending.any():
                return rejected
            rejected[mover[offending]] = True

    def _blocked(self, x, y, theta, linear, angular, dt):
        """Check the footprint along the path of each robot translating near a wall."""
        blocked = np.zeros(self.robot_count, dtype=bool)
        step_length = np.abs(linear) * dt
        suspect = np.flatnonzero((linear != 0.0)
                                 & ~self.checker.clear_for_motion(x, y, step_length))
        if suspect.size == 0:
            return blocked
        samples = max(1, math.ceil(float(np.max(step_length[suspect])) / self._sample_spacing))
        # The path is checked from its start in batches of points, so memory stays bounded
        # whatever the speed; a robot is dropped from later batches once it is blocked.
        first = 1
        while suspect.size and first <= samples:
            count = max(1, PATH_POINTS_PER_BATCH // suspect.size)
            fractions = np.arange(first, min(first + count, samples + 1)) / samples
            index = suspect[:, None]
            path_x, path_y, _ = self._advance(x[index], y[index], theta[index], linear[index],
                                              angular[index], dt * fractions[None, :])
            hit = np.any(self.checker.touches(path_x, path_y, self.radii[index]), axis=1)
            blocked[suspect[hit]] = True
            suspect = suspect[~hit]
            first += count
        return blocked

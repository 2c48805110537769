"""The simulated world: robot poses in one map, stepped together with numpy."""

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy.spatial import cKDTree
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.collision import FootprintChecker
from stdr_lite.core.kinematics import INTEGRATORS, INTEGRATORS_ONE, wrap_angle, wrap_angle_one

# Sampling the path at a quarter cell bounds the depth by which a footprint could clip a
# corner between two samples to spacing**2 / (8 * radius): 0.1 mm for the defaults.
SAMPLES_PER_CELL = 4
PATH_POINTS_PER_BATCH = 1 << 16
# Up to this many bodies a step goes body by body in plain Python, which for so few costs less
# than numpy's per-call overhead; both ways give the same poses to the last bit.
FEW_BODIES = 8
REMEMBERED_STEPS = 1024


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

    def __init__(self, occupancy_map: OccupancyMap, max_radius: float, integrator: str = 'euler',
                 checker: FootprintChecker | None = None):
        """Make an empty world; checker, if given, is the map's, made for max_radius."""
        if integrator not in INTEGRATORS:
            raise ValueError(f'integrator must be one of {", ".join(INTEGRATORS)}, '
                             f'got {integrator!r}')
        self.map = occupancy_map
        self.checker = checker or FootprintChecker(occupancy_map, max_radius)
        self._advance = INTEGRATORS[integrator]
        self._advance_one = INTEGRATORS_ONE[integrator]
        self._blocked_steps = {}
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
        if self.robot_count <= FEW_BODIES:
            return self._step_few(linear, angular, dt, travel_headings)
        linear = np.asarray(linear, dtype=float)
        angular = np.asarray(angular, dtype=float)
        x, y, theta = self.poses.T
        heading, turn = theta, angular
        if travel_headings is not None:
            sliding = ~np.isnan(np.asarray(travel_headings, dtype=float))
            heading = np.where(sliding, travel_headings, theta)
            turn = np.where(sliding, 0.0, angular)
        moves = ~self._blocked(x, y, heading, linear, turn, dt, self.radii)
        new_x, new_y, new_theta = self._advance(x, y, heading, linear, turn, dt)
        if travel_headings is not None:
            new_theta = np.where(sliding, wrap_angle(theta + angular * dt), new_theta)
        new_poses = np.column_stack([new_x, new_y, new_theta])
        moves &= ~self._moving_into_robots(new_poses, moves & (linear != 0.0), dt)
        self.poses = np.where(moves[:, None], new_poses, self.poses)
        return np.where(moves, linear, 0.0), np.where(moves, angular, 0.0)

    def _step_few(self, linear, angular, dt, travel_headings):
        """Take the same step as the vectorised code, one body at a time."""
        linear = [float(value) for value in linear]
        angular = [float(value) for value in angular]
        headings = ([math.nan] * self.robot_count if travel_headings is None
                    else [float(value) for value in travel_headings])
        bodies = zip(self.poses.tolist(), linear, angular, headings, self.radii.tolist())
        ends, moves = [], []
        for (x, y, theta), v, omega, travel, radius in bodies:
            sliding = not math.isnan(travel)
            heading, turn = (travel, 0.0) if sliding else (theta, omega)
            end = self._advance_one(x, y, heading, v, turn, dt)
            if sliding:
                end = (end[0], end[1], wrap_angle_one(theta + omega * dt))
            ends.append(end)
            moves.append(v == 0.0 or self.checker.clear_for_motion_one(x, y, abs(v) * dt, radius)
                         or not self._wall_blocks_one(x, y, heading, v, turn, dt, radius))
        moves = np.array(moves)
        linear, angular = np.array(linear), np.array(angular)
        new_poses = np.array(ends)
        if self.robot_count > 1:
            moves &= ~self._moving_into_robots(new_poses, moves & (linear != 0.0), dt)
        if moves.all():
            self.poses = new_poses
            return linear, angular
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
        start, end = self.poses[:, :2], new_poses[:, :2]
        if self.robot_count <= FEW_BODIES:
            pairs = np.column_stack(np.triu_indices(self.robot_count, 1))
        else:
            longest = float(np.max(np.hypot(*(end - start).T)))
            reach = 2.0 * float(np.max(self.radii)) + 2.0 * longest
            pairs = cKDTree(start).query_pairs(reach, output_type='ndarray')
        pairs = np.concatenate([pairs, pairs[:, ::-1]])
        mover, other = pairs[translating[pairs[:, 0]]].T
        contact = self.radii[mover] + self.radii[other]
        # Each gap, before and after the mover's step, with the other robot where it stands
        # and where it would go: only pairs that could come into contact need looking at.
        (start_x, start_y), (end_x, end_y) = start.T.copy(), end.T.copy()
        after_still = np.hypot(end_x[mover] - start_x[other], end_y[mover] - start_y[other])
        after_moved = np.hypot(end_x[mover] - end_x[other], end_y[mover] - end_y[other])
        close = np.minimum(after_still, after_moved) < contact
        mover, other, contact = mover[close], other[close], contact[close]
        after_still, after_moved = after_still[close], after_moved[close]
        before_still = np.hypot(start_x[mover] - start_x[other], start_y[mover] - start_y[other])
        before_moved = np.hypot(start_x[mover] - end_x[other], start_y[mover] - end_y[other])
        while mover.size:
            other_moved = translating[other] & ~rejected[other]
            after = np.where(other_moved, after_moved, after_still)
            before = np.where(other_moved, before_moved, before_still)
            offending = (after < contact) & (after < before)
            if not offending.any():
                break
            rejected[mover[offending]] = True
            # A rejected robot stays put: its pairs can offend no more.
            keep = ~rejected[mover]
            mover, other, contact = mover[keep], other[keep], contact[keep]
            after_still, after_moved = after_still[keep], after_moved[keep]
            before_still, before_moved = before_still[keep], before_moved[keep]
        return rejected

    def _blocked(self, x, y, theta, linear, angular, dt, radii):
        """
        Check the footprint along the path of each robot translating near a wall.

        Each path is sampled at SAMPLES_PER_CELL points per cell of its own length, from its
        start, in batches of points so memory stays bounded whatever the speed; a robot is
        dropped from later batches once it is blocked.
        """
        blocked = np.zeros(len(radii), dtype=bool)
        step_length = np.abs(linear) * dt
        suspect = np.flatnonzero((linear != 0.0) & ~self.checker.clear_for_motion(
            x, y, step_length, radii))
        if suspect.size == 0:
            return blocked
        samples = np.maximum(1, np.ceil(step_length[suspect] / self._sample_spacing))
        first = 1
        while suspect.size and first <= samples.max():
            count = max(1, PATH_POINTS_PER_BATCH // suspect.size)
            taken = np.arange(first, min(first + count, samples.max() + 1))
            fractions = taken[None, :] / samples[:, None]
            index = suspect[:, None]
            path_x, path_y, _ = self._advance(x[index], y[index], theta[index], linear[index],
                                              angular[index], dt * fractions)
            hit = np.any(self.checker.touches(path_x, path_y, radii[index])
                         & (fractions <= 1.0), axis=1)
            blocked[suspect[hit]] = True
            suspect, samples = suspect[~hit], samples[~hit]
            first += count
        return blocked

    def _wall_blocks_one(self, x, y, heading, linear, turn, dt, radius):
        """
        Whether walls block one body's step, remembered for the pose and motion.

        A body pushing against a wall asks the same question step after step: the answer,
        which depends on nothing else, is looked up instead of worked out again.
        """
        key = (x, y, heading, linear, turn, dt, radius)
        blocked = self._blocked_steps.get(key)
        if blocked is None:
            body = [np.array([value]) for value in (x, y, heading, linear, turn)]
            blocked = bool(self._blocked(*body, dt, np.array([radius]))[0])
            if len(self._blocked_steps) >= REMEMBERED_STEPS:
                self._blocked_steps.clear()
            self._blocked_steps[key] = blocked
        return blocked

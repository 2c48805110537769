"""The simulated world: bodies moving in one map and meeting, stepped together with numpy."""

import math

import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.pose import wrap_angle
from stdr_lite.core.collision import FootprintChecker
from stdr_lite.core.contacts import moving_into_others, overlapped
from stdr_lite.core.entities import SimulatedEntity
from stdr_lite.core.kinematics import INTEGRATORS, INTEGRATORS_ONE
from stdr_lite.core.state import WorldState

# Sampling the path so that no point of a footprint moves more than a quarter cell between
# samples bounds the depth by which it could clip a corner between two samples to
# spacing**2 / (8 * radius) for a circle: 0.1 mm for the defaults.
SAMPLES_PER_CELL = 4
PATH_POINTS_PER_BATCH = 1 << 16
# Up to this many bodies a step goes body by body in plain Python, which for so few costs less
# than numpy's per-call overhead; both ways give the same poses to the last bit.
FEW_BODIES = 8
REMEMBERED_STEPS = 1024


class PlacementError(ValueError):
    """A pose where a body cannot stand: off the map, touching a wall or another body."""


class World:
    """
    Bodies of a WorldState moved in a map: placed, teleported, stepped all at once.

    A footprint is a circle of its radius, or a polygon (shape: its corners in the body's
    frame, radius then its farthest corner's distance). A step whose footprint would touch an
    occupied cell or leave the map anywhere along its path is rejected whole: the body keeps
    x, y and theta. Rotation in place never moves a circle, so it is always allowed; a polygon
    sweeps as it turns, and turning into a wall is rejected like driving into it.
    """

    def __init__(self, occupancy_map: OccupancyMap, max_radius: float, integrator: str = 'euler',
                 checker: FootprintChecker | None = None, bodies_meet: bool = True,
                 state: WorldState | None = None):
        """
        Make a world of the bodies of state (none by default); checker is the map's, if given.

        Bodies that do not meet pass through each other and may stand on each other: each
        meets the walls only, as if alone (independent episodes of learning, side by side).
        """
        self.bodies_meet = bodies_meet
        if integrator not in INTEGRATORS:
            raise ValueError(f'integrator must be one of {", ".join(INTEGRATORS)}, '
                             f'got {integrator!r}')
        self.map = occupancy_map
        self.checker = checker or FootprintChecker(occupancy_map, max_radius)
        self._advance = INTEGRATORS[integrator]
        self._advance_one = INTEGRATORS_ONE[integrator]
        self._blocked_steps = {}
        self._sample_spacing = occupancy_map.resolution / SAMPLES_PER_CELL
        self.state = WorldState() if state is None else state

    @property
    def poses(self) -> np.ndarray:
        """Return the bodies' (x, y, theta), a row each."""
        return self.state.pose

    @property
    def radii(self) -> np.ndarray:
        return self.state.radius

    @property
    def shapes(self) -> list:
        return self.state.shapes

    @property
    def body_count(self) -> int:
        return len(self.state)

    def check_placement(self, pose: tuple, radius: float, ignore: int | None = None,
                        shape: tuple | None = None) -> None:
        """
        Raise PlacementError unless a body of this footprint can stand at pose.

        It must be on the map, clear of walls and clear of every body but the one numbered
        ignore (the body being moved).
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
        footprint = (f'a footprint of radius {radius:g} m' if shape is None
                     else f'a footprint of {len(shape)} corners')
        touches = (self.checker.touches(x, y, radius) if shape is None
                   else self.checker.polygon_touches(x, y, theta, shape)[0])
        if touches:
            raise PlacementError(f'{footprint} at ({x:g}, {y:g}) touches a wall or the map edge')
        other = overlapped((x, y, theta), radius, shape, self.poses, self.radii, self.shapes,
                           ignore) if self.bodies_meet else None
        if other is not None:
            raise PlacementError(f'{footprint} at ({x:g}, {y:g}) overlaps '
                                 f'{self.state.name_of(other)}')

    def add_body(self, pose: tuple, radius: float, shape: tuple | None = None,
                 entity: SimulatedEntity | None = None) -> int:
        """
        Place a body (of entity, or a bare one) and return its row of the state.

        shape is a polygon's corners, None for a circle; a polygon's radius is that of the
        circle round it, which every broad check relies on. PlacementError if it cannot stand
        at pose; nothing changes then.
        """
        if shape is not None and radius < float(np.max(np.hypot(*np.asarray(shape).T))):
            raise ValueError(f'radius {radius:g} m does not reach the farthest corner')
        self.check_placement(pose, radius, shape=shape)
        return self.state.append(pose, float(radius), shape, entity)

    def move_body(self, index: int, pose: tuple) -> None:
        """Teleport body index to pose, or raise PlacementError and leave it where it is."""
        self.check_placement(pose, self.radii[index], ignore=index, shape=self.shapes[index])
        self.state.pose[index] = np.asarray(pose, dtype=float)

    def remove_body(self, index: int) -> None:
        """Take body index out of the world; the bodies after it move down one row."""
        self.state.remove(index)

    def step(self, linear: ArrayLike, angular: ArrayLike, dt: float,
             travel_headings: ArrayLike | None = None,
             lateral: ArrayLike | None = None) -> np.ndarray:
        """
        Advance every body by dt; return which bodies moved (the others were blocked).

        A robot drives at linear along its heading and at lateral (an omni robot's, else
        none) to its left, while turning at angular. A body with a travel heading (NaN for
        none) slides at linear along that fixed world direction while spinning at angular on
        the spot, as a moving obstacle does.
        """
        linear = np.asarray(linear, dtype=float)
        angular = np.asarray(angular, dtype=float)
        theta = self.poses[:, 2]
        heading, speed, turn = _translations(theta, linear, angular, travel_headings, lateral)
        if self.body_count <= FEW_BODIES:
            return self._step_few(heading, speed, turn, angular, dt)
        x, y = self.poses[:, 0], self.poses[:, 1]
        moves = ~self._blocked(np.arange(self.body_count), dt, x, y, heading, speed, turn,
                               theta, angular)
        new_x, new_y, _ = self._advance(x, y, heading, speed, turn, dt)
        new_poses = np.column_stack([new_x, new_y, wrap_angle(theta + angular * dt)])
        if self.bodies_meet:
            moves &= ~moving_into_others(self.poses, new_poses, self.radii, self.shapes,
                                         self.state.polygonal,
                                         moves & self._changes_footprint(speed, angular))
        self.state.pose = np.where(moves[:, None], new_poses, self.poses)
        return moves

    def _changes_footprint(self, speed, angular):
        """Whether each body's step moves its footprint: a circle's turn does not."""
        return (speed != 0.0) | (self.state.polygonal & (angular != 0.0))

    def _step_few(self, heading, speed, turn, angular, dt):
        """Take the same step as the vectorised code, one body at a time."""
        bodies = zip(self.poses.tolist(), heading.tolist(), speed.tolist(), turn.tolist(),
                     angular.tolist(), self.radii.tolist(), self.shapes)
        ends, moves = [], []
        for index, ((x, y, theta), direction, v, bend, omega, radius, shape) in enumerate(bodies):
            end = self._advance_one(x, y, direction, v, bend, dt)
            ends.append((end[0], end[1], wrap_angle(theta + omega * dt)))
            still = v == 0.0 and (shape is None or omega == 0.0)
            moves.append(still or self.checker.clear_for_motion_one(x, y, abs(v) * dt, radius)
                         or not self._wall_blocks_one(index, (x, y, direction, v, bend, theta,
                                                              omega), dt))
        moves = np.array(moves, dtype=bool)
        new_poses = np.array(ends, dtype=float).reshape(-1, 3)
        if self.body_count > 1 and self.bodies_meet:
            moves &= ~moving_into_others(self.poses, new_poses, self.radii, self.shapes,
                                         self.state.polygonal,
                                         moves & self._changes_footprint(speed, angular))
        self.state.pose = np.where(moves[:, None], new_poses, self.poses)
        return moves

    def _blocked(self, bodies, dt, x, y, heading, speed, turn, theta, angular):
        """
        Check the footprint along the path of each of bodies moving near a wall.

        The other arguments hold one value per body of bodies. Each path is sampled so that
        no point of the footprint moves more than a quarter cell between samples, from its
        start; circles go together in batches of points so memory stays bounded whatever the
        speed, and a body is dropped from later batches once it is blocked. Polygons, each of
        its own shape, go one at a time.
        """
        radii, polygonal = self.radii[bodies], self.state.polygonal[bodies]
        blocked = np.zeros(len(bodies), dtype=bool)
        step_length = np.abs(speed) * dt
        moving = (speed != 0.0) | (polygonal & (angular != 0.0))
        clear = self.checker.clear_for_motion(x, y, step_length, radii)
        suspect = np.flatnonzero(moving & ~clear)
        for index in suspect[polygonal[suspect]]:
            sweep = step_length[index] + abs(angular[index]) * dt * radii[index]
            fractions = np.arange(1, max(1, math.ceil(sweep / self._sample_spacing)) + 1)
            fractions = fractions / fractions[-1]
            path_x, path_y, _ = self._advance(x[index], y[index], heading[index], speed[index],
                                              turn[index], dt * fractions)
            blocked[index] = self.checker.polygon_touches(
                path_x, path_y, theta[index] + angular[index] * dt * fractions,
                self.shapes[bodies[index]]).any()
        suspect = suspect[~polygonal[suspect]]
        if suspect.size == 0:
            return blocked
        samples = np.maximum(1, np.ceil(step_length[suspect] / self._sample_spacing))
        first = 1
        while suspect.size and first <= samples.max():
            count = max(1, PATH_POINTS_PER_BATCH // suspect.size)
            taken = np.arange(first, min(first + count, samples.max() + 1))
            fractions = taken[None, :] / samples[:, None]
            index = suspect[:, None]
            path_x, path_y, _ = self._advance(x[index], y[index], heading[index], speed[index],
                                              turn[index], dt * fractions)
            hit = np.any(self.checker.touches(path_x, path_y, radii[index])
                         & (fractions <= 1.0), axis=1)
            blocked[suspect[hit]] = True
            suspect, samples = suspect[~hit], samples[~hit]
            first += count
        return blocked

    def _wall_blocks_one(self, index, motion, dt):
        """
        Whether walls block one body's step, remembered for the pose, motion and footprint.

        A body pushing against a wall asks the same question step after step: the answer,
        which depends on nothing else, is looked up instead of worked out again.
        """
        key = (*motion, dt, self.radii[index], self.shapes[index])
        blocked = self._blocked_steps.get(key)
        if blocked is None:
            blocked = bool(self._blocked(np.array([index]), dt,
                                         *(np.array([value]) for value in motion))[0])
            if len(self._blocked_steps) >= REMEMBERED_STEPS:
                self._blocked_steps.clear()
            self._blocked_steps[key] = blocked
        return blocked


def _translations(theta, linear, angular, travel_headings, lateral):
    """
    Return each body's translation as a unicycle's: its direction, speed and turn rate.

    An omni robot's sideways part turns the direction of travel off its heading; a sliding
    body keeps its travel heading and does not turn while it translates.
    """
    heading, speed, turn = theta, linear, angular
    if lateral is not None:
        lateral = np.asarray(lateral, dtype=float)
        sideways = lateral != 0.0
        if sideways.any():
            heading = np.where(sideways, theta + np.arctan2(lateral, linear), theta)
            speed = np.where(sideways, np.hypot(linear, lateral), linear)
    if travel_headings is not None:
        travel_headings = np.asarray(travel_headings, dtype=float)
        sliding = ~np.isnan(travel_headings)
        heading = np.where(sliding, travel_headings, heading)
        turn = np.where(sliding, 0.0, angular)
    return heading, speed, turn

"""The simulated world: bodies moving in one map and meeting, stepped in one compiled pass."""

import math

from numba import njit
import numpy as np
from numpy.typing import ArrayLike
from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.collision import circle_touches, clear_at, FootprintChecker
from stdr_lite.core.contacts import moving_into_others, overlapped
from stdr_lite.core.entities import SimulatedEntity
from stdr_lite.core.kinematics import integrate, INTEGRATORS, wrap
from stdr_lite.core.setting_values import ARC
from stdr_lite.core.state import StateTable

# Sampling the path so that no point of a footprint moves more than a quarter cell between
# samples bounds the depth by which it could clip a corner between two samples to
# spacing**2 / (8 * radius) for a circle: 0.1 mm for the defaults.
SAMPLES_PER_CELL = 4


class PlacementError(ValueError):
    """A pose where a body cannot stand: off the map, touching a wall or another body."""


class Bodies:
    """
    Bodies of a StateTable moved in a map: placed, teleported, stepped all at once.

    A footprint is a circle of its radius, or a polygon (shape: its corners in the body's
    frame, radius then its farthest corner's distance). A step whose footprint would touch an
    occupied cell or leave the map anywhere along its path is rejected whole: the body keeps
    x, y and theta. Rotation in place never moves a circle, so it is always allowed; a polygon
    sweeps as it turns, and turning into a wall is rejected like driving into it.
    """

    def __init__(self, occupancy_map: OccupancyMap, max_radius: float, integrator: str = 'euler',
                 checker: FootprintChecker | None = None, bodies_meet: bool = True,
                 state: StateTable | None = None):
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
        self._integrator = INTEGRATORS[integrator]
        self._arc = integrator == ARC
        # What a step works out for each body (see _advance), allocated again only when the
        # number of bodies changes.
        self._step_rows, self._moves = np.empty((0, 7)), np.empty(0, dtype=bool)
        self._sample_spacing = occupancy_map.resolution / SAMPLES_PER_CELL
        self.state = StateTable() if state is None else state

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
        the spot, as a moving obstacle does. Compiled in one pass over the bodies (numba), but
        for polygons near a wall and the depths of polygons in contact, weighed in numpy and
        shapely.
        """
        count = self.body_count
        linear, angular = _column(linear, count), _column(angular, count)
        lateral = _column(0.0 if lateral is None else lateral, count)
        travel = _column(np.nan if travel_headings is None else travel_headings, count)
        if self._step_rows.shape[0] != count:
            self._step_rows, self._moves = np.empty((count, 7)), np.empty(count, dtype=bool)
        new_poses, motion, moves = self._step_rows[:, :3], self._step_rows[:, 3:6], self._moves
        polygons_near_walls = _advance(
            self.poses, self.radii, self.state.polygonal, linear, lateral, angular, travel,
            float(dt), self._arc, self._sample_spacing, self._step_rows, moves,
            *self.checker.grid)
        if polygons_near_walls:
            for index in np.flatnonzero(self._step_rows[:, 6] == POLYGON_NEAR_WALL):
                moves[index] = not self._polygon_blocked(index, motion[index], angular[index],
                                                         dt)
        if self.bodies_meet and count > 1:
            changes = (motion[:, 1] != 0.0) | (self.state.polygonal & (angular != 0.0))
            moves &= ~moving_into_others(self.poses, new_poses, self.radii, self.shapes,
                                         self.state.polygonal, moves & changes)
        self.state.pose = np.where(moves[:, None], new_poses, self.poses)
        return moves.copy()

    def _polygon_blocked(self, index, motion, angular, dt):
        """
        Check a polygon's footprint along its path near a wall.

        The path is sampled so that no point of the footprint moves more than a quarter cell
        between samples, from its start; its turn sweeps its corners too.
        """
        heading, speed, turn = motion
        x, y, theta = self.poses[index]
        radius = self.radii[index]
        sweep = abs(speed) * dt + abs(angular) * dt * radius
        fractions = np.arange(1, max(1, math.ceil(sweep / self._sample_spacing)) + 1)
        fractions = fractions / fractions[-1]
        path_x, path_y, _ = self._integrator(x, y, heading, speed, turn, dt * fractions)
        return bool(self.checker.polygon_touches(path_x, path_y, theta + angular * dt * fractions,
                                                 self.shapes[index]).any())


def _column(values, count):
    """Return values (one, or one per body) as a contiguous column of count floats."""
    column = np.asarray(values, dtype=float)
    return np.ascontiguousarray(column if column.shape == (count,) else np.full(count, column))


# What the compiled step makes of each body: it moves, walls block it, or it is a polygon near
# a wall that the Bodies weigh (polygon_touches).
MOVES, BLOCKED, POLYGON_NEAR_WALL = 0, 1, 2


@njit(cache=True)
def _advance(poses, radii, polygonal, linear, lateral, angular, travel, dt, arc, sample_spacing,
             rows, moves, *grid):
    """
    Work out every body's step; return how many are polygons near a wall, left to the caller.

    Each body's row of rows gets its pose after dt, its translation (heading, speed, turn)
    and its verdict (MOVES, BLOCKED, POLYGON_NEAR_WALL); moves whether it moves (a polygon
    near a wall does, unless the caller finds otherwise). An omni robot's sideways part turns
    the direction of travel off its heading; a sliding body (a travel heading, not NaN) keeps
    that direction and does not turn while it translates. A circle near a wall is checked along
    its path, sampled so that no point of it moves more than sample_spacing between samples; a
    circle's turn on the spot never moves it.
    """
    polygons_near_walls = 0
    for body in range(radii.size):
        x, y, theta = poses[body, 0], poses[body, 1], poses[body, 2]
        heading, speed, turn = theta, linear[body], angular[body]
        if lateral[body] != 0.0:
            heading = theta + math.atan2(lateral[body], linear[body])
            speed = math.hypot(linear[body], lateral[body])
        if not math.isnan(travel[body]):
            heading, turn = travel[body], 0.0
        rows[body, 0], rows[body, 1], _ = integrate(x, y, heading, speed, turn, dt, arc)
        rows[body, 2] = wrap(theta + angular[body] * dt)
        rows[body, 3], rows[body, 4], rows[body, 5] = heading, speed, turn
        rows[body, 6] = _verdict(grid, x, y, heading, speed, turn, angular[body], radii[body],
                                 polygonal[body], dt, arc, sample_spacing)
        moves[body] = rows[body, 6] != BLOCKED
        polygons_near_walls += rows[body, 6] == POLYGON_NEAR_WALL
    return polygons_near_walls


@njit(cache=True)
def _verdict(grid, x, y, heading, speed, turn, angular, radius, polygonal, dt, arc,
             sample_spacing):
    step_length = abs(speed) * dt
    if not (math.isfinite(step_length) and math.isfinite(angular)):
        return BLOCKED  # no path to sample: the Bodies used directly, unchecked
    if not (speed != 0.0 or (polygonal and angular != 0.0)):
        return MOVES
    if clear_at(grid, x, y, step_length + radius):
        return MOVES
    if polygonal:
        return POLYGON_NEAR_WALL
    samples = max(1, math.ceil(step_length / sample_spacing))
    for sample in range(1, samples + 1):
        path_x, path_y, _ = integrate(x, y, heading, speed, turn, dt * (sample / samples), arc)
        if circle_touches(grid, path_x, path_y, radius):
            return BLOCKED
    return MOVES

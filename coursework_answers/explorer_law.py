"""
The reference explorer's law: the nearest frontier until none is left, then the goals. No ROS.

A RouteLaw (route_law.py) whose route leads first to the frontier of its map nearest by a
drivable path (frontiers.py: Yamauchi's frontier-based exploration), then to the next, as long
as a frontier is left and explore_for seconds of odometry time have not passed; then to the
course's goals, as the planner-controller drives them. A frontier counts as reached within
PASS_DISTANCE, or once the map no longer shows it as a frontier (seen from afar); one reached,
and one the route planner finds no way to, is given up with the frontier cells around it.
"""

from collections.abc import Sequence
import math

from coursework_answers.frontiers import frontier_cells, nearest_frontier
from coursework_answers.route_law import Pose, RouteLaw
from courseworks.grids import read_cells
import numpy as np
from simple_robot_control.occupancy_map import OccupancyMap
from waypoint_controller.config import ControllerConfig
from waypoint_lab.waypoints import Waypoint

# A frontier is reached this close (the laser sees 4 m on: no need to stand on it); one given
# up takes the frontier cells this close to it along.
PASS_DISTANCE = 0.3
GIVE_UP_DISTANCE = 0.5


class ExplorerLaw(RouteLaw):
    """Explores its map's frontiers first (see the module), then drives the course's goals."""

    def __init__(self, goals: Sequence[Waypoint], radius: float, margin: float,
                 config: ControllerConfig = ControllerConfig(), explore_for: float = math.inf):
        super().__init__(goals, radius, margin, config)
        self.explore_for = explore_for
        self.exploring = True
        self._map = self._frontier_cells = self._given_up = None
        self._frontier = None
        self._elapsed = 0.0

    def use_map(self, occupancy_map: OccupancyMap) -> None:
        super().use_map(occupancy_map)
        self._map = occupancy_map
        self._frontier_cells = None
        if self._given_up is None or self._given_up.shape != occupancy_map.cells.shape:
            self._given_up = np.zeros(occupancy_map.cells.shape, dtype=bool)

    def target(self, pose: Pose) -> Pose:
        """Return the nearest frontier while exploring (here, until a map knows free space)."""
        self._frontier = None
        if self.exploring:
            if not self._knows_free():
                return pose
            self._frontier = nearest_frontier(self._map.cells, self._map.resolution,
                                              tuple(self._map.origin[:2]), pose[:2],
                                              self.radius, self._given_up)
            if self._frontier is not None:
                return (*self._frontier, pose[2])
            self.exploring = False
        return super().target(pose)

    def _plan(self, pose):
        """Plan to the frontier, giving up those no route reaches; to the goals once none is."""
        super()._plan(pose)
        while self.exploring and not self.reachable and self._frontier is not None:
            self._give_up(self._frontier)
            super()._plan(pose)

    def command(self, pose: Pose, dt: float) -> tuple[float, float]:
        """Drive to the frontier, choosing the next once it is reached or seen; then the goals."""
        self._elapsed += dt
        if self.exploring and self._index is not None and self._frontier_done(pose):
            if self._elapsed >= self.explore_for:
                self.exploring = False
            self._plan(pose)
        return super().command(pose, dt)

    def _frontier_done(self, pose):
        if self._frontier is None:
            return self._knows_free()
        x, y = self._frontier
        if math.hypot(x - pose[0], y - pose[1]) < PASS_DISTANCE:
            # Reached: whatever stays unknown there (behind the robot, out of the laser's
            # field) is no longer worth a trip.
            self._give_up(self._frontier)
            return True
        if self._frontier_cells is None:
            self._frontier_cells = frontier_cells(self._map.cells)
        cell = self.grid.cell_of(x, y)
        return cell is None or not self._frontier_cells[cell]

    def _knows_free(self):
        """Whether a map came that knows some free space (a mapper's first is all unknown)."""
        return self._map is not None and read_cells(self._map.cells)[1].any()

    def _give_up(self, point):
        self._given_up |= self.grid.within(point, GIVE_UP_DISTANCE)

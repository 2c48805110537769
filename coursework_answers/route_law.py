"""
The reference planner-controller's law: plan a route to each goal, drive it leg by leg. No ROS.

A control law of the lab's run lifecycle (waypoint_lab/lifecycle.py). At each goal it plans a
route on the latest map (planner.py: walls grown by the robot's radius, a margin beyond it kept
where there is room); with no route, the goal is unreachable and the run reports it so. The
route is driven as the lab's assignment drives a waypoint: turn to face the next corner, then
drive to it with the lab's two PIDs, on heading and on distance; at the goal, turn to its
heading. Turning on the spot keeps the robot on the route's straight legs,
which are clear of the grown walls. A new map (a mapper's, growing) is checked at the next
command: where it shows a wall across the route, the route is planned again from where the
robot is (plans counts the routes planned).
"""

from collections.abc import Sequence
import math

from coursework_answers.planner import plan_route, route_clear
from courseworks.grids import Grid
from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.pose import wrap_angle
from waypoint_controller.config import ControllerConfig
from waypoint_controller.pid import lab_pids
from waypoint_lab.waypoints import Waypoint

# A corner is passed within this distance; the robot drives only when it faces the corner
# within ALIGNED (else it turns on the spot).
PASS_DISTANCE = 0.1
ALIGNED = math.radians(10.0)

Pose = tuple[float, float, float]


class RouteLaw:
    """Plans each goal's route on the map it was given last and drives it (see the module)."""

    def __init__(self, goals: Sequence[Waypoint], radius: float, margin: float,
                 config: ControllerConfig = ControllerConfig()):
        config.validate()
        self.goals, self.radius, self.margin, self.config = list(goals), radius, margin, config
        self.grid = None
        self.reachable = True
        self.route: list[Pose] = []
        self.plans = 0
        self._corner = 0
        self._index = None
        self._map_changed = False
        self._heading, self._distance = lab_pids(config)

    def use_map(self, occupancy_map: OccupancyMap) -> None:
        """
        Plan on occupancy_map from now on; its unknown cells are tried (a map still growing).

        The route is checked against it at the next command, and planned again where a wall
        shows across it.
        """
        self.grid = Grid.from_map(occupancy_map, unknown_is_wall=False)
        self._map_changed = True

    def aim(self, pose: Pose, index: int) -> None:
        """Plan the route from pose to goal index; reachable says whether there is one."""
        self._index = index
        self._plan(pose)

    def target(self, pose: Pose) -> Pose:
        """Return where the route goes: the goal aimed at (an explorer's goes elsewhere first)."""
        goal = self.goals[self._index]
        return goal.x, goal.y, goal.theta

    def _plan(self, pose):
        target = self.target(pose)
        self.plans += 1
        self._map_changed = False
        if self.grid is None:
            route = [target]
        else:
            route = plan_route(self.grid, self.radius, pose, target, self.margin)
        self.reachable = route is not None
        self.route, self._corner = route or [], 0
        self._heading.reset()
        self._distance.reset()

    def remaining(self, pose: Pose) -> float:
        """Return the distance left along the route: the run's stall watch measures progress."""
        corners = self.route[self._corner:]
        if not corners:
            return 0.0
        here = math.hypot(corners[0][0] - pose[0], corners[0][1] - pose[1])
        return here + sum(math.hypot(b[0] - a[0], b[1] - a[1])
                          for a, b in zip(corners, corners[1:]))

    def command(self, pose: Pose, dt: float) -> tuple[float, float]:
        """Return (linear, angular): face the next corner, drive to it; at the goal, turn."""
        if self._map_changed and self._index is not None:
            self._map_changed = False
            if not self.route or not route_clear(self.grid, self.radius,
                                                 [pose] + self.route[self._corner:]):
                self._plan(pose)
        if not self.route:
            return 0.0, 0.0
        while (self._corner < len(self.route) - 1 and math.hypot(
                self.route[self._corner][0] - pose[0],
                self.route[self._corner][1] - pose[1]) < PASS_DISTANCE):
            self._corner += 1
        x, y, theta = self.route[self._corner]
        distance = math.hypot(x - pose[0], y - pose[1])
        if self._corner == len(self.route) - 1 and distance < 0.5 * self.config.distance_tolerance:
            return 0.0, self._heading.update(wrap_angle(theta - pose[2]), dt)
        error = wrap_angle(math.atan2(y - pose[1], x - pose[0]) - pose[2])
        angular = self._heading.update(error, dt)
        if abs(error) > ALIGNED:
            return 0.0, angular
        linear = min(self._distance.update(distance, dt), self.config.max_linear_speed)
        return max(linear, 0.0) * math.cos(error), angular

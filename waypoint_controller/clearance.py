"""
Which plans keep the robot's footprint off the walls of a map. Pure Python and numpy, no ROS.

The map's free space is turned once into a clearance field (metres from each cell to the
nearest occupied one); a plan is free when every pose along it, a cell apart, has more
clearance than the robot's radius. Cells outside the map count as free, as does unknown space,
so that a partial map never pins the robot.
"""

import math

import numpy as np
from scipy.ndimage import distance_transform_edt
from simple_robot_control.occupancy_map import OccupancyMap
from waypoint_controller.planner import Plan, plan_poses

# Plans keep this much more than the robot's radius from walls: tracking is not exact.
MARGIN = 0.01


class Clearance:
    """Distances to the nearest wall over an occupancy map."""

    def __init__(self, occupancy_map: OccupancyMap, robot_radius: float):
        occupied = occupancy_map.occupied
        self.resolution, self.robot_radius = occupancy_map.resolution, robot_radius
        self.origin = occupancy_map.origin
        if occupied.any():
            # From a cell's centre to the nearest wall cell's edge, not its centre.
            self._field = (distance_transform_edt(~occupied) - 0.5) * self.resolution
        else:
            self._field = np.full(occupied.shape, math.inf)

    def at(self, x: float, y: float) -> float:
        """Clearance at a point in metres, interpolated between cell centres (inf off the map)."""
        column = (x - self.origin[0]) / self.resolution - 0.5
        row = (y - self.origin[1]) / self.resolution - 0.5
        height, width = self._field.shape
        if not (-0.5 <= row < height - 0.5 and -0.5 <= column < width - 0.5):
            return math.inf
        left, bottom = min(max(math.floor(column), 0), width - 2), min(max(math.floor(row), 0),
                                                                       height - 2)
        across, up = min(max(column - left, 0.0), 1.0), min(max(row - bottom, 0.0), 1.0)
        field = self._field
        lower = field[bottom, left] * (1 - across) + field[bottom, left + 1] * across
        upper = field[bottom + 1, left] * (1 - across) + field[bottom + 1, left + 1] * across
        return float(lower * (1 - up) + upper * up)

    def is_free(self, plan: Plan) -> bool:
        """
        Whether the footprint stays off the walls all along plan.

        A robot already that close to a wall may move along it or away, not further in.
        """
        # Further than twice the map's diagonal, a path has left the map for good.
        horizon = 2.0 * math.hypot(*self._field.shape) * self.resolution / plan.limits.speed
        poses = plan_poses(plan, self.resolution, horizon)
        limit = min(self.robot_radius + MARGIN, self.at(*poses[0][:2]) - 1e-9)
        return all(self.at(x, y) > limit for x, y, _ in poses[1:])

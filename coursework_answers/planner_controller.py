"""
The planner_controller node: the planning coursework's reference answer, on the lab's runner.

Each goal's route is planned on the map (route_law.py), driven leg by leg, and reported on
robot_status as the lab reports waypoints; a goal no route reaches is reported UNREACHABLE n and
the run goes on. The map is the simulator's /map or, with map_topic, a mapper's growing map:
a new map showing a wall across the route means planning again from where the robot is; with
max_map_age each pose waits for a map that fresh, so in lockstep the robot never outruns the
mapper (which map within that age came first still depends on timing: runs differ).
With explore_for it explores the map's frontiers first (explorer_law.py), the exploration
coursework's reference answer.
"""

import math

from coursework_answers.parameters import PLANNER_CONTROLLER_PARAMETERS
from simple_robot_control.occupancy_map import OccupancyMap
from waypoint_lab.lifecycle import ControlLaw, RunRules
from waypoint_lab.runner import (CourseRunner, NOT_YET, READY, run_controller, run_rules,
                                 WAIT)

DESCRIPTION = ('planner_controller: drive the robot to the goals of WAYPOINT_FILE (x y theta '
               'triples in m, m, degrees) by routes planned on the map, reporting STARTED, '
               'WAYPOINT n, UNREACHABLE n for a goal no route reaches, and FINISHED or ABORTED '
               'on robot_status. Exit code 0 when finished, 1 when aborted, 2 for bad input.')


class PlannerController(CourseRunner):
    """The reference planner-controller: RouteLaw, planning on the map of map_topic."""

    def __init__(self, waypoint_file=None, **kwargs):
        super().__init__('planner_controller', PLANNER_CONTROLLER_PARAMETERS, waypoint_file,
                         **kwargs)

    def build_law(self, params: dict, waypoints: list) -> tuple[ControlLaw, RunRules]:
        # Imported with the node: scipy and the compiled rays load while discovery runs.
        from coursework_answers.explorer_law import ExplorerLaw
        from coursework_answers.route_law import RouteLaw
        from waypoint_controller.config import ControllerConfig
        config = ControllerConfig(
            max_linear_speed=params['max_linear_speed'],
            max_angular_speed=params['max_angular_speed'],
            distance_tolerance=params['distance_tolerance'],
            angle_tolerance=math.radians(params['angle_tolerance_deg']))
        radius, margin = params['robot_radius'], params['wall_margin']
        if params['explore_for'] > 0.0:
            self._law = ExplorerLaw(waypoints, radius, margin, config, params['explore_for'])
        else:
            self._law = RouteLaw(waypoints, radius, margin, config)
        return self._law, run_rules(params)

    def plans_around_walls(self) -> bool:
        return True

    def use_map(self, grid: OccupancyMap) -> None:
        self._law.use_map(grid)
        self.answer_waiting()

    def inputs_ready(self, stamp_ns: int) -> str:
        """With max_map_age, wait for a map of the mapper's no older than that before the pose."""
        age_ns = round(self.params['max_map_age'] * 1e9)
        if not age_ns:
            return READY
        if not self.map_stamp_ns:
            return NOT_YET
        return READY if self.map_stamp_ns >= stamp_ns - age_ns else WAIT

    def waiting_for(self) -> str:
        return (f'a map on {self.params["map_topic"]} stamped within '
                f'{self.params["max_map_age"]:g} s of the odometry')


def main(argv: list[str] | None = None) -> None:
    run_controller('planner_controller', DESCRIPTION, PLANNER_CONTROLLER_PARAMETERS,
                   PlannerController, argv)


if __name__ == '__main__':
    main()

"""The waypoint_controller node: the lab's answer, driven through the lab's runner."""

import dataclasses
import math

from simple_robot_control.occupancy_map import OccupancyMap
from simple_robot_control.parameters import accept_tuning
from simple_robot_control.validation import ConfigError
from waypoint_controller.config import ControllerConfig
from waypoint_controller.control_law import PlannedLaw
from waypoint_controller.parameters import DEFAULTS, PARAMETERS
from waypoint_lab.lifecycle import ControlLaw, RunRules
from waypoint_lab.runner import CourseRunner, run_controller, run_rules

_CONFIG_FIELDS = ('max_linear_speed', 'max_angular_speed', 'distance_tolerance', 'heading_kp',
                  'heading_ki', 'heading_kd', 'distance_kp', 'distance_ki', 'distance_kd')

DESCRIPTION = ('waypoint_controller: drive the robot through the waypoints of WAYPOINT_FILE '
               '(x y theta triples in m, m, degrees) and report STARTED, WAYPOINT n, FINISHED '
               'or ABORTED on robot_status. Exit code 0 when finished, 1 when aborted, 2 for '
               'bad input.')


def controller_config(values: dict) -> ControllerConfig:
    """Return the ControllerConfig that parameter values (by name) describe."""
    return dataclasses.replace(
        DEFAULTS, angle_tolerance=math.radians(values['angle_tolerance_deg']),
        **{name: values[name] for name in _CONFIG_FIELDS})


class WaypointController(CourseRunner):
    """The lab's PID answer (control_law.PlannedLaw) planning around the walls of /map."""

    def __init__(self, waypoint_file=None, **kwargs):
        super().__init__('waypoint_controller', PARAMETERS, waypoint_file, **kwargs)
        accept_tuning(self, PARAMETERS, self._on_tuning)
        # The wall check needs scipy, a sixth of a second to import: imported now, while
        # discovery runs, rather than before the node exists or once the map has come.
        from waypoint_controller.clearance import Clearance
        self._clearance = Clearance

    def build_law(self, params: dict, waypoints: list) -> tuple[ControlLaw, RunRules]:
        self._tuned = {name: params[name] for name in _CONFIG_FIELDS + ('angle_tolerance_deg',)}
        try:
            self._law = PlannedLaw(waypoints, controller_config(self._tuned))
        except ValueError as error:
            raise ConfigError(str(error)) from None
        return self._law, run_rules(params)

    def plans_around_walls(self) -> bool:
        return True

    def use_map(self, grid: OccupancyMap) -> None:
        self._law.avoid(self._clearance(grid, self.params['robot_radius']).is_free)

    def _on_tuning(self, changes):
        """Keep tuned values for the next control tick, where they take effect together."""
        self._tuned.update(changes)
        config = controller_config(self._tuned)
        self.lifecycle.retune(run_rules({**self.params, **self._tuned}),
                              lambda: self._law.reconfigure(config))


def main(argv: list[str] | None = None) -> None:
    run_controller('waypoint_controller', DESCRIPTION, PARAMETERS, WaypointController, argv)


if __name__ == '__main__':
    main()

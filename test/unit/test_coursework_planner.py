"""The reference planner's routes: a few straight legs, each clear of the grown walls."""

import math

from coursework_answers.planner import plan_route
from coursework_answers.reference_run import run_reference
from courseworks.courses import read_course
from courseworks.grids import Grid, inflate
from courseworks.planning import clearance_along
import numpy as np
import pytest
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import shared_file
from stdr_lite.core.robot_description import load_robot


def room_with_a_door():
    """Return an 8 m x 6 m room at 0.1 m, a wall across it with a door at y 2.5-3.5 m."""
    walls = np.zeros((60, 80), dtype=bool)
    walls[0, :] = walls[-1, :] = walls[:, 0] = walls[:, -1] = True
    walls[:, 40] = True
    walls[25:35, 40] = False
    return Grid(walls, 0.1, (0.0, 0.0))


def test_a_route_through_the_door_is_a_few_clear_legs_ending_at_the_goal():
    grid = room_with_a_door()
    route = plan_route(grid, 0.2, (1.0, 1.0, 0.0), (7.0, 5.0, math.pi / 2))
    assert route[-1] == (7.0, 5.0, math.pi / 2)
    assert 2 <= len(route) <= 4
    grown = inflate(grid, 0.2)
    corners = [(1.0, 1.0)] + [waypoint[:2] for waypoint in route]
    for (x0, y0), (x1, y1) in zip(corners, corners[1:]):
        for t in np.linspace(0.0, 1.0, 50):
            assert not grown[grid.cell_of(x0 + t * (x1 - x0), y0 + t * (y1 - y0))]
    through = [waypoint for waypoint in route if abs(waypoint[0] - 4.05) < 1.0]
    assert through and all(2.5 <= y <= 3.5 for _, y, _ in through)
    x, y, theta = route[0]
    assert theta == pytest.approx(math.atan2(y - 1.0, x - 1.0))


def test_a_goal_in_the_open_is_one_leg_and_walled_off_goals_have_no_route():
    grid = room_with_a_door()
    assert plan_route(grid, 0.2, (1.0, 1.0, 0.0), (3.0, 5.0, 0.0)) == [(3.0, 5.0, 0.0)]
    grid.walls[25:35, 40] = True
    assert plan_route(grid, 0.2, (1.0, 1.0, 0.0), (7.0, 5.0, 0.0)) is None
    assert plan_route(grid, 0.2, (1.0, 1.0, 0.0), (4.0, 3.0, 0.0)) is None
    assert plan_route(grid, 0.2, (1.0, 1.0, 0.0), (9.0, 3.0, 0.0)) is None


@pytest.mark.parametrize('scenario', ['simple_walls_planning', 'plus_room_planning',
                                      'plus_room_mapping'])
def test_the_reference_answers_drive_a_scenario_through_the_lab_lifecycle(scenario):
    """Goals reached in order, the unreachable one reported, never closer to a wall than r."""
    course = read_course(shared_file('scenarios', f'{scenario}.txt'))
    run = run_reference(course)
    assert run.exit_code == 0, run.problem
    expected = [('WAYPOINT', number) for number in range(1, len(course.waypoints) + 1)]
    if scenario.endswith('planning'):
        expected[2] = ('UNREACHABLE', 3)
    assert [(status.kind, status.number) for _, status in run.statuses[1:-1]] == expected
    grid = Grid.from_map(load_map(course.map_file))
    radius = load_robot(course.robot_file).radius
    assert clearance_along(grid, run.poses[:, :2])[0] >= radius
    assert (run.cells is None) == scenario.endswith('planning')

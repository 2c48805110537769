"""The courseworks' bundled worlds, robot and scenarios, and one line for each bad scenario."""

import importlib.util
from pathlib import Path
import re

from courseworks.courses import CourseError, find_courses, read_course
from courseworks.exploration import ExplorationThresholds
from courseworks.grids import Grid, inflate
from courseworks.mapping import MapThresholds
from courseworks.names import EXPLORATION, MAPPING, PLANNING
from courseworks.planning import plan_legs, PlanningThresholds
from courseworks.tasks import task_thresholds
import pytest
from simple_robot_control.occupancy_map import load_map
from stdr_lite.core.loading import load_world
from stdr_lite.core.robot_description import load_robot

REPOSITORY = Path(__file__).resolve().parents[2]
# The goals of each bundled scenario no robot can reach, as its goal file's comment says: one
# per planning scenario, none where the robot maps.
UNREACHABLE = {'factory_planning': [3], 'plus_room_planning': [3],
               'simple_walls_planning': [3], 'factory_mapping': [], 'plus_room_mapping': [],
               'simple_walls_mapping': [], 'factory_exploration': [], 'plus_room_exploration': []}
THRESHOLDS = {PLANNING: PlanningThresholds(), MAPPING: MapThresholds(),
              EXPLORATION: ExplorationThresholds(reference_coverage=1.0)}


def map_plans():
    path = REPOSITORY / 'scripts' / 'make_coursework_maps.py'
    spec = importlib.util.spec_from_file_location('make_coursework_maps', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_bundled_maps_are_their_plans_drawn(tmp_path):
    plans = map_plans()
    for name in plans.PLANS:
        plans.write(name, tmp_path)
        for suffix in ('.pgm', '.yaml'):
            assert (tmp_path / f'{name}{suffix}').read_bytes() == (
                REPOSITORY / 'maps' / f'{name}{suffix}').read_bytes(), f'{name}{suffix}'


@pytest.fixture(scope='module')
def scenarios():
    return find_courses([REPOSITORY / 'scenarios'])


def test_every_scenario_names_its_task_world_and_robot(scenarios):
    assert sorted(UNREACHABLE) == [course.name for course in scenarios]
    for course in scenarios:
        world, task = course.name.rsplit('_', 1)
        assert course.task == task
        assert Path(course.map_file).name == f'{world}.yaml'
        assert Path(course.robot_file).name == 'small_laser_robot.yaml'
        assert task_thresholds(course.task, course.thresholds) == THRESHOLDS[task]


def test_each_scenario_starts_clear_and_its_unreachable_goals_are_the_judges(scenarios):
    for course in scenarios:
        grid = Grid.from_map(load_map(course.map_file))
        radius = load_robot(course.robot_file).radius
        assert not inflate(grid, radius)[grid.cell_of(*course.start[:2])], course.name
        legs = plan_legs(grid, radius, course.start, course.waypoints)
        assert [leg.goal for leg in legs if not leg.reachable] == UNREACHABLE[course.name]


def test_the_small_robot_carries_one_laser_of_667_rays_at_10_hz(scenarios):
    course = scenarios[0]
    robot = load_robot(course.robot_file)
    assert robot.radius == 0.1 and [(laser.num_rays, laser.frequency, laser.max_range)
                                    for laser in robot.lasers] == [(667, 10.0, 4.09)]
    world = load_world(course.map_file, [('robot0', course.start, course.robot_file)])
    world.step()
    readings = world.sensor_readings('robot0')
    assert list(readings) == ['laser_0'] and len(readings['laser_0']) == 667


def write(folder, settings):
    (folder / 'goals.txt').write_text('2 2 0\n')
    (folder / 'goals.yaml').write_text(settings)
    return folder / 'goals.txt'


@pytest.mark.parametrize('settings, complaint', [
    ('task: maping\n', 'task must be one of waypoints, mapping, exploration, planning, got '
                       "'maping'"),
    ('task: planning\nthresholds: {max_path_ration: 2}\n',
     "the planning task has no threshold 'max_path_ration' (known: max_path_ratio)"),
    ('task: planning\nthresholds: {max_path_ratio: 0.5}\n',
     'threshold max_path_ratio must be in [1, 100], got 0.5'),
    ('task: mapping\nthresholds: {min_coverage: 1.5}\n',
     'threshold min_coverage must be in [0, 1], got 1.5'),
    ('task: mapping\nthresholds: [0.5]\n',
     'thresholds must be a mapping of name to number, got [0.5]'),
    ('thresholds: {min_coverage: 0.5}\n',
     "the waypoints task has no threshold 'min_coverage' (known: none: the lab has its own "
     'limits)'),
])
def test_a_bad_scenario_is_refused_in_one_line(tmp_path, settings, complaint):
    with pytest.raises(CourseError) as error:
        read_course(write(tmp_path, settings))
    assert str(error.value) == f'{tmp_path / "goals.yaml"}: {complaint}'


def test_the_courseworks_page_example_prints_what_the_page_shows(tmp_path, monkeypatch, capsys):
    page = (REPOSITORY / 'doc' / 'courseworks.md').read_text()
    code, shown = re.findall(r'```python\n(.*?)```\n\n```\n(.*?)```', page, re.DOTALL)[0]
    monkeypatch.chdir(tmp_path)
    exec(compile(code, 'doc/courseworks.md', 'exec'), {})
    assert capsys.readouterr().out == shown

"""
The layout's rules, checked from the code's own imports.

Pure modules (the simulation core, the control law and its parts, the grader's rules, the
shared checks) import no ROS client library, so they run and are tested without a ROS graph;
the lab's controller does not depend on the simulator, and the grader only on its core; no
module grows past 400 lines; every executable lives in a module named after it.
"""

import ast
from pathlib import Path
import re

import pytest

from simple_robot_control.executables import MODULES

REPOSITORY = Path(__file__).resolve().parents[2]
PACKAGES = ('simple_robot_control', 'stdr_lite', 'waypoint_controller', 'lab_grader')
PURE = ['stdr_lite/core/*.py', 'stdr_lite/tools/lab_session.py', 'stdr_lite/viewer/scene.py',
        'simple_robot_control/validation.py', 'simple_robot_control/pose.py',
        'simple_robot_control/input_files.py', 'simple_robot_control/executables.py',
        'simple_robot_control/occupancy_map.py', 'simple_robot_control/command_line.py',
        'simple_robot_control/share.py', 'simple_robot_control/bag.py'] + [
    f'waypoint_controller/{name}.py' for name in (
        'control_law', 'pid', 'schedule', 'stall', 'continuity', 'status', 'waypoints',
        'run_record', 'run_bag', 'planner', 'reeds_shepp', 'clearance')] + [
    f'lab_grader/{name}.py' for name in (
        'courses', 'evidence', 'verdicts', 'grading', 'reports', 'report_page', 'supervision')] + [
    'simple_robot_control/bag_reading.py', 'simple_robot_control/domains.py'] + [
    f'stdr_lite/learning/{name}.py' for name in (
        'course', 'arena', 'waypoints_env', 'vector_env', 'rendering')]
ROS_CLIENT = re.compile(r'^(rclpy|rcl_interfaces|[a-z_]+_msgs|launch)(\.|$)')


def imported_modules(path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            yield node.module


def modules(*patterns):
    return sorted(path for pattern in patterns for path in REPOSITORY.glob(pattern))


@pytest.mark.parametrize('path', modules(*PURE), ids=str)
def test_pure_modules_import_no_ros(path):
    ros = [name for name in imported_modules(path) if ROS_CLIENT.match(name)]
    assert not ros, f'{path.relative_to(REPOSITORY)} imports {ros}'


@pytest.mark.parametrize('path', modules('stdr_lite/core/*.py'), ids=str)
def test_the_simulation_core_knows_nothing_of_nodes_viewer_or_tools(path):
    outward = [name for name in imported_modules(path)
               if name.startswith('stdr_lite.') and not name.startswith('stdr_lite.core')]
    assert not outward


@pytest.mark.parametrize('path', modules('waypoint_controller/*.py'), ids=str)
def test_the_controller_does_not_depend_on_the_simulator(path):
    assert not [name for name in imported_modules(path) if name.split('.')[0] == 'stdr_lite']


@pytest.mark.parametrize('path', modules('simple_robot_control/*.py'), ids=str)
def test_the_shared_runtime_depends_on_neither_tool(path):
    assert not [name for name in imported_modules(path)
                if name.split('.')[0] in ('stdr_lite', 'waypoint_controller')]


@pytest.mark.parametrize('path', modules('lab_grader/*.py'), ids=str)
def test_the_grader_runs_the_simulator_and_reads_only_its_core(path):
    """The grader starts stdr_lite as a process, as a course would, and judges from bags."""
    assert not [name for name in imported_modules(path)
                if name.startswith('stdr_lite') and not name.startswith('stdr_lite.core')]


@pytest.mark.parametrize('path', modules(*(f'{package}/**/*.py' for package in PACKAGES)),
                         ids=str)
def test_no_module_is_over_400_lines(path):
    assert len(path.read_text().splitlines()) <= 400


def test_every_executable_lives_in_a_module_named_after_it():
    setup = (REPOSITORY / 'setup.py').read_text()
    installed = set(re.findall(r"'(\w+)'", setup[setup.index('EXECUTABLES = ('):]
                               .split(')')[0]))
    assert installed == set(MODULES)
    for executable, module in MODULES.items():
        assert module.split('.')[-1] == executable
        assert (REPOSITORY / (module.replace('.', '/') + '.py')).is_file()

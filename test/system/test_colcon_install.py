"""colcon builds the package into the install tree that `ros2 run` and `ros2 launch` use."""

import os
from pathlib import Path
import subprocess
import sys

from installed_executables import EXECUTABLES, PARAMETER_TABLES
import pytest


# Its tests share a module-scoped fixture: one worker runs them all (pytest.ini: loadgroup).
pytestmark = pytest.mark.xdist_group('colcon_install_tree')

REPOSITORY = Path(__file__).resolve().parents[2]
PACKAGE = 'simple_robot_control'


@pytest.fixture(scope='module')
def install_tree(tmp_path_factory):
    workspace = tmp_path_factory.mktemp('colcon_ws')
    colcon = Path(sys.executable).parent / 'colcon'
    result = subprocess.run(
        [str(colcon), 'build', '--base-paths', str(REPOSITORY), '--build-base', 'build',
         '--install-base', 'install', '--event-handlers', 'console_direct-'],
        cwd=workspace, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    return workspace / 'install'


def test_package_is_registered_in_the_ament_index(install_tree):
    prefix = install_tree / PACKAGE
    assert (prefix / 'share/ament_index/resource_index/packages' / PACKAGE).is_file()
    assert (prefix / 'share' / PACKAGE / 'package.xml').is_file()
    assert (prefix / 'share' / PACKAGE / 'maps/lab_room.yaml').is_file()
    assert (prefix / 'share' / PACKAGE / 'maps/lab_room.pgm').is_file()
    assert {path.name for path in (prefix / 'share' / PACKAGE / 'launch').iterdir()} >= {
        'stdr_lite.launch.py', 'waypoints.launch.py', 'scenario.launch.py'}
    assert (prefix / 'share' / PACKAGE / 'waypoints' / 'lab_tour.txt').is_file()
    assert {path.name for path in (prefix / 'share' / PACKAGE / 'config').iterdir()} == {
        f'{name}.yaml' for name in PARAMETER_TABLES} | {
        'fastdds_quick_discovery.xml', 'foxglove_lab_layout.json'}


@pytest.mark.parametrize('name', EXECUTABLES)
def test_executables_are_where_ros2_run_looks(install_tree, name):
    path = install_tree / PACKAGE / 'lib' / PACKAGE / name
    assert os.access(path, os.X_OK)
    command = f'source "{install_tree}/setup.bash" && "{path}" --help'
    result = subprocess.run(['bash', '-c', command], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    assert f'usage: {name}' in result.stdout


def test_the_tests_find_executables_where_ros2_run_does(install_tree):
    """Under colcon test the ament index names the install tree, as on a Jazzy machine."""
    command = (f'source "{install_tree}/setup.bash" && "{sys.executable}" -c '
               '"import processes; print(processes.executable(\'stdr_lite\'))"')
    result = subprocess.run(['bash', '-c', command], capture_output=True, text=True, timeout=60,
                            cwd=REPOSITORY / 'test')
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == str(install_tree / PACKAGE / 'lib' / PACKAGE / 'stdr_lite')

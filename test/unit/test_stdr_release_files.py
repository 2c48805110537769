"""
STDR's own robot files, as its last release ships them, load unchanged.

STDR is GPLv3: its files are not in this repository. Point STDR_RESOURCES at the
stdr_resources/resources folder of an stdr_simulator checkout (branch indigo-devel) to run
these: `make check-stdr STDR_RESOURCES=...`.
"""

import os
from pathlib import Path

import pytest
from stdr_lite.core.robot_description import load_robot

RESOURCES = os.environ.get('STDR_RESOURCES', '')
pytestmark = pytest.mark.skipif(not RESOURCES, reason='STDR_RESOURCES is not set')
# What each file holds: lasers, sonars, polygon corners, kinematic model, noisy motion,
# unsimulated sensors.
RELEASE = {
    'khepera2.yaml': (0, 8, 0, 'ideal', False, ()),
    'khepera3.yaml': (0, 14, 0, 'ideal', False, ()),
    'omni_robot.xml': (1, 5, 0, 'omni', False, ()),
    'omni_robot_noisy.xml': (1, 5, 0, 'omni', True, ()),
    'pandora_robot.xml': (1, 5, 0, 'ideal', False, ()),
    'pandora_robot.yaml': (1, 5, 0, 'ideal', False, ()),
    'random_shape_robot.xml': (1, 0, 6, 'ideal', False, ()),
    'simple_robot.xml': (1, 0, 0, 'ideal', False, ()),
    'square_robot.xml': (1, 0, 4, 'ideal', False, ()),
    'square_robot_rfid_reader.xml': (1, 0, 4, 'ideal', False, ('rfid_reader rfid_reader_0',)),
    'too_simple_robot.xml': (0, 0, 0, 'ideal', False, ()),
}


def test_the_release_has_the_files_we_know():
    assert sorted(path.name for path in (Path(RESOURCES) / 'robots').iterdir()) == sorted(RELEASE)


@pytest.mark.parametrize('name', RELEASE)
def test_each_release_robot_file_loads_as_stdr_reads_it(name):
    robot = load_robot(Path(RESOURCES) / 'robots' / name)
    assert (len(robot.lasers), len(robot.sonars), len(robot.points), robot.kinematic.model,
            robot.kinematic.noisy, robot.unsimulated) == RELEASE[name]

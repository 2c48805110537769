"""The README documents every node parameter, so docs and code cannot drift apart."""

from pathlib import Path

import pytest
from stdr_lite.node import stdr_lite
from stdr_lite.tools import move_robot
from stdr_lite.viewer import stdr_viewer
from waypoint_controller import course_monitor, waypoint_controller

README = (Path(__file__).resolve().parents[2] / 'README.md').read_text()


@pytest.mark.parametrize('module', [stdr_lite, move_robot, waypoint_controller, course_monitor,
                                    stdr_viewer])
def test_every_parameter_has_a_readme_row(module):
    missing = [spec.name for spec in module.PARAMETERS if f'| `{spec.name}` |' not in README]
    assert not missing, f'README lacks rows for {missing}'

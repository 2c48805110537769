"""The README documents every node parameter, so docs and code cannot drift apart."""

from pathlib import Path

import pytest

from stdr_lite import move_robot, simulator_node, viewer_node
from waypoint_controller import controller_node, monitor_node

README = (Path(__file__).resolve().parent.parent / 'README.md').read_text()


@pytest.mark.parametrize('module', [simulator_node, move_robot, controller_node,
                                    monitor_node, viewer_node])
def test_every_parameter_has_a_readme_row(module):
    missing = [spec.name for spec in module.PARAMETERS if f'| `{spec.name}` |' not in README]
    assert not missing, f'README lacks rows for {missing}'

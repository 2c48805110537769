"""The documentation names every node parameter, so docs and code cannot drift apart."""

from pathlib import Path

import pytest
from stdr_lite.node import stdr_lite
from stdr_lite.tools import move_robot
from stdr_lite.viewer import stdr_viewer
from waypoint_controller import course_monitor, waypoint_controller

REPOSITORY = Path(__file__).resolve().parents[2]
PAGES = [REPOSITORY / 'README.md', *sorted(REPOSITORY.glob('doc/*.md'))]
DOCUMENTATION = '\n'.join(path.read_text() for path in PAGES)


@pytest.mark.parametrize('module', [stdr_lite, move_robot, waypoint_controller, course_monitor,
                                    stdr_viewer])
def test_every_parameter_has_a_row_in_the_documentation(module):
    missing = [spec.name for spec in module.PARAMETERS
               if f'| `{spec.name}` |' not in DOCUMENTATION]
    assert not missing, f'the documentation lacks rows for {missing}'


def test_the_readme_links_every_page():
    readme = (REPOSITORY / 'README.md').read_text()
    pages = sorted(path.name for path in REPOSITORY.glob('doc/*.md'))
    assert pages and all(f'(doc/{page})' in readme for page in pages)

"""
The ament linters every ROS 2 Python package runs: flake8 and pep257.

Each runs in a process of its own: flake8 checks files in a pool of forked workers, and a fork
taken while this test process holds DDS threads (from the node tests) can deadlock.
"""

from pathlib import Path
import subprocess
import sys

import pytest

REPOSITORY = Path(__file__).resolve().parent.parent
SOURCES = [str(REPOSITORY / name) for name in
           ('simple_robot_control', 'stdr_lite', 'foxglove_live', 'waypoint_lab',
            'waypoint_controller', 'lab_grader', 'courseworks', 'coursework_answers', 'test',
            'bench', 'launch', 'scripts', 'examples', 'setup.py')
           if (REPOSITORY / name).exists()]


@pytest.mark.linter
@pytest.mark.parametrize('linter', ['ament_flake8', 'ament_pep257'])
def test_linter(linter):
    result = subprocess.run([sys.executable, '-m', f'{linter}.main', *SOURCES],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout[-5000:] + result.stderr[-2000:]

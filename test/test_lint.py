"""The ament linters every ROS 2 Python package runs: flake8 and pep257."""

from pathlib import Path

from ament_flake8.main import main_with_errors
from ament_pep257.main import main as pep257_main
import pytest

REPOSITORY = Path(__file__).resolve().parent.parent
SOURCES = [str(REPOSITORY / name) for name in
           ('stdr_lite', 'waypoint_controller', 'test', 'bench', 'launch', 'scripts', 'setup.py')
           if (REPOSITORY / name).exists()]


@pytest.mark.linter
def test_flake8():
    code, errors = main_with_errors(argv=SOURCES)
    assert code == 0, f'{len(errors)} flake8 errors:\n' + '\n'.join(errors)


@pytest.mark.linter
def test_pep257():
    assert pep257_main(argv=SOURCES) == 0, 'pep257 errors, see the captured output'

"""grade_lab on the mapping coursework: the reference answer passes, a copied map fails."""

from pathlib import Path
import sys

from grade_runs import grade
import pytest
from simple_robot_control.share import installed_executable, shared_file
from test_grade_lab import verdicts

# Its tests share a module-scoped fixture: one worker runs them all (pytest.ini: loadgroup).
pytestmark = pytest.mark.xdist_group('grade_lab_mapping')

COPIER = Path(__file__).resolve().parents[1] / 'controllers' / 'map_copier.py'
# The factory's run (190 s of sim time, a third of the suite's budget for this test) is graded
# by hand before each release; the two smaller worlds here.
SCENARIOS = ('plus_room_mapping', 'simple_walls_mapping')


def reference_script():
    """Return the mapping reference answer as one command: the mapper beside the planner."""
    return (f'{installed_executable("occupancy_mapper")} & mapper=$!\n'
            f'{installed_executable("planner_controller")} "$2" --ros-args '
            '-p map_topic:=/coursework_map -p max_map_age:=1.5\n'
            'code=$?\nkill -INT $mapper\nwait $mapper\nexit $code\n')


@pytest.fixture(scope='module')
def graded(tmp_path_factory):
    """Grade the reference and a map copier on the bundled mapping scenarios of SCENARIOS."""
    root = tmp_path_factory.mktemp('mapping')
    groups = root / 'groups'
    for group, script in (('reference', reference_script()),
                          ('copies_map', f'exec {sys.executable} {COPIER}\n')):
        (groups / group).mkdir(parents=True)
        (groups / group / 'run.sh').write_text(f'#!/bin/sh\n{script}')
        (groups / group / 'run.sh').chmod(0o755)
    report = root / 'report'
    result = grade('--courses', *(shared_file('scenarios', f'{name}.txt') for name in SCENARIOS),
                   '--submissions', groups, '--jobs', 3, '--lockstep', '--real-time-factor', 0,
                   '--report', report, '--', './run.sh', '@', '{waypoints}', cwd=root,
                   timeout=900)
    return result, report


@pytest.mark.parametrize('course', SCENARIOS)
def test_the_reference_mapper_and_planner_pass_the_scenarios(graded, course):
    result, report = graded
    checks = verdicts(report, 'reference', course)
    failed = {name: evidence for name, (passed, evidence) in checks.items() if not passed}
    assert not failed and f'reference / {course}: PASS' in result.stdout
    assert checks['mapping'][0]


def test_a_map_copied_from_the_map_file_fails_as_not_built_from_the_laser(graded):
    result, report = graded
    evidence = verdicts(report, 'copies_map', 'plus_room_mapping')['mapping']
    assert not evidence[0] and 'not built from the laser alone' in evidence[1]
    assert result.returncode == 1

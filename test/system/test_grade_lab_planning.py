"""grade_lab on the planning coursework: the reference answer passes, rule breakers fail."""

from pathlib import Path
import sys

from grade_runs import grade
import pytest
from simple_robot_control.share import installed_executable, shared_file
from test_grade_lab import verdicts

# Its tests share a module-scoped fixture: one worker runs them all (pytest.ini: loadgroup).
pytestmark = pytest.mark.xdist_group('grade_lab_planning')

PLANNERS = Path(__file__).resolve().parents[1] / 'controllers' / 'planners.py'
# The smallest world: the others (the factory's run takes 200 s of sim time) and every answer on
# every scenario are make bench's (bench.courseworks); make scenario's figures in
# doc/courseworks.md.
SCENARIO = 'plus_room_planning'


@pytest.fixture(scope='module')
def graded(tmp_path_factory):
    """Grade the reference and the two rule breakers on the smallest scenario, all at once."""
    root = tmp_path_factory.mktemp('planning')
    groups = root / 'groups'
    for group in ('reference', 'pushes_on', 'gives_up'):
        (groups / group).mkdir(parents=True)
        (groups / group / 'behaviour').write_text(group)
        # The breaker that pushes on stalls at once (a stall of 2 s ends its run as well).
        command = (f'exec {installed_executable("planner_controller")} "$2"\n'
                   if group == 'reference' else f'exec {sys.executable} {PLANNERS} "$@" '
                   '--ros-args -p stall_timeout:=2.0\n')
        script = groups / group / 'run.sh'
        script.write_text(f'#!/bin/sh\n{command}')
        script.chmod(0o755)
    report = root / 'report'
    result = grade('--courses', shared_file('scenarios', f'{SCENARIO}.txt'), '--submissions',
                   groups, '--jobs', 3, '--lockstep', '--real-time-factor', 0, '--report',
                   report, '--', './run.sh', '@', '{waypoints}', cwd=root, timeout=900)
    return result, report


def failed(report, group, course):
    return {name: evidence for name, (passed, evidence) in verdicts(report, group, course).items()
            if not passed}


def test_the_reference_planner_passes(graded):
    result, report = graded
    checks = verdicts(report, 'reference', SCENARIO)
    assert all(passed for passed, _ in checks.values()), failed(report, 'reference', SCENARIO)
    assert f'reference / {SCENARIO}: PASS' in result.stdout
    assert checks['UNREACHABLE 3'][0] and 'planning' in checks


def test_a_planner_that_pushes_on_at_an_unreachable_goal_fails_saying_so(graded):
    _, report = graded
    failures = failed(report, 'pushes_on', SCENARIO)
    assert 'goal 3 is unreachable and was not reported so' in failures['planning']
    assert failures['WAYPOINT 3'].startswith('never sent')
    assert 'WAYPOINT 2' not in failures


def test_a_planner_that_gives_reachable_goals_up_fails_saying_so(graded):
    result, report = graded
    failures = failed(report, 'gives_up', SCENARIO)
    assert 'goal 1 was reported unreachable; the judge reaches it by' in failures['planning']
    assert result.returncode == 1

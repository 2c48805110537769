"""
grade_lab against submissions that try to buy a verdict without driving (controllers/attacks.py).

Each attack must end FAIL, with the line that says what it did, and leave nothing running; the
courses' files stay as they were. grade_lab runs as the user of the tests: when that is root, the
submissions run as root too (see doc/grading.md, what grading protects against).
"""

from pathlib import Path
import re
import sys

from grade_runs import grade, write_course
import psutil
import pytest
from test_grade_lab import verdicts

pytestmark = pytest.mark.xdist_group('grade_lab_attacks')

ATTACKS = Path(__file__).resolve().parents[1] / 'controllers' / 'attacks.py'
GROUPS = ('teleport', 'fake_truth', 'escape', 'kill_simulator', 'flood', 'hog', 'snoop')


@pytest.fixture(scope='module')
def attacks(tmp_path_factory):
    """Grade every attack on a course ahead of the robot, three at a time; give the runs."""
    root = tmp_path_factory.mktemp('attacks')
    courses = root / 'courses'
    write_course(courses, 'ahead', '3.0 2.0 0.0', time_limit=8)
    before = {path.name: path.read_bytes() for path in courses.iterdir()}
    groups = root / 'groups'
    for attack in GROUPS:
        (groups / attack).mkdir(parents=True)
        (groups / attack / 'behaviour').write_text(attack)
    report = root / 'report'
    result = grade('--courses', courses, '--submissions', groups, '--jobs', 3, '--report',
                   report, '--', sys.executable, ATTACKS, '@', '{waypoints}', cwd=root,
                   timeout=900)
    assert {path.name: path.read_bytes() for path in courses.iterdir()} == before
    return result, report, root


def failures(report, group, course):
    return {name: evidence for name, (passed, evidence) in verdicts(report, group, course).items()
            if not passed}


def output(report, group, course):
    return (report / group / course / 'output.txt').read_text()


def test_the_simulator_offers_no_way_to_move_the_robot(attacks):
    _, report, _ = attacks
    assert 'attack: set_entity_state not offered' in output(report, 'teleport', 'ahead')
    assert 'odometry after the move: (1.0, 2.0, 0.0)' in output(report, 'teleport', 'ahead')
    failed = failures(report, 'teleport', 'ahead')
    assert 'while the robot was 2.000 m' in failed['WAYPOINT 1']


def test_truth_odometry_or_clock_published_by_the_submission_fails_it(attacks):
    _, report, _ = attacks
    failed = failures(report, 'fake_truth', 'ahead')
    assert 'fair play' in failed, failed
    assert re.search('/(robot0/ground_truth|robot0/odom|clock) was published by node '
                     "'/attacker' of the submission", failed['fair play'])


def test_a_daemon_that_left_with_env_i_is_ended_and_named(attacks):
    _, report, _ = attacks
    pid = int(re.search(r'attack: daemon pid (\d+)', output(report, 'escape', 'ahead')).group(1))
    assert not psutil.pid_exists(pid) or psutil.Process(pid).status() == psutil.STATUS_ZOMBIE
    failed = failures(report, 'escape', 'ahead')
    assert set(failed) == {'WAYPOINT 1', 'ends when asked'}
    assert f'pid {pid}' in failed['ends when asked']


def test_killing_the_simulator_or_flooding_the_status_is_a_fail_not_an_error(attacks):
    result, report, _ = attacks
    assert 'kill_simulator' in result.stdout and 'ERROR' not in result.stdout, result.stdout
    assert 'attack: killed the simulator' in output(report, 'kill_simulator', 'ahead')
    killed = failures(report, 'kill_simulator', 'ahead')['fair play']
    assert 'the simulator was ended during the run (killed by signal 9), not by the grader' \
        in killed
    flood_failures = failures(report, 'flood', 'ahead')
    assert 'fair play' in flood_failures, (flood_failures, output(report, 'flood', 'ahead'))
    flooded = flood_failures['fair play']
    assert re.search('sent [0-9]+ messages on robot_status, more than 130', flooded)


def test_a_submission_over_its_memory_fails_saying_so(attacks):
    _, report, _ = attacks
    failed = failures(report, 'hog', 'ahead')
    assert 'ran out of the memory grade_lab --memory allows' in failed['ends when asked']


def test_nothing_the_submission_sees_names_the_courses_or_the_reports(attacks):
    _, report, root = attacks
    snooped = output(report, 'snoop', 'ahead')
    assert 'attack: snooped ancestor' in snooped and 'attack: snooped simulator' in snooped
    for folder in (root / 'courses', report):
        assert str(folder) not in snooped
    assert set(failures(report, 'snoop', 'ahead')) == {'WAYPOINT 1'}


def test_courses_changed_or_planted_by_a_submission_are_put_back_and_fail_it(tmp_path):
    courses = tmp_path / 'courses'
    write_course(courses, 'here', '1.0 2.0 0.0', time_limit=8)
    before = {path.name: path.read_bytes() for path in courses.iterdir()}
    (tmp_path / 'group').mkdir()
    (tmp_path / 'group' / 'behaviour').write_text(f'tamper {courses}')
    result = grade('--courses', courses, '--report', tmp_path / 'report', '--',
                   sys.executable, ATTACKS, '@', '{waypoints}', cwd=tmp_path / 'group')
    assert result.returncode == 1, result.stdout + result.stderr
    assert {path.name: path.read_bytes() for path in courses.iterdir()} == before
    page = (tmp_path / 'report' / 'report.md').read_text()
    assert 'here.txt was changed or removed during the run (put back)' in page
    assert 'planted.txt was made in the courses' in page

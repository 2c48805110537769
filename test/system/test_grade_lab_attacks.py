"""
grade_lab against submissions that try to buy a verdict without driving (controllers/attacks.py).

Each attack must end FAIL, with the line that says what it did, and leave nothing running; the
courses' files stay as they were, and an honest group graded beside them passes. grade_lab runs
as the user of the tests: as root (as CI runs it) each submission is sealed off in namespaces
of its own (lab_grader/sandbox.py), and the attacks that only root could try are tried; as
another user, those tests are skipped (doc/grading.md says what holds then).
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
GROUPS = ('teleport', 'fake_truth', 'escape', 'kill_simulator', 'flood', 'hog', 'snoop',
          'kill_reaper', 'status_pipe', 'fill_disk', 'intrude', 'honest', 'tamper')
DISK_MB = 64


@pytest.fixture(scope='module')
def attacks(tmp_path_factory):
    """Grade every attack on a course ahead of the robot, three at a time; give the runs."""
    root = tmp_path_factory.mktemp('attacks')
    courses = root / 'courses'
    write_course(courses, 'ahead', '3.0 2.0 0.0', time_limit=12)
    before = {path.name: path.read_bytes() for path in courses.iterdir()}
    groups = root / 'groups'
    for attack in GROUPS:
        (groups / attack).mkdir(parents=True)
        (groups / attack / 'behaviour').write_text(f'{attack} {courses}')
    report = root / 'report'
    result = grade('--courses', courses, '--submissions', groups, '--jobs', 3, '--report',
                   report, '--disk', DISK_MB, '--', sys.executable, ATTACKS, '@', '{waypoints}',
                   cwd=root, timeout=900)
    assert {path.name: path.read_bytes() for path in courses.iterdir()} == before
    return result, report, root


@pytest.fixture(scope='module')
def sealed(attacks):
    """Skip unless the submissions ran sealed off (grade_lab as root, namespaces allowed)."""
    if 'sandbox: namespaces' not in attacks[0].stdout:
        pytest.skip('grade_lab ran as a user, not root: submissions were not sealed off')


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
    # The run ends at the first sight of it, which may come before the node's name does.
    assert re.search('/(robot0/ground_truth|robot0/odom|clock) was published by (node '
                     r"'/attacker' of the submission|the submission \(a node the graph had not "
                     r'named yet\))', failed['fair play'])


def test_a_daemon_that_left_with_env_i_is_ended_and_named(attacks):
    _, report, _ = attacks
    assert 'attack: daemon pid' in output(report, 'escape', 'ahead')
    failed = failures(report, 'escape', 'ahead')
    assert set(failed) == {'WAYPOINT 1', 'ends when asked'}
    assert 'signal.signal(signal.SIGINT' in failed['ends when asked'], failed
    pid = int(re.search(r'pid (\d+)', failed['ends when asked']).group(1))
    assert not psutil.pid_exists(pid) or psutil.Process(pid).status() == psutil.STATUS_ZOMBIE


def test_flooding_the_status_is_a_fail_not_an_error(attacks):
    result, report, _ = attacks
    assert 'ERROR' not in result.stdout, result.stdout
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
    assert "attack: snooped current world lab_room at ''" in snooped
    for folder in (root / 'courses', report):
        assert str(folder) not in snooped
    assert set(failures(report, 'snoop', 'ahead')) == {'WAYPOINT 1'}


def test_the_simulator_and_the_grader_are_out_of_sight_and_reach(attacks, sealed):
    """Root's submission saw no process but its own: no simulator to stop, steal from or kill."""
    _, report, _ = attacks
    snooped = output(report, 'snoop', 'ahead')
    assert 'snooped ancestor' not in snooped and 'snooped simulator' not in snooped
    assert 'grade_lab' not in snooped
    assert 'attack: found no simulator to kill' in output(report, 'kill_simulator', 'ahead')
    assert 'fair play' not in failures(report, 'kill_simulator', 'ahead')


def test_the_courses_cannot_even_be_read(attacks, sealed):
    _, report, _ = attacks
    said = output(report, 'tamper', 'ahead')
    assert 'attack: could not write into the courses' in said and 'rewrote' not in said


def test_killing_its_reaper_or_lying_on_its_pipe_leaves_no_daemon(attacks, sealed):
    _, report, _ = attacks
    said = output(report, 'kill_reaper', 'ahead')
    assert 'could not kill pid 1: Operation not permitted' in said, said
    assert 'attack: wrote into 0 pipes' in output(report, 'status_pipe', 'ahead')
    for group in ('kill_reaper', 'status_pipe'):
        failed = failures(report, group, 'ahead')
        assert set(failed) == {'WAYPOINT 1', 'ends when asked'}, (group, failed)
        assert 'signal.signal(signal.SIGINT' in failed['ends when asked']


def test_filling_its_disk_is_the_submissions_fail_named(attacks, sealed):
    _, report, _ = attacks
    assert re.search(r'disk full after \d+ MB: No space left on device',
                     output(report, 'fill_disk', 'ahead'))
    failed = failures(report, 'fill_disk', 'ahead')
    assert f'filled its working space: the {DISK_MB} MB of /tmp' in failed['fair play']


def test_a_group_commanding_other_domains_reaches_no_other_course(attacks, sealed):
    _, report, _ = attacks
    assert 'commanding robot0 in domains 0 to 9' in output(report, 'intrude', 'ahead')
    assert failures(report, 'honest', 'ahead') == {}


def test_courses_changed_or_planted_by_a_submission_are_put_back_and_fail_it(tmp_path):
    """Unsealed (as a user, or --sandbox none), the courses' guard puts back what was changed."""
    courses = tmp_path / 'courses'
    write_course(courses, 'here', '1.0 2.0 0.0', time_limit=8)
    before = {path.name: path.read_bytes() for path in courses.iterdir()}
    (tmp_path / 'group').mkdir()
    (tmp_path / 'group' / 'behaviour').write_text(f'tamper {courses}')
    result = grade('--courses', courses, '--report', tmp_path / 'report', '--sandbox', 'none',
                   '--', sys.executable, ATTACKS, '@', '{waypoints}', cwd=tmp_path / 'group')
    assert result.returncode == 1, result.stdout + result.stderr
    assert {path.name: path.read_bytes() for path in courses.iterdir()} == before
    page = (tmp_path / 'report' / 'report.md').read_text()
    assert 'here.txt was changed or removed during the run (put back)' in page
    assert 'planted.txt was made in the courses' in page

"""
grade_lab end to end: our controller passes, dishonest and broken submissions fail as they should.

Submissions written for the tests (test/controllers/student.py) never drive: on a course whose
waypoint is the start pose an honest report is right, on one whose waypoint lies ahead only a
controller that drives there can be. Every run is checked to leave no process behind.
"""

import json
import os
from pathlib import Path
import re
import subprocess
import sys
from xml.etree import ElementTree

from grade_runs import grade, write_course
from processes import executable
import pytest

# Its tests share a module-scoped fixture: one worker runs them all (pytest.ini: loadgroup).
pytestmark = pytest.mark.xdist_group('grade_lab_batch')

STUDENT = Path(__file__).resolve().parents[1] / 'controllers' / 'student.py'
# Those graded on both courses; the others never report a waypoint ahead, so one course does.
ON_BOTH = ('honest', 'early')
ON_HERE = ('off10', 'silent', 'crash', 'hang', 'ignore_sigint', 'fork')


@pytest.fixture(scope='module')
def batch(tmp_path_factory):
    """
    Grade the test submissions, four runs at a time; give ({group: result}, {group: report}).

    honest and early on two courses, the others on the one at the start. grade_lab starts as
    a shell script's background job would, with SIGINT ignored: Ctrl-C must reach the
    submissions all the same (hang ends on it, and so ends when asked).
    """
    root = tmp_path_factory.mktemp('batch')
    results, reports = {}, {}
    for name, behaviours in (('both', ON_BOTH), ('here', ON_HERE)):
        (root / name).mkdir()
        courses = root / name / 'courses'
        # No submission here drives: the time limit only bounds the runs of silent and hang.
        write_course(courses, 'here', '1.0 2.0 0.0', time_limit=5)
        if name == 'both':
            write_course(courses, 'ahead', '2.0 2.0 0.0', time_limit=5, points=2)
        groups = root / name / 'groups'
        for behaviour in behaviours:
            (groups / behaviour).mkdir(parents=True)
            (groups / behaviour / 'behaviour').write_text(behaviour)
        report = root / name / 'report'
        result = grade('--courses', courses, '--submissions', groups, '--jobs', 4, '--report',
                       report, '--', sys.executable, STUDENT, '@', '{waypoints}', cwd=root,
                       timeout=900, sigint_ignored=True)
        for behaviour in behaviours:
            results[behaviour], reports[behaviour] = result, report
    return results, reports


def verdicts(report, group, course):
    """
    Return {check name: (passed, evidence)} of a group's course, from its JUnit suite.

    group None: the one submission graded (its suites are named by course alone).
    """
    suites = ElementTree.parse(report / 'junit.xml').getroot()
    name = course if group is None else f'{group}.{course}'
    suite = next(suite for suite in suites if suite.get('name') == name)
    checks = {}
    for case in suite.iter('testcase'):
        problem = case.find('failure')
        problem = case.find('error') if problem is None else problem
        checks[case.get('name')] = (problem is None, '' if problem is None
                                    else problem.get('message'))
    return checks


def test_each_submission_gets_its_verdict_and_leaves_nothing_running(batch):
    results, reports = batch
    for result in {id(result): result for result in results.values()}.values():
        assert result.returncode == 1, result.stdout + result.stderr
        # A volatile status publisher (rclpy's default) is ordinary: no warning about its QoS.
        assert 'incompatible QoS' not in result.stdout + result.stderr
    expected_failures = {
        ('honest', 'here'): set(),
        ('honest', 'ahead'): {'WAYPOINT 1'},
        ('early', 'here'): set(),
        ('early', 'ahead'): {'WAYPOINT 1'},
        ('off10', 'here'): {'WAYPOINT 1'},
        ('silent', 'here'): {'STARTED', 'WAYPOINT 1', 'FINISHED'},
        ('crash', 'here'): {'STARTED', 'WAYPOINT 1', 'FINISHED', 'ends when asked'},
        ('hang', 'here'): {'WAYPOINT 1', 'FINISHED'},
        ('ignore_sigint', 'here'): {'ends when asked'},
        ('fork', 'here'): {'ends when asked'},
    }
    for (group, course), failing in expected_failures.items():
        checks = verdicts(reports[group], group, course)
        assert set(checks) == {'STARTED', 'WAYPOINT 1', 'FINISHED', 'no wall contact',
                               'ends when asked'}
        assert {name for name, (passed, _) in checks.items() if not passed} == failing, (
            group, course, checks)

    def said(group, course, check):
        return verdicts(reports[group], group, course)[check][1]
    assert 'while the robot was 1.000 m and 0.0° from waypoint 1' in said('early', 'ahead',
                                                                          'WAYPOINT 1')
    assert '10.0 cm and 0.0° off' in said('off10', 'here', 'WAYPOINT 1')
    assert 'no message on robot_status within the time limit of 5 s' in said('silent', 'here',
                                                                             'STARTED')
    crashed = said('crash', 'here', 'ends when asked')
    assert 'crashed' in crashed and 'this submission crashes on purpose' in crashed
    assert 'within the time limit of 5 s' in said('hang', 'here', 'FINISHED')
    assert 'ignored Ctrl-C (SIGINT)' in said('ignore_sigint', 'here', 'ends when asked')
    assert 'left 1 process(es) running after it ended' in said('fork', 'here', 'ends when asked')
    table = results['honest'].stdout
    assert 'submission' in table and 'honest' in table and 'points' in table


def test_the_graders_files_hold_the_fields_courses_collect(batch):
    _, reports = batch
    for behaviour in ON_BOTH + ON_HERE:
        report = reports[behaviour]
        gradescope = json.loads((report / behaviour / 'results.json').read_text())
        assert isinstance(gradescope['score'], (int, float))
        assert [test['name'] for test in gradescope['tests']] == (
            ['ahead', 'here'] if behaviour in ON_BOTH else ['here'])
        for test in gradescope['tests']:
            assert set(test) >= {'name', 'score', 'max_score', 'status', 'output', 'visibility'}
            assert test['status'] in ('passed', 'failed') and isinstance(test['output'], str)
        assert gradescope['score'] == sum(test['score'] for test in gradescope['tests'])
        classroom = json.loads((report / behaviour / 'classroom.json').read_text())
        assert classroom['version'] == 1 and classroom['status'] in ('pass', 'fail', 'error')
        assert classroom['max_score'] == (3 if behaviour in ON_BOTH else 1)
        for test in classroom['tests']:
            assert set(test) >= {'name', 'status', 'score', 'message'}
            assert test['status'] in ('pass', 'fail', 'error')
    report = reports['honest']
    honest = json.loads((report / 'honest' / 'results.json').read_text())
    assert honest['score'] == 1 and {test['name']: test['status'] for test in
                                     honest['tests']} == {'here': 'passed', 'ahead': 'failed'}
    page = (report / 'report.md').read_text()
    assert '## honest' in page and '![here](honest/here/run.png)' in page
    assert (report / 'honest' / 'here' / 'run.mcap').stat().st_size > 0


@pytest.mark.parametrize('arguments, complaint', [
    (['--courses', 'missing.txt', '--', 'python3', '{waypoints}'],
     'missing.txt: no such course file or folder'),
    (['--courses', 'COURSES', '--', 'python3', 'x.py'], 'the command has no {waypoints}'),
    (['--courses', 'COURSES'], "give the submission's command after --"),
    (['--courses', 'COURSES', '--real-time-factor', '0', '--', 'python3', '{waypoints}'],
     '--real-time-factor 0 needs --lockstep'),
    (['--courses', 'COURSES', '--jobs', '0', '--', 'python3', '{waypoints}'],
     '--jobs must be in [1, 32], got 0'),
    (['--courses', 'COURSES', '--', 'no_such_program_here', '{waypoints}'],
     "cannot run 'no_such_program_here': no such program on PATH"),
    (['--courses', 'BAD', '--', 'python3', '{waypoints}'],
     "bad.yaml: unknown field 'time_limt'; did you mean time_limit?"),
])
def test_bad_input_is_one_line_and_exit_code_2(tmp_path, arguments, complaint):
    write_course(tmp_path / 'courses', 'fine', '1.0 2.0 0.0')
    write_course(tmp_path / 'bad', 'bad', '1.0 2.0 0.0', time_limt=3)
    places = {'COURSES': tmp_path / 'courses', 'BAD': tmp_path / 'bad'}
    arguments = [places.get(argument, argument) for argument in arguments]
    result = grade(*arguments, timeout=60, cwd=tmp_path)
    assert result.returncode == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith('grade_lab: error: ') and complaint in lines[0]


def test_another_middleware_is_refused_in_one_line(tmp_path, monkeypatch):
    write_course(tmp_path / 'courses', 'fine', '1.0 2.0 0.0')
    monkeypatch.setenv('RMW_IMPLEMENTATION', 'rmw_cyclonedds_cpp')
    result = grade('--courses', tmp_path / 'courses', '--', 'python3', '{waypoints}',
                   cwd=tmp_path)
    assert result.returncode == 2
    assert result.stderr.strip() == (
        'grade_lab: error: RMW_IMPLEMENTATION=rmw_cyclonedds_cpp: grade_lab grades on '
        'rmw_fastrtps_cpp alone (who publishes is told by its sockets and endpoints); unset it')


@pytest.mark.skipif(os.geteuid() != 0, reason='mounting a small disk takes root')
def test_a_full_report_disk_is_one_line_each_and_exit_code_1(tmp_path):
    """The report folder on a 64 kB disk: what cannot be written is said, nothing half-written."""
    write_course(tmp_path / 'courses', 'fine', '1.0 2.0 0.0', time_limit=5)
    report = tmp_path / 'report'
    report.mkdir()
    tmp_path.chmod(0o755)
    command = [executable('grade_lab'), '--courses', str(tmp_path / 'courses'), '--report',
               str(report), '--', sys.executable, '-c', 'pass',
               '{waypoints}']
    script = f'mount -t tmpfs -o size=64k tmpfs {report} && exec "$@"'
    result = subprocess.run(['unshare', '--mount', '--propagation', 'private', 'sh', '-c',
                             script, 'sh', *command], capture_output=True, text=True,
                            timeout=120, cwd=tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    assert 'Traceback' not in result.stderr + result.stdout
    lines = result.stderr.strip().splitlines()
    assert lines and all(re.fullmatch(r'grade_lab: \S+: not written: No space left on device',
                                      line) for line in lines), lines

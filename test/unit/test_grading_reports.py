"""The tick-off sheet written out: the terminal table, JUnit XML, Gradescope and Classroom."""

import json
from pathlib import Path
from xml.etree import ElementTree

from lab_grader.grading import CourseVerdict, SubmissionVerdict
from lab_grader.reports import classroom_result, gradescope_results, junit_xml, terminal_table
from lab_grader.verdicts import Check, ProcessOutcome
from waypoint_lab.course import Course

PASSED = [Check('STARTED', True, 'first'), Check('FINISHED', True, 'last')]
FAILED = [Check('STARTED', True, 'first'), Check('FINISHED', False, 'never sent')]


def verdict(name, checks, points=1.0, error=''):
    course = Course(name, (), points=points, waypoint_file=Path(f'{name}.txt'))
    return CourseVerdict(course, list(checks), ProcessOutcome(seconds=1.5), error, 3.25, 1.5)


def groups():
    return [SubmissionVerdict('group_a', [verdict('one', PASSED), verdict('two', FAILED, 2.0)]),
            SubmissionVerdict('group_b', [verdict('one', PASSED),
                                          verdict('two', (), 2.0, 'the simulator ended')])]


def test_one_submission_is_a_row_per_course_with_its_failures_below():
    table = terminal_table(groups()[:1]).splitlines()
    assert table[0].split() == ['course', 'result', 'time,', 'path', 'checks', 'passed', 'points']
    assert table[1].split() == ['one', 'PASS', '3.2', 's,', '1.5', 'm', '2/2', '1/1']
    assert table[2].split()[:2] == ['two', 'FAIL'] and table[2].endswith('0/2')
    assert table[3] == '1 of 2 courses passed: 1/3 points'
    assert table[4] == 'two: FAIL FINISHED: never sent'


def test_a_batch_is_a_row_per_submission():
    table = terminal_table(groups()).splitlines()
    assert table[0].split() == ['submission', 'one', 'two', 'points']
    assert table[1].split() == ['group_a', 'PASS', 'FAIL', '1/3']
    assert table[2].split() == ['group_b', 'PASS', 'ERROR', '1/3']
    assert 'group_b / two: ERROR the simulator ended' in table


def test_junit_has_a_suite_per_course_and_a_case_per_check():
    root = ElementTree.fromstring(junit_xml(groups()))
    assert (root.get('tests'), root.get('failures'), root.get('errors')) == ('7', '1', '1')
    names = [suite.get('name') for suite in root]
    assert names == ['group_a.one', 'group_a.two', 'group_b.one', 'group_b.two']
    failure = root[1].find("testcase[@name='FINISHED']/failure")
    assert failure.get('message') == 'never sent'


def test_junit_holds_a_submissions_terminal_colours_as_well_formed_xml():
    """A submission's output (Fast DDS colours its errors) is evidence: the XML must parse."""
    coloured = verdict('one', [Check('FINISHED', False, 'crashed: \x1b[31;1mError\x1b[m')])
    coloured.outcome = ProcessOutcome(seconds=1.5, last_lines=('\x1b[37;1m[RTPS] \x07boom',))
    root = ElementTree.fromstring(junit_xml([SubmissionVerdict('g', [coloured])]))
    assert root[0].find('testcase/failure').get('message') == 'crashed: \ufffd[31;1mError\ufffd[m'
    assert root[0].find('system-out').text == '\ufffd[37;1m[RTPS] \ufffdboom'


def test_the_graders_results_add_up():
    group_a = groups()[0]
    gradescope = json.loads(gradescope_results(group_a))
    assert gradescope['score'] == 1.0
    assert [(test['name'], test['score'], test['max_score'], test['status']) for test in
            gradescope['tests']] == [('one', 1.0, 1.0, 'passed'), ('two', 0.0, 2.0, 'failed')]
    assert 'FAIL FINISHED: never sent' in gradescope['tests'][1]['output']
    classroom = json.loads(classroom_result(group_a, ['python3', 'x.py', '{waypoints}']))
    assert (classroom['version'], classroom['status'], classroom['max_score']) == (1, 'fail', 3.0)
    assert [(test['name'], test['status'], test['score']) for test in classroom['tests']] == [
        ('one', 'pass', 1.0), ('two', 'fail', 0.0)]
    assert classroom['tests'][0]['test_code'] == 'python3 x.py {waypoints}'

"""
Verdicts written where courses collect them: a terminal table, JUnit XML, Gradescope, Classroom.

Gradescope reads /autograder/results/results.json ({score, output, tests: [{name, score,
max_score, status, output, visibility}]}); GitHub Classroom's grading reporter reads a runner's
result ({version: 1, status, max_score, tests: [{name, status, score, message, ...}]}) from a
step output, base64-encoded; CI systems show JUnit XML. A course is one test in the graders'
files, worth its points when every check passes, its checks listed in its output; in JUnit
each check is a test case of the course's suite. No ROS here.
"""

import json
import math
import re
from xml.etree import ElementTree

from lab_grader.grading import CourseVerdict, ERROR, PASS, SubmissionVerdict
from lab_grader.verdicts import HEADING_MATCH, LATENCY, POSITION_MATCH, SLACK

MARKS = {PASS: 'PASS', 'fail': 'FAIL', ERROR: 'ERROR'}
# The characters XML 1.0 has no place for: control codes but tab, newline and return.
_NOT_IN_XML = re.compile('[^\t\n\r\x20-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]')
RULES = (f'a report counts if, between {LATENCY:g} s of sim time before it was sent and '
         f'{SLACK:g} s after, the robot stood in the goal set at the pose reported (within '
         f'{POSITION_MATCH * 100:g} cm and {math.degrees(HEADING_MATCH):g}°)')


def _points(value):
    return f'{value:g}'


def check_lines(verdict: CourseVerdict, passed_too: bool = True) -> list[str]:
    """Return a course's checks as lines 'PASS name: evidence' (failures only if asked)."""
    if verdict.error:
        return [f'ERROR {verdict.error}']
    return [f'{"PASS" if check.passed else "FAIL"} {check.name}: {check.evidence}'
            for check in verdict.checks if passed_too or not check.passed]


def figures(verdict: CourseVerdict) -> str:
    """Say how long the course took and how far the robot drove, where measured."""
    parts = []
    if verdict.time_taken is not None:
        parts.append(f'{verdict.time_taken:.1f} s')
    if verdict.path_length is not None:
        parts.append(f'{verdict.path_length:.1f} m')
    return ', '.join(parts) or '-'


def terminal_table(submissions: list[SubmissionVerdict]) -> str:
    """Return the tick-off sheet: a row per course (one submission) or per submission."""
    if len(submissions) == 1:
        return _course_table(submissions[0])
    courses = [verdict.course.name for verdict in submissions[0].courses]
    rows = [['submission', *courses, 'points']]
    for submission in submissions:
        rows.append([submission.name, *(MARKS[verdict.status] for verdict in
                                        submission.courses),
                     f'{_points(submission.score)}/{_points(submission.max_score)}'])
    lines = _aligned(rows)
    for submission in submissions:
        for verdict in submission.courses:
            lines += [f'{submission.name} / {verdict.course.name}: {line}'
                      for line in check_lines(verdict, passed_too=False)]
    return '\n'.join(lines)


def _course_table(submission):
    rows = [['course', 'result', 'time, path', 'checks passed', 'points']]
    for verdict in submission.courses:
        passed = sum(check.passed for check in verdict.checks)
        rows.append([verdict.course.name, MARKS[verdict.status], figures(verdict),
                     f'{passed}/{len(verdict.checks)}' if verdict.checks else '-',
                     f'{_points(verdict.score)}/{_points(verdict.course.points)}'])
    passed = sum(verdict.status == PASS for verdict in submission.courses)
    lines = _aligned(rows)
    lines.append(f'{passed} of {len(submission.courses)} courses passed: '
                 f'{_points(submission.score)}/{_points(submission.max_score)} points')
    for verdict in submission.courses:
        lines += [f'{verdict.course.name}: {line}'
                  for line in check_lines(verdict, passed_too=False)]
    return '\n'.join(lines)


def _aligned(rows):
    widths = [max(len(row[column]) for row in rows) for column in range(len(rows[0]))]
    return ['  '.join(cell.ljust(width) for cell, width in zip(row, widths)).rstrip()
            for row in rows]


def _output_tail(verdict):
    return '\n'.join(verdict.outcome.last_lines[-20:])


def _xml_text(text):
    """Return text with what XML 1.0 cannot hold (a terminal's escape codes) as U+FFFD."""
    return _NOT_IN_XML.sub('\ufffd', text)


def junit_xml(submissions: list[SubmissionVerdict]) -> bytes:
    """Return JUnit XML: a suite per submission and course, a test case per check."""
    root = ElementTree.Element('testsuites', name='grade_lab')
    totals = {'tests': 0, 'failures': 0, 'errors': 0}
    for submission in submissions:
        for verdict in submission.courses:
            suite_name = (verdict.course.name if len(submissions) == 1
                          else f'{submission.name}.{verdict.course.name}')
            suite = ElementTree.SubElement(root, 'testsuite', name=suite_name)
            counts = {'tests': 0, 'failures': 0, 'errors': 0}
            if verdict.error:
                case = ElementTree.SubElement(suite, 'testcase', classname=suite_name,
                                              name='run')
                ElementTree.SubElement(case, 'error', message=_xml_text(verdict.error))
                counts.update(tests=1, errors=1)
            for check in verdict.checks:
                case = ElementTree.SubElement(suite, 'testcase', classname=suite_name,
                                              name=check.name)
                counts['tests'] += 1
                if not check.passed:
                    evidence = _xml_text(check.evidence)
                    failure = ElementTree.SubElement(case, 'failure', message=evidence)
                    failure.text = evidence
                    counts['failures'] += 1
            ElementTree.SubElement(suite, 'system-out').text = _xml_text(_output_tail(verdict))
            for key, value in counts.items():
                suite.set(key, str(value))
                totals[key] += value
    for key, value in totals.items():
        root.set(key, str(value))
    ElementTree.indent(root)
    return ElementTree.tostring(root, encoding='utf-8', xml_declaration=True)


def gradescope_results(submission: SubmissionVerdict) -> str:
    """Return Gradescope's results.json of one submission: a test per course."""
    tests = [{'name': verdict.course.name, 'score': verdict.score,
              'max_score': verdict.course.points,
              'status': 'passed' if verdict.status == PASS else 'failed',
              'output': '\n'.join(check_lines(verdict)), 'visibility': 'visible'}
             for verdict in submission.courses]
    passed = sum(verdict.status == PASS for verdict in submission.courses)
    return json.dumps({'score': submission.score, 'output': f'{passed} of '
                       f'{len(submission.courses)} courses passed; {RULES}.',
                       'visibility': 'visible', 'tests': tests}, indent=2)


def classroom_result(submission: SubmissionVerdict, command: list[str]) -> str:
    """Return GitHub Classroom's runner result of one submission: a test per course."""
    tests = [{'name': verdict.course.name, 'status': verdict.status,
              'score': verdict.score, 'message': '\n'.join(check_lines(verdict)),
              'test_code': ' '.join(command), 'filename': verdict.course.waypoint_file.name,
              'line_no': 0, 'duration': round(verdict.outcome.seconds * 1000)}
             for verdict in submission.courses]
    return json.dumps({'version': 1, 'status': submission.status,
                       'max_score': submission.max_score, 'tests': tests}, indent=2)

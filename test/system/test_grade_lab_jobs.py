"""grade_lab on our own controller: verdicts agree however many courses run at once."""

from xml.etree import ElementTree

from grade_runs import grade, write_course
from simple_robot_control.share import installed_executable


def short_courses(folder):
    write_course(folder, 'forward', '2.0 2.0 0.0')
    write_course(folder, 'turn', '1.0 2.0 90.0')
    write_course(folder, 'diagonal', '1.6 2.6 45.0')
    write_course(folder, 'back', '0.6 2.0 0.0')
    return folder


def test_verdicts_agree_whatever_the_number_of_runs_at_once(tmp_path):
    """At real time, courses graded four at a time on two cores are judged as one at a time."""
    courses = short_courses(tmp_path / 'courses')
    outcomes = []
    for jobs in (1, 4):
        report = tmp_path / f'jobs{jobs}'
        result = grade('--courses', courses, '--jobs', jobs, '--report', report, '--',
                       installed_executable('waypoint_controller'), '{waypoints}')
        assert result.returncode == 0, result.stdout + result.stderr
        suites = ElementTree.parse(report / 'junit.xml').getroot()
        outcomes.append({(suite.get('name'), case.get('name'), case.find('failure') is None)
                         for suite in suites for case in suite.iter('testcase')})
    assert outcomes[0] == outcomes[1]
    assert len(outcomes[0]) == 4 * 5

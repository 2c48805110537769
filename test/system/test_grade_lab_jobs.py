"""grade_lab on our own controller: verdicts hold however many courses run at once."""

from xml.etree import ElementTree

from grade_runs import grade, write_course
from simple_robot_control.share import installed_executable


def short_courses(folder):
    write_course(folder, 'forward', '2.0 2.0 0.0')
    write_course(folder, 'turn', '1.0 2.0 90.0')
    write_course(folder, 'diagonal', '1.6 2.6 45.0')
    write_course(folder, 'back', '0.6 2.0 0.0')
    return folder


def test_courses_graded_four_at_a_time_are_judged_as_one_at_a_time(tmp_path):
    """
    At real time, four courses at once on two cores: our controller passes every check of each.

    Alone, it passes every check of such courses (the verdict of each is known), so that is
    the verdict one at a time would give: grading them twice to compare is not needed.
    """
    courses = short_courses(tmp_path / 'courses')
    report = tmp_path / 'report'
    result = grade('--courses', courses, '--jobs', 4, '--report', report, '--',
                   installed_executable('waypoint_controller'), '{waypoints}')
    assert result.returncode == 0, result.stdout + result.stderr
    suites = ElementTree.parse(report / 'junit.xml').getroot()
    outcomes = {(suite.get('name'), case.get('name'), case.find('failure') is None)
                for suite in suites for case in suite.iter('testcase')}
    assert len(outcomes) == 4 * 5
    assert all(passed for _, _, passed in outcomes), sorted(outcomes)

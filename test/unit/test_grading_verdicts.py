"""The tick-off sheet's rules on runs made up here: every check, passed and failed, and why."""

import math

from lab_grader.verdicts import Judge, LATENCY, ProcessOutcome
import numpy as np
import pytest
from waypoint_lab.course import Course
from waypoint_lab.run import Report, Run
from waypoint_lab.status import parse_status
from waypoint_lab.waypoints import Waypoint

STEP = 0.02
COURSE = Course('line', (Waypoint(2.0, 2.0, 0.0), Waypoint(3.0, 2.0, 0.0)))


def drive(seconds_still_after=2.0):
    """Drive from (1, 2) to (3, 2) at 0.5 m/s from t = 1 s, then stand; give times and poses."""
    times = np.arange(0.0, 5.0 + seconds_still_after, STEP)
    x = np.clip(1.0 + 0.5 * (times - 1.0), 1.0, 3.0)
    return times, np.column_stack([x, np.full_like(x, 2.0), np.zeros_like(x)])


def at(times, poses, x):
    """Return the first time the robot is at x or beyond, and its pose then."""
    index = int(np.argmax(poses[:, 0] >= x - 1e-9))
    return float(times[index]), tuple(poses[index])


def report(text, time):
    return Report(text, parse_status(text), time)


def pose_text(pose, dx=0.0, dtheta=0.0):
    x, y, theta = pose
    return f'{x + dx:.3f} {y:.3f} {math.degrees(theta) + dtheta:.2f}'


def honest_reports(times, poses, delay=0.0):
    first, second = at(times, poses, 2.0), at(times, poses, 3.0)
    return [report(f'STARTED {pose_text(poses[0])}', 0.5),
            report(f'WAYPOINT 1 {pose_text(first[1])}', first[0] + delay),
            report(f'WAYPOINT 2 {pose_text(second[1])}', second[0] + delay),
            report('FINISHED', second[0] + delay)]


def judge(reports, outcome=ProcessOutcome(ended_by='SIGINT', exit_code=-2), course=COURSE,
          still_after=2.0, stalled=0):
    times, poses = drive(still_after)
    run = Run(course, times, poses, reports, stalled, 3.0 if stalled else None)
    return Judge(course, run, outcome)


def checks(reports, **options):
    return {check.name: check for check in judge(reports, **options).checks()}


def failing(reports, **options):
    return {name: check.evidence for name, check in checks(reports, **options).items()
            if not check.passed}


def test_an_honest_run_passes_every_check_with_its_figures():
    times, poses = drive()
    run = judge(honest_reports(times, poses))
    assert [check.name for check in run.checks()] == [
        'STARTED', 'WAYPOINT 1', 'WAYPOINT 2', 'FINISHED', 'no wall contact', 'ends when asked']
    assert all(check.passed for check in run.checks()), run.checks()
    assert run.time_taken == pytest.approx(4.5)
    assert run.path_length == pytest.approx(2.0, abs=0.011)


def test_a_report_heard_late_counts_within_the_latency_allowance_only():
    times, poses = drive()
    assert not failing(honest_reports(times, poses, delay=LATENCY - 0.1))
    problems = failing(honest_reports(times, poses, delay=LATENCY + 0.25))
    assert 'm and 0.0° from waypoint 1' in problems['WAYPOINT 1']


def test_a_report_before_the_goal_set_fails_naming_the_waypoint():
    times, poses = drive()
    reports = honest_reports(times, poses)
    early_time, early_pose = at(times, poses, 1.5)
    reports[1] = report(f'WAYPOINT 1 {pose_text(early_pose)}', early_time)
    nearest = 2.0 - 1.5 - 0.5 * 0.04  # the robot drives on for the window's slack after it
    assert failing(reports) == {'WAYPOINT 1': f'sent at t = {early_time:.2f} s while the robot '
                                f'was {nearest:.3f} m and 0.0° from waypoint 1 (goal set: 0.1 m '
                                'and 5.0°)'}


@pytest.mark.parametrize('dx, dtheta, complaint', [
    (0.1, 0.0, '10.0 cm and 0.0° off (at most 2 cm and 1.0°)'),
    (0.0, 3.0, '0.0 cm and 3.0° off'),
])
def test_a_report_of_a_pose_not_the_true_one_fails(dx, dtheta, complaint):
    times, poses = drive()
    reports = honest_reports(times, poses)
    time, pose = at(times, poses, 3.0)
    reports[2] = report(f'WAYPOINT 2 {pose_text(pose, dx, dtheta)}', time + 0.5)
    problem = failing(reports)['WAYPOINT 2']
    assert problem.startswith('reported (') and complaint in problem


def test_order_counts_and_repeats_fail():
    times, poses = drive()
    started, first, second, finished = honest_reports(times, poses)
    assert failing([first, started, second, finished])['STARTED'].startswith(
        "the first message was 'WAYPOINT 1")
    assert 'out of order' in failing([started, second, first, finished])['WAYPOINT 1']
    assert failing([started, first, first, second, finished])['WAYPOINT 1'] == 'sent 2 times'
    assert failing([started, started, first, second, finished])['STARTED'] == 'sent 2 times'
    assert failing([started, first, finished, second])['FINISHED'] == 'sent before WAYPOINT 2'
    assert failing([started, first, second, finished, report('hello', 5.0)])[
        'FINISHED'] == "1 message(s) after it, the first 'hello'"


def test_a_robot_still_moving_after_finished_fails_and_lockstep_stands_still():
    times, poses = drive()
    started, first, _, _ = honest_reports(times, poses)
    time, pose = at(times, poses, 2.3)
    moving = [started, first, report(f'WAYPOINT 2 {pose_text(pose)}', time),
              report('FINISHED', time)]
    course = Course('line', (Waypoint(2.0, 2.0, 0.0), Waypoint(2.3, 2.0, 0.0)))
    assert 'the robot did not stop: it moved' in failing(moving, course=course)['FINISHED']
    assert 'did not step on after it' in checks(
        honest_reports(*drive(0.4)), still_after=0.4)['FINISHED'].evidence


def test_contact_and_graded_limits():
    times, poses = drive()
    reports = honest_reports(times, poses)
    assert failing(reports, stalled=5) == {
        'no wall contact': 'pushed against a wall for 0.10 s (5 steps), first at t = 3.00 s '
        'at (2.000, 2.000, 0.0°)'}
    limited = Course('line', COURSE.waypoints, max_time=4.0, max_path_length=3.0)
    results = checks(reports, course=limited)
    assert not results['time'].passed and results['time'].evidence == (
        '4.50 s, over the limit of 4 s')
    assert results['path length'].passed


@pytest.mark.parametrize('outcome, passed, words', [
    (ProcessOutcome(exit_code=0, seconds=7.0), True, 'exited by itself with exit code 0'),
    (ProcessOutcome(exit_code=1, seconds=2.0, last_lines=('Traceback', 'ValueError: x')),
     False, 'crashed after 2.0 s: exit code 1; its last lines:\n    Traceback\n    ValueError'),
    (ProcessOutcome(exit_code=-11), False, 'killed by signal 11'),
    (ProcessOutcome(ended_by='SIGINT', exit_code=1, stop_seconds=0.3), True,
     'ended on Ctrl-C (SIGINT) in 0.3 s'),
    (ProcessOutcome(ended_by='SIGTERM', exit_code=-15, stop_seconds=5.0), False,
     'ignored Ctrl-C (SIGINT) for 5 s: ended only by SIGTERM'),
    (ProcessOutcome(leftovers=('pid 7 (sleep 600)',)), False,
     'left 1 process(es) running after it ended, killed: pid 7 (sleep 600)'),
    (ProcessOutcome(start_error='cannot start x: No such file'), False, 'cannot start x'),
])
def test_how_the_program_ended(outcome, passed, words):
    times, poses = drive()
    ending = checks(honest_reports(times, poses), outcome=outcome)['ends when asked']
    assert ending.passed == passed and words in ending.evidence


def test_silence_says_why_the_run_ended():
    problems = failing([], outcome=ProcessOutcome(ended_by='SIGINT', timed_out=True))
    assert problems['STARTED'] == 'no message on robot_status within the time limit of 120 s'
    assert problems['WAYPOINT 1'] == 'never sent'
    crashed = failing([], outcome=ProcessOutcome(exit_code=1, seconds=0.4))
    assert crashed['FINISHED'] == 'never sent (the program ended after 0.4 s, exit code 1)'

"""The grader's evidence: the simulator's socket, who publishes where, a drivable path."""

import math
import os
from pathlib import Path
import socket

from lab_grader.grading import grade_course, RunEvidence
from lab_grader.publishers import find_intruders, process_bits, Publisher
from lab_grader.recorder import status_limit
from lab_grader.simulator_link import SimulatorLink, SpeedLimits
from lab_grader.verdicts import FAIR_PLAY, ProcessOutcome, undrivable
from waypoint_lab.course import Course
from waypoint_lab.run import assemble_run
from waypoint_lab.waypoints import Waypoint

COURSE = Course('here', (Waypoint(1.0, 2.0, 0.0),))
LIMITS = SpeedLimits(0.02, 1.0, 2.0)


def gid(pid, vendor=b'\x01\x0f'):
    """Make a Fast DDS endpoint id of a process: vendor, host, the pid's low 16 bits, the rest."""
    return vendor + b'\x78\xfd' + (pid & 0xFFFF).to_bytes(2, 'little') + bytes(10)


def test_a_publisher_is_traced_to_its_process_by_the_low_bits_of_its_pid():
    assert process_bits(gid(4571)) == 4571
    assert process_bits(gid(70000)) == 70000 & 0xFFFF
    assert process_bits(gid(4571, vendor=b'\x01\x10')) is None
    assert process_bits(b'\x01') is None


def test_only_the_simulator_may_publish_on_its_topics_and_only_the_submission_its_status():
    simulator, submission, stranger = 100, 200, 300
    found = find_intruders(
        [Publisher('/clock', '/stdr_lite', gid(simulator)),
         Publisher('/robot0/ground_truth', '/cheat', gid(submission)),
         Publisher('/tf', '/demo', gid(stranger))],
        [Publisher('/robot_status', '/student', gid(submission)),
         Publisher('/robot_status', '/other', gid(stranger))],
        simulator, {submission, 201}, running={simulator, submission, stranger})
    assert found.fouls == ["/robot0/ground_truth was published by node '/cheat' of the "
                           'submission (only the simulator publishes it)']
    assert len(found.strangers) == 2
    assert all('a process outside this run' in line for line in found.strangers)
    assert "'/demo'" in found.strangers[0] and '/robot_status' in found.strangers[1]


def test_a_publisher_whose_process_has_ended_is_the_submissions():
    """The domain was empty at the start: a process gone by now was one of the run's."""
    found = find_intruders([Publisher('/clock', '/gone', gid(400))],
                           [Publisher('/robot_status', '/gone', gid(400))], 100, {200},
                           running={100, 200, 300})
    assert found.strangers == [] and len(found.fouls) == 1


def test_a_run_may_send_ten_times_an_honest_runs_statuses_and_a_hundred_more():
    assert status_limit(COURSE) == 130


def path(poses, step=0.02, stalled=()):
    return [(index * step, tuple(pose), 1_000 + index, index in stalled)
            for index, pose in enumerate(poses)]


def test_a_path_faster_than_the_speed_limits_is_not_drivable():
    still = assemble_run(COURSE, path([(1.0, 2.0, 0.0)] * 3), [])
    assert undrivable(still, LIMITS) == ''
    driven = assemble_run(COURSE, path([(1.0 + 0.02 * i, 2.0, 0.0) for i in range(5)]), [])
    assert undrivable(driven, LIMITS) == ''
    jumped = assemble_run(COURSE, path([(1.0, 2.0, 0.0), (1.0, 2.0, 0.0), (4.0, 2.0, 0.0)]),
                          [])
    problem = undrivable(jumped, LIMITS)
    assert 'not drivable: the robot went 3.000 m' in problem and 't = 0.04 s' in problem
    spun = assemble_run(COURSE, path([(1.0, 2.0, 0.0), (1.0, 2.0, 1.0)]), [])
    assert 'turned 57.3°' in undrivable(spun, LIMITS)
    # Across the wrap at pi a small turn is a small turn.
    wrapped = assemble_run(COURSE, path([(1.0, 2.0, math.pi - 0.01),
                                         (1.0, 2.0, -math.pi + 0.01)]), [])
    assert undrivable(wrapped, LIMITS) == ''


def test_statuses_are_dated_by_the_truth_sent_before_them():
    run = assemble_run(COURSE, path([(1.0, 2.0, 0.0)] * 10, stalled={4}),
                       [(1_003, 'STARTED 1.000 2.000 0.00'), (1_007, 'FINISHED')])
    assert [report.time for report in run.reports] == [0.06, 0.14]
    assert run.stalled_steps == 1 and run.first_stall == 0.08


def evidence(truth, statuses, fouls=()):
    return RunEvidence(ProcessOutcome(ended_by='SIGINT', exit_code=0), Path('run.mcap'), '',
                       truth, statuses, LIMITS, fouls)


HONEST = [(1_001, 'STARTED 1.000 2.000 0.00'), (1_002, 'WAYPOINT 1 1.000 2.000 0.00'),
          (1_003, 'FINISHED')]


def test_an_honest_run_shows_no_fair_play_line_and_a_foul_fails_it():
    verdict = grade_course(COURSE, evidence(path([(1.0, 2.0, 0.0)] * 60), HONEST))
    assert verdict.status == 'pass'
    assert FAIR_PLAY not in [check.name for check in verdict.checks]
    fouled = grade_course(COURSE, evidence(path([(1.0, 2.0, 0.0)] * 60), HONEST,
                                           ('/clock was published by node ...',)))
    assert fouled.status == 'fail'
    assert [check.name for check in fouled.failures] == [FAIR_PLAY]
    teleported = grade_course(COURSE, evidence(
        path([(3.0, 2.0, 0.0)] * 5 + [(1.0, 2.0, 0.0)] * 55),
        [(sent + 10, text) for sent, text in HONEST]))
    assert [check.name for check in teleported.failures] == [FAIR_PLAY]
    assert 'not drivable' in teleported.failures[0].evidence


def test_a_foul_fails_the_course_even_when_the_run_also_broke_off():
    broken = evidence([], [], ('the simulator was ended during the run (killed by signal 9), '
                               'not by the grader',))
    broken.error = 'the simulator ended'
    verdict = grade_course(COURSE, broken)
    assert verdict.status == 'fail'
    assert 'killed by signal 9' in verdict.checks[-2].evidence


def test_the_link_keeps_the_graded_robots_truth_and_refuses_what_is_no_line_of_the_simulator():
    link = SimulatorLink('robot0')
    theirs = os.dup(link.descriptor)
    link.handed_over()
    writer = socket.socket(fileno=theirs)
    writer.sendall(b'limits 0.02 1.5 2.5\n'
                   b'truth robot0 20000000 1000 1.0 2.0 0.5 0\n'
                   b'truth robot1 20000000 1000 9.0 9.0 0.0 0\n'
                   b'truth robot0 40000000 1001 1.1 2.0 0.5 1\n')
    assert link.play()
    assert writer.recv(5) == b'play\n'
    writer.sendall(b'truth robot0 oops\n')
    writer.close()
    link.close()
    assert link.limits == SpeedLimits(0.02, 1.5, 2.5)
    assert link.truth() == [(0.02, (1.0, 2.0, 0.5), 1000, False),
                            (0.04, (1.1, 2.0, 0.5), 1001, True)]
    assert 'truth robot0 oops' in link.problem
    assert link.last_sent == 1001
    assert not link.play()

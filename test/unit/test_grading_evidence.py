"""The grader's evidence: the simulator's socket, who publishes where, a drivable path."""

import math
import os
from pathlib import Path
import socket

from lab_grader.grading import grade_course, RunEvidence
from lab_grader.publishers import (domain_ports, find_intruders, Owner, Publisher,
                                   socket_owners, strangers)
from lab_grader.recorder import status_limit
from lab_grader.simulator_link import SimulatorLink, SpeedLimits
from lab_grader.verdicts import FAIR_PLAY, ProcessOutcome, undrivable
from waypoint_lab.course import Course
from waypoint_lab.run import assemble_run
from waypoint_lab.waypoints import Waypoint

COURSE = Course('here', (Waypoint(1.0, 2.0, 0.0),))
LIMITS = SpeedLimits(0.02, 1.0, 2.0)


def gid(number):
    """Make an endpoint id: what a publisher claims of itself, nothing the grader trusts."""
    return b'\x01\x0f' + number.to_bytes(14, 'little')


def test_only_the_simulators_own_endpoints_may_publish_on_its_topics():
    simulator = [Publisher('/clock', '/stdr_lite', gid(1)),
                 Publisher('/robot0/odom', '/stdr_lite', gid(2))]
    forged = Publisher('/robot0/ground_truth', '/stdr_lite', gid(3))
    found = find_intruders(simulator + [forged], {gid(1), gid(2)}, [])
    assert found.fouls == ["/robot0/ground_truth was published by node '/stdr_lite' of the "
                           'submission (only the simulator publishes it)']
    assert found.strangers == []


def test_a_publisher_whose_node_is_not_yet_on_the_graph_is_said_so():
    early = Publisher('/clock', '_NODE_NAMESPACE_UNKNOWN_/_NODE_NAME_UNKNOWN_', gid(3))
    assert find_intruders([early], {gid(1)}, []).fouls == [
        '/clock was published by the submission (a node the graph had not named yet) (only the '
        'simulator publishes it)']


def test_with_another_program_in_the_domain_nobody_is_blamed_and_it_is_named():
    found = find_intruders([Publisher('/clock', '/x', gid(3))], {gid(1)}, ['another (pid 9)'])
    assert found.fouls == [] and found.strangers == ['another (pid 9)']


def fake_proc(folder, sockets, processes):
    """Write a /proc of crafted UDP sockets (port, uid, inode) and processes (pid: inodes)."""
    lines = ['  sl  local_address rem_address   st tx_queue rx_queue tr tm->when retrnsmt   uid'
             '  timeout inode']
    for number, (port, uid, inode) in enumerate(sockets):
        lines.append(f'{number:4}: 0100007F:{port:04X} 00000000:0000 07 00000000:00000000 '
                     f'00:00000000 00000000 {uid:5} 0 {inode} 2 0000000000000000 0')
    (folder / 'net').mkdir(parents=True)
    (folder / 'net' / 'udp').write_text('\n'.join(lines) + '\n')
    for pid, inodes in processes.items():
        (folder / str(pid) / 'fd').mkdir(parents=True)
        for descriptor, inode in enumerate(inodes):
            (folder / str(pid) / 'fd' / str(descriptor)).symlink_to(f'socket:[{inode}]')
    return folder


def test_who_joined_a_domain_is_told_by_the_kernel_not_by_the_endpoints(tmp_path):
    """Domain 5's ports are 8650-8899: a socket there is a participant's, its owner known."""
    assert domain_ports(5) == range(8650, 8900)
    proc = fake_proc(tmp_path, [(8660, 0, 101), (8662, 0, 102), (8664, 1000, 103),
                                (7410, 1000, 104), (8666, 2000, 105)],
                     {10: [101], 20: [102], 30: [103], 40: [104]})
    owners = socket_owners(5, proc)
    assert owners == {Owner(10, 0), Owner(20, 0), Owner(30, 1000), Owner(0, 2000)}
    named = strangers(owners, run_pids={10, 20}, submission_uid=None)
    assert len(named) == 2 and '(uid 2000,' in named[0] and 'pid 30, uid 1000' in named[1]
    assert strangers(owners, run_pids={10, 20, 30}, submission_uid=2000) == []


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

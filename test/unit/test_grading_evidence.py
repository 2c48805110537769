"""A graded run read from its bag: statuses dated by when they were sent, stalls, lost steps."""

import math

from lab_grader.evidence import read_evidence
import pytest
from rosbags.typesys import get_typestore, Stores
from simple_robot_control.bag import BagWriter
from test_run_bag import LATCHED, odometry

STORE = get_typestore(Stores.ROS2_JAZZY)
T = STORE.types
MS = 1_000_000


def write_run(path, steps=50, skip=(), late_status=0):
    """
    Write a run as the grader's recorder would, wall time 1 ms per step of 20 ms.

    A status is sent at step 10 but written (received) late_status steps later; stall is true
    from step 30 on; the steps in skip have no ground truth.
    """
    bag = BagWriter(path)
    truth = bag.add_topic('/robot0/ground_truth', 'nav_msgs/msg/Odometry', LATCHED)
    stall = bag.add_topic('/robot0/stall', 'std_msgs/msg/Bool', LATCHED)
    status = bag.add_topic('/robot_status', 'std_msgs/msg/String', LATCHED)
    pending = []
    for step in range(steps):
        sent = 1000 * MS + step * MS
        if step not in skip:
            bag.write(truth, sent, STORE.serialize_cdr(odometry(step * 0.02, 1.0 + 0.01 * step),
                                                       'nav_msgs/msg/Odometry'), sent)
            bag.write(stall, sent, STORE.serialize_cdr(T['std_msgs/msg/Bool'](data=step >= 30),
                                                       'std_msgs/msg/Bool'), sent)
        if step == 10:
            pending.append((step + late_status, sent + MS // 2, 'WAYPOINT 1 1.100 2.000 0.00'))
        for due, when, text in [item for item in pending if item[0] == step]:
            bag.write(status, sent, STORE.serialize_cdr(T['std_msgs/msg/String'](data=text),
                                                        'std_msgs/msg/String'), when)
            pending.remove((due, when, text))
    bag.close()


@pytest.mark.parametrize('late', [0, 25])
def test_a_status_is_dated_by_when_it_was_sent_however_late_it_was_received(tmp_path, late):
    write_run(tmp_path / 'run.mcap', late_status=late)
    evidence = read_evidence(tmp_path / 'run.mcap')
    assert len(evidence.times) == 50 and evidence.step == pytest.approx(0.02)
    [report] = evidence.reports
    assert report.time == pytest.approx(0.2) and report.status.number == 1
    assert evidence.pose_at(report.time)[0] == pytest.approx(1.1)
    assert evidence.stalled_steps == 20 and evidence.first_stall == pytest.approx(0.6)
    assert evidence.stalled_seconds == pytest.approx(0.4)
    assert evidence.path_length(0.0, 0.2) == pytest.approx(0.1)
    assert evidence.missing_steps == 0


def test_steps_lost_by_the_recorder_are_counted(tmp_path):
    write_run(tmp_path / 'run.mcap', skip={5, 6, 40})
    assert read_evidence(tmp_path / 'run.mcap').missing_steps == 3


def test_a_robots_own_topics_only(tmp_path):
    write_run(tmp_path / 'run.mcap')
    evidence = read_evidence(tmp_path / 'run.mcap', robot_name='robot1')
    assert not len(evidence.times) and evidence.pose_at(1.0) is None
    assert evidence.reports[0].time == 0.0 and not math.isnan(evidence.step)

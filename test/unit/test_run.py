"""The one model of a run, read from a bag: course, path, reports dated as sent, stalls, cuts."""

import math

import pytest
from run_bags import LATCHED, odometry, STORE, T, write_run
from simple_robot_control.bag import BagWriter
from waypoint_lab.course import Course
from waypoint_lab.plot_run import main as plot_run
from waypoint_lab.run import read_run, RunError
from waypoint_lab.waypoints import Waypoint

MS = 1_000_000
COURSE = Course('line', (Waypoint(1.1, 2.0, 0.0),))


def test_a_bag_gives_the_course_the_path_and_the_dated_statuses(tmp_path):
    write_run(tmp_path / 'run.mcap').close()
    run = read_run(tmp_path / 'run.mcap')
    assert run.course.waypoints == ((3.0, 2.0, 0.0),) and run.course.name == ''
    assert len(run.poses) == 101 and run.poses[-1] == pytest.approx((3.0, 2.0, 0.0))
    assert [report.text for report in run.statuses] == [
        'STARTED 1.000 2.000 0.00', 'WAYPOINT 1 3.000 2.000 0.00', 'FINISHED']
    assert run.statuses[1].time == pytest.approx(2.0) and run.result == 'FINISHED'
    assert run.duration == pytest.approx(2.0)
    assert [report.text for report in run.foreign] == ['hello from another node']
    assert not run.cut_short


def test_a_bag_folder_is_read_as_its_mcap_file(tmp_path):
    (tmp_path / 'run').mkdir()
    write_run(tmp_path / 'run' / 'run_0.mcap').close()
    assert read_run(tmp_path / 'run').result == 'FINISHED'


def test_a_bag_cut_short_is_read_up_to_its_last_chunk(tmp_path):
    bag = write_run(tmp_path / 'cut.mcap', steps=20_000, finish=False)
    bag._stream.flush()  # killed here: no summary, the last chunk unwritten
    run = read_run(tmp_path / 'cut.mcap')
    assert 0 < len(run.poses) < 20_001 and run.cut_short
    assert run.result is None


def test_a_bag_without_the_course_needs_it_given(tmp_path):
    bag = BagWriter(tmp_path / 'run.mcap')
    channel = bag.add_topic('/robot0/odom', 'nav_msgs/msg/Odometry', LATCHED)
    bag.write(channel, 0, STORE.serialize_cdr(odometry(0.0, 1.0), 'nav_msgs/msg/Odometry'))
    bag.close()
    with pytest.raises(RunError, match='no /waypoints in the bag'):
        read_run(tmp_path / 'run.mcap')
    assert len(read_run(tmp_path / 'run.mcap', course=COURSE).poses) == 1


def test_a_course_off_any_map_is_refused_in_one_line(tmp_path, capsys):
    write_run(tmp_path / 'run.mcap', goal_x=1e308).close()
    with pytest.raises(RunError, match='/waypoints: a waypoint off any map'):
        read_run(tmp_path / 'run.mcap')
    assert plot_run([str(tmp_path / 'run.mcap')]) == 2
    error = capsys.readouterr().err
    assert len(error.splitlines()) == 1 and 'a waypoint off any map' in error
    assert not (tmp_path / 'run.png').exists()


def write_graded_run(path, steps=50, skip=(), late_status=0):
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
    write_graded_run(tmp_path / 'run.mcap', late_status=late)
    run = read_run(tmp_path / 'run.mcap', path_topic='ground_truth', course=COURSE)
    assert len(run.times) == 50 and run.step == pytest.approx(0.02)
    [report] = run.reports
    assert report.time == pytest.approx(0.2) and report.status.number == 1
    assert run.pose_at(report.time)[0] == pytest.approx(1.1)
    assert run.stalled_steps == 20 and run.first_stall == pytest.approx(0.6)
    assert run.stalled_seconds == pytest.approx(0.4)
    assert run.path_length(0.0, 0.2) == pytest.approx(0.1)
    assert run.missing_steps == 0


def test_steps_lost_by_the_recorder_are_counted(tmp_path):
    write_graded_run(tmp_path / 'run.mcap', skip={5, 6, 40})
    assert read_run(tmp_path / 'run.mcap', path_topic='ground_truth',
                    course=COURSE).missing_steps == 3


def test_a_robots_own_topics_only(tmp_path):
    write_graded_run(tmp_path / 'run.mcap')
    run = read_run(tmp_path / 'run.mcap', 'robot1', 'ground_truth', COURSE)
    assert not len(run.times) and run.pose_at(1.0) is None
    assert run.reports[0].time == 0.0 and not math.isnan(run.step)


def test_a_status_sent_before_any_pose_is_dated_by_the_first_and_ties_go_by_order(tmp_path):
    bag = BagWriter(tmp_path / 'run.mcap')
    status = bag.add_topic('/robot_status', 'std_msgs/msg/String', LATCHED)
    odom = bag.add_topic('/robot0/odom', 'nav_msgs/msg/Odometry', LATCHED)

    def say(time, text):
        bag.write(status, time, STORE.serialize_cdr(T['std_msgs/msg/String'](data=text),
                                                    'std_msgs/msg/String'))
    say(0, 'STARTED 1.000 2.000 0.00')
    for seconds, x in ((15.0, 1.0), (16.0, 1.1)):
        bag.write(odom, MS, STORE.serialize_cdr(odometry(seconds, x), 'nav_msgs/msg/Odometry'))
    say(MS, 'WAYPOINT 1 1.100 2.000 0.00')
    bag.close()
    run = read_run(tmp_path / 'run.mcap', course=COURSE)
    assert [report.time for report in run.statuses] == [15.0, 16.0]

"""A run read back from a bag: course, path and statuses; foreign statuses and cut bags."""

import math

import numpy as np
import pytest
from rosbags.typesys import get_typestore, Stores
from simple_robot_control.bag import BagWriter
from waypoint_controller.plot_run import main as plot_run
from waypoint_controller.run_bag import load_bag
from waypoint_controller.run_record import RunRecordError

STORE = get_typestore(Stores.ROS2_JAZZY)
T = STORE.types
LATCHED = [{'history': 'keep_last', 'depth': 1, 'reliability': 'reliable',
            'durability': 'transient_local', 'deadline': {'sec': 0, 'nsec': 0},
            'lifespan': {'sec': 0, 'nsec': 0}, 'liveliness': 'automatic',
            'liveliness_lease_duration': {'sec': 0, 'nsec': 0},
            'avoid_ros_namespace_conventions': False}]


def header(seconds):
    stamp = T['builtin_interfaces/msg/Time'](sec=int(seconds),
                                             nanosec=round(seconds % 1 * 1e9))
    return T['std_msgs/msg/Header'](stamp=stamp, frame_id='map')


def pose(x, y, theta):
    return T['geometry_msgs/msg/Pose'](
        position=T['geometry_msgs/msg/Point'](x=x, y=y, z=0.0),
        orientation=T['geometry_msgs/msg/Quaternion'](x=0.0, y=0.0, z=math.sin(theta / 2),
                                                      w=math.cos(theta / 2)))


def odometry(seconds, x):
    covariance = np.zeros(36)
    return T['nav_msgs/msg/Odometry'](
        header=header(seconds), child_frame_id='robot0/base_link',
        pose=T['geometry_msgs/msg/PoseWithCovariance'](pose=pose(x, 2.0, 0.0),
                                                       covariance=covariance),
        twist=T['geometry_msgs/msg/TwistWithCovariance'](
            twist=T['geometry_msgs/msg/Twist'](
                linear=T['geometry_msgs/msg/Vector3'](x=0.5, y=0.0, z=0.0),
                angular=T['geometry_msgs/msg/Vector3'](x=0.0, y=0.0, z=0.0)),
            covariance=covariance))


def write_run(path, steps=100, finish=True, goal_x=3.0):
    """Drive from x = 1 to 3 in steps, reporting STARTED and WAYPOINT 1 (and FINISHED)."""
    bag = BagWriter(path)
    course = bag.add_topic('/waypoints', 'nav_msgs/msg/Path', LATCHED)
    odom = bag.add_topic('/robot0/odom', 'nav_msgs/msg/Odometry', LATCHED)
    status = bag.add_topic('/robot_status', 'std_msgs/msg/String', LATCHED)

    def write(channel, time, message, kind):
        bag.write(channel, round(time * 1e9), STORE.serialize_cdr(message, kind))
    path_message = T['nav_msgs/msg/Path'](header=header(0), poses=[
        T['geometry_msgs/msg/PoseStamped'](header=header(0), pose=pose(goal_x, 2.0, 0.0))])
    write(course, 0.0, path_message, 'nav_msgs/msg/Path')
    for step in range(steps + 1):
        time, x = step * 0.02, 1.0 + 2.0 * step / steps
        write(odom, time, odometry(time, x), 'nav_msgs/msg/Odometry')
        if step == 0:
            for text in ('hello from another node', 'STARTED 1.000 2.000 0.00'):
                write(status, time, T['std_msgs/msg/String'](data=text), 'std_msgs/msg/String')
    if finish:
        for text in ('WAYPOINT 1 3.000 2.000 0.00', 'FINISHED'):
            write(status, time, T['std_msgs/msg/String'](data=text), 'std_msgs/msg/String')
    return bag


def test_a_bag_gives_the_course_the_path_and_the_dated_statuses(tmp_path):
    write_run(tmp_path / 'run.mcap').close()
    record = load_bag(tmp_path / 'run.mcap')
    assert [(w.x, w.y, w.theta) for w in record.waypoints] == [(3.0, 2.0, 0.0)]
    assert len(record.poses) == 101 and record.poses[-1] == pytest.approx((3.0, 2.0, 0.0))
    assert [text for _, text in record.statuses] == [
        'STARTED 1.000 2.000 0.00', 'WAYPOINT 1 3.000 2.000 0.00', 'FINISHED']
    assert record.statuses[1][0] == pytest.approx(2.0) and record.result == 'FINISHED'
    assert len(record.skipped_lines) == 1 and record.cut_short_line is None


def test_a_bag_folder_is_read_as_its_mcap_file(tmp_path):
    (tmp_path / 'run').mkdir()
    write_run(tmp_path / 'run' / 'run_0.mcap').close()
    assert load_bag(tmp_path / 'run').result == 'FINISHED'


def test_a_bag_cut_short_is_read_up_to_its_last_chunk(tmp_path):
    bag = write_run(tmp_path / 'cut.mcap', steps=20_000, finish=False)
    bag._stream.flush()  # killed here: no summary, the last chunk unwritten
    record = load_bag(tmp_path / 'cut.mcap')
    assert 0 < len(record.poses) < 20_001 and record.cut_short_line is not None
    assert record.result is None


def test_a_bag_without_the_course_needs_it_given(tmp_path):
    bag = BagWriter(tmp_path / 'run.mcap')
    channel = bag.add_topic('/robot0/odom', 'nav_msgs/msg/Odometry', LATCHED)
    bag.write(channel, 0, STORE.serialize_cdr(odometry(0.0, 1.0), 'nav_msgs/msg/Odometry'))
    bag.close()
    with pytest.raises(RunRecordError, match='no /waypoints in the bag'):
        load_bag(tmp_path / 'run.mcap')
    assert len(load_bag(tmp_path / 'run.mcap', course=[]).poses) == 1


def test_a_course_off_any_map_is_refused_in_one_line(tmp_path, capsys):
    write_run(tmp_path / 'run.mcap', goal_x=1e308).close()
    with pytest.raises(RunRecordError, match='/waypoints: a waypoint off any map'):
        load_bag(tmp_path / 'run.mcap')
    assert plot_run([str(tmp_path / 'run.mcap')]) == 2
    error = capsys.readouterr().err
    assert len(error.splitlines()) == 1 and 'a waypoint off any map' in error
    assert not (tmp_path / 'run.png').exists()

"""A short run, recorded by course_monitor, drawn by plot_run."""

import json
import math

from full_disk import fill_up_after
from mcap.reader import make_reader
from nav_msgs.msg import Odometry
import numpy as np
from PIL import Image
import pytest
from rclpy.node import Node
from rclpy.serialization import deserialize_message
from ros_helpers import overrides, spin_until, wait_for_subscribers
from simple_robot_control.occupancy_map import load_map
from simple_robot_control.share import BUNDLED_MAP, shared_file
from std_msgs.msg import String
from stdr_lite.node.stdr_lite import StdrLite
from waypoint_controller.waypoint_controller import WaypointController
from waypoint_lab.course_monitor import CourseMonitor
from waypoint_lab.interface import status_qos
from waypoint_lab.plot_run import main as plot_run
from waypoint_lab.run import read_run
from waypoint_lab.run_picture import DPI, FIGURE_SIZE, render_run

COURSE = '2.5 2 0\n2.5 3 90\n'


def start_recorded_run(ros_context, executor, tmp_path):
    """Start driving a two-waypoint course in lockstep, course_monitor recording its bag."""
    course, record = tmp_path / 'course.txt', tmp_path / 'run.mcap'
    course.write_text(COURSE)
    output = []
    simulator = StdrLite(context=ros_context,
                         parameter_overrides=overrides(lockstep=True, real_time_factor=0.0))
    monitor = CourseMonitor(str(course), write=output.append, interactive=False,
                            context=ros_context, parameter_overrides=overrides(bag=str(record)))
    for node in (simulator, monitor):
        executor.add_node(node)
    spin_until(executor, lambda: '/robot0/odom' in monitor.recording.topics, what='the record')
    executor.add_node(WaypointController(str(course), context=ros_context))
    return course, record, monitor, output


@pytest.fixture
def recorded_run(ros_context, executor, tmp_path):
    """Drive a two-waypoint course in lockstep, course_monitor recording its bag; give paths."""
    course, record, monitor, output = start_recorded_run(ros_context, executor, tmp_path)
    received = monitor.recording.received
    executor.spin_until_future_complete(monitor.finished, timeout_sec=60.0)
    assert monitor.finished.result() == 0
    spin_until(executor, lambda: received['/waypoints'] and received['/robot_status'] == 4,
               what='the course and the statuses recorded')
    monitor.shut_down()
    return course, record, ''.join(output)


def test_monitor_prints_each_status_and_a_summary(recorded_run):
    _, _, output = recorded_run
    lines = output.splitlines()
    assert [line.split()[0] for line in lines[:4]] == ['STARTED', 'WAYPOINT', 'WAYPOINT',
                                                       'FINISHED']
    assert lines[4].startswith('[' + '#' * 20 + '] 2/2 waypoints | sim ')
    assert '\r' not in output


def test_record_holds_the_run(recorded_run):
    course, record_path, _ = recorded_run
    run = read_run(record_path)
    assert run.course.name == 'course.txt' and len(run.course.waypoints) == 2
    assert run.result == 'FINISHED'
    assert np.all(np.diff(run.times) > 0.0)
    assert run.poses[0] == pytest.approx((1.0, 2.0, 0.0), abs=0.05)
    # Dated by the odometry heard before it: the pose it reports (the controller speaks before
    # it commands, and lockstep steps only on the command).
    for report in run.statuses[1:3]:
        assert run.pose_at(report.time) == pytest.approx(report.status.pose, abs=1e-3)
    assert run.statuses[3].time == run.statuses[2].time
    assert math.dist(run.poses[-1][:2], (2.5, 3.0)) <= 0.1


def test_picture_of_the_run_is_a_png_of_the_expected_size(recorded_run, tmp_path):
    _, record_path, _ = recorded_run
    picture = tmp_path / 'run.png'
    render_run(read_run(record_path), load_map(shared_file('maps', 'lab_room.yaml')), 0.2,
               picture)
    assert picture.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    with Image.open(picture) as image:
        assert image.size == (FIGURE_SIZE[0] * DPI, FIGURE_SIZE[1] * DPI)
        pixels = np.asarray(image.convert('RGB'), dtype=float)
    assert pixels.std() > 20.0
    colourful = np.ptp(pixels, axis=2) > 60
    assert colourful.sum() > 500


def test_plot_run_command_writes_beside_the_record(recorded_run, capsys):
    _, record_path, _ = recorded_run
    assert plot_run([str(record_path)]) == 0
    assert record_path.with_suffix('.png').is_file()
    assert 'wrote' in capsys.readouterr().out


@pytest.mark.parametrize('args, message', [
    (['missing.jsonl'], 'missing.jsonl: cannot read the bag'),
    (['missing.mcap'], 'missing.mcap: cannot read the bag'),
    (['RECORD', '--map', '/no/map.yaml'], '/no/map.yaml: cannot read map file'),
    (['RECORD', '--robot-radius', '-1'], '--robot-radius must be in (0, 10], got -1'),
    (['RECORD', '--output', 'FOLDER'], 'is a folder, not a file'),
    (['RECORD', '--output', 'RECORD'], 'an input of this run: refusing to overwrite it'),
    (['RECORD', '--output', 'MAP'], 'an input of this run: refusing to overwrite it'),
])
def test_plot_run_refuses_bad_input_in_one_line(recorded_run, capsys, args, message):
    _, record_path, _ = recorded_run
    names = {'RECORD': str(record_path), 'FOLDER': str(record_path.parent),
             'MAP': shared_file(*BUNDLED_MAP)}
    args = [names.get(arg, arg) for arg in args]
    assert plot_run(args) == 2
    error = capsys.readouterr().err
    assert message in error and len(error.strip().splitlines()) == 1


def test_plot_run_writes_the_png_exactly_where_it_is_told(recorded_run):
    _, record_path, _ = recorded_run
    output = record_path.parent / 'picture'
    assert plot_run([str(record_path), '--output', str(output)]) == 0
    assert output.read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    assert not output.with_suffix('.png').exists()


def monitor_with_speaker(ros_context, executor, course_text, tmp_path, **parameters):
    """Give (monitor, its output, status and odometry publishers) on a course of a test's."""
    course = tmp_path / 'course.txt'
    course.write_text(course_text)
    output = []
    monitor = CourseMonitor(str(course), write=output.append, interactive=False,
                            context=ros_context, parameter_overrides=overrides(**parameters))
    speaker = Node('speaker', context=ros_context)
    status = speaker.create_publisher(String, 'robot_status',
                                      status_qos(len(course_text.splitlines())))
    odometry = speaker.create_publisher(Odometry, '/robot0/odom', 10)
    for node in (monitor, speaker):
        executor.add_node(node)
    wait_for_subscribers(executor, status)
    wait_for_subscribers(executor, odometry)
    return monitor, output, status, odometry


def test_the_monitor_says_what_is_no_status_of_the_course(ros_context, executor, tmp_path):
    bag = tmp_path / 'run.mcap'
    monitor, output, status, odometry = monitor_with_speaker(ros_context, executor, COURSE,
                                                             tmp_path, bag=str(bag))
    broken = Odometry()
    broken.pose.pose.position.x = math.nan
    odometry.publish(broken)
    texts = ['hello \x1b[2J from another node', 'WAYPOINT -1 1 2 3', 'STARTED nan nan nan',
             'WAYPOINT 3 1.000 2.000 0.00', 'x' * 1_000_000, 'STARTED 1.000 2.000 0.00',
             'ABORTED 1 1.000 2.000 0.00']
    for count, text in enumerate(texts, start=1):
        status.publish(String(data=text))
        spin_until(executor, lambda: len(output) >= count, what=f'the monitor on {text[:20]}')
    executor.spin_until_future_complete(monitor.finished, timeout_sec=10.0)
    assert monitor.finished.result() == 1
    monitor.shut_down()
    printed = ''.join(output)
    assert printed.count('(not a status of this course: ') == 5
    assert '\x1b' not in printed and len(printed) < 2000
    # The record keeps the course's statuses only, as doc/tools.md says.
    with open(bag, 'rb') as stream:
        kept = [deserialize_message(message.data, String).data for _, channel, message
                in make_reader(stream).iter_messages() if channel.topic == '/robot_status']
    assert kept == texts[-2:]


def test_the_run_exported_as_json_lines_holds_the_same(recorded_run, tmp_path):
    _, record_path, _ = recorded_run
    exported = tmp_path / 'run.jsonl'
    assert plot_run([str(record_path), '--output', str(tmp_path / 'run.png'),
                     '--export-jsonl', str(exported)]) == 0
    run = read_run(record_path)
    header, *entries = map(json.loads, exported.read_text().splitlines())
    assert header['course'] == 'course.txt' and header['distance_tolerance'] == 0.1
    assert np.allclose(header['waypoints'], run.course.waypoints)
    assert [(entry['t'], entry['status']) for entry in entries if 'status' in entry] == [
        (report.time, report.text) for report in run.statuses]
    poses = [entry for entry in entries if 'pose' in entry]
    assert np.allclose([entry['pose'] for entry in poses], run.poses)
    assert [entry['t'] for entry in entries] == sorted(entry['t'] for entry in entries)


def test_plot_run_refuses_a_broken_bag_in_one_line(tmp_path, capsys):
    broken = tmp_path / 'broken.mcap'
    broken.write_bytes(b'not an mcap file at all')
    assert plot_run([str(broken), '--output', str(tmp_path / 'broken.png')]) == 2
    error = capsys.readouterr().err
    assert error.startswith(f'plot_run: error: {broken}: not a readable MCAP bag')
    assert len(error.strip().splitlines()) == 1


def test_a_full_disk_stops_the_recording_not_the_run(ros_context, executor, tmp_path,
                                                     monkeypatch, capsys):
    fill_up_after(monkeypatch, 16 << 10)
    _, record, monitor, output = start_recorded_run(ros_context, executor, tmp_path)
    spin_until(executor, lambda: monitor.recording.failed, timeout=60.0,
               what='the disk to fill up')
    executor.spin_until_future_complete(monitor.finished, timeout_sec=60.0)
    assert monitor.finished.result() == 0
    assert [line.split()[0] for line in ''.join(output).splitlines()[:4]] == [
        'STARTED', 'WAYPOINT', 'WAYPOINT', 'FINISHED']
    monitor.shut_down()  # no traceback, no second complaint
    assert record.stat().st_size <= 16 << 10
    assert plot_run([str(record), '--output', str(tmp_path / 'run.png')]) == 2
    error = capsys.readouterr().err
    assert error.strip() == (f'plot_run: error: {record}: the bag ends before its first '
                             'complete chunk (its recording was stopped early, or the disk was '
                             'full): no run in it')


def test_a_started_heard_before_any_odometry_is_dated_by_the_odometry(
        ros_context, executor, tmp_path):
    """A monitor started after the controller hears its (latched) STARTED first."""
    monitor, output, status, odometry = monitor_with_speaker(ros_context, executor, '2 2 0\n',
                                                             tmp_path)
    status.publish(String(data='STARTED 1.000 2.000 0.00'))
    spin_until(executor, lambda: output, what='STARTED printed')
    for seconds, x in ((15, 1.0), (16, 2.0)):
        message = Odometry()
        message.header.stamp.sec = seconds
        message.pose.pose.position.x, message.pose.pose.position.y = x, 2.0
        message.pose.pose.orientation.w = 1.0
        odometry.publish(message)
        spin_until(executor, lambda: (monitor.sim_time or 0.0) > seconds - 0.5,
                   what=f'odometry at {seconds} s')
    for text in ('WAYPOINT 1 2.000 2.000 0.00', 'FINISHED'):
        status.publish(String(data=text))
    executor.spin_until_future_complete(monitor.finished, timeout_sec=10.0)
    assert monitor.finished.result() == 0
    monitor.shut_down()
    assert '1/1 waypoints | sim 1.0 s' in ''.join(output)

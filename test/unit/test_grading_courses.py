"""Courses to grade on: waypoint files, their YAML beside them, and one line for each mistake."""

import math
import os
from pathlib import Path
import shutil

from courseworks.courses import CourseError, find_courses, read_course
import pytest
from simple_robot_control.share import BUNDLED_MAP, shared_file
from waypoint_lab.course import Course


def write(folder, name, waypoints='1.0 2.0 0.0', settings=None):
    folder.mkdir(exist_ok=True)
    (folder / f'{name}.txt').write_text(waypoints + '\n')
    if settings is not None:
        (folder / f'{name}.yaml').write_text(settings)
    return folder / f'{name}.txt'


def test_a_folder_gives_its_waypoint_files_with_the_labs_defaults(tmp_path):
    write(tmp_path, 'b', '3 2 90')
    write(tmp_path, 'a', '2 2 0 4 2 180')
    (tmp_path / 'notes.md').write_text('not a course')
    courses = find_courses([tmp_path])
    assert [course.name for course in courses] == ['a', 'b']
    a = courses[0]
    assert [(w.x, w.y, w.theta) for w in a.waypoints] == [(2.0, 2.0, 0.0), (4.0, 2.0, math.pi)]
    assert (a.start, a.map_file, a.robot_file) == ((1.0, 2.0, 0.0), '', '')
    assert (a.distance_tolerance, a.angle_tolerance) == (0.1, pytest.approx(math.radians(5)))
    assert (a.time_limit, a.points, a.max_time, a.max_path_length) == (120.0, 1.0, None, None)


def test_a_courses_yaml_sets_its_world_limits_and_points(tmp_path):
    bundled = Path(shared_file(*BUNDLED_MAP))
    (tmp_path / 'room.yaml').write_text(bundled.read_text().replace('lab_room.pgm', 'room.pgm'))
    shutil.copyfile(bundled.with_suffix('.pgm'), tmp_path / 'room.pgm')
    path = write(tmp_path, 'hidden', '5 5 0', 'start: [2.0, 3.0, 90]\nmap: room.yaml\n'
                 'robot: turtlebot3_burger\ntime_limit: 30\npoints: 2.5\n'
                 'distance_tolerance: 0.05\nangle_tolerance_deg: 2\nmax_time: 20\n'
                 'max_path_length: 12.5\n')
    course = read_course(path, Course('', (), time_limit=99.0))
    assert course.start == (2.0, 3.0, pytest.approx(math.pi / 2))
    assert course.map_file == str(tmp_path / 'room.yaml')
    assert course.robot_file.endswith('turtlebot3_burger.xml')
    assert (course.time_limit, course.points, course.max_time, course.max_path_length) == (
        30.0, 2.5, 20.0, 12.5)
    assert course.angle_tolerance == pytest.approx(math.radians(2))
    assert read_course(write(tmp_path, 'plain')).time_limit == 120.0
    assert find_courses([path], Course('', (), time_limit=99.0))[0].points == 2.5


def test_a_mapping_course_may_name_where_its_map_is_read(tmp_path):
    course = read_course(write(tmp_path, 'c', settings='task: mapping\nmap_topic: built/map\n'))
    assert course.map_topic == '/built/map'
    assert read_course(write(tmp_path, 'd', settings='task: mapping\n')).map_topic == ''


def test_the_bundled_map_is_known_by_name(tmp_path):
    course = read_course(write(tmp_path, 'c', settings='map: lab_room\n'))
    assert course.map_file == shared_file(*BUNDLED_MAP)


@pytest.mark.parametrize('settings, complaint', [
    ('time_limt: 5\n', "c.yaml: unknown field 'time_limt'; did you mean time_limit?"),
    ('start: [1, 2]\n', 'c.yaml: start must be [x, y, theta] (m, m, degrees), got'),
    ('start: [1, 2, .inf]\n', 'c.yaml: start theta (degrees) must be in [-3600, 3600]'),
    ('time_limit: 0\n', 'c.yaml: time_limit must be in [1, 86400], got 0'),
    ('points: -1\n', 'c.yaml: points must be in [0, 1000000], got -1'),
    ('map: nowhere.yaml\n', "c.yaml: map 'nowhere.yaml': no such file beside it"),
    ('map: factory.yaml\n', "c.yaml: map 'factory.yaml': no such file beside it"),
    ('map: nowhere\n', "c.yaml: map 'nowhere' is no bundled map (factory, lab_room, plus_room, "
     "simple_walls); a file of the course's is named with its suffix (nowhere.yaml)"),
    ('- a list\n', 'c.yaml: course settings must be a mapping of fields'),
    ('a: [\n', 'c.yaml:2: course settings is not valid YAML'),
    ('distance_tolerance: yes\n', 'distance_tolerance must be in (0, 10], got True'),
    ('map_topic: my map\n', "map_topic must be a topic name (ROS names joined by '/'"),
])
def test_a_bad_setting_is_one_line_naming_the_file_and_field(tmp_path, settings, complaint):
    with pytest.raises(CourseError) as raised:
        read_course(write(tmp_path, 'c', settings=settings))
    assert complaint in str(raised.value) and '\n' not in str(raised.value)


def test_bad_courses_are_refused_whole(tmp_path):
    with pytest.raises(CourseError, match='no such course file or folder'):
        find_courses([tmp_path / 'missing'])
    with pytest.raises(CourseError, match='a folder with no course'):
        find_courses([tmp_path])
    with pytest.raises(CourseError, match=r'bad.txt:1: .six. is not a number'):
        find_courses([write(tmp_path, 'bad', 'six 2 0')])
    one, two = tmp_path / 'one', tmp_path / 'two'
    write(one, 'same')
    write(two, 'same')
    with pytest.raises(CourseError, match='two courses named same'):
        find_courses([one, two])


def hostile_course(folder, kind):
    """Write a course whose YAML names a file a course must not: outside, or no regular file."""
    bundled = Path(shared_file(*BUNDLED_MAP))
    settings = {'absolute': 'map: /etc/passwd\n', 'climbing': 'map: ../../etc/passwd\n',
                'robot': 'robot: /etc/passwd\n', 'folder': 'map: maps/\n',
                'zero image': 'map: room.yaml\n', 'fifo image': 'map: room.yaml\n',
                'link out': 'map: room.yaml\n', 'bad map': 'map: room.yaml\n'}[kind]
    path = write(folder, 'c', settings=settings)
    (folder / 'maps').mkdir()
    image = {'zero image': '/dev/zero', 'fifo image': 'fifo.pgm', 'bad map': 'room.pgm'}.get(
        kind, 'room.pgm')
    if kind != 'link out':
        (folder / 'room.yaml').write_text(bundled.read_text().replace('lab_room.pgm', image))
    else:
        (folder / 'room.yaml').symlink_to(bundled)
    if kind == 'fifo image':
        os.mkfifo(folder / 'fifo.pgm')
    if kind == 'bad map':
        (folder / 'room.pgm').write_bytes(b'P5 not an image')
    return path


@pytest.mark.parametrize('kind, complaint', [
    ('absolute', "map '/etc/passwd' leads outside the course's folder (/etc/passwd)"),
    ('climbing', "map '../../etc/passwd' leads outside the course's folder"),
    ('robot', "robot '/etc/passwd' leads outside the course's folder"),
    ('folder', "map 'maps/' is no regular file (a folder, a FIFO or a device)"),
    ('zero image', "image '/dev/zero' leads outside the course's folder"),
    ('fifo image', "image 'fifo.pgm' is no regular file"),
    ('link out', "map 'room.yaml' leads outside the course's folder"),
    ('bad map', 'c.yaml: map: '),
])
def test_a_course_names_only_regular_files_beside_it_that_load(tmp_path, kind, complaint):
    """Checked whole before anything runs: one line naming the file and the key, no hang."""
    with pytest.raises(CourseError) as raised:
        read_course(hostile_course(tmp_path, kind))
    assert complaint in str(raised.value) and '\n' not in str(raised.value), str(raised.value)
    assert str(raised.value).startswith(str(tmp_path / ''))  # c.yaml, or the map's for its image


def test_a_fifo_in_place_of_a_courses_yaml_is_refused_not_skipped(tmp_path):
    path = write(tmp_path, 'c')
    os.mkfifo(tmp_path / 'c.yaml')
    with pytest.raises(CourseError, match='c.yaml: course settings is not a regular file'):
        read_course(path)

"""Waypoint files: the formats the lab allows, and one clear line for every kind of error."""

import math
import os

from hypothesis import given, strategies as st
import pytest
from waypoint_lab.waypoints import (load_waypoints, MAX_WAYPOINTS, parse_waypoints,
                                    Waypoint, WaypointFileError)


def test_lab_format_all_on_one_line():
    expected = [Waypoint(1, 2, math.pi / 2), Waypoint(3, 4, -math.pi / 4)]
    assert parse_waypoints('1 2 90 3 4 -45') == expected


def test_one_per_line_with_comments_and_blank_lines():
    text = '# course\n\n1.5 -2 180  # first\n\t3e0 4.25 0\n\n'
    assert parse_waypoints(text) == [Waypoint(1.5, -2, math.pi), Waypoint(3, 4.25, 0)]


@given(st.lists(st.tuples(st.floats(-1e6, 1e6), st.floats(-1e6, 1e6),
                          st.floats(-3600.0, 3600.0)), min_size=1, max_size=20),
       st.lists(st.sampled_from([' ', '\t', '\n', '  \n ']), min_size=1))
def test_any_whitespace_layout_reads_the_same_numbers(triples, separators):
    numbers = [value for triple in triples for value in triple]
    text = ''.join(repr(value) + separators[i % len(separators)]
                   for i, value in enumerate(numbers))
    parsed = parse_waypoints(text)
    assert [(w.x, w.y, w.theta) for w in parsed] == [
        (x, y, math.radians(theta)) for x, y, theta in triples]


@pytest.mark.parametrize('text, expected', [
    ('1 2 3\n4 five 6\n', "course.txt:2: 'five' is not a number"),
    ('1 2 nan\n', "course.txt:1: 'nan' is not a number"),
    ('1 2 3\n\n4 inf 6\n', "course.txt:3: 'inf' is not a number"),
    ('1 5_0 3\n', "course.txt:1: '5_0' is not a number (write plain decimals"),
    ('1 \u0661\u0662 3\n', "course.txt:1: '\u0661\u0662' is not a number"),
    ('0x10 1 2\n', "course.txt:1: '0x10' is not a number"),
    ('1 2 1e999\n', "course.txt:1: '1e999' is not a number"),
    ('1 2 3\n4 5\n', 'course.txt:2: 5 numbers is not a whole number'),
    ('', 'course.txt: no waypoints'),
    ('# only a comment\n\n', 'course.txt: no waypoints'),
    ('1 2 3\n4 5 1e17\n', 'course.txt:2: waypoint 2: theta (degrees) must be in [-3600, 3600], '
     'got 1e+17'),
    ('1e7 2 3\n', 'course.txt:1: waypoint 1: x must be in [-1000000, 1000000]'),
    ('1 2 3\n' * (MAX_WAYPOINTS + 1), f'course.txt:{MAX_WAYPOINTS + 1}: more than 10,000 '
     'waypoints'),
])
def test_bad_files_name_file_line_and_token(tmp_path, text, expected):
    path = tmp_path / 'course.txt'
    path.write_text(text)
    with pytest.raises(WaypointFileError) as raised:
        load_waypoints(path)
    message = str(raised.value)
    assert expected in message and str(tmp_path) in message and '\n' not in message


def test_missing_file_is_named(tmp_path):
    with pytest.raises(WaypointFileError, match='nowhere.txt: cannot read waypoint file'):
        load_waypoints(tmp_path / 'nowhere.txt')


def test_binary_file_is_refused(tmp_path):
    path = tmp_path / 'course.bin'
    path.write_bytes(b'\xff\xfe\x00\x81')
    with pytest.raises(WaypointFileError, match='course.bin: waypoint file is not a text file'):
        load_waypoints(path)


def test_a_file_saved_with_a_byte_order_mark_reads_as_without(tmp_path):
    path = tmp_path / 'notepad.txt'
    path.write_bytes('\ufeff1 2 90\r\n3 4 0\r\n'.encode('utf-8'))
    assert load_waypoints(path) == [Waypoint(1, 2, math.pi / 2), Waypoint(3, 4, 0)]


@pytest.mark.parametrize('make, message', [
    (lambda path: os.mkfifo(path), 'waypoint file is not a regular file'),
    (lambda path: path.symlink_to('/dev/zero'), 'waypoint file is not a regular file'),
    (lambda path: path.write_bytes(b'1 ' * (6 << 20)), 'waypoint file is too large'),
])
def test_what_is_not_a_course_file_is_refused_before_reading(tmp_path, make, message):
    path = tmp_path / 'course.txt'
    make(path)
    with pytest.raises(WaypointFileError, match=message):
        load_waypoints(path)

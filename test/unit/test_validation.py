"""Checks of user numbers and names: one rule each, one line of complaint."""

import math

import pytest
from simple_robot_control.validation import (Bounds, compact, is_finite_number, NON_NEGATIVE,
                                             parse_decimal, POSITIVE, ros_name_problem,
                                             topic_name_problem)


@pytest.mark.parametrize('value, finite', [(1, True), (2.5, True), (-0.0, True),
                                           (math.nan, False), (math.inf, False), (True, False),
                                           ('3', False), (None, False)])
def test_finite_numbers(value, finite):
    assert is_finite_number(value) is finite


@pytest.mark.parametrize('bounds, text, inside, outside', [
    (POSITIVE, 'positive', [1e-9, 5.0], [0.0, -1.0, math.inf]),
    (NON_NEGATIVE, '>= 0', [0.0, 3.0], [-1e-9, math.nan]),
    (Bounds(5.0, 100.0), 'in [5, 100]', [5.0, 100.0], [4.99, 100.1]),
    (Bounds(0.0, 10.0, low_open=True), 'in (0, 10]', [10.0], [0.0, 1e308]),
])
def test_bounds_describe_and_judge(bounds, text, inside, outside):
    assert bounds.text() == text
    assert all(bounds.problem('x', value) is None for value in inside)
    for value in outside:
        assert bounds.problem('speed', value) == f'speed must be {text}, got {compact(value)}'


def test_numbers_are_printed_compactly():
    assert compact(1e308) == '1e+308'
    assert compact(0.1 + 0.2) == '0.3'
    assert compact('x') == "'x'"


@pytest.mark.parametrize('name', ['robot0', 'scout', 'a_b1', 'Laser_0'])
def test_ros_names_pass(name):
    assert ros_name_problem(name, 'robot name') is None


@pytest.mark.parametrize('name', ['robé', '0robot', '_x', 'a__b', 'x_', 'a/b', '', 'a b', 7])
def test_other_names_are_refused_in_one_line(name):
    problem = ros_name_problem(name, 'robot name')
    assert problem.startswith('robot name must be a ROS name (') and '\n' not in problem
    assert problem.endswith(f'got {name!r}')


@pytest.mark.parametrize('text, value', [('2', 2.0), ('-0.5', -0.5), ('.5', 0.5), ('1e3', 1000.0),
                                         ('+3.', 3.0), ('7E-1', 0.7)])
def test_plain_decimals_are_read(text, value):
    assert parse_decimal(text) == value


@pytest.mark.parametrize('text', ['5_0', '\u0661\u0662', 'inf', 'nan', '0x10', '1e999', '',
                                  ' 1', '1,5', '--1'])
def test_what_python_would_also_take_is_refused(text):
    assert parse_decimal(text) is None


@pytest.mark.parametrize('name', ['/map', 'map', 'robot0/map', '/robot0/coursework_map'])
def test_topic_names_are_ros_names_joined_by_slashes(name):
    assert topic_name_problem(name, 'map_topic') is None


@pytest.mark.parametrize('name', ['', '/', 'map/', '//map', '/0map', 'a b', '/map__x', 3])
def test_other_topic_names_are_refused_in_one_line_naming_the_parameter(name):
    problem = topic_name_problem(name, 'map_topic')
    assert problem.startswith('map_topic must be a topic name') and '\n' not in problem

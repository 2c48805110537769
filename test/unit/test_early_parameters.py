"""A command line's parameters judged before the node loads: only what rcl reads for sure."""

import subprocess
import sys

from installed_executables import ENTRY_POINTS, parameter_table, PARAMETER_TABLES
import pytest
from simple_robot_control.early_parameters import early_problem, given_parameters, UNSURE
from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.validation import Bounds

SPECS = (ParameterSpec('rate_hz', 50.0, 'steps a second', Bounds(1.0, 1000.0)),
         ParameterSpec('robot_name', 'robot0', 'a robot', ros_name=True),
         ParameterSpec('lockstep', False, 'wait for answers'),
         ParameterSpec('pose', [1.0, 2.0, 0.0], 'a pose'),
         ParameterSpec('topics', ('*',), 'topics'))


def command_line(*arguments):
    return ['node', 'positional', '--ros-args', *arguments]


def values(*arguments, node_name='node'):
    return given_parameters(command_line(*arguments), node_name).values


@pytest.mark.parametrize('text, value', [
    ('5', 5), ('-3', -3), ('2.5', 2.5), ('1e3', 1000.0), ('.5', 0.5), ('true', True),
    ('False', False), ('robot1', 'robot1'), ('/tmp/a.yaml', '/tmp/a.yaml'), ('"5"', '5'),
    ("'true'", 'true'), ('[1, 2]', [1, 2]), ('[a, b]', ['a', 'b']), ('[1.5, 2.5]', [1.5, 2.5]),
])
def test_values_rcl_reads_one_way_are_read_so(text, value):
    assert values('-p', f'x:={text}') == {'x': [value]}


@pytest.mark.parametrize('text', [
    'yes', 'On', 'n', '010', '0x10', '.inf', '-.inf', 'nan', 'Infinity', 'null', '~', '',
    '1e999', '9' * 30, '[1, 2.0]', '[1, a]', '[]', '{a: 1}', '!!str 5', '&anchor 5', '|\n 5',
    './maps/a.yaml', '1_000', '12:30',
])
def test_values_rcl_may_read_otherwise_are_left_to_the_node(text):
    assert values('-p', f'x:={text}') == {'x': [UNSURE]}


def test_each_refusal_is_the_one_the_node_makes():
    assert early_problem(command_line('-p', 'rate_hz:=-1'), 'node', SPECS) == (
        'rate_hz must be in [1, 1000], got -1')
    assert early_problem(command_line('-p', 'rate_hz:=abc'), 'node', SPECS) == (
        "parameter rate_hz: expected a number, got 'abc'")
    assert early_problem(command_line('-p', 'lockstep:=1'), 'node', SPECS) == (
        'parameter lockstep: expected a boolean (true or false), got 1')
    assert early_problem(command_line('-p', 'robot_name:="5"'), 'node', SPECS).startswith(
        'robot_name must be a ROS name')
    assert early_problem(command_line('-p', 'topics:=[a, 5]'), 'node', SPECS) is None
    assert early_problem(command_line('-p', 'rat_hz:=5'), 'node', SPECS) == (
        "unknown parameter 'rat_hz' for node; did you mean rate_hz?")


def test_good_values_and_whole_numbers_for_doubles_pass():
    arguments = command_line('-p', 'rate_hz:=20', '-p', 'pose:=[1, 2, 3]', '-p', 'lockstep:=true',
                             '-p', 'topics:=[/a, b]', '-p', 'use_sim_time:=true')
    assert early_problem(arguments, 'node', SPECS) is None


def test_the_table_is_judged_first_then_the_names_in_its_order():
    arguments = command_line('-p', 'unknown:=1', '-p', 'lockstep:=2', '-p', 'rate_hz:=0')
    assert early_problem(arguments, 'node', SPECS).startswith('rate_hz must be in')


def test_a_value_given_twice_is_refused_only_when_both_are_bad():
    assert early_problem(command_line('-p', 'rate_hz:=0', '-p', 'rate_hz:=5'), 'node',
                         SPECS) is None
    assert early_problem(command_line('-p', 'rate_hz:=0', '-p', 'rate_hz:=-2'), 'node',
                         SPECS) == 'rate_hz must be in [1, 1000], got -2'


def test_only_ros_arguments_are_read():
    arguments = ['node', '-p', 'rate_hz:=0', '--ros-args', '-p', 'rate_hz:=5', '--',
                 '-p', 'rate_hz:=0', '--ros-args', '--log-level', 'debug', '-r', 'a:=b',
                 '--enable-rosout-logs']
    assert given_parameters(arguments, 'node').values == {'rate_hz': [5]}


@pytest.mark.parametrize('arguments', [
    ['--unknown-flag'], ['-p'], ['-p', 'no_assignment'], ['-p', '9bad:=1'], ['-p', 'x:=[[['],
    ['--params-file', '/no/such/file.yaml'], ['-r', 'other:__node:=renamed'],
])
def test_what_is_not_understood_is_left_to_the_node(arguments):
    assert given_parameters(command_line(*arguments), 'node') is None


def test_a_parameter_for_a_named_node_is_left_to_the_node():
    given = given_parameters(command_line('-p', 'node:rate_hz:=0'), 'node')
    assert 'rate_hz' in given.unsure
    assert early_problem(command_line('-p', 'node:rate_hz:=0'), 'node', SPECS) is None


def test_a_parameters_file_gives_its_entries_for_this_node_and_every_node(tmp_path):
    path = tmp_path / 'parameters.yaml'
    path.write_text('/**:\n  ros__parameters:\n    lockstep: true\n'
                    'node:\n  ros__parameters:\n    rate_hz: 0.5\n    qos:\n      depth: 3\n'
                    'other:\n  ros__parameters:\n    rate_hz: 2000.0\n'
                    '/team/*:\n  ros__parameters:\n    robot_name: 5\n')
    given = given_parameters(command_line('--params-file', str(path)), 'node')
    assert given.values == {'lockstep': [True], 'rate_hz': [0.5], 'qos.depth': [3]}
    assert given.unsure == {'robot_name'}
    assert early_problem(command_line('--params-file', str(path)), 'node', SPECS) == (
        'rate_hz must be in [1, 1000], got 0.5')


def test_a_renamed_node_takes_the_entries_of_its_new_name(tmp_path):
    path = tmp_path / 'parameters.yaml'
    path.write_text('/team:\n  scout:\n    ros__parameters:\n      rate_hz: 9.0\n'
                    'node:\n  ros__parameters:\n    rate_hz: 3.0\n')
    renamed = command_line('--params-file', str(path), '-r', '__node:=scout', '-r',
                           '__ns:=/team')
    assert given_parameters(renamed, 'node').values == {'rate_hz': [9.0]}


def test_a_hostile_parameters_file_is_left_to_rcl(tmp_path):
    nested = tmp_path / 'nested.yaml'
    nested.write_text('node:\n  ros__parameters:\n    pose: ' + '[' * 5000 + ']' * 5000 + '\n')
    large = tmp_path / 'large.yaml'
    large.write_text('node:\n  ros__parameters:\n' + '    # padding\n' * 200_000)
    not_a_mapping = tmp_path / 'list.yaml'
    not_a_mapping.write_text('- node\n')
    for path in (nested, large, not_a_mapping):
        assert given_parameters(command_line('--params-file', str(path)), 'node') is None


def test_every_node_executable_has_a_parameter_table_that_loads_light():
    """The tables load without numpy, rclpy or numba: that is what makes the check early."""
    assert all(parameter_table(name) for name in PARAMETER_TABLES)
    modules = sorted({module for module, _ in ENTRY_POINTS.values()})
    script = ('import importlib, sys\n'
              f'for module in {modules!r}:\n'
              '    for executable in importlib.import_module(module).EXECUTABLES.values():\n'
              '        executable.parameter_table()\n'
              "print(sorted(m for m in sys.modules if m.split('.')[0] in "
              "('numpy', 'rclpy', 'numba', 'rcl_interfaces', 'scipy')))\n")
    result = subprocess.run([sys.executable, '-c', script], capture_output=True, text=True,
                            timeout=60, check=True, cwd='/')
    assert result.stdout.strip() == '[]', result.stdout


def test_a_topic_whose_default_is_empty_takes_empty_as_none_and_checks_the_rest():
    optional = ParameterSpec('map_topic', '', 'a map to record too', topic=True)
    required = ParameterSpec('map_topic', '/map', 'the map', topic=True)
    assert optional.problem('') is None and optional.problem('/coursework_map') is None
    assert optional.problem('/bad topic') is not None and required.problem('') is not None
    assert 'or empty' in optional.constraint_text()
    assert 'or empty' not in required.constraint_text()

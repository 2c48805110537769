"""What the package reads is bounded before it is parsed, and what it writes destroys nothing."""

import os

import pytest
from simple_robot_control import input_files
from simple_robot_control.input_files import (MAX_DESCRIPTION_BYTES, MAX_ELEMENTS,
                                              MAX_FOLDER_FILES, MAX_NESTING, output_problem,
                                              parse_yaml, read_yaml, yaml_files)
import yaml


class Refused(ValueError):
    pass


def parse(text, **kwargs):
    return parse_yaml(text, 'robot.yaml', 'robot file', Refused, **kwargs)


@pytest.mark.parametrize('text, words', [
    ('[' * 5000 + ']' * 5000, 'robot.yaml:1: robot file is nested too deeply'),
    ('[' * (MAX_NESTING + 1) + ']' * (MAX_NESTING + 1),
     f'robot.yaml: robot file is nested more than {MAX_NESTING} levels deep'),
    ('a: ' + '{b: ' * 40 + '1' + '}' * 40, 'nested more than'),
    ('x' * (MAX_DESCRIPTION_BYTES + 1), 'robot.yaml: robot file is too large (16,385 characters; '
     'at most 16,384)'),
    ('a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1, 1]\n' + ''.join(
        f'{chr(98 + k)}: &{chr(98 + k)} [' + ', '.join([f'*{chr(97 + k)}'] * 10) + ']\n'
        for k in range(6)), f'holds more than {MAX_ELEMENTS:,} values'),
    ('a: [1, 2\nb: 3', 'robot.yaml:2: robot file is not valid YAML'),
])
def test_yaml_beyond_its_bounds_is_refused_before_it_becomes_objects(text, words):
    with pytest.raises(Refused) as refused:
        parse(text)
    assert words in str(refused.value) and '\n' not in str(refused.value)


def test_yaml_within_its_bounds_reads_as_yaml_1_2_numbers():
    text = '[' * MAX_NESTING + ']' * MAX_NESTING
    assert parse(text) is not None
    assert parse('{rate: 1e3, small: 5E-3, aliased: &x [1], again: *x}') == {
        'rate': 1000.0, 'small': 0.005, 'aliased': [1], 'again': [1]}
    assert parse('') is None


def test_a_file_is_bounded_by_the_size_its_kind_allows(tmp_path):
    path = tmp_path / 'list.yaml'
    path.write_text('robots: [' + ', '.join(['{}'] * 20000) + ']\n')
    with pytest.raises(Refused, match='robot list is too large'):
        read_yaml(path, 'robot list', Refused)
    assert len(read_yaml(path, 'robot list', Refused, max_bytes=1 << 20)['robots']) == 20000


def test_output_that_would_destroy_something_is_refused(tmp_path):
    course = tmp_path / 'course.txt'
    course.write_text('1 2 3\n')
    os.mkfifo(tmp_path / 'fifo')
    assert 'an input of this run' in output_problem(str(course), inputs=[str(course)])
    assert 'an input of this run' in output_problem(str(tmp_path / '.' / 'course.txt'),
                                                    inputs=[str(course)])
    assert output_problem(str(tmp_path)) == 'is a folder, not a file'
    assert 'not a regular file' in output_problem(str(tmp_path / 'fifo'))
    assert 'not a regular file' in output_problem('/dev/null')
    assert 'is not an existing folder' in output_problem(str(tmp_path / 'no' / 'run.jsonl'))
    assert output_problem(str(tmp_path / 'run.jsonl'), inputs=[str(course)]) is None
    assert output_problem(str(course)) is None


def test_folders_give_their_regular_yaml_files_only(tmp_path, monkeypatch):
    for name in ('b.yaml', 'a.yml', 'notes.txt'):
        (tmp_path / name).write_text('x: 1\n')
    os.mkfifo(tmp_path / 'trap.yaml')
    (tmp_path / 'folder.yaml').mkdir()
    assert yaml_files(tmp_path) == ([str(tmp_path / 'a.yml'), str(tmp_path / 'b.yaml')], '')
    monkeypatch.setattr('simple_robot_control.input_files.MAX_FOLDER_FILES', 1)
    found, note = yaml_files(tmp_path)
    assert len(found) == 1 and 'taking at most 1 files' in note
    assert MAX_FOLDER_FILES == 1000
    assert yaml_files(tmp_path / 'none')[1].endswith('cannot read it: No such file or directory')


def test_without_libyaml_the_nesting_is_bounded_while_composing():
    """The pure-Python composer recurses once per level: it stops at the bound, not the stack."""
    deep = '[' * 5000 + ']' * 5000
    with pytest.raises(yaml.YAMLError):
        input_files._PythonLoader(deep).get_single_node()
    shallow = '[' * MAX_NESTING + ']' * MAX_NESTING
    assert input_files._PythonLoader(shallow).get_single_node() is not None

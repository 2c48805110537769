"""
A command line's ROS parameters, judged before the node's code loads.

rclpy, numpy, numba and the message packages take one to two seconds of CPU to load; a value
refused after that wastes it (five to forty-five seconds on a loaded server). So each
executable's parameter table lives in a light module, and the values the command line gives
(`--ros-args -p name:=value`, `--params-file file`) are read here as rcl reads them and judged
by the same rules the node applies when it declares them.

Only what is read for sure is judged early: a value rcl might type otherwise (`yes`, `0x10`,
`.inf`, a block scalar), a parameters file entry for nodes named by a pattern, a parameter
meant for a named node, or a command line with anything not understood here leaves the values
to the node's own check, which runs in every case. So an early refusal is always one the node
would make, in the same words.
"""

from dataclasses import dataclass, field
import re

from simple_robot_control.parameter_specs import ParameterSpec, unknown_problem
from simple_robot_control.validation import parse_decimal
import yaml

ROS_ARGS = '--ros-args'
_PARAMETER_FLAGS = ('-p', '--param')
_REMAP_FLAGS = ('-r', '--remap')
_PARAMETERS_FILE_FLAG = '--params-file'
_FLAGS_WITH_A_VALUE = ('-e', '--enclave', '--log-level', '--log-config-file',
                       '--log-file-name')
_FLAGS_ALONE = ('--enable-rosout-logs', '--disable-rosout-logs', '--enable-stdout-logs',
                '--disable-stdout-logs', '--enable-external-lib-logs',
                '--disable-external-lib-logs')
# Remapping targets that rename the node (a rename of one named node is left to rcl).
_RENAMES = ('__node', '__name', '__ns')
_PARAMETERS_KEY = 'ros__parameters'
_EVERY_NODE = '/**'
# A parameters file larger than this is left to rcl.
_LARGEST_FILE = 1 << 20
# Plain words rcl reads as booleans for sure; others it may (yes, on, y) are left to it.
_BOOLEANS = {'true': True, 'True': True, 'TRUE': True,
             'false': False, 'False': False, 'FALSE': False}
_MAYBE_BOOLEANS = {'y', 'yes', 'n', 'no', 'on', 'off'}
# A whole number with no leading zero (rcl's strtol would read 010 as octal), within int64.
_INTEGER = re.compile(r'[+-]?(?:0|[1-9][0-9]*)', re.ASCII)
_DIGITS = re.compile(r'[+-]?[0-9]+', re.ASCII)
_INT64 = 1 << 63
# A parameter name as rcl takes it; anything else is left to rcl to refuse.
_NAME = re.compile(r'[A-Za-z_][A-Za-z0-9_.]*', re.ASCII)
# A plain word rcl takes as a string: not a number, boolean or null to either YAML reading.
_WORD = re.compile(r'[A-Za-z_/][A-Za-z0-9_/.\-]*', re.ASCII)


class _Unsure:
    """A value whose type rcl may read otherwise than this module: never judged early."""


UNSURE = _Unsure()


@dataclass
class GivenParameters:
    """The values a command line gives one node, in rcl's order, and the names left to it."""

    values: dict = field(default_factory=dict)
    unsure: set = field(default_factory=set)

    def add(self, name: str, value: object) -> None:
        self.values.setdefault(name, []).append(value)


def early_problem(argv: list, node_name: str, specs: tuple) -> str | None:
    """
    Return the line the node would refuse argv's parameters with, where sure; else None.

    Parameters are judged in the table's order, then names the node does not take, as
    declare_parameters does. A parameter given more than once is refused only when every value
    given is bad, whichever of them rcl would keep.
    """
    given = given_parameters(argv, node_name)
    if given is None:
        return None
    for spec in specs:
        if spec.name in given.values and spec.name not in given.unsure:
            problems = [_judged(spec, value) for value in given.values[spec.name]]
            if all(problems):
                return problems[-1]
    sure = [name for name in given.values if name not in given.unsure]
    return unknown_problem(node_name, sure, specs)


def given_parameters(argv: list, node_name: str) -> GivenParameters | None:
    """Read argv's --ros-args sections; None when any part of them is not understood."""
    files, rules, name, namespace = [], [], node_name, '/'
    arguments, index, in_ros_args = list(argv[1:]), 0, False
    while index < len(arguments):
        argument = arguments[index]
        if argument == ROS_ARGS:
            in_ros_args = True
        elif not in_ros_args:
            pass
        elif argument == '--':
            in_ros_args = False
        elif argument in _FLAGS_ALONE:
            pass
        elif index + 1 == len(arguments):
            return None
        else:
            index += 1
            value = arguments[index]
            if argument in _PARAMETER_FLAGS:
                rules.append(value)
            elif argument == _PARAMETERS_FILE_FLAG:
                files.append(value)
            elif argument in _REMAP_FLAGS:
                target, _, replacement = value.partition(':=')
                if ':' in target and target.endswith(_RENAMES):
                    return None
                if target in ('__node', '__name'):
                    name = replacement
                elif target == '__ns':
                    namespace = replacement
            elif argument not in _FLAGS_WITH_A_VALUE:
                return None
        index += 1
    given = GivenParameters()
    full_name = namespace.rstrip('/') + '/' + name
    try:
        for path in files:
            _read_file(path, full_name, given)
        for rule in rules:
            _read_rule(rule, given)
    except (OSError, UnicodeDecodeError, ValueError, RecursionError, yaml.YAMLError):
        return None
    return given


def _read_rule(rule, given):
    """Take one -p rule, name:=value (a YAML value), or node:name:=value for one node only."""
    target, separator, text = rule.partition(':=')
    if not separator:
        raise ValueError(rule)
    if ':' in target:
        given.unsure.add(target.partition(':')[2])
        return
    if not _NAME.fullmatch(target):
        raise ValueError(rule)
    given.add(target, _typed(yaml.compose(text, Loader=yaml.SafeLoader)))


def _read_file(path, full_name, given):
    """Take the values a parameters file gives the node full_name (its namespace and name)."""
    with open(path, encoding='utf-8') as stream:
        text = stream.read(_LARGEST_FILE + 1)
    if len(text) > _LARGEST_FILE:
        raise ValueError(path)
    root = yaml.compose(text, Loader=yaml.SafeLoader)
    for node_key, parameters in _node_entries(root, ()):
        key = '/' + '/'.join(part.strip('/') for part in node_key)
        if key == _EVERY_NODE or key == full_name:
            for name, value in _flattened(parameters, ''):
                given.add(name, value)
        elif '*' in key:
            given.unsure.update(name for name, _ in _flattened(parameters, ''))


def _node_entries(node, path):
    """Yield (path of keys, parameters' mapping) for each ros__parameters in the file."""
    if not isinstance(node, yaml.MappingNode):
        raise ValueError('not a mapping')
    for key, value in node.value:
        _require_text(key)
        if key.value == _PARAMETERS_KEY:
            yield path, value
        else:
            yield from _node_entries(value, path + (key.value,))


def _flattened(node, prefix):
    """Yield (name, value) for each parameter; nested mappings are dotted names."""
    if not isinstance(node, yaml.MappingNode):
        raise ValueError('not a mapping')
    for key, value in node.value:
        _require_text(key)
        name = prefix + key.value
        if isinstance(value, yaml.MappingNode):
            yield from _flattened(value, name + '.')
        else:
            yield name, _typed(value)


def _typed(node):
    """Return the value rcl reads from a YAML node, or UNSURE where it might read otherwise."""
    if isinstance(node, yaml.SequenceNode):
        items = [_typed(item) for item in node.value]
        kinds = {type(item) for item in items}
        return items if len(kinds) == 1 and UNSURE not in items else UNSURE
    if not isinstance(node, yaml.ScalarNode):
        return UNSURE
    mark = node.start_mark
    if mark.buffer is not None and mark.buffer[mark.pointer] in '!&':
        return UNSURE  # a tag or an anchor
    if node.style in ('"', "'"):
        return node.value
    text = node.value
    if node.style is not None or text.lower() in _MAYBE_BOOLEANS:
        return UNSURE
    if text in _BOOLEANS:
        return _BOOLEANS[text]
    if _DIGITS.fullmatch(text):
        number = int(text)
        whole = _INTEGER.fullmatch(text) and -_INT64 <= number < _INT64
        return number if whole else UNSURE
    number = parse_decimal(text)
    if number is not None:
        return number
    if _WORD.fullmatch(text) and not text.lower().startswith(('inf', 'nan', 'null')):
        return text
    return UNSURE


def _require_text(key):
    if not isinstance(key, yaml.ScalarNode):
        raise ValueError('a key that is not a text')


def _judged(spec: ParameterSpec, value) -> str | None:
    if value is UNSURE:
        return None
    typed = spec.as_declared_type(value)
    if typed is None:
        return spec.type_problem(value)
    return spec.problem(typed)

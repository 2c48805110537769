"""stdr_ctl's arguments: every count, wait and name is bounded before anything is sent."""

import pytest
from stdr_lite.node.results import MAX_ACTION_STEPS, MAX_SERVICE_STEPS
from stdr_lite.tools.ctl_commands import build_arguments, COMMANDS, SCOPES


@pytest.mark.parametrize('arguments, words', [
    (['step', '18446744073709551616'], f'not a whole number of steps from 1 to '
     f'{MAX_SERVICE_STEPS:,}'),
    (['step', '0'], 'not a whole number of steps'),
    (['step', '\u0662'], 'not a whole number of steps'),
    (['simulate', str(MAX_ACTION_STEPS + 1)], f'from 1 to {MAX_ACTION_STEPS:,}'),
    (['--simulator', '/bad name', 'state'],
     "not the full name of a node (such as /stdr_lite): '/bad name'"),
    (['--simulator', '', 'state'], "not the full name of a node (such as /stdr_lite): ''"),
    (['--simulator', '//', 'state'], "not the full name of a node (such as /stdr_lite): '//'"),
    (['--timeout', '-1', 'state'], 'a timeout must be in (0, 3600] seconds'),
    (['--timeout', 'nan', 'state'], 'not a finite number'),
    (['state', '--timeout', '0'], 'a timeout must be in (0, 3600] seconds'),
    (['reset', 'everything'], "invalid choice: 'everything' (choose from all, spawned, state"),
])
def test_out_of_range_arguments_are_refused_in_one_line(capsys, arguments, words):
    with pytest.raises(SystemExit) as ended:
        build_arguments().parse_args(arguments)
    assert ended.value.code == 2
    error = capsys.readouterr().err
    assert words in error and error.startswith('stdr_ctl') and ': error: ' in error
    assert len(error.strip().splitlines()) == 1


def test_the_largest_counts_pass():
    parser = build_arguments()
    assert parser.parse_args(['step', str(MAX_SERVICE_STEPS)]).steps == MAX_SERVICE_STEPS
    assert parser.parse_args(['simulate', str(MAX_ACTION_STEPS)]).steps == MAX_ACTION_STEPS
    assert parser.parse_args(['--simulator', '/team_a/sim', 'state']).simulator == '/team_a/sim'


def test_reset_with_no_scope_resets_all():
    options = build_arguments().parse_args(['reset'])
    assert options.scope == []
    assert COMMANDS['reset'][2](options).fields['scope'] == SCOPES['all']


@pytest.mark.parametrize('arguments', [
    ['--timeout', '3', '--simulator', '/sim2', 'list'],
    ['list', '--timeout', '3', '--simulator', '/sim2'],
    ['--timeout', '9', 'list', '--simulator', '/sim2', '--timeout', '3'],
])
def test_timeout_and_simulator_go_before_or_after_the_command(arguments):
    options = build_arguments().parse_args(arguments)
    assert (options.timeout, options.simulator) == (3.0, '/sim2')


def test_defaults_hold_when_neither_is_given():
    options = build_arguments().parse_args(['list'])
    assert (options.timeout, options.simulator) == (10.0, '/stdr_lite')

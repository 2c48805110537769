"""stdr_ctl's arguments: every count, wait and name is bounded before anything is sent."""

import pytest
from stdr_lite.node.results import MAX_ACTION_STEPS, MAX_SERVICE_STEPS
from stdr_lite.tools.ctl_commands import build_arguments


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

"""How an executable ended, in one line, as the launch file prints it."""

import pytest

from simple_robot_control.exit_codes import describe_exit


@pytest.mark.parametrize('code, words', [
    (0, 'finished'), (1, 'the run failed'), (2, 'refused its input'), (-9, 'killed'),
    (7, 'ended unexpectedly')])
def test_every_code_has_a_meaning(code, words):
    line = describe_exit('waypoint_controller', code)
    assert line.startswith(f'waypoint_controller exited with code {code}: ')
    assert words in line and '\n' not in line

"""The lab dialogue: it re-asks until it gets a finite number and stops at end of input."""

import math

import pytest
from stdr_lite.tools.lab_session import ask_motion, ask_number, EndOfInput, format_pose


def scripted(*answers):
    """Return a read_line that gives answers in turn, then None (end of input)."""
    remaining = list(answers)
    return lambda: remaining.pop(0) if remaining else None


def test_motion_is_asked_in_the_labs_order_with_degrees_converted():
    written = []
    motion = ask_motion(scripted('1', '10', '9'), written.append)
    assert motion == pytest.approx((1.0, math.radians(10), 9.0))
    assert written == ['Enter desired linear velocity: ', 'Enter desired rotational velocity: ',
                       'Enter desired duration: ']


@pytest.mark.parametrize('bad', ['abc', 'nan', 'inf', '-inf', '', '1e999', '5_0'])
def test_non_finite_answers_are_refused_with_one_line(bad):
    written = []
    assert ask_number('v: ', scripted(bad, '2.5'), written.append) == 2.5
    complaint = written[1]
    assert complaint.startswith('Not a finite number') and complaint.count('\n') == 1


def test_negative_duration_is_refused():
    written = []
    assert ask_number('d: ', scripted('-1', '3'), written.append, minimum=0.0) == 3.0
    assert 'at least 0' in written[1]


def test_end_of_input_ends_the_dialogue():
    with pytest.raises(EndOfInput):
        ask_motion(scripted('1', '0'), lambda text: None)


def test_pose_line_reports_theta_in_degrees():
    assert format_pose(0.5701, 7.7209, math.radians(177.0069)) == (
        'Current position, x: 0.570, y: 7.721, theta: 177.01')

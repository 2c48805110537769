"""policy_controller: the shipped policy drives a live robot through a course; bad input."""

import signal

from processes import run, start_logged, stop


def test_a_file_that_is_no_policy_is_one_line_and_exit_code_2(tmp_path):
    bad = tmp_path / 'policy.npz'
    bad.write_text('weights, honestly')
    course = tmp_path / 'course.txt'
    course.write_text('2 2 0\n')
    result = run('policy_controller', str(course), '--ros-args', '-p', f'policy:={bad}')
    assert result.returncode == 2
    assert result.stderr.startswith(f'policy_controller: error: {bad}: not a policy file: ')
    assert len(result.stderr.splitlines()) == 1 and 'Traceback' not in result.stderr


def test_the_shipped_policy_drives_a_live_robot_to_finished(tmp_path):
    course = tmp_path / 'ahead.txt'
    course.write_text('2.5 2.0 0\n2.5 3.5 90\n')
    simulator = start_logged('stdr_lite', '--ros-args', '-p', 'real_time_factor:=2.0',
                             '--log-level', 'warn', log=tmp_path / 'stdr_lite.log')
    try:
        result = run('policy_controller', str(course), timeout=120)
    finally:
        assert stop(simulator, signal.SIGINT)[0] == 0
    assert result.returncode == 0, result.stderr
    texts = [line.split(']: ')[-1] for line in result.stderr.splitlines()]
    assert [text.split()[0] for text in texts if text.split()[0].isupper()] == [
        'STARTED', 'WAYPOINT', 'WAYPOINT', 'FINISHED']
    assert 'Traceback' not in result.stderr

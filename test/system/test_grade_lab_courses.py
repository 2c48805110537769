"""grade_lab on our own controller: every bundled course passes."""

from grade_runs import grade
from simple_robot_control.share import installed_executable, shared_file


def test_our_controller_passes_every_bundled_course(tmp_path):
    # In lockstep a run's outcome is the commands' alone: as fast as it goes, as at any pace.
    result = grade('--courses', shared_file('waypoints'), '--jobs', 2, '--lockstep',
                   '--real-time-factor', 0, '--report', tmp_path / 'report', '--',
                   installed_executable('waypoint_controller'), '{waypoints}')
    assert result.returncode == 0, result.stdout + result.stderr
    assert '6 of 6 courses passed: 6/6 points' in result.stdout
    for course in ('lab_tour', 'square', 'rotations', 'behind', 'wraparound', 'lab_format'):
        assert (tmp_path / 'report' / course / 'run.png').is_file()

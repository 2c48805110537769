"""The documentation's commands run exactly as printed, from the folder they are typed in."""

import os
from pathlib import Path
import re
import shlex
import signal
import subprocess
import sys

from grade_runs import grade, write_course
from processes import executable, stop, wait_for_text

REPOSITORY = Path(__file__).resolve().parents[2]
STUDENT = REPOSITORY / 'test' / 'controllers' / 'student.py'
# Each group's controller.py: the test submission, honest (it reports the pose it is at).
CONTROLLER = ('import runpy, sys\n'
              f'sys.argv = [{str(STUDENT)!r}, "honest", sys.argv[1]]\n'
              f'runpy.run_path({str(STUDENT)!r}, run_name="__main__")\n')


def readme_command(program):
    """Return the README's command line of program, its continuation lines joined."""
    text = (REPOSITORY / 'README.md').read_text().replace('\\\n', ' ')
    line = next(line for line in text.splitlines() if line.startswith(f'{program} '))
    return shlex.split(line.split('#')[0])


def test_the_readmes_grade_lab_example_runs_as_printed(tmp_path, monkeypatch):
    """Relative --courses, --submissions and --report, as a teacher types them."""
    command = readme_command('grade_lab')
    assert command == ['grade_lab', '--courses', 'hidden/', '--submissions', 'groups/',
                       '--jobs', '4', '--report', 'report', '--', 'python3', 'controller.py',
                       '{waypoints}']
    write_course(tmp_path / 'hidden', 'here', '1.0 2.0 0.0', time_limit=20)
    for group in ('group_a', 'group_b'):
        (tmp_path / 'groups' / group).mkdir(parents=True)
        (tmp_path / 'groups' / group / 'controller.py').write_text(CONTROLLER)
    # As after `source .venv/bin/activate`: python3 is the one with rclpy.
    monkeypatch.setenv('PATH', f'{Path(sys.executable).parent}{os.pathsep}{os.environ["PATH"]}')
    result = grade(*command[1:], cwd=tmp_path, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    for group in ('group_a', 'group_b'):
        assert re.search(rf'{group}\s+PASS', result.stdout), result.stdout
        assert (tmp_path / 'report' / group / 'results.json').is_file()
    assert (tmp_path / 'report' / 'report.md').is_file()


def test_the_viewer_without_a_display_says_so_in_one_line(tmp_path):
    """students.md's `stdr_viewer` typed over ssh: no window, and it says how to see a frame."""
    environment = {key: value for key, value in os.environ.items()
                   if key not in ('DISPLAY', 'WAYLAND_DISPLAY', 'SDL_VIDEODRIVER')}
    log = tmp_path / 'viewer.log'
    with open(log, 'w') as output:
        viewer = subprocess.Popen([executable('stdr_viewer')], stdout=output,
                                  stderr=subprocess.STDOUT, env=environment, cwd=tmp_path)
    try:
        said = wait_for_text(log, 'no display here', viewer, timeout=30.0)
    finally:
        code, _ = stop(viewer, signal.SIGINT)
    assert code == 0
    line = next(line for line in said.splitlines() if 'no display here' in line)
    assert '-p screenshot:=view.png' in line and 'XDG_RUNTIME_DIR' not in said

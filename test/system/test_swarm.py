"""make swarm's script: a picture once the viewer shows the run, or one line; nothing left."""

import os
from pathlib import Path
import subprocess
import sys

from grade_runs import TAG, tagged_processes

REPOSITORY = Path(__file__).resolve().parents[2]


def swarm(folder, **settings):
    """Run scripts/swarm.sh offscreen in folder, as make swarm does; return its result."""
    environment = {key: value for key, value in os.environ.items() if key != 'DISPLAY'}
    environment.update(settings, SCREENSHOT=str(folder / 'swarm.png'), **{TAG: str(folder)},
                       PATH=f'{Path(sys.executable).parent}{os.pathsep}{environment["PATH"]}')
    return subprocess.run(['bash', str(REPOSITORY / 'scripts' / 'swarm.sh')], cwd=folder,
                          env=environment, capture_output=True, text=True, timeout=300)


def test_the_swarm_picture_comes_once_the_run_is_shown_and_nothing_is_left(tmp_path):
    result = swarm(tmp_path, SECONDS_TO_RUN='1')
    assert result.returncode == 0, result.stdout + result.stderr
    assert 'swarm: the run is shown' in result.stdout
    assert (tmp_path / 'swarm.png').read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    assert not tagged_processes(str(tmp_path), tmp_path)


def test_no_picture_in_time_is_one_line_and_exit_code_1(tmp_path):
    result = swarm(tmp_path, SECONDS_TO_RUN='1', SHOW_WITHIN='0')
    assert result.returncode == 1
    assert result.stderr.strip().splitlines()[-1] == (
        'swarm: stdr_viewer showed no run within 0 s: no picture')
    assert not (tmp_path / 'swarm.png').exists()
    assert not tagged_processes(str(tmp_path), tmp_path)

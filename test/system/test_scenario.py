"""make scenario's script: a coursework scenario brought up in one command, or refused."""

import os
from pathlib import Path
import subprocess
import sys

REPOSITORY = Path(__file__).resolve().parents[2]


def scenario(tmp_path, name, **variables):
    return subprocess.run(
        ['bash', str(REPOSITORY / 'scripts' / 'scenario.sh')], capture_output=True, text=True,
        cwd=tmp_path, timeout=300,
        env=dict(os.environ, SCENARIO=name, **variables,
                 PATH=f'{Path(sys.executable).parent}{os.pathsep}{os.environ["PATH"]}'))


def test_a_mapping_scenario_runs_its_reference_answer_and_is_judged(tmp_path):
    """The run, drawn; then the task's judge: its line, and its reading of every cell."""
    result = scenario(tmp_path, 'plus_room_mapping', REAL_TIME_FACTOR='0')
    assert result.returncode == 0, result.stdout + result.stderr
    lines = result.stdout.splitlines()
    assert 'FINISHED' in lines and 'Traceback' not in result.stderr
    assert any(line.startswith('mapping: PASS: agreement ') for line in lines), lines
    for name in ('run.png', 'task.png', 'run.mcap'):
        assert (tmp_path / name).is_file(), name


def test_an_unknown_scenario_is_refused_in_one_line(tmp_path):
    result = scenario(tmp_path, 'factory_planing')
    assert result.returncode == 2
    assert result.stderr.splitlines() == [
        "scenario: 'factory_planing' is neither a course file nor a bundled scenario "
        '(factory_exploration, factory_mapping, factory_planning, plus_room_exploration, '
        'plus_room_mapping, plus_room_planning, simple_walls_mapping, simple_walls_planning)']

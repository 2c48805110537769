"""
What sealing submissions off costs: grade_lab on the bundled scenarios, sandboxed and not.

The eight coursework scenarios are graded with their reference answers (courseworks/names.py),
in lockstep as fast as they go, two at a time: once with each submission sealed off
(`--sandbox namespaces`: a uid and namespaces of its own, needing root) and once as grade_lab's
own user (`--sandbox none`), round after round, interleaved. Printed: each grading's wall
seconds and verdicts, and the sealed over the unsealed wall time (target at most 1.2).

--smoke grades the lab's rotations course with waypoint_controller instead (seconds), as make
test does. Not root (or namespaces refused), it grades unsealed alone and says so.
"""

import argparse
import os
from pathlib import Path
import statistics
import subprocess
import sys
import tempfile
import time

from coursework_answers.answers import REFERENCE_ANSWERS
from courseworks.courses import find_courses
from lab_grader.sandbox import choose_mode, NAMESPACES
from simple_robot_control.share import installed_executable, shared_file

SCENARIOS = ('factory_planning', 'plus_room_planning', 'simple_walls_planning',
             'factory_mapping', 'plus_room_mapping', 'simple_walls_mapping',
             'factory_exploration', 'plus_room_exploration')
SMOKE = (('waypoints', 'rotations.txt'),)
TARGET = 1.2


def answer_script(task: str) -> str:
    """Return a shell script running a task's reference answer: its helpers, then its law."""
    answer = REFERENCE_ANSWERS[task]
    lines = ['#!/bin/sh']
    for number, helper in enumerate(answer.helpers):
        lines.append(f'{installed_executable(helper)} & helper{number}=$!')
    parameters = ''.join(f' -p {name}:={value}' for name, value in answer.parameters.items())
    lines.append(f'{installed_executable(answer.controller)} "$2"'
                 + (f' --ros-args{parameters}' if parameters else ''))
    lines.append('code=$?')
    lines += [f'kill -INT $helper{number}; wait $helper{number}'
              for number in range(len(answer.helpers))]
    lines.append('exit $code')
    return '\n'.join(lines) + '\n'


def grade(scenarios: tuple[str, ...], sandbox: str, folder: Path) -> tuple[float, str]:
    """Grade the scenarios with their answers, one grade_lab per task; return (wall s, table)."""
    by_task = {}
    for shared_folder, name in scenarios:
        path = shared_file(shared_folder, name)
        by_task.setdefault(find_courses([path])[0].task, []).append(path)
    seconds, tables = 0.0, []
    for task, paths in by_task.items():
        group = folder / sandbox / task / 'reference'
        group.mkdir(parents=True)
        (group / 'run.sh').write_text(answer_script(task))
        (group / 'run.sh').chmod(0o755)
        began = time.monotonic()
        result = subprocess.run(
            [installed_executable('grade_lab'), '--courses', *paths, '--jobs', '2',
             '--lockstep', '--real-time-factor', '0', '--sandbox', sandbox, '--', './run.sh',
             '@', '{waypoints}'], cwd=group, capture_output=True, text=True, timeout=3600,
            env=dict(os.environ, ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST'))
        seconds += time.monotonic() - began
        if result.returncode not in (0, 1):
            sys.exit(f'grade_lab failed: {result.stderr.strip()[-500:]}')
        names = {Path(name).stem for _, name in scenarios}
        tables.append('\n'.join(line for line in result.stdout.splitlines()
                                if line.split()[:1] and line.split()[0] in names))
    return seconds, '\n'.join(tables)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--smoke', action='store_true', help='one small scenario (seconds)')
    parser.add_argument('--rounds', type=int, default=1, help='rounds of both gradings')
    options = parser.parse_args(argv)
    scenarios = SMOKE if options.smoke else tuple(('scenarios', f'{name}.txt')
                                                  for name in SCENARIOS)
    mode, why = choose_mode('auto')
    sandboxes = ('none', 'namespaces') if mode == NAMESPACES else ('none',)
    if mode != NAMESPACES:
        print(f'sealed grading not measured: {why}')
    times = {sandbox: [] for sandbox in sandboxes}
    with tempfile.TemporaryDirectory(prefix='bench-grading-') as scratch:
        for round_number in range(options.rounds):
            for sandbox in sandboxes:
                folder = Path(scratch) / str(round_number)
                seconds, table = grade(scenarios, sandbox, folder)
                times[sandbox].append(seconds)
                print(f'--sandbox {sandbox:10} {seconds:6.1f} s wall, {len(scenarios)} '
                      f'scenario(s):\n{table}', flush=True)
    if 'namespaces' in times:
        ratio = statistics.median(times['namespaces']) / statistics.median(times['none'])
        print(f'sealed / unsealed wall time: {ratio:.2f} (target at most {TARGET:g}: '
              f'{"met" if ratio <= TARGET else "missed"})')
    return 0


if __name__ == '__main__':
    sys.exit(main())

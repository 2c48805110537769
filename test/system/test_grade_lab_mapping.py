"""grade_lab on the mapping and exploration courseworks: the answers pass, cheats fail."""

import os
from pathlib import Path
import re
import shutil
import sys

from grade_runs import grade
import pytest
from simple_robot_control.share import installed_executable, shared_file
from test_grade_lab import verdicts

# Its tests share a module-scoped fixture: one worker runs them all (pytest.ini: loadgroup).
pytestmark = pytest.mark.xdist_group('grade_lab_mapping')

COPIER = Path(__file__).resolve().parents[1] / 'controllers' / 'map_copier.py'
PORTED_MAPPER = Path(__file__).resolve().parents[2] / 'examples' / 'porting' / 'coarse_mapper.py'
VENV_BIN = str(Path(sys.executable).parent)
# Every mapper on the smallest world (the factory's run, 190 s of sim time, and every answer on
# every scenario are make bench's: bench.courseworks; make scenario's test runs the reference on
# the same world, through make scenario's door).
SCENARIO = 'plus_room_mapping'


def reference_script(*parameters):
    """Return a reference answer as one command: the mapper beside the planner on its map."""
    extra = ''.join(f' -p {parameter}' for parameter in parameters)
    return (f'{installed_executable("occupancy_mapper")} & mapper=$!\n'
            f'{installed_executable("planner_controller")} "$2" --ros-args '
            f'-p map_topic:=/coursework_map -p max_map_age:=1.5{extra}\n'
            'code=$?\nkill -INT $mapper\nwait $mapper\nexit $code\n')


def porting_script():
    """
    Return doc/porting.md's run.sh, as printed: the ported mapper beside the reference planner.

    It names the nodes as a user with the venv active does: the venv's bin goes first on PATH.
    """
    page = (Path(__file__).resolve().parents[2] / 'doc' / 'porting.md').read_text()
    [script] = re.findall(r'```sh\n#!/bin/sh\n(.*?)```', page, re.DOTALL)
    return script


def write_groups(folder, scripts):
    for group, script in scripts.items():
        (folder / group).mkdir(parents=True)
        (folder / group / 'run.sh').write_text(f'#!/bin/sh\n{script}')
        (folder / group / 'run.sh').chmod(0o755)
    return folder


@pytest.fixture(scope='module')
def graded(tmp_path_factory):
    """
    Grade the mappers and explorers; give the results and reports.

    The mappers: the reference, doc/porting.md's ported one, a map copier and one sending a
    map far larger than the world. The copier publishes the world's map file and ends, having
    driven nowhere: on the exploration scenario it stands for an explorer that stands still.
    """
    root = tmp_path_factory.mktemp('mapping')
    copier = f'exec {sys.executable} {COPIER}\n'
    gradings = (
        (write_groups(root / 'mapping', {'reference': reference_script(),
                                         'copies_map': copier,
                                         'coarse_mapper': porting_script(),
                                         'huge_map': copier.replace('\n', ' --huge\n')}),
         (SCENARIO,)),
        (write_groups(root / 'exploration', {
            'explorer': reference_script('explore_for:=3600.0'), 'stands_still': copier}),
         ('plus_room_exploration',)))
    shutil.copy(PORTED_MAPPER, root / 'mapping' / 'coarse_mapper')
    results = {}
    path = os.environ['PATH']
    os.environ['PATH'] = f'{VENV_BIN}:{path}'
    try:
        for groups, scenarios in gradings:
            results[groups.name] = grade(
                '--courses', *(shared_file('scenarios', f'{name}.txt') for name in scenarios),
                '--submissions', groups, '--jobs', 4, '--lockstep', '--real-time-factor', 0,
                '--report', root / 'report' / groups.name, '--', './run.sh', '@',
                '{waypoints}', cwd=root, timeout=900)
    finally:
        os.environ['PATH'] = path
    return results, root / 'report'


def test_the_reference_mapper_and_planner_pass(graded):
    results, report = graded
    checks = verdicts(report / 'mapping', 'reference', SCENARIO)
    failed = {name: evidence for name, (passed, evidence) in checks.items() if not passed}
    assert not failed and f'reference / {SCENARIO}: PASS' in results['mapping'].stdout, (
        results['mapping'].stdout)
    assert checks['mapping'][0]


def test_a_mapper_written_the_stdr_way_at_a_quarter_metre_passes(graded):
    """doc/porting.md's mapper: static_map at start, 0.25 m cells over the world's 0.05 m."""
    _, report = graded
    passed, evidence = verdicts(report / 'mapping', 'coarse_mapper', SCENARIO)['mapping']
    assert passed, evidence


def test_a_map_copied_from_the_map_file_fails_as_not_built_from_the_laser(graded):
    results, report = graded
    evidence = verdicts(report / 'mapping', 'copies_map', SCENARIO)['mapping']
    assert not evidence[0] and 'not built from the laser alone' in evidence[1]
    assert results['mapping'].returncode == 1


def test_a_map_larger_than_the_world_is_refused_as_it_comes(graded):
    _, report = graded
    passed, evidence = verdicts(report / 'mapping', 'huge_map', SCENARIO)['mapping']
    assert not passed and '16,000,104 bytes on /coursework_map' in evidence
    assert ("more than a map of the world's 300x300 cells at 4 times finer takes: refused as "
            'it came') in evidence
    bag = report / 'mapping' / 'huge_map' / SCENARIO / 'run.mcap'
    assert bag.stat().st_size < 4 << 20, 'the refused map is not in the bag either'


def test_the_reference_explorer_passes_and_one_standing_still_fails(graded):
    results, report = graded
    explored = verdicts(report / 'exploration', 'explorer', 'plus_room_exploration')
    assert all(passed for passed, _ in explored.values()) and 'exploration' in explored
    passed, evidence = verdicts(report / 'exploration', 'stands_still',
                                'plus_room_exploration')['exploration']
    assert not passed and evidence.startswith('saw 18.6% of the reachable free space, needs '
                                              "80.0% (80% of the reference explorer's 100.0%)")

"""The interface packages the PyPI route lacks: built with upstream's hashes, only when needed."""

import json
import os
from pathlib import Path
import shutil
import subprocess
import sys

import pytest

REPOSITORY = Path(__file__).resolve().parents[2]
BUILD = REPOSITORY / 'scripts' / 'build_interfaces.sh'
# From the upstream Jazzy definitions; a built package must give the same.
UPSTREAM_HASHES = {
    'tf2_msgs/msg/TFMessage':
        'RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087',
    'simulation_interfaces/srv/SpawnEntity':
        'RIHS01_d4c086345d4194a5fc4c9ae45095736ca4062b5cdac4d06a42dec93d683e03cf',
    'simulation_interfaces/srv/StepSimulation':
        'RIHS01_913fe0653690ce6bf8f09f316e6a626747012e9fca31e26719910d417aa8565c',
    'simulation_interfaces/srv/SetSimulationState':
        'RIHS01_a868b916dce49974f637ba252141258c4b07b0c06858b88af560e3eb6bfbcb30',
    'simulation_interfaces/msg/EntityState':
        'RIHS01_2e0464a85eb80a939025075d6c20761eca6a4cb9d6baf2c0ba373467c8b598d0',
    'simulation_interfaces/action/SimulateSteps':
        'RIHS01_f0837c898e1219cd73bf4c041feab41e8c533e8e1057e982744dba7b093467eb',
}
# STDR's stdr_msgs has no ROS 2 release: its one service here is pinned, so that a change to
# the definition (which would part it from every client built against it) is seen.
PINNED_HASHES = {
    'stdr_msgs/srv/MoveRobot':
        'RIHS01_0cc151cb1961655846081c757c7ad72d6bb6a3fe9a30ce95b50574d4e3a2d21b',
}
# The Jazzy release of simulation_interfaces (1.5.1): every definition, by kind.
SIMULATION_INTERFACES = {
    'msg': ['Bounds', 'EntityCategory', 'EntityFilters', 'EntityInfo', 'EntityState',
            'NamedPose', 'Resource', 'Result', 'SimulationState', 'SimulatorFeatures',
            'SpawnEntity', 'SpawnResult', 'Spawnable', 'TagsFilter', 'WorldResource'],
    'srv': ['DeleteEntity', 'GetAvailableWorlds', 'GetCurrentWorld', 'GetEntities',
            'GetEntitiesStates', 'GetEntityBounds', 'GetEntityInfo', 'GetEntityState',
            'GetNamedPoseBounds', 'GetNamedPoses', 'GetSimulationState', 'GetSimulatorFeatures',
            'GetSpawnables', 'LoadWorld', 'ResetSimulation', 'SetEntityInfo', 'SetEntityState',
            'SetSimulationState', 'SpawnEntities', 'SpawnEntity', 'StepSimulation',
            'UnloadWorld'],
    'action': ['SimulateSteps'],
}


def share_of(package):
    try:
        from ament_index_python.packages import get_package_share_directory
        return Path(get_package_share_directory(package))
    except (ImportError, LookupError, OSError):
        return Path(sys.prefix) / 'share' / package


@pytest.mark.parametrize('interface', [*UPSTREAM_HASHES, *PINNED_HASHES])
def test_built_types_hash_as_upstream(interface):
    package, kind, name = interface.split('/')
    description = json.loads((share_of(package) / kind / f'{name}.json').read_text())
    hashes = {entry['type_name']: entry['hash_string'] for entry in description['type_hashes']}
    assert hashes[interface] == {**UPSTREAM_HASHES, **PINNED_HASHES}[interface]


@pytest.mark.parametrize('kind', SIMULATION_INTERFACES)
def test_every_simulation_interface_is_built(kind):
    """Each definition of the release, and no other, is written, built and importable."""
    sources = REPOSITORY / 'interfaces' / 'simulation_interfaces' / kind
    assert sorted(path.stem for path in sources.iterdir()) == SIMULATION_INTERFACES[kind]
    module = __import__(f'simulation_interfaces.{kind}', fromlist=['*'])
    for name in SIMULATION_INTERFACES[kind]:
        assert (share_of('simulation_interfaces') / kind / f'{name}.json').is_file()
        assert hasattr(module, name)


def run_build(interfaces):
    return subprocess.run(['bash', str(BUILD), sys.prefix, str(interfaces)], capture_output=True,
                          text=True, timeout=600, env=dict(os.environ))


def test_a_second_install_builds_nothing():
    result = run_build(REPOSITORY / 'interfaces')
    assert result.returncode == 0, result.stderr
    for line in result.stdout.splitlines():
        assert line.endswith(('up to date', 'provided by this environment; not built')), line


def test_a_package_that_imports_already_is_left_alone(tmp_path):
    """As on a ROS machine, where rosdep installed the real package."""
    shutil.copytree(REPOSITORY / 'interfaces' / 'cmake', tmp_path / 'cmake')
    shutil.copytree(REPOSITORY / 'interfaces' / 'tf2_msgs', tmp_path / 'geometry_msgs')
    result = run_build(tmp_path)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == ['geometry_msgs: provided by this environment; not built']


def test_colcon_leaves_the_interfaces_to_rosdep():
    assert (REPOSITORY / 'interfaces' / 'COLCON_IGNORE').is_file()


def built_here(name):
    """Return the digest this environment's build of name came from, or skip the test."""
    stamp = Path(sys.prefix) / 'share' / name / 'built_from_interfaces'
    if not stamp.is_file():
        pytest.skip(f'{name} is provided by this environment, not built from interfaces/')
    return stamp.read_text().strip()


@pytest.mark.parametrize('name', ['simulation_interfaces', 'tf2_msgs'])
def test_only_what_rclpy_uses_is_generated(name):
    built_here(name)
    libraries = sorted(path.name for path in (Path(sys.prefix) / 'lib').glob(f'lib{name}__*'))
    assert f'lib{name}__rosidl_typesupport_c.so' in libraries
    assert f'lib{name}__rosidl_typesupport_fastrtps_c.so' in libraries
    assert not [library for library in libraries if library.endswith('_cpp.so')], libraries
    assert not list((Path(sys.prefix) / 'include' / name).rglob('*.hpp'))


def test_another_environment_gets_the_build_from_the_cache(tmp_path):
    """A second clone restores the build kept in the machine's cache, moved to its prefix."""
    digest = built_here('tf2_msgs')
    cache = Path(os.environ.get('SIMPLE_ROBOT_CONTROL_CACHE') or Path(
        os.environ.get('XDG_CACHE_HOME') or Path.home() / '.cache') / 'simple_robot_control')
    if not (cache / 'interfaces' / f'tf2_msgs-{digest}.tar.gz').is_file():
        pytest.skip('this environment was built with the cache off or cleared')
    other = tmp_path / 'venv'
    (other / 'bin').mkdir(parents=True)
    (other / 'bin' / 'python').write_text(f'#!/bin/sh\nexec {sys.executable} "$@"\n')
    (other / 'bin' / 'python').chmod(0o755)
    # A stale build of its own, so that its Python (ours) importing tf2_msgs does not count.
    (other / 'share' / 'tf2_msgs').mkdir(parents=True)
    (other / 'share' / 'tf2_msgs' / 'built_from_interfaces').write_text('stale\n')
    interfaces = tmp_path / 'interfaces'
    shutil.copytree(REPOSITORY / 'interfaces' / 'cmake', interfaces / 'cmake')
    shutil.copytree(REPOSITORY / 'interfaces' / 'tf2_msgs', interfaces / 'tf2_msgs')
    result = subprocess.run(['bash', str(BUILD), str(other), str(interfaces)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines() == [f'tf2_msgs: restored from {cache / "interfaces"}']
    assert (other / 'share' / 'tf2_msgs' / 'built_from_interfaces').read_text().strip() == digest
    assert (other / 'lib' / 'libtf2_msgs__rosidl_typesupport_c.so').is_file()
    assert list(other.glob('lib/python3*/site-packages/tf2_msgs/msg/_tf_message.py'))
    restored = [path for path in other.rglob('*') if path.is_file() and path.suffix != '.so'
                and path.parent.name != 'bin']
    assert not [path for path in restored if sys.prefix in path.read_text(errors='ignore')]
    assert [path for path in restored if str(other) in path.read_text(errors='ignore')]

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
}


def share_of(package):
    try:
        from ament_index_python.packages import get_package_share_directory
        return Path(get_package_share_directory(package))
    except (ImportError, LookupError, OSError):
        return Path(sys.prefix) / 'share' / package


@pytest.mark.parametrize('interface', UPSTREAM_HASHES)
def test_built_types_hash_as_upstream(interface):
    package, kind, name = interface.split('/')
    description = json.loads((share_of(package) / kind / f'{name}.json').read_text())
    hashes = {entry['type_name']: entry['hash_string'] for entry in description['type_hashes']}
    assert hashes[interface] == UPSTREAM_HASHES[interface]


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

"""package.xml's rosdep keys: each one rosdistro has, or ours in rosdep/, installing setup.py's."""

import ast
from pathlib import Path
import xml.etree.ElementTree as ElementTree

import yaml

REPOSITORY = Path(__file__).resolve().parents[2]
# The pip keys package.xml names that rosdistro's rosdep/python.yaml has (read 2026-12-05);
# a new pip key goes here once rosdistro has it, or into rosdep/simple_robot_control.yaml.
ROSDISTRO_PIP_KEYS = {'python3-rosbags-pip', 'python3-gymnasium-pip'}


def exec_depends():
    root = ElementTree.parse(REPOSITORY / 'package.xml').getroot()
    return {element.text for element in root.iter('exec_depend')}


def install_requires():
    tree = ast.parse((REPOSITORY / 'setup.py').read_text())
    [requires] = [keyword.value for node in ast.walk(tree) if isinstance(node, ast.Call)
                  for keyword in node.keywords if keyword.arg == 'install_requires']
    return {item.split('>')[0].split('=')[0].lower() for item in ast.literal_eval(requires)}


def our_keys():
    return yaml.safe_load((REPOSITORY / 'rosdep' / 'simple_robot_control.yaml').read_text())


def test_every_pip_key_is_rosdistros_or_ours():
    pip_keys = {key for key in exec_depends() if key.endswith('-pip')}
    assert pip_keys == ROSDISTRO_PIP_KEYS | set(our_keys())
    assert not ROSDISTRO_PIP_KEYS & set(our_keys())


def test_our_keys_install_what_setup_py_requires_on_every_platform():
    for key, platforms in our_keys().items():
        assert set(platforms) == {'debian', 'fedora', 'osx', 'ubuntu'}, key
        for platform, installer in platforms.items():
            [package] = installer['pip']['packages']
            assert package in install_requires(), (key, platform)
            assert key == f'python3-{package}-pip'

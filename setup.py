"""Build and install simple_robot_control (ament_python; also installable with pip)."""

import ast
from glob import glob
import os
import sys
import sysconfig

from setuptools import find_packages, setup

PACKAGE_NAME = 'simple_robot_control'
SHARE = f'share/{PACKAGE_NAME}'


# The packages that declare executables, each in its executables.py (EXECUTABLES).
EXECUTABLE_PACKAGES = ('stdr_lite', 'foxglove_live', 'waypoint_lab', 'waypoint_controller',
                       'lab_grader', 'coursework_answers')


def console_scripts():
    """
    Return a console script for each executable the packages declare, by its package.

    Read from the source as text: importing it here would find an installed copy first.
    """
    scripts = []
    for package in EXECUTABLE_PACKAGES:
        path = os.path.join(os.path.dirname(os.path.abspath(__file__)), package,
                            'executables.py')
        with open(path, encoding='utf-8') as source:
            tree = ast.parse(source.read())
        table = next(node.value for node in tree.body if isinstance(node, ast.Assign)
                     and [target.id for target in node.targets] == ['EXECUTABLES'])
        scripts += [f'{key.value} = {package}.executables:{key.value}' for key in table.keys]
    return sorted(scripts)


setup(
    name=PACKAGE_NAME,
    version='0.1.0',
    packages=find_packages(include=[PACKAGE_NAME, 'stdr_lite', 'stdr_lite.*', 'foxglove_live',
                                    'waypoint_lab', 'waypoint_lab.*', 'waypoint_controller',
                                    'lab_grader', 'courseworks',
                                    'coursework_answers']),
    data_files=[
        ('share/ament_index/resource_index/packages', [f'resource/{PACKAGE_NAME}']),
        (SHARE, ['package.xml']),
        # Signals held from the interpreter's first lines (simple_robot_control/early_signals.py).
        (os.path.relpath(sysconfig.get_path('purelib'), sys.prefix),
         ['resource/00_simple_robot_control_signals.pth']),
        (f'{SHARE}/maps', sorted(glob('maps/*.yaml') + glob('maps/*.pgm'))),
        (f'{SHARE}/launch', sorted(glob('launch/*.launch.py'))),
        (f'{SHARE}/waypoints', sorted(glob('waypoints/*.txt'))),
        (f'{SHARE}/scenarios', sorted(glob('scenarios/*.txt') + glob('scenarios/*.yaml'))),
        (f'{SHARE}/robots', sorted(glob('robots/*.yaml') + glob('robots/*.xml'))),
        *((f'{SHARE}/{folder}', sorted(glob(f'{folder}/*.xml')))
          for folder in sorted(glob('sensor_files/*'))),
        (f'{SHARE}/obstacles', sorted(glob('obstacles/*.yaml'))),
        (f'{SHARE}/config',
         sorted(glob('config/*.yaml') + glob('config/*.xml') + glob('config/*.json'))),
        (f'{SHARE}/rviz', sorted(glob('rviz/*.rviz'))),
    ],
    python_requires='>=3.10',
    install_requires=['setuptools', 'numpy', 'PyYAML', 'Pillow', 'matplotlib', 'scipy', 'shapely',
                      'pygame', 'regex', 'mcap', 'rosbags', 'psutil', 'numba', 'gymnasium',
                      'foxglove-sdk>=0.30', 'pettingzoo'],
    package_data={'waypoint_lab.learning': ['policies/*.npz']},
    zip_safe=True,
    maintainer='simple_robot_control maintainers',
    maintainer_email='maintainers@simple-robot-control.org',
    description='A small STDR-equivalent simulator and a PID waypoint controller for ROS 2.',
    license='Apache-2.0',
    extras_require={'test': ['pytest', 'hypothesis']},
    entry_points={
        'console_scripts': console_scripts(),
    },
)

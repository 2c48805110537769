"""
How every course of a grading is run, and what its processes are given. No ROS.

Their environments and the simulator's command line; grade_lab reads this before rclpy, which
refuses at import an RMW it was not built for.

The simulator and the recorder run as the grader; the submission gets what running a program
takes and nothing of the grader's (no variable naming the courses or the reports). Sealed in
namespaces (sandbox.py), every process of the run meets over UDP on the SUBNET range: Fast DDS's
shared memory does not cross uids, nor the submission's own /dev/shm, and the LOCALHOST range
forces it on; the namespace's only network is its loopback.
"""

from collections.abc import Mapping
from dataclasses import dataclass, field
import os
from pathlib import Path

from courseworks.courses import world_parameters
from lab_grader.sandbox import SandboxPolicy
from simple_robot_control.share import installed_executable, shared_file
from waypoint_lab.course import Course
import yaml

PLACEHOLDER = '{waypoints}'
# How DDS runs in a course's network namespace, whose only network is its loopback.
SEALED_DDS = {'ROS_AUTOMATIC_DISCOVERY_RANGE': 'SUBNET', 'FASTDDS_BUILTIN_TRANSPORTS': 'UDPv4'}
# What the submission's environment keeps of the grader's: what finds programs, libraries and
# ROS, the language, and the run's ROS settings (course_environment).
SUBMISSION_VARIABLES = frozenset((
    'PATH', 'PYTHONPATH', 'LD_LIBRARY_PATH', 'VIRTUAL_ENV', 'AMENT_PREFIX_PATH',
    'CMAKE_PREFIX_PATH', 'COLCON_PREFIX_PATH', 'PKG_CONFIG_PATH', 'ROS_DISTRO', 'ROS_VERSION',
    'ROS_PYTHON_VERSION', 'ROS_DOMAIN_ID', 'ROS_AUTOMATIC_DISCOVERY_RANGE', 'ROS_STATIC_PEERS',
    'RMW_IMPLEMENTATION', 'FASTRTPS_DEFAULT_PROFILES_FILE', 'FASTDDS_BUILTIN_TRANSPORTS',
    'PYTHONUNBUFFERED', 'LANG', 'LANGUAGE', 'TZ', 'TERM', 'USER', 'LOGNAME', 'SHELL'))


# The middleware the evidence rules were built and tested on (Jazzy's default, the wheels' only).
GRADED_RMW = 'rmw_fastrtps_cpp'


def middleware_problem(environment: Mapping[str, str]) -> str:
    """Say why grading cannot run on the middleware environment names, or return ''."""
    rmw = environment.get('RMW_IMPLEMENTATION', '') or GRADED_RMW
    if rmw == GRADED_RMW:
        return ''
    return (f'RMW_IMPLEMENTATION={rmw}: grade_lab grades on {GRADED_RMW} alone (who publishes '
            'is told by its sockets and endpoints); unset it')


def course_environment(domain_id: int, sealed: bool = False) -> dict:
    """
    Return the environment of a run's processes: loopback discovery in its own domain.

    A sealed run's processes meet over UDP alone, on the SUBNET range (see above).
    """
    environment = dict(os.environ, ROS_DOMAIN_ID=str(domain_id),
                       ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST', ROS_STATIC_PEERS='',
                       PYTHONUNBUFFERED='1')
    environment.setdefault('FASTRTPS_DEFAULT_PROFILES_FILE',
                           shared_file('config', 'fastdds_quick_discovery.xml'))
    if sealed:
        environment.update(SEALED_DDS)
    return environment


def submission_environment(course_environment: dict, working: Path | str,
                           hidden: tuple[str, ...]) -> dict:
    """
    Return the submission's environment: what running a program takes, and nothing of the grader.

    The variables of SUBMISSION_VARIABLES (and LC_*) are kept, unless their value names a
    hidden folder (the courses', the reports'); home, temporary files and ROS's logs are the
    submission's working folder.
    """
    kept = {name: value for name, value in course_environment.items()
            if (name in SUBMISSION_VARIABLES or name.startswith('LC_'))
            and not any(folder in value for folder in hidden)}
    folder = str(working)
    return dict(kept, HOME=folder, TMPDIR=folder, ROS_HOME=folder,
                ROS_LOG_DIR=f'{folder}/log')


def simulator_command(course: Course, settings: 'RunSettings', link_descriptor: int,
                      folder: Path) -> list[str]:
    """
    Return the stdr_lite command line of a course: supervised, at the course's start.

    The parameters go in a file of the grader's private folder, so that the command line
    (which any process may read) names no course file.
    """
    parameters = {'lockstep': bool(settings.lockstep),
                  'real_time_factor': float(settings.real_time_factor),
                  'robot_name': settings.robot_name,
                  'supervisor_fd': link_descriptor, **world_parameters(course)}
    path = Path(folder) / 'simulator.yaml'
    path.write_text(yaml.safe_dump({'stdr_lite': {'ros__parameters': parameters}}))
    return [installed_executable('stdr_lite'), '--ros-args', '--params-file', str(path)]


@dataclass(frozen=True)
class RunSettings:
    """How every course of a grading is run."""

    command: tuple[str, ...]
    cwd: str = '.'
    lockstep: bool = False
    real_time_factor: float = 1.0
    robot_name: str = 'robot0'
    memory_mb: int = 0
    hidden: tuple[str, ...] = ()
    sandbox: SandboxPolicy = field(default_factory=SandboxPolicy)

"""Locate the files this package installs (maps, robots, waypoint courses, launch files)."""

import glob
import os
import sys

PACKAGE_NAME = 'simple_robot_control'
BUNDLED_MAP = ('maps', 'lab_room.yaml')
BUNDLED_ROBOT = ('robots', 'lab_robot.yaml')
# Files robot files may include by name, in the layout of STDR's resources folder (laser_sensors/,
# range_sensors/); the ament marker folder resource/ is another thing.
BUNDLED_RESOURCES = ('sensor_files',)


def share_directory() -> str:
    """
    Return the package's share directory.

    A colcon build or a ROS installation registers it in the ament index; a pip install into
    a virtual environment puts it under the environment's prefix.
    """
    try:
        from ament_index_python.packages import get_package_share_directory
        return get_package_share_directory(PACKAGE_NAME)
    except (ImportError, LookupError, OSError):
        return os.path.join(sys.prefix, 'share', PACKAGE_NAME)


def missing_packages(packages: list[str]) -> list[str]:
    """Return those of the ROS packages that the ament index does not know (not installed)."""
    try:
        from ament_index_python.packages import get_package_prefix
    except ImportError:
        return list(packages)
    missing = []
    for package in packages:
        try:
            get_package_prefix(package)
        except (LookupError, ValueError, OSError):
            missing.append(package)
    return missing


def installed_executable(name: str) -> str:
    """
    Return the path of one of the package's executables, wherever it was installed.

    First where `ros2 run` looks (lib/<package>/ of the prefix the ament index gives: a colcon
    install tree or a ROS installation), then where pip puts it: lib/<package>/ of the
    environment for an editable install, beside the interpreter for a plain one.
    FileNotFoundError names the places looked at.
    """
    candidates = []
    try:
        from ament_index_python.packages import get_package_prefix
        candidates.append(os.path.join(get_package_prefix(PACKAGE_NAME), 'lib', PACKAGE_NAME,
                                       name))
    except (ImportError, LookupError, OSError, ValueError):
        pass
    candidates += [os.path.join(sys.prefix, 'lib', PACKAGE_NAME, name),
                   os.path.join(os.path.dirname(sys.executable), name)]
    for path in candidates:
        if os.path.isfile(path) and os.access(path, os.X_OK):
            return path
    raise FileNotFoundError(f'{name} is not installed (looked in {", ".join(candidates)})')


def shared_file(*parts: str) -> str:
    """Path of a file under the share directory."""
    return os.path.join(share_directory(), *parts)


def bundled_files(*folders: str) -> dict:
    """Return the YAML and XML files installed in share folders by name (less the suffix)."""
    paths = sorted((path for folder in folders for suffix in ('yaml', 'xml')
                    for path in glob.glob(shared_file(folder, f'*.{suffix}'))),
                   key=os.path.basename)
    return {os.path.splitext(os.path.basename(path))[0]: path for path in paths}

"""The executables setup.py installed, as the package's metadata lists them, with their tables."""

from importlib import import_module
from importlib.metadata import distribution

# name -> (the module of its entry point, its Executable there)
ENTRY_POINTS = {
    point.name: (point.module, import_module(point.module).EXECUTABLES[point.name])
    for point in distribution('simple_robot_control').entry_points
    if point.group == 'console_scripts'}
EXECUTABLES = {name: executable for name, (_, executable) in ENTRY_POINTS.items()}
PARAMETER_TABLES = sorted(name for name, executable in EXECUTABLES.items()
                          if executable.parameters)


def parameter_table(name: str) -> tuple:
    """Return the ParameterSpecs of the executable name's node; () where it takes none."""
    return EXECUTABLES[name].parameter_table()

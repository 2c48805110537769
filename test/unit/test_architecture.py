"""
The layout's rules (doc/layout.md), checked from the code's own imports.

Pure modules (the simulation core, the lab's contract, the control law and its parts, the
grader's rules, the shared checks) import no ROS client library, so they run and are tested
without a ROS graph. The arrows run one way: the simulator (stdr_lite) knows neither the lab
(waypoint_lab) nor its answer (waypoint_controller); the lab's contract knows neither the answer
nor the grader; the grader grades any controller and never imports the answer; the answer stands
on the contract, never on the simulator. No module grows past 400 lines; every executable
lives in a module named after it; each of the lab's numbers is written once.
"""

import ast
from importlib import import_module
from pathlib import Path
import re
import subprocess
import sys

from installed_executables import ENTRY_POINTS
import pytest


REPOSITORY = Path(__file__).resolve().parents[2]
PACKAGES = ('simple_robot_control', 'stdr_lite', 'foxglove_live', 'waypoint_lab',
            'waypoint_controller', 'lab_grader', 'courseworks', 'coursework_answers')
PURE = ['stdr_lite/core/*.py', 'stdr_lite/tools/lab_session.py', 'stdr_lite/viewer/scene.py',
        'simple_robot_control/validation.py', 'simple_robot_control/pose.py',
        'simple_robot_control/input_files.py', 'simple_robot_control/executables.py',
        'simple_robot_control/occupancy_map.py', 'simple_robot_control/command_line.py',
        'simple_robot_control/share.py', 'simple_robot_control/bag.py',
        'simple_robot_control/parameter_specs.py', 'simple_robot_control/early_parameters.py',
        'foxglove_live/parameters.py', 'stdr_lite/node/parameters.py',
        'stdr_lite/viewer/parameters.py', 'stdr_lite/tools/parameters.py'] + [
    f'waypoint_controller/{name}.py' for name in (
        'control_law', 'pid', 'planner', 'reeds_shepp',
        'clearance', 'config', 'parameters')] + [
    f'waypoint_lab/{name}.py' for name in (
        'course', 'rules', 'parameters', 'waypoints', 'status', 'lifecycle', 'run', 'plot_run',
        'run_picture')] + [
    f'lab_grader/{name}.py' for name in (
        'verdicts', 'grading', 'reports', 'report_page', 'supervision', 'sandbox',
        'jail', 'publishers', 'reaper')] + [
    'simple_robot_control/bag_reading.py', 'lab_grader/domains.py'] + [
    f'waypoint_lab/learning/{name}.py' for name in (
        'task', 'arena', 'waypoints_env', 'vector_env', 'rendering')] + [
    'courseworks/*.py'] + [f'coursework_answers/{name}.py' for name in (
        'mapper', 'frontiers', 'planner', 'route_law', 'parameters', 'reference_run', 'answers')]
# The packages that declare executables (setup.py's EXECUTABLE_PACKAGES, read from its text).
EXECUTABLE_PACKAGES = next(
    ast.literal_eval(node.value) for node in ast.parse((REPOSITORY / 'setup.py').read_text()).body
    if isinstance(node, ast.Assign) and [t.id for t in node.targets] == ['EXECUTABLE_PACKAGES'])
ROS_CLIENT = re.compile(r'^(rclpy|rcl_interfaces|[a-z_]+_msgs|launch)(\.|$)')


def imported_modules(path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            yield node.module


def modules(*patterns):
    return sorted(path for pattern in patterns for path in REPOSITORY.glob(pattern))


@pytest.mark.parametrize('path', modules(*PURE), ids=str)
def test_pure_modules_import_no_ros(path):
    ros = [name for name in imported_modules(path) if ROS_CLIENT.match(name)]
    assert not ros, f'{path.relative_to(REPOSITORY)} imports {ros}'


# What runs where `pip install .` gives no ROS (doc/python.md): the Python API (stdr_lite's
# names come from these, on first use), the environments, the policy, the judges, plot_run.
ROS_FREE_DOORS = ('stdr_lite.core.loading', 'stdr_lite.core.simulation',
                  'waypoint_lab.learning.waypoints_env', 'waypoint_lab.learning.vector_env',
                  'waypoint_lab.learning.parallel_env', 'waypoint_lab.learning.numpy_policy',
                  'courseworks.mapping', 'courseworks.exploration', 'courseworks.planning',
                  'waypoint_lab.plot_run')


def module_path(name):
    """Return the file of one of our modules (a package's __init__.py), or None."""
    base = REPOSITORY.joinpath(*name.split('.'))
    for path in (base / '__init__.py', base.with_suffix('.py')):
        if path.is_file():
            return path
    return None


def imports_at_any_depth(name):
    """Return every module our module name imports, itself or through ours, at any depth."""
    found, waiting = set(), [name] + [name.rsplit('.', depth)[0]
                                      for depth in range(1, name.count('.') + 1)]
    while waiting:
        path = module_path(waiting.pop())
        if path is None:
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                names = [node.module] + [f'{node.module}.{alias.name}' for alias in node.names]
            else:
                continue
            # Importing a module imports the packages that hold it first.
            parents = [name.rsplit('.', depth)[0] for name in names
                       for depth in range(1, name.count('.') + 1)]
            for imported in names + parents:
                if imported not in found and (module_path(imported) or '.' not in imported
                                              or ROS_CLIENT.match(imported)):
                    found.add(imported)
                    waiting.append(imported)
    return found


@pytest.mark.parametrize('door', ROS_FREE_DOORS)
def test_the_doors_that_run_without_ros_import_none_at_any_depth(door):
    ros = sorted(name for name in imports_at_any_depth(door) if ROS_CLIENT.match(name))
    assert not ros, f'{door} imports {ros}'


@pytest.mark.parametrize('path', modules('stdr_lite/core/*.py'), ids=str)
def test_the_simulation_core_knows_nothing_of_nodes_viewer_or_tools(path):
    outward = [name for name in imported_modules(path)
               if name.startswith('stdr_lite.') and not name.startswith('stdr_lite.core')]
    assert not outward


def packages_imported(path):
    return {name.split('.')[0] for name in imported_modules(path)}


# Which of our packages each may import: the arrows of doc/layout.md, all pointing down.
ALLOWED = {
    'simple_robot_control': set(),
    'stdr_lite': {'simple_robot_control'},
    'foxglove_live': {'simple_robot_control'},
    'waypoint_lab': {'simple_robot_control', 'stdr_lite'},
    'waypoint_controller': {'simple_robot_control', 'waypoint_lab'},
    'lab_grader': {'simple_robot_control', 'stdr_lite', 'waypoint_lab', 'courseworks'},
    'courseworks': {'simple_robot_control', 'stdr_lite', 'waypoint_lab'},
    'coursework_answers': {'simple_robot_control', 'stdr_lite', 'waypoint_lab',
                           'waypoint_controller', 'courseworks'},
}


@pytest.mark.parametrize('path', modules(*(f'{package}/**/*.py' for package in PACKAGES)),
                         ids=str)
def test_imports_between_packages_run_down_the_layout(path):
    package = path.relative_to(REPOSITORY).parts[0]
    ours = packages_imported(path) & set(PACKAGES) - {package}
    assert ours <= ALLOWED[package], (
        f'{path.relative_to(REPOSITORY)} imports {sorted(ours - ALLOWED[package])}')


@pytest.mark.parametrize('path', modules('waypoint_lab/*.py'), ids=str)
def test_the_contract_and_its_tools_need_no_simulator(path):
    """Only the lab's Gymnasium task (waypoint_lab/learning) is built on the simulator."""
    assert 'stdr_lite' not in packages_imported(path)


@pytest.mark.parametrize('path', modules('courseworks/*.py'), ids=str)
def test_the_courseworks_read_the_world_as_the_simulations_core_loads_it(path):
    """Course files and judges read maps and robots by stdr_lite.core, and nothing else of it."""
    assert not [name for name in imported_modules(path)
                if name.startswith('stdr_lite') and not name.startswith('stdr_lite.core')]


@pytest.mark.parametrize('path', modules('lab_grader/*.py'), ids=str)
def test_the_grader_runs_the_simulator_and_reads_only_its_core(path):
    """The grader starts stdr_lite as a process, as a course would, and judges what it heard."""
    assert not [name for name in imported_modules(path)
                if name.startswith('stdr_lite') and not name.startswith('stdr_lite.core')]


# The lab's numbers and names, each written in waypoint_lab/rules.py alone: the goal set's d and
# t (a tolerance given as a number, or math.radians(5.0)), the start pose, the status topic.
CONTRACT = REPOSITORY / 'waypoint_lab' / 'rules.py'
STATUS_TOPICS = ('robot_status', '/robot_status')
START = (1.0, 2.0, 0.0)


def lab_constants(path):
    """Yield (line, what) of each of the lab's constants written as a literal in path."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Constant) and node.value in STATUS_TOPICS:
            yield node.lineno, 'the status topic'
        elif isinstance(node, ast.Tuple) and all(isinstance(item, ast.Constant)
                                                 for item in node.elts) and tuple(
                item.value for item in node.elts) == START:
            yield node.lineno, 'the start pose'
        elif (isinstance(node, ast.Call) and getattr(node.func, 'attr', '') == 'radians'
              and node.args and getattr(node.args[0], 'value', None) == 5.0):
            yield node.lineno, 'the angle tolerance'
        elif ((isinstance(node, ast.keyword) and node.arg or '').endswith('_tolerance')
              and isinstance(node.value, ast.Constant)):
            yield node.lineno, f'{node.arg} given as a number'
        elif (isinstance(node, (ast.Assign, ast.AnnAssign))
              and isinstance(node.value, ast.Constant)
              and any(getattr(target, 'id', '').endswith('tolerance')
                      for target in getattr(node, 'targets', [getattr(node, 'target', None)]))):
            yield node.lineno, 'a tolerance given as a number'


@pytest.mark.parametrize('path', [path for path in modules(
    'waypoint_lab/**/*.py', 'waypoint_controller/*.py', 'lab_grader/*.py') if path != CONTRACT],
    ids=str)
def test_each_lab_constant_is_written_once(path):
    written = list(lab_constants(path))
    assert not written, f'{path.relative_to(REPOSITORY)}: {written} (use waypoint_lab.rules)'


def test_the_contract_holds_the_lab_constants():
    found = {what for _, what in lab_constants(CONTRACT)}
    assert {'the status topic', 'the start pose', 'the angle tolerance'} <= found


@pytest.mark.parametrize('path', modules(*(f'{package}/**/*.py' for package in PACKAGES)),
                         ids=str)
def test_no_module_is_over_400_lines(path):
    assert len(path.read_text().splitlines()) <= 400


def test_every_executable_lives_in_a_module_named_after_it_in_the_package_declaring_it():
    """
    A console script for each executable a package declares, and for nothing else.

    Each package's executables.py names modules of its own only, so the imports it makes by
    name run no arrow the layout's test cannot see.
    """
    declared = {}
    for package in EXECUTABLE_PACKAGES:
        for name, executable in import_module(f'{package}.executables').EXECUTABLES.items():
            declared[name] = f'{package}.executables'
            assert executable.module.split('.')[0] == package
            assert executable.module.split('.')[-1] == name
            assert (REPOSITORY / (executable.module.replace('.', '/') + '.py')).is_file()
            table = executable.parameters.partition(':')[0]
            assert not table or table.split('.')[0] == package
    assert {name: module for name, (module, _) in ENTRY_POINTS.items()} == declared


def test_the_early_signals_know_every_package_that_declares_executables():
    """The .pth holding signals from the first line finds our console scripts by package."""
    pth = (REPOSITORY / 'resource' / '00_simple_robot_control_signals.pth').read_text()
    assert pth.count('\n') == 1 and f'{EXECUTABLE_PACKAGES!r}' in pth


def test_the_ground_floor_names_no_package_above_it():
    """Not in an import, nor in a string that importlib would load."""
    above = set(PACKAGES) - {'simple_robot_control'}
    for path in modules('simple_robot_control/*.py'):
        names = {node.value.split('.')[0] for node in ast.walk(ast.parse(path.read_text()))
                 if isinstance(node, ast.Constant) and isinstance(node.value, str)}
        assert not names & above, f'{path.relative_to(REPOSITORY)} names {names & above}'


def layout_sections():
    """Return the modules doc/layout.md names under each package of its tree: name -> {file}."""
    text = (REPOSITORY / 'doc' / 'layout.md').read_text()
    block = next(block for block in re.findall(r'```\n(.*?)```', text, re.S)
                 if block.startswith('simple_robot_control/'))
    sections, current = {}, None
    for line in block.splitlines():
        heading = re.match(r'^([a-z_]+)/\s', line)
        if heading:
            current = sections.setdefault(heading.group(1), set())
        if current is not None:
            current |= set(re.findall(r'\b([a-z_0-9]+\.py)\b', line))
    return sections


def test_the_layout_page_names_every_module_and_no_other():
    sections = layout_sections()
    assert set(sections) == set(PACKAGES)
    for package, named in sections.items():
        tree = {path.name for path in (REPOSITORY / package).rglob('*.py')
                if path.name != '__init__.py'}
        assert tree <= named, f'doc/layout.md lacks {sorted(tree - named)} under {package}/'
        stray = {name for name in named - tree if not (REPOSITORY / name).is_file()}
        assert not stray, f'doc/layout.md names {sorted(stray)} under {package}/: not there'


def unannotated(path):
    """Yield the public functions of path whose parameters or return lack an annotation."""
    def visit(node, private):
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.ClassDef):
                yield from visit(child, private or child.name.startswith('_'))
            elif isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if private or child.name.startswith('_'):
                    continue
                arguments = [argument for argument in child.args.args + child.args.kwonlyargs
                             if argument.arg not in ('self', 'cls')]
                if child.returns is None or any(argument.annotation is None
                                                for argument in arguments):
                    yield f'{child.name} (line {child.lineno})'
    yield from visit(ast.parse(path.read_text()), False)


@pytest.mark.parametrize('path', modules(*(f'{package}/**/*.py' for package in PACKAGES)),
                         ids=str)
def test_every_public_function_is_annotated(path):
    """Its parameters and what it returns."""
    missing = list(unannotated(path))
    assert not missing, f'{path.relative_to(REPOSITORY)}: {missing}'


@pytest.mark.parametrize('path', modules(*(f'{package}/**/*.py' for package in PACKAGES)),
                         ids=str)
def test_no_function_is_over_50_lines(path):
    """Split a longer one by role."""
    name = str(path.relative_to(REPOSITORY))
    long = [node.name for node in ast.walk(ast.parse(path.read_text()))
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
            and node.end_lineno - node.lineno >= 50]
    assert not long, f'{name}: {long} over 50 lines'


def test_grade_lab_and_the_course_reader_start_without_the_judges_libraries():
    """A grading of the lab, or a refused command line, does not wait a second for scipy."""
    probe = ('import sys, lab_grader.grade_lab, courseworks.courses\n'
             "print(sorted({'scipy', 'numba', 'matplotlib'} & set(sys.modules)))")
    loaded = subprocess.run([sys.executable, '-c', probe], capture_output=True, text=True,
                            check=True).stdout
    assert loaded.strip() == '[]'

"""Parameters: the example files start each node, and `ros2 param set` tunes the controller."""

from pathlib import Path

from installed_executables import parameter_table, PARAMETER_TABLES
from nav_msgs.msg import Odometry
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient
from ros_helpers import overrides, spin_until
from simple_robot_control.early_parameters import early_problem
from simple_robot_control.parameters import declare_parameters
from simple_robot_control.validation import ConfigError
from stdr_lite.node.stdr_lite import StdrLite
from waypoint_controller.waypoint_controller import WaypointController
from waypoint_lab.course_monitor import CourseMonitor
import yaml

CONFIG = Path(__file__).resolve().parents[2] / 'config'
NODES = {name: parameter_table(name) for name in PARAMETER_TABLES}


@pytest.mark.parametrize('node', NODES)
def test_each_node_has_an_example_file_of_its_parameters_at_their_defaults(node):
    values = yaml.safe_load((CONFIG / f'{node}.yaml').read_text())[node]['ros__parameters']
    assert values == {spec.name: list(spec.default) if isinstance(spec.default, tuple)
                      else spec.default for spec in NODES[node]}


def params_file_arguments(tmp_path, node, **changes):
    """Return --ros-args for a copy of the node's example file with some values changed."""
    data = yaml.safe_load((CONFIG / f'{node}.yaml').read_text())
    data[node]['ros__parameters'].update(changes)
    path = tmp_path / f'{node}.yaml'
    path.write_text(yaml.safe_dump(data))
    return ['--ros-args', '--params-file', str(path)]


def test_nodes_start_from_their_parameter_files(ros_context, tmp_path):
    simulator = StdrLite(context=ros_context, cli_args=params_file_arguments(
        tmp_path, 'stdr_lite', rate_hz=25.0, robot_name='scout'))
    controller = WaypointController(context=ros_context, cli_args=params_file_arguments(
        tmp_path, 'waypoint_controller', heading_kp=3.0))
    monitor = CourseMonitor(context=ros_context, write=lambda text: None, interactive=False,
                            cli_args=params_file_arguments(tmp_path, 'course_monitor'))
    try:
        assert simulator.simulation.dt == pytest.approx(0.04)
        assert simulator.simulation.names == ['scout']
        assert controller.get_parameter('heading_kp').value == 3.0
        assert monitor.get_parameter('distance_tolerance').value == 0.1
    finally:
        for node in (simulator, controller, monitor):
            node.destroy_node()


@pytest.fixture
def tuning(ros_context, executor, tmp_path):
    """Run a long straight course in lockstep; give a parameter client and the speeds seen."""
    course = tmp_path / 'course.txt'
    course.write_text('12 2 0\n')
    simulator = StdrLite(context=ros_context,
                         parameter_overrides=overrides(lockstep=True, real_time_factor=20.0))
    controller = WaypointController(str(course), context=ros_context)
    watcher = Node('watcher', context=ros_context)
    speeds = []
    watcher.create_subscription(Odometry, '/robot0/odom',
                                lambda message: speeds.append(message.twist.twist.linear.x), 100)
    for node in (simulator, controller, watcher):
        executor.add_node(node)
    client = AsyncParameterClient(watcher, 'waypoint_controller')
    assert client.wait_for_services(timeout_sec=10.0)
    spin_until(executor, lambda: speeds and speeds[-1] == pytest.approx(0.5),
               what='the robot at full speed')
    return client, speeds, controller


def answer(executor, future):
    spin_until(executor, future.done, what='the parameter service')
    return future.result().results


def test_param_set_changes_the_speed_limit_of_a_running_controller(executor, tuning):
    client, speeds, _ = tuning
    (result,) = answer(executor, client.set_parameters([Parameter('max_linear_speed',
                                                                  value=0.2)]))
    assert result.successful
    count = len(speeds)
    spin_until(executor, lambda: len(speeds) > count + 20, what='odometry after tuning')
    assert max(speeds[-10:]) == pytest.approx(0.2)


@pytest.mark.parametrize('parameters, reason', [
    ([Parameter('heading_kp', value=-1.0)], 'heading_kp must be in (0, 1000], got -1'),
    ([Parameter('distance_tolerance', value=float('inf'))],
     'distance_tolerance must be in (0, 10], got inf'),
    ([Parameter('control_rate_hz', value=10.0)], 'read-only'),
])
def test_a_refused_value_leaves_the_old_one(executor, tuning, parameters, reason):
    client, _, controller = tuning
    (result,) = answer(executor, client.set_parameters(parameters))
    assert not result.successful and reason in result.reason
    name = parameters[0].name
    defaults = {spec.name: spec.default for spec in parameter_table('waypoint_controller')}
    assert controller.get_parameter(name).value == defaults[name]


def test_a_request_is_applied_whole_or_not_at_all(executor, tuning):
    client, speeds, controller = tuning
    future = client.set_parameters_atomically([Parameter('max_linear_speed', value=0.2),
                                               Parameter('heading_ki', value=-2.0)])
    spin_until(executor, future.done, what='the parameter service')
    assert not future.result().result.successful
    assert controller.get_parameter('max_linear_speed').value == 0.5
    count = len(speeds)
    spin_until(executor, lambda: len(speeds) > count + 20, what='odometry after the refusal')
    assert max(speeds[-10:]) == pytest.approx(0.5)


def test_a_whole_number_is_taken_for_a_double_as_ros2_param_set_sends_it(executor, tuning):
    client, speeds, controller = tuning
    (result,) = answer(executor, client.set_parameters([Parameter('heading_kp', value=3)]))
    assert result.successful, result.reason
    assert controller.get_parameter('heading_kp').value == 3.0
    assert controller.get_parameter('heading_kp').type_ == Parameter.Type.DOUBLE
    (refused,) = answer(executor, client.set_parameters([Parameter('heading_kp', value=2000)]))
    assert not refused.successful and 'heading_kp must be in (0, 1000], got 2000' in (
        refused.reason)


def test_whole_numbers_are_taken_for_doubles_at_start(ros_context):
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        rate_hz=25, initial_pose=[2, 3, 0]))
    try:
        assert simulator.simulation.dt == pytest.approx(0.04)
        assert simulator.simulation.pose('robot0') == (2.0, 3.0, 0.0)
    finally:
        simulator.destroy_node()


@pytest.mark.parametrize('executable, arguments', [
    ('stdr_lite', ['-p', 'rate_hz:=-1']), ('stdr_lite', ['-p', 'rate_hz:=abc']),
    ('stdr_lite', ['-p', 'lockstep:=1']), ('stdr_lite', ['-p', 'robot_name:="5"']),
    ('stdr_lite', ['-p', 'rat_hz:=5']), ('stdr_lite', ['-p', 'initial_pose:=[a, b]']),
    ('stdr_lite', ['-p', 'resource_paths:=[1, 2]']), ('stdr_lite', ['-p', 'sensor_seed:=2.5']),
    ('stdr_lite', ['-p', 'integrator:=rk4']), ('record_run', ['-p', 'topics:=/odom']),
    ('waypoint_controller', ['-p', 'heading_kp:=0']), ('foxglove_live', ['-p', 'port:=70000']),
])
def test_an_early_refusal_is_the_one_the_node_makes(ros_context, executable, arguments):
    """The executable refuses before loading its node in the words of the node's own check."""
    specs = parameter_table(executable)
    early = early_problem([executable, '--ros-args', *arguments], executable, specs)
    assert early is not None
    node = Node(executable, context=ros_context, cli_args=['--ros-args', *arguments])
    try:
        with pytest.raises(ConfigError) as refusal:
            declare_parameters(node, specs)
        assert str(refusal.value) == early
    finally:
        node.destroy_node()

"""The standard simulation API, time and worlds: every answer and every refusal, in-process."""

from geometry_msgs.msg import PoseStamped
from map_fixtures import png_header, walled_room, write_map
from nav_msgs.msg import OccupancyGrid, Odometry
from nav_msgs.srv import GetMap
import pytest
from rclpy.action import ActionClient
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.task import Future
from rclpy.time import Time
from ros_helpers import overrides, ServiceCaller, spin_for, spin_until
from rosgraph_msgs.msg import Clock
from simple_robot_control.exit_codes import EXIT_OK
from simulation_interfaces.action import SimulateSteps
from simulation_interfaces.msg import Result, SimulationState, SimulatorFeatures
from simulation_interfaces.srv import (GetAvailableWorlds, GetCurrentWorld, GetSimulationState,
                                       GetSimulatorFeatures, LoadWorld, ResetSimulation,
                                       SetSimulationState, SpawnEntity, StepSimulation,
                                       UnloadWorld)

from stdr_lite.node.control_services import IMPLEMENTED
from stdr_lite.node.results import MAX_SERVICE_STEPS
from stdr_lite.node.stdr_lite import StdrLite
from stdr_lite.tools.ctl_commands import build_arguments
from stdr_lite.tools.stdr_ctl import StdrCtl

OK = Result.RESULT_OK
S = SimulationState
LATCHED = QoSProfile(depth=1, reliability=ReliabilityPolicy.RELIABLE,
                     durability=DurabilityPolicy.TRANSIENT_LOCAL)


class Watcher(Node):
    """Keeps the /clock and robot0 odometry stamps it hears, and every /map."""

    def __init__(self, context):
        super().__init__('watcher', context=context)
        self.clock, self.odometry, self.maps = [], [], []
        self.create_subscription(Clock, '/clock', lambda message: self.clock.append(
            Time.from_msg(message.clock).nanoseconds), 100)
        self.create_subscription(Odometry, '/robot0/odom', self.odometry.append, 100)
        self.create_subscription(OccupancyGrid, '/map', self.maps.append, LATCHED)


@pytest.fixture
def world(ros_context, executor):
    """Give (simulator, watcher, call) with stdr_lite free-running at 20x real time."""
    simulator = StdrLite(context=ros_context,
                         parameter_overrides=overrides(real_time_factor=20.0))
    watcher = Watcher(ros_context)
    for node in (simulator, watcher):
        executor.add_node(node)
    return simulator, watcher, ServiceCaller(executor, watcher)


def set_state(call, state):
    return call(SetSimulationState, 'set_simulation_state', state=S(state=state)).result


def test_features_are_exactly_those_served(world):
    _, _, call = world
    features = call(GetSimulatorFeatures, 'get_simulator_features').features
    assert sorted(features.features) == sorted(IMPLEMENTED)
    assert SimulatorFeatures.NAMED_POSES not in features.features
    assert list(features.spawn_formats) == ['stdr_robot_yaml', 'stdr_robot_xml',
                                            'stdr_lite_obstacle_yaml']
    assert 'doc/simulation_api.md' in features.custom_info


def test_pause_holds_clock_and_odometry_and_play_resumes(world, executor):
    simulator, watcher, call = world
    spin_until(executor, lambda: len(watcher.clock) > 5, what='the clock running')
    assert set_state(call, S.STATE_PAUSED).result == OK
    held = simulator.simulation.step_count
    count = len(watcher.odometry)
    spin_for(executor, 0.4)
    assert simulator.simulation.step_count == held and len(watcher.odometry) == count
    state = call(GetSimulationState, 'get_simulation_state')
    assert (state.state.state, state.result.result) == (S.STATE_PAUSED, OK)
    assert set_state(call, S.STATE_PAUSED).result == (
        SetSimulationState.Response.ALREADY_IN_TARGET_STATE)
    assert set_state(call, S.STATE_PLAYING).result == OK
    spin_until(executor, lambda: simulator.simulation.step_count > held + 5, what='steps')


def test_stop_is_pause_and_reset(world, executor):
    simulator, watcher, call = world
    spin_until(executor, lambda: simulator.simulation.step_count > 20, what='steps')
    simulator.simulation.teleport('robot0', (5.0, 5.0, 1.0))
    assert set_state(call, S.STATE_STOPPED).result == OK
    assert simulator.simulation.step_count == 0
    assert simulator.simulation.pose('robot0') == (1.0, 2.0, 0.0)
    spin_for(executor, 0.3)
    assert simulator.simulation.step_count == 0
    spin_until(executor, lambda: watcher.clock and watcher.clock[-1] == 0, what='clock at 0')


@pytest.mark.parametrize('target', [S.STATE_NO_WORLD, S.STATE_LOADING_WORLD, 9])
def test_states_not_to_be_set_are_refused(world, target):
    _, _, call = world
    assert set_state(call, target).result == SetSimulationState.Response.INCORRECT_TRANSITION


def test_quitting_ends_the_node_cleanly(world, executor):
    simulator, _, call = world
    assert set_state(call, S.STATE_QUITTING).result == OK
    spin_until(executor, simulator.finished.done, what='the end')
    assert simulator.finished.result() == 0


def test_step_takes_exactly_n_steps_only_when_paused(world, executor):
    simulator, _, call = world
    answer = call(StepSimulation, 'step_simulation', steps=3).result
    assert answer.result == Result.RESULT_INCORRECT_STATE and 'pause it first' in (
        answer.error_message)
    set_state(call, S.STATE_PAUSED)
    before = simulator.simulation.step_count
    assert call(StepSimulation, 'step_simulation', steps=7).result.result == OK
    assert simulator.simulation.step_count == before + 7
    refused = call(StepSimulation, 'step_simulation', steps=MAX_SERVICE_STEPS + 1).result
    assert refused.result == Result.RESULT_OPERATION_FAILED
    assert simulator.simulation.step_count == before + 7


def run_goal(executor, node, steps, cancel_after=None):
    client = ActionClient(node, SimulateSteps, '/stdr_lite/simulate_steps')
    try:
        spin_until(executor, client.server_is_ready, what='the action server')
        feedback = []
        sent = client.send_goal_async(SimulateSteps.Goal(steps=steps),
                                      feedback_callback=lambda message: feedback.append(
                                          message.feedback.completed_steps))
        spin_until(executor, sent.done, what='the goal accepted')
        handle = sent.result()
        if cancel_after is not None:
            spin_until(executor, lambda: len(feedback) >= cancel_after, what='some steps')
            handle.cancel_goal_async()
        done = handle.get_result_async()
        spin_until(executor, done.done, timeout=30.0, what='the result')
        return done.result(), feedback
    finally:
        # Node.destroy_node leaves an action client, and so its node, alive in the graph.
        client.destroy()


def test_simulate_steps_gives_feedback_per_step(world, executor):
    simulator, watcher, call = world
    set_state(call, S.STATE_PAUSED)
    before = simulator.simulation.step_count
    outcome, feedback = run_goal(executor, watcher, 25)
    assert outcome.result.result.result == OK
    assert feedback == list(range(1, 26))
    assert simulator.simulation.step_count == before + 25


def test_simulate_steps_can_be_canceled_and_wants_a_pause(world, executor):
    simulator, watcher, call = world
    outcome, _ = run_goal(executor, watcher, 5)
    assert outcome.result.result.result == Result.RESULT_INCORRECT_STATE
    set_state(call, S.STATE_PAUSED)
    outcome, feedback = run_goal(executor, watcher, 10 ** 9, cancel_after=5)
    assert outcome.result.result.result == Result.RESULT_OPERATION_FAILED
    taken = simulator.simulation.step_count
    spin_for(executor, 0.3)
    assert simulator.simulation.step_count == taken and 5 <= len(feedback) < 10 ** 9


def test_simulate_steps_waits_for_the_controller_in_lockstep(ros_context, executor):
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        lockstep=True, real_time_factor=0.0))
    watcher = Watcher(ros_context)
    for node in (simulator, watcher):
        executor.add_node(node)
    call = ServiceCaller(executor, watcher)
    set_state(call, S.STATE_PAUSED)
    sent = ActionClient(watcher, SimulateSteps, '/stdr_lite/simulate_steps')
    try:
        spin_until(executor, sent.server_is_ready, what='the action server')
        sent.send_goal_async(SimulateSteps.Goal(steps=3))
        spin_for(executor, 0.5)
        assert simulator.simulation.step_count == 0
    finally:
        sent.destroy()


def test_reset_by_scope_and_unknown_scopes(world, executor):
    simulator, _, call = world
    simulation = simulator.simulation
    spin_until(executor, lambda: simulation.step_count > 10, what='steps')
    call(SpawnEntity, 'spawn_entity', name='rock', uri='obstacle',
         initial_pose=pose_at(8.0, 8.0))
    simulation.teleport('robot0', (4.0, 4.0, 0.0))
    assert call(ResetSimulation, 'reset_simulation',
                scope=ResetSimulation.Request.SCOPE_SPAWNED).result.result == OK
    assert simulation.names == ['robot0'] and simulation.pose('robot0') == (4.0, 4.0, 0.0)
    unknown = call(ResetSimulation, 'reset_simulation', scope=8).result
    assert unknown.result == Result.RESULT_FEATURE_UNSUPPORTED
    assert simulation.pose('robot0') == (4.0, 4.0, 0.0)
    assert call(ResetSimulation, 'reset_simulation').result.result == OK
    assert simulation.pose('robot0') == (1.0, 2.0, 0.0) and simulation.step_count < 5


BUNDLED_WORLDS = ['factory', 'lab_room', 'plus_room', 'simple_walls']


def pose_at(x, y):
    pose = PoseStamped()
    pose.pose.position.x, pose.pose.position.y = x, y
    pose.pose.orientation.w = 1.0
    return pose


def test_worlds_are_maps_loaded_and_unloaded(world, executor, tmp_path):
    simulator, watcher, call = world
    worlds = call(GetAvailableWorlds, 'get_available_worlds',
                  additional_sources=[str(tmp_path)])
    assert [entry.name for entry in worlds.worlds] == BUNDLED_WORLDS
    small = write_map(tmp_path, walled_room(30, 30), name='small')
    big = write_map(tmp_path, walled_room(500, 300), name='big')
    assert [entry.name for entry in call(GetAvailableWorlds, 'get_available_worlds',
                                         additional_sources=[str(tmp_path)]).worlds] == [
        *BUNDLED_WORLDS, 'big', 'small']
    refused = call(LoadWorld, 'load_world', uri=str(small)).result
    assert refused.result == Result.RESULT_OPERATION_FAILED and 'robot0' in refused.error_message
    assert simulator.simulation.occupancy_map.width == 400
    call(SpawnEntity, 'spawn_entity', name='rock', uri='obstacle',
         initial_pose=pose_at(8.0, 8.0))
    loaded = call(LoadWorld, 'load_world', uri=big.as_uri())
    assert loaded.result.result == OK and loaded.world.name == 'big'
    assert simulator.simulation.names == ['robot0']
    assert call(GetSimulationState, 'get_simulation_state').state.state == S.STATE_STOPPED
    spin_until(executor, lambda: watcher.maps and watcher.maps[-1].info.width == 500,
               what='the new /map')
    assert call(GetCurrentWorld, 'get_current_world').world.name == 'big'
    assert call(UnloadWorld, 'unload_world').result.result == OK
    assert call(GetCurrentWorld, 'get_current_world').result.result == (
        GetCurrentWorld.Response.NO_WORLD_LOADED)
    assert set_state(call, S.STATE_PLAYING).result == (
        SetSimulationState.Response.INCORRECT_TRANSITION)
    assert call(SpawnEntity, 'spawn_entity', name='rock', uri='obstacle',
                initial_pose=pose_at(8.0, 8.0)).result.result == Result.RESULT_INCORRECT_STATE
    assert call(LoadWorld, 'load_world', uri='lab_room').result.result == OK


@pytest.mark.parametrize('uri, text, code', [
    ('', '', LoadWorld.Response.NO_RESOURCE),
    ('', 'image: x.pgm', Result.RESULT_FEATURE_UNSUPPORTED),
    ('world.sdf', '', LoadWorld.Response.UNSUPPORTED_FORMAT),
    ('/no/such/world.yaml', '', Result.RESULT_NOT_FOUND),
    ('BROKEN', '', LoadWorld.Response.RESOURCE_PARSE_ERROR),
    ('NO_IMAGE', '', LoadWorld.Response.MISSING_ASSETS),
    ('HUGE', '', LoadWorld.Response.UNSUPPORTED_ASSETS),
])
def test_a_world_that_cannot_load_changes_nothing(world, tmp_path, uri, text, code):
    simulator, _, call = world
    (tmp_path / 'broken.yaml').write_text('image: [unclosed')
    (tmp_path / 'noimage.yaml').write_text('image: gone.pgm\nresolution: 0.05\n'
                                           'origin: [0, 0, 0]\n')
    (tmp_path / 'huge.png').write_bytes(png_header(14000, 14000))
    (tmp_path / 'huge.yaml').write_text('image: huge.png\nresolution: 0.05\norigin: [0, 0, 0]\n')
    uri = {'BROKEN': str(tmp_path / 'broken.yaml'), 'NO_IMAGE': str(tmp_path / 'noimage.yaml'),
           'HUGE': str(tmp_path / 'huge.yaml')}.get(uri, uri)
    answer = call(LoadWorld, 'load_world', uri=uri, resource_string=text).result
    assert answer.result == code and answer.error_message
    assert simulator.simulation.occupancy_map.width == 400
    assert call(GetSimulationState, 'get_simulation_state').state.state == S.STATE_PLAYING


def test_stdr_ctl_follows_a_goal_whose_acceptance_reply_was_lost(world, executor, ros_context):
    simulator, _, call = world
    set_state(call, S.STATE_PAUSED)
    before = simulator.simulation.step_count
    lines = []
    ctl = StdrCtl(build_arguments().parse_args(['simulate', '5']), write=lines.append,
                  context=ros_context)
    send = ctl._client.call_async
    # The request reaches the simulator; its reply never comes back (discovery lagging).
    ctl._client.call_async = lambda request: (send(request), Future())[1]
    executor.add_node(ctl)
    executor.spin_until_future_complete(ctl.finished, timeout_sec=10.0)
    assert ctl.finished.result() == EXIT_OK
    assert lines == ['simulated 5']
    assert simulator.simulation.step_count == before + 5


def test_the_map_is_served_on_both_names_and_follows_load_world(world, executor, tmp_path):
    """ROS 1 code waits for static_map, Nav2's for map_server/map: both answer the world."""
    _, watcher, call = world
    clients = [watcher.create_client(GetMap, name) for name in ('/static_map',
                                                                '/map_server/map')]

    def maps():
        futures = [client.call_async(GetMap.Request()) for client in clients]
        spin_until(executor, lambda: all(future.done() for future in futures), what='the maps')
        return [future.result().map for future in futures]

    for client in clients:
        spin_until(executor, client.service_is_ready, what=client.srv_name)
    for grid in maps():
        assert (grid.info.width, grid.info.height, grid.header.frame_id) == (400, 300, 'map')
        assert grid.info.resolution == pytest.approx(0.05) and grid.data[0] == 100
    big = write_map(tmp_path, walled_room(500, 300), name='big')
    assert call(LoadWorld, 'load_world', uri=str(big)).result.result == OK
    assert [grid.info.width for grid in maps()] == [500, 500]

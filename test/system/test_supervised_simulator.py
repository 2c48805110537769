"""stdr_lite under a supervisor (supervisor_fd), as grade_lab runs it: its truth out, play in."""

import socket
import subprocess

from processes import start
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.node import Node
from ros_helpers import spin_until
from simulation_interfaces.srv import GetCurrentWorld

WORLD_CHANGING = ('set_simulation_state', 'step_simulation', 'reset_simulation', 'load_world',
                  'unload_world', 'spawn_entity', 'spawn_entities', 'delete_entity',
                  'set_entity_state', '_action/send_goal')


def test_a_supervised_simulator_plays_on_its_word_serves_no_change_and_ends_with_it(
        ros_context, executor):
    ours, theirs = socket.socketpair()
    simulator = start('stdr_lite', '--ros-args', '-p', f'supervisor_fd:={theirs.fileno()}',
                      '-p', 'real_time_factor:=4.0', pass_fds=(theirs.fileno(),))
    theirs.close()
    stream = ours.makefile('rb')
    try:
        assert stream.readline() == b'limits 0.02 100.0 100.0\n'
        node = Node('looker', context=ros_context)
        executor.add_node(node)

        def services():
            return {name for name, _ in node.get_service_names_and_types()
                    if name.startswith('/stdr_lite/')}
        spin_until(executor, lambda: '/stdr_lite/get_entity_state' in services(), timeout=20.0,
                   what="the simulator's queries")
        assert not [name for name in services() if name.rsplit('/', 1)[-1] in WORLD_CHANGING
                    or 'simulate_steps' in name], services()
        assert not node.get_subscriptions_info_by_topic('/robot0/initialpose')
        assert '/robot0/replace' not in {name for name, _ in node.get_service_names_and_types()}
        assert '/stdr_lite/get_available_worlds' not in services()
        world = call(executor, node, GetCurrentWorld, '/stdr_lite/get_current_world',
                     GetCurrentWorld.Request()).world
        assert (world.name, world.world_resource.uri) == ('lab_room', '')
        sim_time = Parameter(name='use_sim_time', value=ParameterValue(
            type=ParameterType.PARAMETER_BOOL, bool_value=True))
        refused = call(executor, node, SetParameters, '/stdr_lite/set_parameters',
                       SetParameters.Request(parameters=[sim_time])).results[0]
        assert not refused.successful and 'supervised' in refused.reason
        ours.sendall(b'play\n')
        first = stream.readline().split()
        second = stream.readline().split()
        assert first[:2] == [b'truth', b'robot0'] and first[4:] == [b'1.0', b'2.0', b'0.0', b'0']
        assert int(second[2]) - int(first[2]) == 20_000_000
        assert int(second[3]) > int(first[3])
    finally:
        stream.close()
        ours.close()
        try:
            assert simulator.wait(timeout=15) == 0
        except subprocess.TimeoutExpired:
            simulator.kill()
            simulator.wait()
            raise


def call(executor, node, kind, name, request):
    client = node.create_client(kind, name)
    future = client.call_async(request)
    spin_until(executor, future.done, timeout=10.0, what=f'the answer of {name}')
    return future.result()

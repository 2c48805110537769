"""
stdr_ctl's commands: what each asks the simulator, and what it prints of the answer.

No ROS node here, only the requests and argument parsing; stdr_ctl.py sends them.
"""

import argparse
from dataclasses import dataclass, field
import os
from typing import Callable

from rclpy.exceptions import InvalidServiceNameException
from rclpy.validate_full_topic_name import validate_full_topic_name
from simple_robot_control.command_line import OneLineParser
from simple_robot_control.pose import pose_from_message, set_pose
from simple_robot_control.validation import describe, parse_decimal
from simulation_interfaces.action import SimulateSteps
from simulation_interfaces.msg import (EntityCategory, EntityFilters, EntityState,
                                       SimulationState, SimulatorFeatures)
from simulation_interfaces.srv import (DeleteEntity, GetAvailableWorlds, GetCurrentWorld,
                                       GetEntitiesStates, GetEntityInfo, GetEntityState,
                                       GetSimulationState, GetSimulatorFeatures, GetSpawnables,
                                       LoadWorld, ResetSimulation, SetEntityState,
                                       SetSimulationState, SpawnEntity, StepSimulation,
                                       UnloadWorld)
from stdr_lite.node.results import MAX_ACTION_STEPS, MAX_SERVICE_STEPS

DESCRIPTION = ('stdr_ctl: control a running stdr_lite through the standard simulation services '
               '(simulation_interfaces): time, entities and worlds. Prints the answer; exit '
               'code 0 when the simulator answers RESULT_OK, 1 when it refuses or does not '
               'answer, 2 for bad arguments. Poses are x y in metres and theta in radians, in '
               'the map frame.')
STATES = {'play': SimulationState.STATE_PLAYING, 'pause': SimulationState.STATE_PAUSED,
          'stop': SimulationState.STATE_STOPPED, 'quit': SimulationState.STATE_QUITTING}
SCOPES = {'all': ResetSimulation.Request.SCOPE_ALL, 'time': ResetSimulation.Request.SCOPE_TIME,
          'state': ResetSimulation.Request.SCOPE_STATE,
          'spawned': ResetSimulation.Request.SCOPE_SPAWNED}
CATEGORIES = {'robot': EntityCategory.CATEGORY_ROBOT,
              'static': EntityCategory.CATEGORY_STATIC_OBJECT,
              'moving': EntityCategory.CATEGORY_DYNAMIC_OBJECT}


def constant_names(message_class: type) -> dict:
    """Return {value: NAME} of a message class's integer constants."""
    return {getattr(message_class, name): name for name in dir(message_class)
            if name.isupper() and isinstance(getattr(message_class, name), int)}


STATE_NAMES = {value: name.removeprefix('STATE_').lower()
               for value, name in constant_names(SimulationState).items()}
FEATURE_NAMES = {value: name.lower() for value, name in constant_names(SimulatorFeatures).items()}
CATEGORY_NAMES = {value: name for name, value in CATEGORIES.items()}


@dataclass
class Call:
    """
    One request, what to print of its answer, and any request that follows from the answer.

    kind is a service type, or the SimulateSteps action, whose answer may take any time.
    """

    kind: type
    service: str
    fields: dict = field(default_factory=dict)
    report: Callable = lambda response: []
    then: Callable = None

    @property
    def is_action(self) -> bool:
        return self.kind is SimulateSteps


def finite(text: str) -> float:
    """Parse a finite number written as a plain decimal, for argparse."""
    value = parse_decimal(text)
    if value is None:
        raise argparse.ArgumentTypeError(f'not a finite number: {text!r}')
    return value


def step_count(most: int) -> Callable[[str], int]:
    """Return a parser of a number of steps (a whole number from 1 to most), for argparse."""
    def parse(text):
        if not (text.isascii() and text.isdigit()) or not 1 <= int(text) <= most:
            raise argparse.ArgumentTypeError(f'not a whole number of steps from 1 to {most:,}: '
                                             f'{describe(text)}')
        return int(text)
    return parse


def timeout(text: str) -> float:
    """Parse a wait in seconds, in (0, 3600], for argparse."""
    value = finite(text)
    if not 0.0 < value <= 3600.0:
        raise argparse.ArgumentTypeError(f'a timeout must be in (0, 3600] seconds, got {text!r}')
    return value


def scope_name(text: str) -> str:
    """Parse a reset scope (argparse's choices refuse nargs='*' given none, in Python 3.11)."""
    if text not in SCOPES:
        raise argparse.ArgumentTypeError(f'invalid choice: {text!r} (choose from '
                                         f'{", ".join(sorted(SCOPES))})')
    return text


def simulator_name(text: str) -> str:
    """Parse the full name of a simulator node, whose services are <name>/<service>."""
    problem = argparse.ArgumentTypeError(f'not the full name of a node (such as /stdr_lite): '
                                         f'{describe(text)}')
    if not text.strip('/'):
        raise problem
    try:
        validate_full_topic_name(f'{text.rstrip("/")}/get_simulation_state', is_service=True)
    except InvalidServiceNameException:
        raise problem from None
    return text


def format_pose(pose: tuple) -> str:
    return f'x {pose[0]:.3f} y {pose[1]:.3f} theta {pose[2]:.4f}'


def _state_lines(name, state):
    twist, stamp = state.twist, state.header.stamp
    return [f'{name}: {format_pose(pose_from_message(state.pose))}; velocity x '
            f'{twist.linear.x:.3f} y {twist.linear.y:.3f} angular {twist.angular.z:.4f}; '
            f'sim time {stamp.sec + stamp.nanosec * 1e-9:.3f} s']


def _entity_state(pose, velocity=(0.0, 0.0, 0.0)):
    state = EntityState()
    set_pose(state.pose, *pose)
    state.twist.linear.x, state.twist.linear.y, state.twist.angular.z = velocity
    return state


def _spawn(options):
    request = SpawnEntity.Request(name=options.name,
                                  allow_renaming=options.rename or not options.name,
                                  entity_namespace=options.namespace)
    if options.text:
        request.resource_string = options.resource
    else:
        # The simulator may run in another folder: a file here is sent by its full path.
        local = os.path.isfile(options.resource) and '://' not in options.resource
        request.uri = os.path.abspath(options.resource) if local else options.resource
    set_pose(request.initial_pose.pose, options.x, options.y, options.theta)
    return Call(SpawnEntity, 'spawn_entity', {'request': request},
                lambda response: [f'spawned {response.entity_name}'])


def _set_velocity(options):
    def with_velocity(response):
        pose = pose_from_message(response.state.pose)
        return Call(SetEntityState, 'set_entity_state', {'entity': options.name, 'state': (
            _entity_state(pose, (options.vx, options.vy, options.angular)))},
            lambda _: [f'{options.name} moves at x {options.vx:g} y {options.vy:g} m/s, '
                       f'{options.angular:g} rad/s'])
    return Call(GetEntityState, 'get_entity_state', {'entity': options.name}, then=with_velocity)


def _list(options):
    filters = EntityFilters(filter=options.regex, categories=[
        EntityCategory(category=CATEGORIES[name]) for name in options.category])
    return Call(GetEntitiesStates, 'get_entities_states', {'filters': filters},
                lambda response: [line for name, state in zip(response.entities,
                                                              response.states)
                                  for line in _state_lines(name, state)])


def _worlds(response):
    return [f'{world.name}: {world.world_resource.uri}' for world in response.worlds]


COMMANDS = {
    'features': ('the features the simulator implements', lambda parser: None,
                 lambda options: Call(GetSimulatorFeatures, 'get_simulator_features', report=(
                     lambda response: [
                         'features: ' + ' '.join(FEATURE_NAMES.get(value, str(value)) for value
                                                 in response.features.features),
                         'spawn formats: ' + ' '.join(response.features.spawn_formats),
                         response.features.custom_info]))),
    'state': ('whether the simulation plays, is paused or stopped', lambda parser: None,
              lambda options: Call(GetSimulationState, 'get_simulation_state', report=(
                  lambda response: [STATE_NAMES.get(response.state.state, '?')]))),
    **{name: (f'{name} the simulation', lambda parser: None,
              lambda options, state=state, name=name: Call(
                  SetSimulationState, 'set_simulation_state',
                  {'state': SimulationState(state=state)}, lambda _: [STATE_NAMES[state]]))
       for name, state in STATES.items()},
    'step': ('take N steps while paused, then answer (StepSimulation)',
             lambda parser: parser.add_argument('steps', type=step_count(MAX_SERVICE_STEPS)),
             lambda options: Call(StepSimulation, 'step_simulation', {'steps': options.steps},
                                  lambda _: [f'stepped {options.steps}'])),
    'simulate': ('take N steps while paused as an action, paced as when playing '
                 '(SimulateSteps); Ctrl-C cancels',
                 lambda parser: parser.add_argument('steps', type=step_count(MAX_ACTION_STEPS)),
                 lambda options: Call(SimulateSteps, 'simulate_steps', {'steps': options.steps},
                                      lambda _: [f'simulated {options.steps}'])),
    'reset': ('reset time, state and spawned entities, or the scopes given',
              lambda parser: parser.add_argument('scope', nargs='*', type=scope_name,
                                                 metavar=f'{{{",".join(sorted(SCOPES))}}}'),
              lambda options: Call(ResetSimulation, 'reset_simulation', {'scope': sum(
                  {SCOPES[name] for name in options.scope}) if options.scope and 'all' not in (
                  options.scope) else SCOPES['all']}, lambda _: ['reset'])),
    'list': ('entities with their poses and velocities', lambda parser: (
        parser.add_argument('regex', nargs='?', default='', help='names matching this'),
        parser.add_argument('--category', action='append', default=[],
                            choices=sorted(CATEGORIES))), _list),
    'info': ('what an entity is', lambda parser: parser.add_argument('name'),
             lambda options: Call(GetEntityInfo, 'get_entity_info', {'entity': options.name},
                                  lambda response: [
                                      f'{options.name}: '
                                      f'{CATEGORY_NAMES.get(response.info.category.category)}; '
                                      f'{response.info.description}; tags '
                                      f'{" ".join(response.info.tags)}'])),
    'get': ("an entity's pose and velocity", lambda parser: parser.add_argument('name'),
            lambda options: Call(GetEntityState, 'get_entity_state', {'entity': options.name},
                                 lambda response: _state_lines(options.name, response.state))),
    'spawn': ('add a robot or obstacle: RESOURCE is a bundled spawnable (lab_robot, '
              'turtlebot3_burger, obstacle, moving_obstacle), a robot file (STDR XML, nested or '
              'flat YAML) or obstacle file by path or file:// URI, or with --text the text '
              'of such a file',
              lambda parser: (
                  parser.add_argument('resource'), parser.add_argument('x', type=finite),
                  parser.add_argument('y', type=finite),
                  parser.add_argument('theta', type=finite, nargs='?', default=0.0),
                  parser.add_argument('--name', default='', help='default: the first free '
                                      'of robot0, robot1, ... (obstacle0, ...)'),
                  parser.add_argument('--namespace', default='', help="a robot's topics; "
                                      'default: its name'),
                  parser.add_argument('--rename', action='store_true',
                                      help='take another name if this one is taken'),
                  parser.add_argument('--text', '--yaml', action='store_true',
                                      help="RESOURCE is the file's text (YAML or XML)")),
              _spawn),
    'delete': ('remove an entity', lambda parser: parser.add_argument('name'),
               lambda options: Call(DeleteEntity, 'delete_entity', {'entity': options.name},
                                    lambda _: [f'deleted {options.name}'])),
    'move': ('teleport an entity to a pose, standing still', lambda parser: (
        parser.add_argument('name'), parser.add_argument('x', type=finite),
        parser.add_argument('y', type=finite),
        parser.add_argument('theta', type=finite, nargs='?', default=0.0)),
        lambda options: Call(SetEntityState, 'set_entity_state', {
            'entity': options.name,
            'state': _entity_state((options.x, options.y, options.theta))},
            lambda _: [f'{options.name} at {format_pose((options.x, options.y, options.theta))}'
                       ])),
    'set-velocity': ('set an entity moving: x y in m/s (map frame; a robot only along its '
                     'heading), angular in rad/s', lambda parser: (
                         parser.add_argument('name'), parser.add_argument('vx', type=finite),
                         parser.add_argument('vy', type=finite),
                         parser.add_argument('angular', type=finite)), _set_velocity),
    'spawnables': ('what can be spawned, and from the folders given',
                   lambda parser: parser.add_argument('folders', nargs='*'),
                   lambda options: Call(GetSpawnables, 'get_spawnables',
                                        {'sources': options.folders}, lambda response: [
                                            f'{item.uri}: {item.description}'
                                            for item in response.spawnables])),
    'worlds': ('the maps that can be loaded, and those in the folders given',
               lambda parser: parser.add_argument('folders', nargs='*'),
               lambda options: Call(GetAvailableWorlds, 'get_available_worlds',
                                    {'additional_sources': options.folders}, _worlds)),
    'world': ('the map loaded now', lambda parser: None,
              lambda options: Call(GetCurrentWorld, 'get_current_world', report=(
                  lambda response: [f'{response.world.name}: '
                                    f'{response.world.world_resource.uri}']))),
    'load-world': ('switch to a map: a bundled map name, a map_server YAML path or file:// URI',
                   lambda parser: parser.add_argument('uri'),
                   lambda options: Call(LoadWorld, 'load_world', {'uri': options.uri},
                                        lambda response: [f'loaded {response.world.name}'])),
    'unload-world': ('take the map and every entity away', lambda parser: None,
                     lambda options: Call(UnloadWorld, 'unload_world',
                                          report=lambda _: ['unloaded'])),
}


def build_arguments() -> argparse.ArgumentParser:
    """Return stdr_ctl's parser: --simulator and --timeout go before or after the command."""
    parser = OneLineParser(prog='stdr_ctl', description=DESCRIPTION)
    _add_common(parser, '/stdr_lite', 10.0)
    commands = parser.add_subparsers(dest='command', required=True, metavar='COMMAND')
    for name, (summary, add_arguments, _) in COMMANDS.items():
        command = commands.add_parser(name, help=summary, description=summary)
        # Given after the command, they override those before it; absent, they leave them.
        _add_common(command, argparse.SUPPRESS, argparse.SUPPRESS)
        add_arguments(command)
    return parser


def _add_common(parser, simulator, seconds):
    parser.add_argument('--simulator', default=simulator, type=simulator_name,
                        help='the simulator node whose services to call (default /stdr_lite)')
    parser.add_argument('--timeout', type=timeout, default=seconds,
                        help='seconds to wait for the simulator to answer, in (0, 3600] '
                        '(default 10)')

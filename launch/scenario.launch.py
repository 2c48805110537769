"""
Bring a coursework scenario up: its world, its robot at its start, its task's reference answer.

ros2 launch simple_robot_control scenario.launch.py scenario:=factory_planning

scenario is a bundled scenario's name (scenarios/) or a course file's path; controller runs
another executable of this package (yours, installed beside it) in the place of the reference
answer. The controller runs on the simulator's clock (use_sim_time). The launch ends when the
controller does, or the simulator, and says how it ended.
"""

from pathlib import Path

from coursework_answers.answers import REFERENCE_ANSWERS
from courseworks.courses import read_course, world_parameters
from launch import LaunchDescription
from launch.actions import (DeclareLaunchArgument, EmitEvent, LogInfo, OpaqueFunction,
                            RegisterEventHandler)
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from simple_robot_control.exit_codes import describe_exit
from simple_robot_control.share import shared_file


def report_and_shut_down(name):
    """Return an exit handler that says how the node name ended, then ends the launch."""
    def report(event, context):
        outcome = describe_exit(name, event.returncode)
        return [LogInfo(msg=outcome), EmitEvent(event=Shutdown(reason=outcome))]
    return report


def bring_up(context):
    """Read the scenario, then start the simulator in its world and the controller on it."""
    name = LaunchConfiguration('scenario').perform(context)
    path = Path(name) if name.endswith('.txt') else Path(shared_file('scenarios',
                                                                     f'{name}.txt'))
    course = read_course(path)
    answer = REFERENCE_ANSWERS[course.task]
    chosen = LaunchConfiguration('controller').perform(context)
    executable = chosen or answer.controller
    # Your controller takes none of the reference's parameters; its helpers (a mapper) stay.
    parameters = {} if chosen else dict(answer.parameters)
    simulator = Node(
        package='simple_robot_control', executable='stdr_lite', name='stdr_lite',
        output='screen',
        parameters=[{**world_parameters(course),
                     'lockstep': LaunchConfiguration('lockstep').perform(context) == 'true',
                     'real_time_factor': float(
                         LaunchConfiguration('real_time_factor').perform(context))}])
    controller = Node(
        package='simple_robot_control', executable=executable, name=executable,
        output='screen',
        parameters=[{**parameters, 'use_sim_time': True,
                     'waypoint_file': str(course.waypoint_file)}])
    helpers = [Node(package='simple_robot_control', executable=helper, name=helper,
                    output='screen', parameters=[{'use_sim_time': True}])
               for helper in answer.helpers]
    return [
        simulator, *helpers, controller,
        RegisterEventHandler(OnProcessExit(target_action=controller,
                                           on_exit=report_and_shut_down(executable))),
        RegisterEventHandler(OnProcessExit(target_action=simulator,
                                           on_exit=report_and_shut_down('stdr_lite'))),
    ]


def generate_launch_description():
    return LaunchDescription([
        DeclareLaunchArgument('scenario', default_value='factory_planning',
                              description='a bundled scenario (scenarios/) or a course file'),
        DeclareLaunchArgument('controller', default_value='',
                              description="the controller's executable; empty: the task's "
                              'reference answer'),
        DeclareLaunchArgument('real_time_factor', default_value='1.0',
                              description='at most this many simulated seconds per wall '
                              'second; 0: as fast as the controller keeps up'),
        DeclareLaunchArgument('lockstep', default_value='true',
                              description='advance the simulator only as fast as the '
                              'controller answers, so every run gives the same result'),
        OpaqueFunction(function=bring_up),
    ])

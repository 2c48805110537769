"""
Start the stdr_lite simulator, and RViz on request.

ros2 launch simple_robot_control stdr_lite.launch.py [rviz:=true] [real_time_factor:=2.0] ...

What the launch needs is looked up before anything starts: with rviz:=true on a machine
without rviz2, it says so and ends, leaving no simulator behind. The launch also ends, saying
how, when the simulator does.
"""

from launch import LaunchDescription
from launch.actions import (DeclareLaunchArgument, EmitEvent, LogInfo, OpaqueFunction,
                            RegisterEventHandler)
from launch.conditions import IfCondition
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from launch_ros.substitutions import FindPackageShare
from simple_robot_control.exit_codes import describe_exit
from simple_robot_control.share import missing_packages

ARGUMENTS = {
    'map_yaml': ('', 'map_server YAML of the world; empty for the bundled lab_room', str),
    'rate_hz': ('50.0', 'simulation steps per simulated second', float),
    'real_time_factor': ('1.0', 'simulated seconds per wall second; 0 = as fast as possible',
                         float),
    'integrator': ('euler', 'euler or arc', str),
    'lockstep': ('false', 'step only once the controller has answered the last odometry',
                 bool),
    'robot_description': ('', 'STDR robot YAML; empty for the bundled lab robot', str),
    'robots_file': ('', 'robot list YAML; empty for one robot, robot0', str),
    'odom_rate_hz': ('0.0', 'odometry and TF rate; 0 = every step', float),
    'odom_noise_distance': ('0.0', 'odometry drift: m of distance error after 1 m', float),
    'odom_noise_turn': ('0.0', 'odometry drift: rad of heading error after turning 1 rad',
                        float),
    'odom_noise_heading_per_distance': ('0.0', 'odometry drift: rad of heading error after '
                                        '1 m straight', float),
    'cmd_vel_stamped': ('false', 'take geometry_msgs/TwistStamped commands', bool),
}


def end_with(reason):
    """Say why the launch ends, and end it."""
    return [LogInfo(msg=reason), EmitEvent(event=Shutdown(reason=reason))]


def start_nodes(context):
    """Start the simulator (and RViz), once everything they need is known to be installed."""
    with_rviz = IfCondition(LaunchConfiguration('rviz')).evaluate(context)
    missing = missing_packages(['rviz2'] if with_rviz else [])
    if missing:
        return end_with(f'rviz:=true, but {", ".join(missing)} is not installed: nothing was '
                        'started (install it, or leave rviz:=false)')
    simulator = Node(
        package='simple_robot_control', executable='stdr_lite', name='stdr_lite',
        output='screen',
        parameters=[{name: ParameterValue(LaunchConfiguration(name), value_type=kind)
                     for name, (_, _, kind) in ARGUMENTS.items()}])
    actions = [simulator, RegisterEventHandler(OnProcessExit(
        target_action=simulator,
        on_exit=lambda event, _: end_with(describe_exit('stdr_lite', event.returncode))))]
    if with_rviz:
        view = PathJoinSubstitution([FindPackageShare('simple_robot_control'), 'rviz',
                                     'stdr_lite.rviz'])
        actions.append(Node(package='rviz2', executable='rviz2', name='rviz2',
                            arguments=['-d', view]))
    return actions


def generate_launch_description():
    return LaunchDescription([
        *(DeclareLaunchArgument(name, default_value=default, description=description)
          for name, (default, description, _) in ARGUMENTS.items()),
        DeclareLaunchArgument('rviz', default_value='false',
                              description='also start rviz2 with the bundled view'),
        OpaqueFunction(function=start_nodes),
    ])

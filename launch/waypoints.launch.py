"""
Run a waypoint course in stdr_lite.

ros2 launch simple_robot_control waypoints.launch.py waypoint_file:=/path/to/course.txt

The launch ends when the controller does, or the simulator, and says how it ended (finished,
aborted, or input refused): `ros2 launch` itself returns 0 whatever its nodes did.
"""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument, EmitEvent, LogInfo, RegisterEventHandler
from launch.event_handlers import OnProcessExit
from launch.events import Shutdown
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue
from simple_robot_control.exit_codes import describe_exit


def report_and_shut_down(name):
    """Return an exit handler that says how the node name ended, then ends the launch."""
    def report(event, context):
        outcome = describe_exit(name, event.returncode)
        return [LogInfo(msg=outcome), EmitEvent(event=Shutdown(reason=outcome))]
    return report


def generate_launch_description():
    simulator = Node(
        package='simple_robot_control', executable='stdr_lite', name='stdr_lite',
        output='screen',
        parameters=[{'map_yaml': LaunchConfiguration('map_yaml'),
                     'real_time_factor': ParameterValue(LaunchConfiguration('real_time_factor'),
                                                        value_type=float),
                     'lockstep': ParameterValue(LaunchConfiguration('lockstep'),
                                                value_type=bool)}])
    controller = Node(
        package='simple_robot_control', executable='waypoint_controller',
        name='waypoint_controller', output='screen',
        parameters=[{'use_sim_time': True,
                     'waypoint_file': LaunchConfiguration('waypoint_file')}])
    return LaunchDescription([
        DeclareLaunchArgument('waypoint_file', default_value='',
                              description='waypoint file; empty for the bundled lab tour'),
        DeclareLaunchArgument('map_yaml', default_value='',
                              description='map_server YAML; empty for the bundled lab_room'),
        DeclareLaunchArgument('real_time_factor', default_value='1.0',
                              description='at most this many simulated seconds per wall '
                              'second; 0: as fast as the controller keeps up'),
        DeclareLaunchArgument('lockstep', default_value='true',
                              description='advance the simulator only as fast as the '
                              'controller answers, so every run gives the same result'),
        simulator,
        controller,
        RegisterEventHandler(OnProcessExit(target_action=controller,
                                           on_exit=report_and_shut_down('waypoint_controller'))),
        RegisterEventHandler(OnProcessExit(target_action=simulator,
                                           on_exit=report_and_shut_down('stdr_lite'))),
    ])

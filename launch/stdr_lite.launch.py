"""Start the stdr_lite simulator: ros2 launch simple_robot_control stdr_lite.launch.py."""

from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue

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
}


def generate_launch_description():
    return LaunchDescription([
        *(DeclareLaunchArgument(name, default_value=default, description=description)
          for name, (default, description, _) in ARGUMENTS.items()),
        Node(package='simple_robot_control', executable='stdr_lite', name='stdr_lite',
             output='screen',
             parameters=[{name: ParameterValue(LaunchConfiguration(name), value_type=kind)
                          for name, (_, _, kind) in ARGUMENTS.items()}]),
    ])

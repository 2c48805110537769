"""
The stdr_lite node's parameters and the frames they name: plain data, light to load.

The executable judges a command line against this table before the simulation's code loads
(early_parameters.py); simulation_setup.py builds the simulation the parameters describe.
"""

from __future__ import annotations

from dataclasses import dataclass
import os
from typing import TYPE_CHECKING

from simple_robot_control.parameter_specs import ParameterSpec
from simple_robot_control.share import BUNDLED_RESOURCES, shared_file
from simple_robot_control.validation import Bounds, NON_NEGATIVE, require, shorten
from stdr_lite.core.setting_values import (DEFAULT_POSE, INTEGRATOR_NAMES, SAFETY_ANGULAR_SPEED,
                                           SAFETY_CEILING, SAFETY_LINEAR_SPEED,
                                           SENSOR_NOISE_MODES)

if TYPE_CHECKING:  # the table stays light: the specs' module loads numpy
    from stdr_lite.core.robot_description import LaserSpec, SonarSpec

FRAME_STYLES = ('rep105', 'stdr')
OPTIONAL_TOPICS = ('auto', 'eager', 'on_demand')
# Beyond this many robots, 'auto' makes the optional topics on demand.
ON_DEMAND_ABOVE = 100
# STDR's frame at the map's origin, in which its robots' poses are given.
STDR_STATIC_FRAME = 'map_static'
REP105_FRAMES = ('odom_frame_id', 'base_frame_id')
RESOURCE_PATHS = ParameterSpec(
    'resource_paths', (), "folders where robot files' includes (filename elements) are looked "
    'for, after the folder above the robot file and beside the including file; the bundled '
    'resources come last', constraints='existing folders')
PARAMETERS = (
    ParameterSpec('map_yaml', '', 'map_server YAML file of the world; empty for the bundled '
                  'lab_room (20 m x 15 m)'),
    ParameterSpec('rate_hz', 50.0, 'simulation steps per simulated second; dt = 1/rate_hz',
                  Bounds(1.0, 1000.0)),
    ParameterSpec('integrator', 'euler', "'euler' (the lab's equation 2) or 'arc' (exact "
                  'constant-velocity arc)', choices=INTEGRATOR_NAMES),
    ParameterSpec('real_time_factor', 1.0, 'simulated seconds per wall-clock second; 0 steps '
                  'as fast as the CPU allows', Bounds(0.0, 10000.0)),
    ParameterSpec('lockstep', False, 'advance only once every robot has answered its latest '
                  'odometry with a cmd_vel, so sim time never runs ahead of the controller; '
                  'real_time_factor is then an upper bound'),
    ParameterSpec('paused', False, 'start paused: nothing steps or is published until a '
                  'set_simulation_state asks to play (as Gazebo starts with paused:=true)'),
    ParameterSpec('robot_description', '', 'robot file of the robots (STDR XML, nested or flat '
                  'YAML); empty for the bundled lab robot'),
    RESOURCE_PATHS,
    ParameterSpec('robots_file', '', 'YAML robot list {robots: [{name, description, pose}]}; '
                  'empty: one robot, robot_name at initial_pose'),
    ParameterSpec('robot_name', 'robot0', 'name of the one robot when there is no robots_file: '
                  'topics are /<name>/cmd_vel, /<name>/odom, ...', ros_name=True),
    ParameterSpec('robot_radius', 0.0, 'footprint radius of that robot [m]; 0 takes the '
                  'one in robot_description', Bounds(0.0, 10.0)),
    ParameterSpec('initial_pose', list(DEFAULT_POSE), 'start pose of that robot [x m, y m, theta '
                  'rad] in the map frame', constraints='off walls, on the map'),
    ParameterSpec('max_linear_speed', 0.0, 'commands beyond this linear speed are clamped '
                  '[m/s]; 0 clamps none (STDR), short of safety_linear_speed',
                  Bounds(0.0, SAFETY_CEILING)),
    ParameterSpec('max_angular_speed', 0.0, 'commands beyond this angular speed are clamped '
                  '[rad/s]; 0 clamps none (STDR), short of safety_angular_speed',
                  Bounds(0.0, SAFETY_CEILING)),
    ParameterSpec('safety_linear_speed', SAFETY_LINEAR_SPEED, 'the safety bound: commands '
                  'beyond this linear speed are clamped, with a warning, whatever the limits '
                  '(STDR has none; raise it to apply faster commands as STDR does) [m/s]',
                  Bounds(1.0, SAFETY_CEILING)),
    ParameterSpec('safety_angular_speed', SAFETY_ANGULAR_SPEED, 'the safety bound: commands '
                  'beyond this angular speed are clamped, with a warning, whatever the limits '
                  '(STDR has none; raise it to apply faster commands as STDR does) [rad/s]',
                  Bounds(1.0, SAFETY_CEILING)),
    ParameterSpec('cmd_vel_timeout', 0.0, 'stop a robot whose last command is older than '
                  'this [s of sim time]; 0 holds the last command forever (STDR)',
                  Bounds(0.0, 3600.0)),
    ParameterSpec('sensor_seed', 0, 'seed of the sensor noise, so that runs repeat',
                  NON_NEGATIVE),
    ParameterSpec('sensor_noise', 'auto', "whose described sensor noise is applied: 'auto' "
                  "reads a robot file in STDR's layouts (XML, nested YAML) as STDR does, without "
                  "its noise (STDR never applies it), and applies the flat layout's (the bundled "
                  "lab_robot's); 'all' applies every file's noise; 'none' no file's",
                  choices=SENSOR_NOISE_MODES),
    ParameterSpec('motion_seed', 0, "seed of the robots' motion noise (a robot file's "
                  'kinematic parameters), so that runs repeat', NON_NEGATIVE),
    ParameterSpec('odom_rate_hz', 0.0, 'odometry, ground truth and TF published this often '
                  '[Hz of sim time]; 0 publishes every step. In lockstep the controller answers '
                  'each odometry published', Bounds(0.0, 1000.0),
                  constraints='at most rate_hz'),
    ParameterSpec('odom_noise_distance', 0.0, 'odometry drift: std of the distance error '
                  'after driving 1 m [m/sqrt(m)]; 0 with the two below: exact odometry',
                  Bounds(0.0, 1.0)),
    ParameterSpec('odom_noise_turn', 0.0, 'odometry drift: std of the heading error after '
                  'turning 1 rad [rad/sqrt(rad)]', Bounds(0.0, 1.0)),
    ParameterSpec('odom_noise_heading_per_distance', 0.0, 'odometry drift: std of the heading '
                  'error after driving 1 m straight [rad/sqrt(m)]', Bounds(0.0, 1.0)),
    ParameterSpec('odom_seed', 0, 'seed of the odometry drift, so that runs repeat',
                  NON_NEGATIVE),
    ParameterSpec('cmd_vel_stamped', False, 'take commands as geometry_msgs/TwistStamped (as '
                  'Nav2 sends from Kilted on) instead of geometry_msgs/Twist'),
    ParameterSpec('optional_topics', 'auto', "when each robot's ground truth and sensor "
                  "topics are made: 'eager' at once; 'on_demand' once the graph shows a "
                  'reader (within a second; they are absent from a topic list until then); '
                  f"'auto' eager up to {ON_DEMAND_ABOVE} robots, on demand beyond (every "
                  'endpoint slows the making of the next: a swarm starts in seconds)',
                  choices=OPTIONAL_TOPICS),
    ParameterSpec('frame_style', 'rep105', "the TF tree: 'rep105' map -> <robot>/odom -> "
                  "<robot>/base_link -> <robot>/<sensor>; 'stdr' STDR's, map -> map_static -> "
                  '<robot> -> <robot>_<sensor>, with the odometry in map_static',
                  choices=FRAME_STYLES),
    ParameterSpec('map_visible', True, "publish the world's map on /map (transient local) and "
                  'serve it as nav_msgs/GetMap; false: only its geometry, as nav_msgs/'
                  'MapMetaData on /map_metadata (transient local), for a task whose robot must '
                  'build the map itself'),
    ParameterSpec('map_frame_id', 'map', 'frame of /map and of the ground truth; the root of '
                  'the TF tree', ros_name=True),
    ParameterSpec('odom_frame_id', 'odom', "frame of a robot's odometry (REP-105), as "
                  '<robot>/odom', ros_name=True),
    ParameterSpec('supervisor_fd', -1, 'a connected Unix socket inherited from a supervising '
                  'process (grade_lab): the simulation starts paused and plays when it says '
                  'so, the true state of every step goes to it, and nothing that moves, '
                  'resets, steps, spawns or deletes is served; -1: none',
                  Bounds(-1.0, 65535.0)),
    ParameterSpec('base_frame_id', 'base_link', 'frame of a robot body (REP-105), as '
                  '<robot>/base_link; its sensors are <robot>/<frame_id>', ros_name=True),
)


@dataclass(frozen=True)
class Frames:
    """
    Frame names: the map's, and each robot's under its name, in one of two trees.

    REP-105's: map -> <robot>/odom -> <robot>/base_link -> <robot>/<sensor>. STDR's (stdr):
    map -> map_static (the map's origin) -> <robot> -> <robot>_<sensor>, where the odometry
    is framed in map_static, as stdr_robot frames it.
    """

    map_frame: str
    odom_frame: str
    base_frame: str
    style: str = 'rep105'

    @property
    def stdr(self) -> bool:
        return self.style == 'stdr'

    def odom(self, robot: str) -> str:
        """Return the frame of a robot's odometry (its pose's parent)."""
        return STDR_STATIC_FRAME if self.stdr else f'{robot}/{self.odom_frame}'

    def base(self, robot: str) -> str:
        return robot if self.stdr else f'{robot}/{self.base_frame}'

    def sensor(self, robot: str, spec: LaserSpec | SonarSpec) -> str:
        return f'{robot}_{spec.frame_id}' if self.stdr else f'{robot}/{spec.frame_id}'


def frames(params: dict) -> Frames:
    """Return the frame names; a robot's odometry and body frames must differ."""
    if params['frame_style'] == 'stdr':
        changed = [spec.name for spec in PARAMETERS if spec.name in REP105_FRAMES
                   and params[spec.name] != spec.default]
        require(not changed, f'{", ".join(changed)}: REP-105 frames; with frame_style stdr a '
                "robot's body frame is its name and its odometry's frame is "
                f'{STDR_STATIC_FRAME}')
    require(params['odom_frame_id'] != params['base_frame_id'],
            f'odom_frame_id and base_frame_id are both {params["odom_frame_id"]!r}: a robot\'s '
            'odometry frame and body frame must differ (REP-105: <robot>/odom -> '
            '<robot>/base_link)')
    return Frames(params['map_frame_id'], params['odom_frame_id'], params['base_frame_id'],
                  params['frame_style'])


def search_path(params: dict) -> tuple[str, ...]:
    """Return where robot files' includes are looked for: resource_paths, then the bundled."""
    for folder in params['resource_paths']:
        require(os.path.isdir(folder), f'resource_paths: {shorten(folder)} is not a folder')
    return tuple(params['resource_paths']) + (shared_file(*BUNDLED_RESOURCES),)

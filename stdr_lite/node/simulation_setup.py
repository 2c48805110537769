"""The simulation the stdr_lite node's parameters describe (parameters.py holds the table)."""

from dataclasses import replace

from simple_robot_control.occupancy_map import MapError
from simple_robot_control.share import BUNDLED_ROBOT, shared_file
from simple_robot_control.validation import ConfigError, require
from stdr_lite.core.bodies import PlacementError
from stdr_lite.core.loading import load_world
from stdr_lite.core.robot_description import (load_robot, RobotDescription, RobotEntry,
                                              RobotFileError)
from stdr_lite.core.robot_list import load_robot_list
from stdr_lite.core.setting_values import OdometryNoise
from stdr_lite.core.simulation import RequestError, Simulation, SimulationSettings
from stdr_lite.node.parameters import PARAMETERS


def build_simulation(params: dict, folders: tuple[str, ...]
                     ) -> tuple[Simulation, RobotDescription]:
    """
    Return the simulation the parameters describe, and the robots' default description.

    folders is where robot files' includes are looked for (search_path). Anything that cannot
    be used raises ConfigError with one line naming it.
    """
    require(params['odom_rate_hz'] <= params['rate_hz'],
            f'odom_rate_hz must be at most rate_hz ({params["rate_hz"]:g}), got '
            f'{params["odom_rate_hz"]:g}')
    settings = SimulationSettings(
        odometry_noise=OdometryNoise(params['odom_noise_distance'], params['odom_noise_turn'],
                                     params['odom_noise_heading_per_distance']),
        **{name: params[name] for name in (
            'rate_hz', 'integrator', 'max_linear_speed', 'max_angular_speed',
            'safety_linear_speed', 'safety_angular_speed', 'cmd_vel_timeout',
            'sensor_seed', 'sensor_noise', 'odom_rate_hz', 'odom_seed', 'motion_seed')})
    try:
        description = load_robot(params['robot_description'] or shared_file(*BUNDLED_ROBOT),
                                 folders)
        entries = _robot_entries(params, description, folders)
        return load_world(params['map_yaml'], entries, settings), description
    except (MapError, RobotFileError, PlacementError, RequestError) as error:
        raise ConfigError(str(error)) from None


def _robot_entries(params, description, folders):
    single = {name: params[name] for name in ('robot_name', 'robot_radius', 'initial_pose')}
    if not params['robots_file']:
        require(len(single['initial_pose']) == 3,
                f'initial_pose must be [x, y, theta], got {single["initial_pose"]}')
        if single['robot_radius'] > 0.0:
            description = replace(description, radius=single['robot_radius'], points=())
        return [RobotEntry(single['robot_name'], description, tuple(single['initial_pose']))]
    changed = [spec.name for spec in PARAMETERS
               if spec.name in single and single[spec.name] != spec.default]
    require(not changed, f'robots_file lists the robots; drop {", ".join(changed)}')
    return load_robot_list(params['robots_file'], description, folders)


def start_line(simulation: Simulation, params: dict, supervised: bool) -> str:
    """Return the line the node logs at start: the world, the robots, the rate and the modes."""
    names = simulation.names
    robots = (', '.join(f'{name} at {tuple(round(v, 3) for v in simulation.pose(name))}'
                        for name in names) if len(names) <= 5 else f'{len(names)} robots')
    robots = robots or 'no robots'
    modes = ''.join(f', {mode}' for mode in ('lockstep', 'paused') if params[mode])
    modes += ', supervised' if supervised else ''
    grid = simulation.occupancy_map
    return (f'{grid.source} {grid.width}x{grid.height} cells, {robots}, '
            f'{params["rate_hz"]:g} Hz {params["integrator"]}, real_time_factor '
            f'{params["real_time_factor"]:g}{modes}')

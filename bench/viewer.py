"""
Measure how many frames per second stdr_viewer can paint (a benchmark, not a test).

Ten lab robots in the lab room, each with a full 667-ray laser scan, five sonar cones and a
trail, are painted offscreen at the viewer's default window size, as the viewer paints them.
"""

import argparse
import math
import os
import sys
import time

from bench.realtime import crowded_simulation
from stdr_lite.core.robot_description import LaserSpec
from stdr_lite.viewer.parameters import PARAMETERS
from stdr_lite.viewer.pygame_quiet import pygame
from stdr_lite.viewer.scene import LaserReading, Painter, Scene, SonarReading, View

PARAMETER_DEFAULTS = {spec.name: spec.default for spec in PARAMETERS}


def crowded_scene(robot_count, seed=4):
    """Build the scene the viewer would have after a while: readings, trails and all."""
    simulation, _ = crowded_simulation(robot_count, seed)
    occupancy_map = simulation.occupancy_map
    scene = Scene()
    scene.set_map(occupancy_map.cells, occupancy_map.resolution, occupancy_map.origin[:2])
    jobs = [(name, sensor.spec) for name in simulation.robot_names
            for sensor in simulation.robot(name).sensors]
    for name in simulation.robot_names:
        x, y, theta = simulation.pose(name)
        for step in range(200):
            scene.move(name, (x - 0.02 * step * math.cos(theta),
                              y - 0.02 * step * math.sin(theta), theta))
        scene.move(name, (x, y, theta))
    for (name, spec), reading in zip(jobs, simulation.read_sensors(jobs)):
        robot = scene.robot(name)
        if isinstance(spec, LaserSpec):
            robot.lasers[spec.frame_id] = LaserReading(
                spec.min_angle, (spec.max_angle - spec.min_angle) / (spec.num_rays - 1),
                spec.max_range, reading)
        else:
            robot.sonars[spec.frame_id] = SonarReading(spec.cone_angle, spec.min_range,
                                                       spec.max_range, reading)
    for name in simulation.robot_names:
        robot = simulation.robot(name)
        look = scene.own_look(name)
        look.radius = robot.description.radius
        look.mounts = {sensor.spec.frame_id: sensor.spec.pose for sensor in robot.sensors}
    return scene


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--robots', type=int, default=10)
    parser.add_argument('--frames', type=int, default=200)
    parser.add_argument('--smoke', action='store_true',
                        help='tiny sizes, seconds: that it runs and prints its figures')
    args = parser.parse_args(argv)
    if args.smoke:
        args.robots, args.frames = 2, 5
    os.environ['SDL_VIDEODRIVER'] = 'dummy'
    pygame.font.init()
    surface = pygame.Surface((1000, 750))
    scene = crowded_scene(args.robots)
    view = View(surface.get_size())
    view.fit(scene.extent())
    painter = Painter(pygame.font.Font(None, 22))
    started = time.perf_counter()
    for _ in range(args.frames):
        painter.draw(surface, scene, view)
    rate = args.frames / (time.perf_counter() - started)
    wanted = PARAMETER_DEFAULTS['fps']
    print(f'{args.robots} robots with laser, sonars and trails, 1000x750: {rate:.0f} frames '
          f"per second: {rate / wanted:.1f}x the viewer's own rate ({wanted:g} fps, target "
          '>= 1x)')
    return 0


if __name__ == '__main__':
    sys.exit(main())

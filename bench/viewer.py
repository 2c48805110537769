#!/usr/bin/env python3
"""
Measure how many frames per second stdr_viewer can paint (a benchmark, not a test).

Ten lab robots in the lab room, each with a full 667-ray laser scan, five sonar cones and a
trail, are painted offscreen at the viewer's default window size, as the viewer paints them.
"""

import argparse
import os
import sys
import time

import numpy as np
from realtime import place_robots

from stdr_lite.occupancy_map import load_map
from stdr_lite.pygame_quiet import pygame
from stdr_lite.robot_description import load_robot_or_default
from stdr_lite.sensors import RangeFinder, read_sensors
from stdr_lite.share import shared_file
from stdr_lite.viewer_scene import LaserReading, Painter, Scene, SonarReading, View
from stdr_lite.world import World


def ten_robot_scene(robot_count, seed=4):
    """Build the scene the viewer would have after a while: readings, trails and all."""
    occupancy_map = load_map(shared_file('maps', 'lab_room.yaml'))
    description = load_robot_or_default('')
    world = World(occupancy_map, description.radius)
    rng = np.random.default_rng(seed)
    place_robots(world, robot_count, rng)
    scene = Scene()
    scene.set_map(occupancy_map.cells, occupancy_map.resolution, occupancy_map.origin[:2])
    jobs = [(index, spec) for index in range(robot_count)
            for spec in description.lasers + description.sonars]
    readings = read_sensors(RangeFinder(occupancy_map), world.poses, world.radii, jobs, rng)
    for (index, spec), reading in zip(jobs, readings):
        robot = scene.robot(f'robot{index}')
        x, y, theta = world.poses[index]
        for step in range(200):
            scene.move(f'robot{index}', (x - 0.02 * step * np.cos(theta),
                                         y - 0.02 * step * np.sin(theta), theta))
        scene.move(f'robot{index}', (x, y, theta))
        if spec in description.lasers:
            robot.lasers[spec.frame_id] = LaserReading(
                spec.min_angle, (spec.max_angle - spec.min_angle) / (spec.num_rays - 1),
                spec.max_range, reading)
        else:
            robot.sonars[spec.frame_id] = SonarReading(spec.cone_angle, spec.min_range,
                                                       spec.max_range, reading)
    return scene, description


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.strip().splitlines()[0])
    parser.add_argument('--robots', type=int, default=10)
    parser.add_argument('--frames', type=int, default=200)
    args = parser.parse_args(argv)
    os.environ['SDL_VIDEODRIVER'] = 'dummy'
    pygame.font.init()
    surface = pygame.Surface((1000, 750))
    scene, description = ten_robot_scene(args.robots)
    view = View(surface.get_size())
    view.fit(scene.extent())
    painter = Painter(pygame.font.Font(None, 22))
    started = time.perf_counter()
    for _ in range(args.frames):
        painter.draw(surface, scene, view, lambda name: description)
    rate = args.frames / (time.perf_counter() - started)
    print(f'{args.robots} robots with laser, sonars and trails, 1000x750: {rate:.0f} frames '
          'per second (target >= 20)')
    return 0


if __name__ == '__main__':
    sys.exit(main())

"""
The mapping coursework's judge: a submitted occupancy grid against the world.

Judged over what the robot's own laser could have seen along its true path. No ROS here.

A cell the laser could have seen is one some ray of it crossed, from a pose the robot truly
held, before the first wall (seen free) or the first wall itself (seen wall); the rays follow
the ground-truth map (rays.py), so nothing hidden behind a wall or out of range counts
against a submission. A submitted cell reads as nav_msgs/OccupancyGrid's readers take it
(map_server's thresholds): occupied from 65, free up to 25, unknown otherwise. Walls are
judged with a cell of slack either way: a wall drawn one cell off is neither false nor missed.
A map of another resolution or origin (a student's 0.25 m grid over a 0.05 m world) is read on
the world's cells: each takes the value of the submitted cell holding its centre (on_world_cells),
and the slack is then a submitted cell (a coarse wall covers the world's cells beside it).
A map that knows cells no ray could have reached (behind walls, in a room never entered) was
not built from the laser: the task hides /map, and the judge fails a map that knows too much.
"""

from dataclasses import dataclass
import math

from courseworks.grids import Grid, read_cells
from courseworks.judgement import Judgement
from courseworks.rays import cast_scan
from courseworks.thresholds import MapThresholds
import numpy as np
from numpy.typing import ArrayLike
from scipy import ndimage

WALL_SLACK_CELLS = 1
# A mapper's evidence spreads a little past what the rays crossed (noise, odometry drift): cells
# this far from a seen cell do not count as known beyond sight.
SIGHT_SLACK_CELLS = 3


@dataclass(frozen=True)
class Laser:
    """A laser as a robot file gives it: angles in radians, ranges in metres, pose on the robot."""

    min_angle: float
    max_angle: float
    num_rays: int
    max_range: float
    pose: tuple[float, float, float] = (0.0, 0.0, 0.0)
    frequency: float = 0.0


@dataclass(frozen=True)
class Sight:
    """What the laser could have seen: seen_free and seen_wall are boolean grids."""

    seen_free: np.ndarray
    seen_wall: np.ndarray

    @property
    def seen(self) -> np.ndarray:
        return self.seen_free | self.seen_wall


@dataclass(frozen=True)
class MapJudgement(Judgement):
    """A submitted map's figures, and why it failed (empty when it passed)."""

    agreement: float
    false_walls: float
    missed_walls: float
    coverage: float
    unseen: float
    failures: tuple[str, ...]


def seen_along(grid: Grid, poses: ArrayLike, laser: Laser) -> Sight:
    """Return the cells laser could have seen from each robot pose (x, y, theta) of poses."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 3)
    free_counts = np.zeros(grid.shape, dtype=np.int32)
    wall_counts = np.zeros(grid.shape, dtype=np.int32)
    increment = ((laser.max_angle - laser.min_angle) / (laser.num_rays - 1)
                 if laser.num_rays > 1 else 0.0)
    offset_x, offset_y, offset_theta = laser.pose
    for x, y, theta in poses:
        sensor_x = x + offset_x * math.cos(theta) - offset_y * math.sin(theta)
        sensor_y = y + offset_x * math.sin(theta) + offset_y * math.cos(theta)
        cast_scan(grid.walls, (sensor_x - grid.origin[0]) / grid.resolution,
                  (sensor_y - grid.origin[1]) / grid.resolution, theta + offset_theta,
                  laser.min_angle, increment, laser.num_rays, laser.max_range / grid.resolution,
                  free_counts, wall_counts)
    return Sight(free_counts > 0, wall_counts > 0)


def scan_every(laser: Laser, step: float) -> int:
    """Return how many steps of step seconds apart one scan of laser takes (each, at no rate)."""
    return max(1, round(1.0 / (laser.frequency * step))) if laser.frequency > 0 else 1


def seen_along_run(grid: Grid, poses: ArrayLike, step: float, laser: Laser) -> Sight:
    """Return what laser could have seen along a pose per step, scanning at its rate."""
    return seen_along(grid, np.asarray(poses, dtype=float)[::scan_every(laser, step)], laser)


def on_world_cells(cells: ArrayLike, resolution: float, origin: tuple, world_shape: tuple,
                   world_resolution: float, world_origin: tuple) -> np.ndarray:
    """
    Return a grid's reading of each of the world's cells: the value of its cell at their centre.

    Both grids along x (origin yaw 0); the world's cells outside the grid read unknown (-1).
    """
    cells = np.asarray(cells)
    rows, columns = world_shape

    def indices(count, world_start, start, size):
        centres = world_start + (np.arange(count) + 0.5) * world_resolution
        found = np.floor((centres - start) / resolution).astype(np.int64)
        return found, (found >= 0) & (found < size)
    row_of, row_inside = indices(rows, world_origin[1], origin[1], cells.shape[0])
    column_of, column_inside = indices(columns, world_origin[0], origin[0], cells.shape[1])
    read = np.full(world_shape, -1, dtype=np.int8)
    inside = np.ix_(row_inside, column_inside)
    read[inside] = cells[np.ix_(row_of[row_inside], column_of[column_inside])]
    return read


def _judged_cells(sight, walls, free, wall_slack_cells):
    """Return the judge's masks of the world's cells: what is right, false, missed, ..."""
    near = np.ones((2 * wall_slack_cells + 1,) * 2, dtype=bool)
    true_wall_near = ndimage.binary_dilation(sight.seen_wall, structure=near)
    drawn_wall_near = ndimage.binary_dilation(walls, structure=near)
    seen = sight.seen
    sight_slack = max(SIGHT_SLACK_CELLS, wall_slack_cells)
    known = walls | free
    return {
        'said': seen & known,
        'false': sight.seen_free & walls & ~true_wall_near,
        'missed': sight.seen_wall & ~drawn_wall_near,
        'right': (sight.seen_free & free) | (sight.seen_free & walls & true_wall_near) | (
            sight.seen_wall & walls) | (sight.seen_wall & free & drawn_wall_near),
        'known': known,
        'beyond_sight': known & ~ndimage.binary_dilation(seen, structure=np.ones(
            (2 * sight_slack + 1,) * 2, dtype=bool)),
    }


# How the judge read each of the world's cells (map_readings), for a picture of it.
NOT_SEEN, AGREED, WRONG, FALSE_WALL, MISSED_WALL, BEYOND_SIGHT, NOT_SAID = range(7)


def map_readings(sight: Sight, submitted: ArrayLike,
                 wall_slack_cells: int = WALL_SLACK_CELLS) -> np.ndarray:
    """
    Return a code per world cell of the judge's reading of a map (on the world's cells).

    Where several hold, the first of: known beyond sight, false wall, missed wall, agreed,
    said wrong, seen but not said, not seen.
    """
    walls, free = read_cells(submitted)
    masks = _judged_cells(sight, walls, free, wall_slack_cells)
    codes = np.full(walls.shape, NOT_SEEN, dtype=np.int8)
    codes[sight.seen] = NOT_SAID
    codes[masks['said'] & ~masks['right']] = WRONG
    codes[masks['said'] & masks['right']] = AGREED
    codes[masks['missed']] = MISSED_WALL
    codes[masks['false']] = FALSE_WALL
    codes[masks['beyond_sight']] = BEYOND_SIGHT
    return codes


def judge_map(sight: Sight, submitted: ArrayLike,
              thresholds: MapThresholds = MapThresholds(),
              wall_slack_cells: int = WALL_SLACK_CELLS) -> MapJudgement:
    """
    Judge a submitted grid (values as nav_msgs/OccupancyGrid's, the world's shape).

    Walls are judged with wall_slack_cells of slack either way (a submitted cell, in the
    world's cells, for a coarser map), and sight with as much at least: a coarse cell the laser
    saw a corner of is known as a whole.

    agreement: of the seen cells the map says something of, the fraction it is right about;
    false walls: of the seen free cells, the fraction drawn as walls with no wall a cell away;
    missed walls: of the seen walls, the fraction with no wall drawn within a cell;
    coverage: of the seen cells, the fraction the map says something of;
    unseen: of the cells the map says something of, the fraction no ray could have reached.
    """
    walls, free = read_cells(submitted)
    if walls.shape != sight.seen_free.shape:
        raise ValueError(f'a map of {walls.shape[1]}x{walls.shape[0]} cells, the world has '
                         f'{sight.seen_free.shape[1]}x{sight.seen_free.shape[0]}')
    masks = _judged_cells(sight, walls, free, wall_slack_cells)
    said = masks['said']
    figures = {
        'agreement': _fraction(masks['right'] & said, said),
        'false_walls': _fraction(masks['false'], sight.seen_free),
        'missed_walls': _fraction(masks['missed'], sight.seen_wall),
        'coverage': _fraction(said, sight.seen),
        'unseen': _fraction(masks['beyond_sight'], masks['known']),
    }
    failures = []
    if figures['agreement'] < thresholds.min_agreement:
        failures.append(f'agreement {figures["agreement"]:.1%} < {thresholds.min_agreement:.0%}')
    if figures['false_walls'] > thresholds.max_false_walls:
        failures.append(f'false walls {figures["false_walls"]:.1%} > '
                        f'{thresholds.max_false_walls:.0%} of the free cells seen')
    if figures['missed_walls'] > thresholds.max_missed_walls:
        failures.append(f'missed walls {figures["missed_walls"]:.1%} > '
                        f'{thresholds.max_missed_walls:.0%} of the walls seen')
    if figures['coverage'] < thresholds.min_coverage:
        failures.append(f'coverage {figures["coverage"]:.1%} < {thresholds.min_coverage:.0%} '
                        'of the cells the laser could have seen')
    if figures['unseen'] > thresholds.max_unseen:
        failures.append(f'the map knows {figures["unseen"]:.1%} of its cells where no ray '
                        "from the robot's path reached: not built from the laser alone")
    return MapJudgement(failures=tuple(failures), **figures)


def _fraction(part, whole):
    total = int(np.count_nonzero(whole))
    return float(np.count_nonzero(part)) / total if total else 0.0

"""
A recorded run drawn over its map as a PNG, for plot_run and grade_lab's reports.

Figures are built with matplotlib's object API and the Agg canvas, never pyplot, so no display
or GUI toolkit is involved and nothing global is left behind. matplotlib takes about 0.4 s to
import: grade_lab imports this module only when it draws, so that it answers bad input and
starts its runs without it.
"""

import math
import os

from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import EllipseCollection, LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from matplotlib.transforms import Affine2D
import numpy as np
from simple_robot_control.occupancy_map import OccupancyMap
from waypoint_lab.run import Run
from waypoint_lab.status import STARTED, WAYPOINT

FIGURE_SIZE = (10.0, 7.5)
DPI = 100
HEADING_ARROW = 0.5
ZOOM_MARGIN = 1.0
# Beyond this many waypoints their numbers would cover the picture: only circles and arrows.
MAX_NUMBERED_WAYPOINTS = 100


def render_run(run: Run, occupancy_map: OccupancyMap, robot_radius: float,
               output_path: str | os.PathLike, title: str | None = None) -> None:
    """Write a PNG of the run: walls, path coloured by time, goals, reports, footprints."""
    figure = Figure(figsize=FIGURE_SIZE, dpi=DPI, layout='constrained')
    FigureCanvasAgg(figure)
    axes = figure.subplots()
    draw_map(axes, occupancy_map)
    _draw_path(figure, axes, run)
    _draw_waypoints(axes, run.course)
    _draw_reports(axes, run)
    _draw_footprints(axes, run, robot_radius)
    _zoom_to_run(axes, run)
    axes.legend(loc='upper right', fontsize='small')
    axes.set_aspect('equal')
    axes.set_xlabel('x [m]')
    axes.set_ylabel('y [m]')
    result = run.result or 'UNFINISHED'
    named = f'{run.course.name}: ' if run.course.name else ''
    axes.set_title(title or f'{named}{result} after {run.duration:.1f} s sim time, '
                   f'{len(run.course.waypoints)} waypoints')
    figure.savefig(output_path, dpi=DPI, format='png')


def draw_map(axes: Axes, occupancy_map: OccupancyMap) -> None:
    """
    Occupied cells black, free white, a mapper's likelihoods between, unknown grey.

    Row 0 of the map is its bottom edge.
    """
    cells = occupancy_map.cells
    shades = np.where(cells < 0, 0.75, 1.0 - np.clip(cells, 0, 100) / 100.0)
    width, height = occupancy_map.extent
    origin_x, origin_y, yaw = occupancy_map.origin
    placement = Affine2D().rotate(yaw).translate(origin_x, origin_y) + axes.transData
    axes.imshow(shades, cmap='gray', vmin=0.0, vmax=1.0, origin='lower',
                extent=(0.0, width, 0.0, height), transform=placement, interpolation='nearest')
    corners = placement.transform([(0.0, 0.0), (width, 0.0), (0.0, height), (width, height)])
    corners = axes.transData.inverted().transform(corners)
    axes.set_xlim(corners[:, 0].min(), corners[:, 0].max())
    axes.set_ylim(corners[:, 1].min(), corners[:, 1].max())


def _zoom_to_run(axes, run):
    """Show the part of the map the run used, with a margin, rather than the whole map."""
    points = [(w.x, w.y) for w in run.course.waypoints] + [pose[:2] for pose in run.poses]
    low_x, high_x = axes.get_xlim()
    low_y, high_y = axes.get_ylim()
    (min_x, min_y), (max_x, max_y) = np.min(points, axis=0), np.max(points, axis=0)
    axes.set_xlim(max(low_x, min_x - ZOOM_MARGIN), min(high_x, max_x + ZOOM_MARGIN))
    axes.set_ylim(max(low_y, min_y - ZOOM_MARGIN), min(high_y, max_y + ZOOM_MARGIN))


def _draw_path(figure, axes, run):
    if len(run.poses) < 2:
        return
    points = run.poses[:, :2]
    segments = np.stack([points[:-1], points[1:]], axis=1)
    path = LineCollection(segments, cmap='viridis', linewidths=2.0, zorder=3)
    path.set_array(run.times[:-1])
    axes.add_collection(path)
    figure.colorbar(path, ax=axes, label='sim time [s]', shrink=0.8)


def _draw_waypoints(axes, course):
    """Each goal circle and heading arrow, in one collection each; numbers on short courses."""
    if not course.waypoints:
        return
    x, y, theta = np.asarray(course.waypoints).T
    diameter = 2.0 * course.distance_tolerance
    axes.add_collection(EllipseCollection(
        np.full(x.size, diameter), np.full(x.size, diameter), np.zeros(x.size), units='xy',
        offsets=np.column_stack([x, y]), offset_transform=axes.transData, facecolors='none',
        edgecolors='tab:orange', linewidths=1.5, zorder=4))
    axes.plot([], [], 'o', markerfacecolor='none', markeredgecolor='tab:orange',
              markeredgewidth=1.5, label='waypoint: goal circle, heading')
    axes.quiver(x, y, HEADING_ARROW * np.cos(theta), HEADING_ARROW * np.sin(theta),
                angles='xy', scale_units='xy', scale=1.0, color='tab:orange', width=0.003,
                zorder=4)
    if len(course.waypoints) <= MAX_NUMBERED_WAYPOINTS:
        for number, waypoint in enumerate(course.waypoints, start=1):
            axes.annotate(str(number), (waypoint.x, waypoint.y), textcoords='offset points',
                          xytext=(6, -12), color='tab:orange', fontweight='bold', zorder=4)


def _draw_reports(axes, run):
    """Mark the pose each WAYPOINT message reported."""
    reported = run.reported_poses(WAYPOINT)
    if reported:
        x, y, _ = np.asarray(reported).T
        axes.plot(x, y, 'x', color='tab:red', markersize=9, markeredgewidth=2, zorder=5,
                  label='pose reported in WAYPOINT')


def _draw_footprints(axes, run, robot_radius):
    """Draw the robot where STARTED put it (else where the path begins) and where it ended."""
    if not len(run.poses):
        return
    started = run.reported_poses(STARTED)
    start = started[0] if started else run.poses[0]
    for (x, y, theta), colour, label in ((start, 'tab:green', 'robot at start'),
                                         (run.poses[-1], 'tab:blue', 'robot at end')):
        axes.add_patch(Circle((x, y), robot_radius, fill=False, edgecolor=colour,
                              linewidth=2.0, zorder=6, label=label))
        axes.plot([x, x + robot_radius * math.cos(theta)],
                  [y, y + robot_radius * math.sin(theta)], color=colour, linewidth=2.0,
                  zorder=6)

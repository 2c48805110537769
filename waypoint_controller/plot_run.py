"""
plot_run: draw a recorded run over its map as a PNG.

Figures are built with matplotlib's object API and the Agg canvas, never pyplot, so no display
or GUI toolkit is involved and nothing global is left behind.
"""

import math
import os
import sys

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import EllipseCollection, LineCollection
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from matplotlib.transforms import Affine2D
import numpy as np
from simple_robot_control.bag_reading import is_bag
from simple_robot_control.command_line import OneLineParser
from simple_robot_control.input_files import output_problem
from simple_robot_control.occupancy_map import load_map, MapError
from simple_robot_control.share import BUNDLED_MAP, shared_file
from simple_robot_control.validation import Bounds, compact
from waypoint_controller.run_bag import load_bag
from waypoint_controller.run_record import export_run, load_run, RunRecordError
from waypoint_controller.status import STARTED, WAYPOINT
from waypoint_controller.waypoints import load_waypoints, WaypointFileError

FIGURE_SIZE = (10.0, 7.5)
DPI = 100
HEADING_ARROW = 0.5
ZOOM_MARGIN = 1.0
RADIUS = Bounds(0.0, 10.0, low_open=True)
# Beyond this many waypoints their numbers would cover the picture: only circles and arrows.
MAX_NUMBERED_WAYPOINTS = 100


def render_run(record, occupancy_map, robot_radius, output_path, title=None):
    """Write a PNG of the run: walls, path coloured by time, goals, reports, footprints."""
    figure = Figure(figsize=FIGURE_SIZE, dpi=DPI, layout='constrained')
    FigureCanvasAgg(figure)
    axes = figure.subplots()
    _draw_map(axes, occupancy_map)
    _draw_path(figure, axes, record)
    _draw_waypoints(axes, record)
    _draw_reports(axes, record)
    _draw_footprints(axes, record, robot_radius)
    _zoom_to_run(axes, record)
    axes.legend(loc='upper right', fontsize='small')
    axes.set_aspect('equal')
    axes.set_xlabel('x [m]')
    axes.set_ylabel('y [m]')
    result = record.result or 'UNFINISHED'
    named = f'{record.course}: ' if record.course else ''
    axes.set_title(title or f'{named}{result} after {record.duration:.1f} s sim time, '
                   f'{len(record.waypoints)} waypoints')
    figure.savefig(output_path, dpi=DPI, format='png')


def _draw_map(axes, occupancy_map):
    """Occupied cells black, unknown grey, free white; row 0 of the map is its bottom edge."""
    shades = np.full(occupancy_map.cells.shape, 1.0)
    shades[occupancy_map.cells < 0] = 0.75
    shades[occupancy_map.occupied] = 0.0
    width, height = occupancy_map.extent
    origin_x, origin_y, yaw = occupancy_map.origin
    placement = Affine2D().rotate(yaw).translate(origin_x, origin_y) + axes.transData
    axes.imshow(shades, cmap='gray', vmin=0.0, vmax=1.0, origin='lower',
                extent=(0.0, width, 0.0, height), transform=placement, interpolation='nearest')
    corners = placement.transform([(0.0, 0.0), (width, 0.0), (0.0, height), (width, height)])
    corners = axes.transData.inverted().transform(corners)
    axes.set_xlim(corners[:, 0].min(), corners[:, 0].max())
    axes.set_ylim(corners[:, 1].min(), corners[:, 1].max())


def _zoom_to_run(axes, record):
    """Show the part of the map the run used, with a margin, rather than the whole map."""
    points = [(w.x, w.y) for w in record.waypoints] + [pose[:2] for pose in record.poses]
    low_x, high_x = axes.get_xlim()
    low_y, high_y = axes.get_ylim()
    (min_x, min_y), (max_x, max_y) = np.min(points, axis=0), np.max(points, axis=0)
    axes.set_xlim(max(low_x, min_x - ZOOM_MARGIN), min(high_x, max_x + ZOOM_MARGIN))
    axes.set_ylim(max(low_y, min_y - ZOOM_MARGIN), min(high_y, max_y + ZOOM_MARGIN))


def _draw_path(figure, axes, record):
    if len(record.poses) < 2:
        return
    points = np.asarray(record.poses)[:, :2]
    segments = np.stack([points[:-1], points[1:]], axis=1)
    path = LineCollection(segments, cmap='viridis', linewidths=2.0, zorder=3)
    path.set_array(np.asarray(record.times)[:-1])
    axes.add_collection(path)
    figure.colorbar(path, ax=axes, label='sim time [s]', shrink=0.8)


def _draw_waypoints(axes, record):
    """Each goal circle and heading arrow, in one collection each; numbers on short courses."""
    if not record.waypoints:
        return
    x, y, theta = np.asarray([(w.x, w.y, w.theta) for w in record.waypoints]).T
    diameter = 2.0 * record.distance_tolerance
    axes.add_collection(EllipseCollection(
        np.full(x.size, diameter), np.full(x.size, diameter), np.zeros(x.size), units='xy',
        offsets=np.column_stack([x, y]), offset_transform=axes.transData, facecolors='none',
        edgecolors='tab:orange', linewidths=1.5, zorder=4))
    axes.plot([], [], 'o', markerfacecolor='none', markeredgecolor='tab:orange',
              markeredgewidth=1.5, label='waypoint: goal circle, heading')
    axes.quiver(x, y, HEADING_ARROW * np.cos(theta), HEADING_ARROW * np.sin(theta),
                angles='xy', scale_units='xy', scale=1.0, color='tab:orange', width=0.003,
                zorder=4)
    if len(record.waypoints) <= MAX_NUMBERED_WAYPOINTS:
        for number, waypoint in enumerate(record.waypoints, start=1):
            axes.annotate(str(number), (waypoint.x, waypoint.y), textcoords='offset points',
                          xytext=(6, -12), color='tab:orange', fontweight='bold', zorder=4)


def _draw_reports(axes, record):
    """Mark the pose each WAYPOINT message reported."""
    reported = record.reported_poses(WAYPOINT)
    if reported:
        x, y, _ = np.asarray(reported).T
        axes.plot(x, y, 'x', color='tab:red', markersize=9, markeredgewidth=2, zorder=5,
                  label='pose reported in WAYPOINT')


def _draw_footprints(axes, record, robot_radius):
    """Draw the robot where STARTED put it (else where the record begins) and where it ended."""
    if not record.poses:
        return
    started = record.reported_poses(STARTED)
    start = record.poses[0]
    if started:
        start = started[0]
    for (x, y, theta), colour, label in ((start, 'tab:green', 'robot at start'),
                                         (record.poses[-1], 'tab:blue', 'robot at end')):
        axes.add_patch(Circle((x, y), robot_radius, fill=False, edgecolor=colour,
                              linewidth=2.0, zorder=6, label=label))
        axes.plot([x, x + robot_radius * math.cos(theta)],
                  [y, y + robot_radius * math.sin(theta)], color=colour, linewidth=2.0,
                  zorder=6)


def main(argv=None):
    parser = OneLineParser(
        prog='plot_run', description='Draw a recorded run as a PNG: the map, the path coloured '
        'by time, each waypoint with its goal circle and heading, the poses reported on '
        'robot_status, and the footprint at start and end. The record is a rosbag2 bag in '
        'MCAP (from course_monitor, record_run or a ros2 bag record of the run: an .mcap file '
        'or a bag folder), or JSON lines (plot_run --export-jsonl).')
    parser.add_argument('record', help='the run: a bag (.mcap file or folder) or JSON lines')
    parser.add_argument('--course', help="the course's waypoint file, for a bag recorded "
                        "without the controller's /waypoints")
    parser.add_argument('--robot-name', default='robot0',
                        help='the robot of the run, in a bag (default robot0)')
    parser.add_argument('--export-jsonl', metavar='FILE',
                        help='also write the run as JSON lines (doc/tools.md), for tools of '
                        'your own')
    parser.add_argument('--map', default=shared_file(*BUNDLED_MAP),
                        help='map_server YAML of the world (default: the bundled lab_room)')
    parser.add_argument('--robot-radius', type=float, default=0.2,
                        help='footprint radius [m] (default 0.2)')
    parser.add_argument('--output', '-o', help='PNG to write (default: RECORD with .png)')
    args = parser.parse_args(argv)
    output = args.output or os.path.splitext(args.record)[0] + '.png'
    try:
        if not RADIUS.contains(args.robot_radius):
            raise ValueError(f'--robot-radius must be {RADIUS.text()}, got '
                             f'{compact(args.robot_radius)}')
        for option, path in (('--output', output), ('--export-jsonl', args.export_jsonl)):
            problem = path and output_problem(path, inputs=[args.record, args.map])
            if problem:
                raise ValueError(f'{option} {path}: {problem}')
        record = _load(args)
        render_run(record, load_map(args.map), args.robot_radius, output)
        if args.export_jsonl:
            export_run(record, args.export_jsonl, complain=lambda line: print(
                f'plot_run: {line}', file=sys.stderr))
    except (RunRecordError, MapError, ValueError, OSError) as error:
        print(f'plot_run: error: {error}', file=sys.stderr)
        return 2
    if record.cut_short_line is not None and is_bag(args.record):
        print(f'plot_run: {args.record}: the bag was cut short (an interrupted recording); '
              f'drew the run up to its last complete chunk', file=sys.stderr)
    elif record.cut_short_line is not None:
        print(f'plot_run: {args.record}:{record.cut_short_line}: the last line was cut short '
              '(an interrupted run); drew the run up to the line before it', file=sys.stderr)
    if record.skipped_lines:
        lines = ', '.join(map(str, record.skipped_lines[:5]))
        more = ', ...' if len(record.skipped_lines) > 5 else ''
        print(f'plot_run: {args.record}: left out {len(record.skipped_lines)} status lines that '
              f'are no robot_status of the lab (lines {lines}{more})', file=sys.stderr)
    print(f'wrote {output}')
    return 0


def _load(args):
    """Read the run from a bag or a JSON-lines record, as the path says."""
    if not is_bag(args.record):
        return load_run(args.record)
    try:
        course = load_waypoints(args.course) if args.course else None
    except WaypointFileError as error:
        raise ValueError(str(error)) from None
    return load_bag(args.record, args.robot_name, course,
                    course_name=os.path.basename(args.course) if args.course else '')


if __name__ == '__main__':
    sys.exit(main())

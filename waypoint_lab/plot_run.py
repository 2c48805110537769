"""
plot_run: draw a recorded run over its map as a PNG (and export it as JSON lines).

The run is read from its bag into the one model of a run (run.py), the one grade_lab judges
from what it heard, and drawn by run_picture.py.
"""

import json
import os
import sys

from simple_robot_control.command_line import OneLineParser
from simple_robot_control.input_files import output_problem
from simple_robot_control.occupancy_map import load_map, MapError
from simple_robot_control.share import BUNDLED_MAP, shared_file
from simple_robot_control.validation import Bounds, compact, shorten
from waypoint_lab.course import Course
from waypoint_lab.run import read_run, Run, RunError
from waypoint_lab.run_picture import render_run
from waypoint_lab.waypoints import load_waypoints, WaypointFileError

RADIUS = Bounds(0.0, 10.0, low_open=True)


def export_jsonl(run: Run, path: str | os.PathLike) -> None:
    """
    Write a run as JSON lines (doc/tools.md), for tools of one's own; OSError if it cannot.

    The first line describes the course; then every pose and lab status in time order (a pose
    before a status of the same time), times in sim seconds, angles in radians.
    """
    course = run.course
    entries = [{'course': course.name, 'waypoints': [list(w) for w in course.waypoints],
                'distance_tolerance': course.distance_tolerance,
                'angle_tolerance': course.angle_tolerance}]
    timed = [(time, 0, {'t': time, 'pose': pose})
             for time, pose in zip(run.times.tolist(), run.poses.tolist())]
    timed += [(report.time, 1, {'t': report.time, 'status': report.text})
              for report in run.statuses]
    entries += [entry for _, _, entry in sorted(timed, key=lambda item: item[:2])]
    with open(path, 'w', encoding='utf-8') as stream:
        stream.writelines(json.dumps(entry) + '\n' for entry in entries)


def _parser():
    parser = OneLineParser(
        prog='plot_run', description='Draw a recorded run as a PNG: the map, the path coloured '
        'by time, each waypoint with its goal circle and heading, the poses reported on '
        'robot_status, and the footprint at start and end. The record is a rosbag2 bag in '
        'MCAP (from course_monitor, record_run or a ros2 bag record of the run: an .mcap file '
        'or a bag folder).')
    parser.add_argument('record', help='the run: a bag (.mcap file or folder)')
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
    return parser


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    output = args.output or os.path.splitext(args.record)[0] + '.png'
    try:
        if not RADIUS.contains(args.robot_radius):
            raise ValueError(f'--robot-radius must be {RADIUS.text()}, got '
                             f'{compact(args.robot_radius)}')
        for option, path in (('--output', output), ('--export-jsonl', args.export_jsonl)):
            problem = path and output_problem(path, inputs=[args.record, args.map])
            if problem:
                raise ValueError(f'{option} {path}: {problem}')
        run = _load(args)
        render_run(run, load_map(args.map), args.robot_radius, output)
    except (RunError, MapError, ValueError, OSError) as error:
        print(f'plot_run: error: {error}', file=sys.stderr)
        return 2
    if args.export_jsonl:
        try:
            export_jsonl(run, args.export_jsonl)
        except OSError as error:
            print(f'plot_run: error: {args.export_jsonl}: cannot write the export '
                  f'({error.strerror})', file=sys.stderr)
            return 2
    if run.cut_short:
        print(f'plot_run: {args.record}: the bag was cut short (an interrupted recording); '
              f'drew the run up to its last complete chunk', file=sys.stderr)
    foreign = run.foreign
    if foreign:
        texts = ', '.join(repr(shorten(report.text, 40)) for report in foreign[:3])
        more = ', ...' if len(foreign) > 3 else ''
        print(f'plot_run: {args.record}: left out {len(foreign)} robot_status message(s) that '
              f'are no status of the lab ({texts}{more})', file=sys.stderr)
    print(f'wrote {output}')
    return 0


def _load(args):
    """Read the run from its bag, with the course given or the bag's own."""
    course = None
    if args.course:
        try:
            course = Course(os.path.basename(args.course), tuple(load_waypoints(args.course)))
        except WaypointFileError as error:
            raise ValueError(str(error)) from None
    run = read_run(args.record, args.robot_name, 'odom', course)
    if not len(run.times):
        raise RunError(f'{args.record}: no odometry on {run.path_topic} in the bag')
    return run


if __name__ == '__main__':
    sys.exit(main())

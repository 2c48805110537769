"""
The grading's report for people: a Markdown page with a picture of every course run.

Each picture is plot_run's (run_picture.py): the map, the robot's true path coloured by time
(from the simulator's ground truth, not the submission's odometry), each waypoint's goal set
and the poses the submission reported in its WAYPOINT messages, drawn against that path. No
ROS here.
"""

from datetime import datetime
from pathlib import Path

from lab_grader.grading import CourseVerdict, SubmissionVerdict
from lab_grader.reports import figures, MARKS, RULES, terminal_table
from simple_robot_control.occupancy_map import load_map, MapError
from simple_robot_control.share import BUNDLED_MAP, BUNDLED_RESOURCES, shared_file
from stdr_lite.core.robot_description import load_robot, RobotFileError

LAB_ROBOT_RADIUS = 0.2


def draw_course(verdict: CourseVerdict) -> str:
    """
    Draw a judged course's run as run.png beside its bag; return why not, or ''.

    A mapping or exploration course also gets task.png: its judge's reading of the world's
    cells (task_picture.py).
    """
    course, folder, run = verdict.course, verdict.folder, verdict.run
    if run is None or not len(run.times):
        return 'no true path was recorded'
    # Here, not at the top: matplotlib is a third of grade_lab's start, needed only to draw.
    from waypoint_lab.run_picture import render_run
    try:
        radius = (load_robot(course.robot_file, (shared_file(*BUNDLED_RESOURCES),)).radius
                  if course.robot_file else LAB_ROBOT_RADIUS)
        occupancy_map = load_map(course.map_file or shared_file(*BUNDLED_MAP))
        render_run(run, occupancy_map, radius, folder / 'run.png',
                   f'{course.name}: {MARKS[verdict.status]}, the true path and the poses '
                   'reported')
        if verdict.task_picture is not None:
            from lab_grader.task_picture import render_task_picture
            render_task_picture(verdict.task_picture, run.poses[:, :2], folder / 'task.png')
    except (MapError, RobotFileError, OSError, ValueError) as error:
        return f'no picture: {error}'
    return ''


def markdown_report(submissions: list[SubmissionVerdict], command: list[str],
                    settings_line: str, report_folder: Path) -> str:
    """Return the report page: the table, the rules, then every course's checks and picture."""
    lines = ['# Tick-off sheet', '',
             f'Graded {datetime.now().astimezone():%Y-%m-%d %H:%M %Z} by `grade_lab`: '
             f'`{" ".join(command)}`, {settings_line}.', '',
             f"Rules: {RULES}. Each course runs in a ROS domain of its own; the robot's true "
             'path comes from the simulator, not from the submission.', '',
             '```', terminal_table(submissions), '```', '']
    for submission in submissions:
        if len(submissions) > 1:
            lines += [f'## {submission.name}', '']
        for verdict in submission.courses:
            lines += _course_section(verdict, report_folder, len(submissions) > 1)
    return '\n'.join(lines)


def _course_section(verdict, report_folder, nested):
    heading = '###' if nested else '##'
    lines = [f'{heading} {verdict.course.name}: {MARKS[verdict.status]}', '']
    for name in ('run.png', 'task.png'):
        if verdict.folder is not None and (verdict.folder / name).is_file():
            picture = (verdict.folder / name).relative_to(report_folder)
            lines += [f'![{verdict.course.name}]({picture.as_posix()})', '']
    if verdict.picture_problem:
        lines += [f'({verdict.picture_problem})', '']
    lines += [f'(run.mcap: {note})' for note in verdict.notes] + ([''] if verdict.notes else [])
    lines += ['| check | result | evidence |', '|---|---|---|']
    if verdict.error:
        lines.append(f'| run | ERROR | {_cell(verdict.error)} |')
    lines += [f'| {check.name} | {"PASS" if check.passed else "FAIL"} | {_cell(check.evidence)} |'
              for check in verdict.checks]
    outcome = verdict.outcome
    lines += ['', f'Time and path: {figures(verdict)}; the program ran {outcome.seconds:.1f} s, '
              f'ended {outcome.ended_by}, exit code {outcome.exit_code}.', '']
    if verdict.failures and outcome.last_lines:
        lines += ['Its last lines:', '', '```', *outcome.last_lines[-20:], '```', '']
    return lines


def _cell(text):
    return text.replace('|', '\\|').replace('\n', ' ')

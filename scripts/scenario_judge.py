"""
Judge a scenario's recorded run as grade_lab's coursework judge would, and draw its reading.

    python3 scripts/scenario_judge.py SCENARIO BAG PICTURE

SCENARIO is what scenario_setup.py took (a bundled scenario's name or a course file's path),
BAG the run course_monitor recorded (ground truth, statuses, and for mapping the map topic the
course names). Prints the task's check as the report would (PASS or FAIL, and why) and, for
mapping and exploration, writes PICTURE: each of the world's cells as the judge read it, with
the true path over it (lab_grader/task_picture.py, the report's task.png). The grader judges
what it heard live, never a bag: this is make scenario's look at the same rules, for a
mapper's author. One line on stderr and exit code 2 when the bag or scenario cannot be read.
"""

import sys

from courseworks.courses import CourseError, read_course, submitted_map_topic
from lab_grader.task_checks import judge_task
from lab_grader.task_picture import render_task_picture
from scenario_setup import scenario_file  # beside this script
from simple_robot_control.bag_reading import BagMessages, BagReadError
from simple_robot_control.occupancy_map import MapError, OccupancyMap
from waypoint_lab.run import read_run, RunError


def main(argv: list[str]) -> int:
    name, bag, picture_file = argv[1:4]
    try:
        course = read_course(scenario_file(name))
        run = read_run(bag, path_topic='ground_truth', course=course)
        submitted = _last_map(bag, submitted_map_topic(course))
    except (CourseError, RunError, BagReadError) as error:
        print(f'scenario: {error}', file=sys.stderr)
        return 2
    checks, picture = judge_task(course, run, submitted)
    for check in checks:
        print(f'{check.name}: {"PASS" if check.passed else "FAIL"}: {check.evidence}')
    if picture is not None:
        render_task_picture(picture, run.poses[:, :2], picture_file)
        print(f"wrote {picture_file} (the judge's reading of each cell)")
    return 0


def _last_map(bag: str, topic: str) -> OccupancyMap | str | None:
    """Return the bag's last map on topic, the line saying why it is none, or None."""
    last = None
    for item in BagMessages(bag, {topic}):
        last = item.message
    if last is None:
        return None
    try:
        return OccupancyMap.from_grid_message(last, topic)
    except MapError as error:
        return str(error)


if __name__ == '__main__':
    sys.exit(main(sys.argv))

"""
grade_lab: the lab's tick-off sheet, automated: grade a controller on hidden courses.

    grade_lab --courses DIR_OR_FILES [--jobs N] [--report DIR] [--lockstep]
              -- python3 my_controller.py {waypoints}

Every course runs in isolation (course_run.py) and is judged from what its recorder heard
live, never from the bag it writes (verdicts.py); the table goes to the terminal and, with
--report, the reports to a folder. With --submissions, each folder in it is a group's
submission, graded by the same command run in that folder.
Exit code 0 when every course of every submission passes, 1 otherwise, 2 for bad input.
"""

import argparse
from concurrent.futures import as_completed, ThreadPoolExecutor
import ctypes
import json
import math
import os
from pathlib import Path
import shutil
import signal
import sys
import tempfile
import threading

from courseworks.courses import (ANGLE_TOLERANCE_DEGREES, course_files, CourseError,
                                 DISTANCE_TOLERANCE_RANGE, find_courses, TIME_LIMIT_RANGE)
from lab_grader.course_guard import CourseGuard, CourseGuardError
from lab_grader.grading import grade_course, PASS, RunEvidence, SubmissionVerdict
from lab_grader.report_page import draw_course, markdown_report
from lab_grader.reports import (classroom_result, gradescope_results, junit_xml, MARKS,
                                RULES, terminal_table)
from lab_grader.run_environment import (course_environment, middleware_problem, PLACEHOLDER,
                                        RunSettings, SEALED_DDS, submission_environment)
from lab_grader.sandbox import (CHOICES, choose_mode, describe_mode, DISK_MB, NAMESPACES,
                                needed_paths, SandboxError, SandboxPolicy)
from lab_grader.submission_process import sandbox_problem
from lab_grader.supervision import become_subreaper
from lab_grader.verdicts import ProcessOutcome
from simple_robot_control.command_line import OneLineParser
from simple_robot_control.exit_codes import EXIT_BAD_INPUT, EXIT_FAILED, EXIT_OK
from simple_robot_control.share import shared_file
from simple_robot_control.validation import Bounds, compact, is_ros_name
from waypoint_lab.course import Course
from waypoint_lab.rules import ANGLE_TOLERANCE, DISTANCE_TOLERANCE, TIME_LIMIT

JOBS = Bounds(1, 32)
MEMORY = Bounds(0, 1 << 20)
DISK = Bounds(1, 1 << 16)
MEMORY_MB = 4096
# grade_lab runs again with its arguments in an unnamed file of this descriptor, so that its
# command line, which any process may read, names no course and no report folder.
ARGUMENTS_FD = 'GRADE_LAB_ARGUMENTS_FD'
_PR_SET_DUMPABLE = 4
REAL_TIME_FACTOR = Bounds(0.0, 100.0)
DESCRIPTION = ('Grade a lab controller on courses it has not seen, as the tick-off sheet '
               'would: each course runs in a ROS domain of its own (stdr_lite, a recorder and '
               'the submission), and is judged from what the recorder heard live against the '
               f"simulator's ground truth: STARTED, each WAYPOINT in order and honest ({RULES}), "
               'FINISHED with the robot stopped, no wall contact, and a program that ends when '
               'asked. Give '
               f"the submission's command after --, with {PLACEHOLDER} where the course's "
               'waypoint file goes.')


def build_parser() -> OneLineParser:
    parser = OneLineParser(prog='grade_lab', description=DESCRIPTION, usage=(
        'grade_lab --courses DIR_OR_FILES [--submissions DIR] [--jobs N] [--report DIR] '
        f'[--lockstep] ... -- COMMAND ... {PLACEHOLDER} ...'))
    parser.add_argument('--courses', nargs='+', required=True, metavar='DIR_OR_FILE',
                        help='waypoint files, or folders of them (*.txt), each with an '
                        'optional YAML of the same name (start, map, robot, time_limit, '
                        'points, tolerances, max_time, max_path_length; doc/grading.md)')
    parser.add_argument('--submissions', metavar='DIR', help='a folder holding one folder '
                        "per submission (a group's): the command runs in each")
    parser.add_argument('--jobs', type=int, default=1, help=f'courses run at once '
                        f'(default 1; {JOBS.text()})')
    parser.add_argument('--report', metavar='DIR', help='write the reports there: report.md '
                        "with a picture per course, junit.xml, Gradescope's results.json, "
                        "GitHub Classroom's classroom.json, and each run's bag and output")
    parser.add_argument('--lockstep', action='store_true', help='run the simulator in '
                        'lockstep, for controllers that answer every odometry with one cmd_vel')
    parser.add_argument('--real-time-factor', type=float, default=1.0, help='sim seconds per '
                        'wall second (default 1: student code runs on wall time; 0, as fast as '
                        'it goes, needs --lockstep)')
    parser.add_argument('--time-limit', type=float, default=TIME_LIMIT, help='wall seconds a '
                        f"course may take (default {TIME_LIMIT:g}; a course's YAML may set its "
                        'own)')
    parser.add_argument('--distance-tolerance', type=float, default=DISTANCE_TOLERANCE,
                        help=f"goal set radius d [m] (default {DISTANCE_TOLERANCE:g}, the lab's)")
    parser.add_argument('--angle-tolerance', type=float, default=math.degrees(ANGLE_TOLERANCE),
                        help='goal set heading tolerance t [degrees] (default '
                        f"{math.degrees(ANGLE_TOLERANCE):g}, the lab's)")
    parser.add_argument('--robot-name', default='robot0', help='the robot (default robot0)')
    parser.add_argument('--sandbox', choices=CHOICES, default='auto', help='how each '
                        'submission is sealed off (default auto: namespaces where grade_lab '
                        'is root and the kernel allows them, a uid and namespaces of its own '
                        "each; else none: grade_lab's own user, said at the start)")
    parser.add_argument('--disk', type=int, default=DISK_MB, metavar='MB', help='what a '
                        f'sandboxed submission may write, in MB (default {DISK_MB}; '
                        f'{DISK.text()})')
    parser.add_argument('--memory', type=int, default=MEMORY_MB, metavar='MB',
                        help='writable memory each process of a submission may take, in MB '
                        f'(default {MEMORY_MB}; 0: no limit; {MEMORY.text()}); beyond it its '
                        'allocations fail, and the course with them')
    return parser


def parse(argv: list[str]) -> tuple[argparse.Namespace, list[str]]:
    """Return (options, command); exit 2 with one line for bad input."""
    parser = build_parser()
    split = argv.index('--') if '--' in argv else len(argv)
    options = parser.parse_args(argv[:split])
    if split == len(argv):
        parser.error(f"give the submission's command after --, with {PLACEHOLDER} where the "
                     'waypoint file goes')
    command = argv[split + 1:]
    problems = [
        not command and 'no command after --',
        command and not any(PLACEHOLDER in part for part in command)
        and f'the command has no {PLACEHOLDER}: where does the waypoint file go?',
        JOBS.problem('--jobs', options.jobs),
        REAL_TIME_FACTOR.problem('--real-time-factor', options.real_time_factor),
        MEMORY.problem('--memory', options.memory),
        DISK.problem('--disk', options.disk),
        options.real_time_factor == 0.0 and not options.lockstep
        and '--real-time-factor 0 needs --lockstep (the simulator would outrun the controller)',
        TIME_LIMIT_RANGE.problem('--time-limit', options.time_limit),
        DISTANCE_TOLERANCE_RANGE.problem('--distance-tolerance', options.distance_tolerance),
        ANGLE_TOLERANCE_DEGREES.problem('--angle-tolerance', options.angle_tolerance),
        not is_ros_name(options.robot_name) and f'--robot-name {options.robot_name!r} is no '
        'ROS name',
        options.report and Path(options.report).exists() and not Path(options.report).is_dir()
        and f'--report {options.report}: not a folder',
    ]
    problem = next((problem for problem in problems if problem), None)
    if problem:
        parser.error(problem)
    return options, command


def command_problem(command: list[str], submissions: list[tuple[str, Path]]) -> str:
    """Say why the command cannot start in some submission's folder, or return ''."""
    program = command[0]
    if '/' not in program:
        found = shutil.which(program)
        return '' if found else f'cannot run {program!r}: no such program on PATH'
    for _, folder in submissions:
        path = folder / program
        if not (path.is_file() and os.access(path, os.X_OK)):
            return f'cannot run {program!r} in {folder}: no such executable file'
    return ''


def submissions_of(options: argparse.Namespace) -> list[tuple[str, Path]]:
    """Return (name, folder) of each submission: the folders of --submissions, or this one."""
    if not options.submissions:
        return [(Path.cwd().name or 'submission', Path.cwd())]
    folder = Path(options.submissions)
    if not folder.is_dir():
        raise CourseError(f'--submissions {folder}: not a folder')
    found = sorted(child for child in folder.iterdir()
                   if child.is_dir() and not child.name.startswith('.'))
    if not found:
        raise CourseError(f'--submissions {folder}: no submission folder in it')
    return [(child.name, child.resolve()) for child in found]


class Grading:
    """Runs every course of every submission, --jobs at a time, until done or interrupted."""

    def __init__(self, options, command, courses, submissions, folder, guard, sandbox):
        self.options, self.command = options, command
        self.courses, self.submissions, self.folder = courses, submissions, folder
        self.guard, self._guarding = guard, threading.Lock()
        self.sandbox = sandbox
        self.stopping = threading.Event()
        self.hidden = tuple(str(Path(path).resolve()) for path in options.courses) + (
            (str(folder),) if options.report else ())

    def run(self) -> list[SubmissionVerdict]:
        """Return a SubmissionVerdict per submission, its courses in course order."""
        verdicts = {name: {} for name, _ in self.submissions}
        jobs = [(name, cwd, course) for name, cwd in self.submissions for course in self.courses]
        with ThreadPoolExecutor(max_workers=self.options.jobs) as pool:
            running = {pool.submit(self._grade, *job): job for job in jobs}
            for done in as_completed(running):
                name, _, course = running[done]
                verdict = done.result()
                verdicts[name][course.name] = verdict
                who = f'{name} / ' if len(self.submissions) > 1 else ''
                print(f'{who}{course.name}: {MARKS[verdict.status]}', flush=True)
        return [SubmissionVerdict(name, [verdicts[name][course.name] for course in self.courses])
                for name, _ in self.submissions]

    def _grade(self, name, cwd, course):
        settings = RunSettings(tuple(self.command), str(cwd), self.options.lockstep,
                               self.options.real_time_factor, self.options.robot_name,
                               self.options.memory, self.hidden, self.sandbox)
        folder = self.folder / (name if len(self.submissions) > 1 else '') / course.name
        if self.stopping.is_set():
            return grade_course(course, RunEvidence(ProcessOutcome(start_error='not run'),
                                                    folder / 'run.mcap',
                                                    'grading was interrupted'))
        # Here: rclpy refuses at import an RMW it was not built for, before main() could say so.
        from lab_grader.course_run import run_course
        try:
            evidence = run_course(course, settings, folder, self.stopping)
        except OSError as error:
            # Its folder in the report, or its namespaces: the machine's doing, not the group's.
            evidence = RunEvidence(ProcessOutcome(start_error='not run'), folder / 'run.mcap',
                                   f'the run could not be set up: {error}')
        with self._guarding:
            evidence.fouls += tuple(self.guard.check())
        verdict = grade_course(course, evidence, self.options.robot_name)
        if self.options.report:
            verdict.picture_problem = draw_course(verdict)
        return verdict


def write_reports(options: argparse.Namespace, command: list[str],
                  submissions: list[SubmissionVerdict], folder: Path) -> list[str]:
    """
    Write report.md and junit.xml, and each submission's Gradescope and Classroom files.

    Each is written whole or not at all (a full disk leaves no half file where a reader
    looks); return a line for each that could not be.
    """
    mode = (f'{"lockstep" if options.lockstep else "free-running"} at real-time factor '
            f'{compact(options.real_time_factor)}, {options.jobs} at a time')
    reports = [(folder / 'report.md', markdown_report(submissions, command, mode, folder)),
               (folder / 'junit.xml', junit_xml(submissions))]
    for submission in submissions:
        place = folder / submission.name if len(submissions) > 1 else folder
        reports += [(place / 'results.json', gradescope_results(submission)),
                    (place / 'classroom.json', classroom_result(submission, command))]
    problems = []
    for path, content in reports:
        problem = _write_whole(path, content.encode() if isinstance(content, str) else content)
        if problem:
            problems.append(problem)
    return problems


def _write_whole(path, data):
    """Write path by a file beside it renamed over it; say why not, or return ''."""
    partial = path.with_name(f'.{path.name}.partial')
    try:
        partial.write_bytes(data)
        partial.replace(path)
        return ''
    except OSError as error:
        partial.unlink(missing_ok=True)
        return f'{path}: not written: {error.strerror}'


def hide_arguments() -> list[str]:
    """
    Return the command line's arguments, having first run again without them, if need be.

    Any process of the machine may read a command line (/proc/<pid>/cmdline): grade_lab's would
    name the courses and the report folder to the submissions it runs. So grade_lab runs again,
    as the same process, with its arguments in an unnamed in-memory file; and it makes itself
    non-dumpable, so that no other process of its user reads its environment, its open files
    or its folder through /proc, or attaches to it.
    """
    descriptor = os.environ.pop(ARGUMENTS_FD, None)
    if descriptor is not None:
        with os.fdopen(int(descriptor), 'rb') as stream:
            arguments = json.loads(stream.read())
    else:
        arguments = sys.argv[1:]
        if arguments and hasattr(os, 'memfd_create'):
            memory = os.memfd_create('grade_lab-arguments', 0)
            os.write(memory, json.dumps(arguments).encode())
            os.lseek(memory, 0, os.SEEK_SET)
            os.set_inheritable(memory, True)
            sys.stdout.flush()
            program = os.path.abspath(sys.argv[0])
            os.execve(sys.executable, [sys.executable, program],
                      dict(os.environ, **{ARGUMENTS_FD: str(memory)}))
    try:
        ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_DUMPABLE, 0, 0, 0, 0)
    except (OSError, AttributeError):
        pass
    return arguments


def sandbox_policy(options: argparse.Namespace, courses: list[Course], folder: Path | None,
                   submissions: list[tuple[str, Path]]) -> SandboxPolicy:
    """
    Return how the submissions are sealed off, checked: SandboxError says why it cannot be.

    Hidden from them: the courses' folders (and those of their maps and robots, bundled ones
    aside) and the report folder. Sealed, their uid must run this package's Python (probed
    once, in the first submission's folder).
    """
    mode, why = choose_mode(options.sandbox)
    prefix = os.path.realpath(sys.prefix)
    hidden = {str(Path(path).resolve()) for path in options.courses if Path(path).is_dir()}
    hidden |= {str(Path(path).resolve().parent) for path in course_files(courses)
               if not str(Path(path).resolve()).startswith(prefix + '/')}
    if folder is not None:
        hidden.add(str(folder))
        if mode == NAMESPACES:
            folder.chmod(0o700)
    if mode == NAMESPACES:
        # This process makes participants only in its courses' namespaces (course_run.py).
        os.environ.update(SEALED_DDS)
    sandbox = SandboxPolicy(mode, tuple(sorted(hidden)), needed_paths(os.environ), options.disk,
                            why=why)
    for _, cwd in submissions:
        problem = sandbox.problem(str(cwd))
        if problem:
            raise SandboxError(problem)
    if sandbox.sealed:
        uid = sandbox.uids.take()
        try:
            with tempfile.TemporaryDirectory(prefix='grade_lab-probe-') as scratch:
                environment = submission_environment(course_environment(0, True), scratch, ())
                problem = sandbox_problem(sandbox.jail(uid, str(submissions[0][1]), {}),
                                          environment, Path(scratch) / 'output.txt')
        finally:
            sandbox.uids.give_back(uid)
        if problem:
            raise SandboxError(f'--sandbox {mode}: {problem}')
    return sandbox


def _report(options, command, verdicts, folder):
    """Print the table, write the reports if asked; return the problems writing them met."""
    print(terminal_table(verdicts))
    if folder is None:
        return []
    problems = write_reports(options, command, verdicts, folder)
    for problem in problems:
        print(f'grade_lab: {problem}', file=sys.stderr)
    if not problems:
        print(f'reports in {folder}: report.md, junit.xml, results.json, classroom.json')
    return problems


def main(argv: list[str] | None = None) -> int:
    argv = hide_arguments() if argv is None else list(argv)
    options, command = parse(argv)
    problem = middleware_problem(os.environ)
    if problem:
        print(f'grade_lab: error: {problem}', file=sys.stderr)
        return EXIT_BAD_INPUT
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
    os.environ['ROS_STATIC_PEERS'] = ''
    os.environ.setdefault('FASTRTPS_DEFAULT_PROFILES_FILE',
                          shared_file('config', 'fastdds_quick_discovery.xml'))
    defaults = Course('', (), time_limit=options.time_limit,
                      distance_tolerance=options.distance_tolerance,
                      angle_tolerance=math.radians(options.angle_tolerance))
    try:
        courses = find_courses(options.courses, defaults)
        guard = CourseGuard([path for path in options.courses if Path(path).is_dir()],
                            course_files(courses))
        submissions = submissions_of(options)
        problem = command_problem(command, submissions)
        if problem:
            raise CourseError(problem)
        # Absolute: each submission runs in its own folder, and is handed paths in this one.
        folder = Path(options.report).resolve() if options.report else None
        if folder is not None:
            folder.mkdir(parents=True, exist_ok=True)
        sandbox = sandbox_policy(options, courses, folder, submissions)
    except (CourseError, CourseGuardError, SandboxError, OSError) as error:
        print(f'grade_lab: error: {error}', file=sys.stderr)
        return EXIT_BAD_INPUT
    become_subreaper()
    print(f'grade_lab: sandbox: {describe_mode(sandbox.mode, options.disk, sandbox.why)}',
          flush=True)
    with tempfile.TemporaryDirectory(prefix='grade_lab-') as scratch:
        grading = Grading(options, command, courses, submissions, folder or Path(scratch),
                          guard, sandbox)
        for number in (signal.SIGINT, signal.SIGTERM):
            signal.signal(number, lambda *_: grading.stopping.set())
        print(f'grade_lab: {len(courses)} course(s) x {len(submissions)} submission(s), '
              f'{options.jobs} at a time: {" ".join(command)}', flush=True)
        verdicts = grading.run()
        problems = _report(options, command, verdicts, folder)
    if grading.stopping.is_set():
        print('grade_lab: interrupted: courses not run are errors', file=sys.stderr)
    passed = all(verdict.status == PASS for verdict in verdicts)
    return EXIT_OK if passed and not problems else EXIT_FAILED


if __name__ == '__main__':
    sys.exit(main())

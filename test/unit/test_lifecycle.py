"""The lab's run lifecycle, fed poses directly: statuses, aborts, pacing, limits."""

import math

from coursework_answers.explorer_law import ExplorerLaw
from coursework_answers.route_law import RouteLaw
import pytest
from stdr_lite.core.kinematics import arc_step
from waypoint_controller.control_law import PlannedLaw
from waypoint_lab.lifecycle import (ControlLaw, ExploringLaw, FunctionLaw, Outcome, PlanningLaw,
                                    RoutingLaw, RunLifecycle, RunRules)
from waypoint_lab.status import parse_status
from waypoint_lab.waypoints import Waypoint

MS = 1_000_000
COURSE = [Waypoint(1.0, 0.0, 0.0), Waypoint(1.0, 0.0, math.pi / 2)]


class Recorder:
    """A law that says what it was told and answers a fixed command."""

    def __init__(self, answer=(0.3, 0.1)):
        self.answer, self.aims, self.commands = answer, [], []

    def aim(self, pose, index):
        self.aims.append((pose, index))

    def command(self, pose, dt):
        self.commands.append((pose, dt))
        return self.answer


def kinds(outcome):
    return [parse_status(text).kind for text in outcome.statuses]


def test_a_student_function_drives_a_course_to_finished():
    def law(pose, goal, dt):
        bearing = math.atan2(goal.y - pose[1], goal.x - pose[0])
        distance = math.hypot(goal.x - pose[0], goal.y - pose[1])
        if distance > 0.05:
            heading_error = math.remainder(bearing - pose[2], math.tau)
            return 0.5 * max(0.0, math.cos(heading_error)), 2.0 * heading_error
        return 0.0, 2.0 * math.remainder(goal.theta - pose[2], math.tau)
    run = RunLifecycle(COURSE, FunctionLaw(COURSE, law))
    pose, texts, command = (0.0, 0.0, 0.3), [], (0.0, 0.0)
    for step in range(2000):
        outcome = run.observe(step * 20 * MS, pose)
        texts += outcome.statuses
        command = outcome.command or command
        if outcome.exit_code is not None:
            break
        pose = tuple(float(value) for value in arc_step(*pose, *command, 0.02))
    assert outcome.exit_code == 0
    assert [parse_status(text).kind for text in texts] == ['STARTED', 'WAYPOINT', 'WAYPOINT',
                                                           'FINISHED']


def test_one_pose_in_several_goal_sets_reports_each_then_finishes():
    law = Recorder()
    outcome = RunLifecycle([Waypoint(0, 0, 0), Waypoint(0.05, 0, 0)], law).observe(0, (0, 0, 0))
    assert kinds(outcome) == ['STARTED', 'WAYPOINT', 'WAYPOINT', 'FINISHED']
    assert outcome.reached == (0, 1) and outcome.exit_code == 0
    assert outcome.command == (0.0, 0.0) and law.aims == []


def test_the_law_is_aimed_at_start_and_at_each_new_waypoint():
    law = Recorder()
    run = RunLifecycle(COURSE, law)
    run.observe(0, (0.0, 0.0, 0.0))
    run.observe(2000 * MS, (0.95, 0.0, 0.0))
    assert [index for _, index in law.aims] == [0, 1]


def test_commands_come_once_per_control_period_and_are_held_between():
    law = Recorder()
    run = RunLifecycle(COURSE, law, RunRules(control_period_ns=50 * MS))
    commands = [run.observe(stamp * 20 * MS, (0.0, 0.0, 0.0)).command for stamp in range(6)]
    assert commands == [(0.3, 0.1), None, None, (0.3, 0.1), None, (0.3, 0.1)]
    assert [dt for _, dt in law.commands] == pytest.approx([0.05, 0.06, 0.04])


def test_a_stamp_seen_before_changes_nothing():
    run = RunLifecycle(COURSE, Recorder())
    assert kinds(run.observe(0, (0.0, 0.0, 0.0))) == ['STARTED']
    assert run.observe(0, (0.0, 0.0, 0.0)) == run.observe(0, (0.5, 0.0, 0.0))
    assert run.observe(0, (0.0, 0.0, 0.0)).command is None


def test_commands_are_held_to_the_speed_limits():
    run = RunLifecycle(COURSE, Recorder((3.0, -7.0)), RunRules(max_linear_speed=0.4,
                                                               max_angular_speed=0.8))
    assert run.observe(0, (0.0, 0.0, 0.0)).command == (0.4, -0.8)


@pytest.mark.parametrize('answer', [(math.nan, 0.0), (0.1, math.inf), 'fast', (1.0,), None])
def test_a_command_that_is_no_pair_of_numbers_aborts_the_run(answer):
    outcome = RunLifecycle(COURSE, Recorder(answer)).observe(0, (0.0, 0.0, 0.0))
    assert kinds(outcome) == ['STARTED', 'ABORTED'] and outcome.exit_code == 1
    assert outcome.command == (0.0, 0.0)
    assert outcome.problem.startswith(f'the control law answered {answer!r}')


def test_no_progress_for_the_stall_timeout_aborts_at_the_current_waypoint():
    run = RunLifecycle(COURSE, Recorder(), RunRules(stall_timeout=1.0))
    outcomes = [run.observe(stamp * 100 * MS, (0.0, 0.0, 0.0)) for stamp in range(12)]
    ended = [outcome for outcome in outcomes if outcome.exit_code is not None]
    assert len(ended) == 1 and ended[0] is outcomes[11]
    assert ended[0].statuses == ('ABORTED 1 0.000 0.000 0.00',)
    assert 'waypoint 1 (1, 0, 0 deg) unreachable: no progress for 1 s' in ended[0].problem
    assert run.observe(1300 * MS, (0.0, 0.0, 0.0)) == Outcome()


def test_progress_in_heading_alone_keeps_the_run_alive():
    run = RunLifecycle([Waypoint(0.0, 0.0, 3.0)], Recorder(), RunRules(stall_timeout=1.0))
    for stamp in range(30):
        outcome = run.observe(stamp * 100 * MS, (0.0, 0.0, 0.1 * stamp))
        assert outcome.exit_code is None


def test_a_jump_faster_than_the_robot_is_driven_ends_the_run():
    run = RunLifecycle(COURSE, Recorder())
    run.observe(0, (0.0, 0.0, 0.0))
    outcome = run.observe(20 * MS, (0.5, 0.0, 0.0))
    assert kinds(outcome) == ['ABORTED'] and outcome.exit_code == 1
    assert 'faster than it is driven: it was moved (a teleport' in outcome.problem


def test_odometry_time_going_back_ends_the_run():
    run = RunLifecycle(COURSE, Recorder())
    run.observe(40 * MS, (0.0, 0.0, 0.0))
    outcome = run.observe(20 * MS, (0.0, 0.0, 0.0))
    assert outcome.exit_code == 1 and 'the simulator restarted' in outcome.problem


def test_tuned_rules_take_effect_together_at_the_next_tick():
    called = []
    run = RunLifecycle(COURSE, Recorder((3.0, 3.0)), RunRules(control_period_ns=50 * MS))
    assert run.observe(0, (0.0, 0.0, 0.0)).command == (0.5, 1.0)
    run.retune(RunRules(max_linear_speed=0.2, max_angular_speed=0.2,
                        control_period_ns=50 * MS), lambda: called.append(True))
    assert run.observe(20 * MS, (0.0, 0.0, 0.0)).command is None and not called
    assert run.observe(60 * MS, (0.0, 0.0, 0.0)).command == (0.2, 0.2) and called


def test_a_course_without_waypoints_is_refused():
    with pytest.raises(ValueError, match='at least one waypoint'):
        RunLifecycle([], Recorder())


class Planner(Recorder):
    """A law that finds the goals of given indices unreachable when aimed at them."""

    def __init__(self, unreachable):
        super().__init__()
        self.unreachable, self.reachable = set(unreachable), True

    def aim(self, pose, index):
        super().aim(pose, index)
        self.reachable = index not in self.unreachable


def test_a_goal_the_law_finds_unreachable_is_reported_and_the_run_goes_on():
    course = [Waypoint(0.0, 0.0, 0.0), Waypoint(5.0, 0.0, 0.0), Waypoint(9.0, 0.0, 0.0),
              Waypoint(1.0, 0.0, 0.0)]
    law = Planner({1, 2})
    run = RunLifecycle(course, law)
    outcome = run.observe(0, (0.0, 0.0, 0.0))
    assert kinds(outcome) == ['STARTED', 'WAYPOINT', 'UNREACHABLE', 'UNREACHABLE']
    assert [parse_status(text).number for text in outcome.statuses[1:]] == [1, 2, 3]
    assert [index for _, index in law.aims] == [1, 2, 3] and outcome.exit_code is None
    ending = run.observe(2000 * MS, (0.97, 0.0, 0.0))
    assert kinds(ending) == ['WAYPOINT', 'FINISHED'] and ending.exit_code == 0


def test_a_law_that_finds_its_goal_unreachable_later_gives_it_up_then():
    law = Planner(set())
    run = RunLifecycle(COURSE, law)
    run.observe(0, (0.0, 0.0, 0.0))
    law.reachable = False
    outcome = run.observe(20 * MS, (0.0, 0.0, 0.0))
    assert kinds(outcome) == ['UNREACHABLE'] and parse_status(outcome.statuses[0]).number == 1
    assert [index for _, index in law.aims] == [0, 1] and outcome.exit_code is None


def test_no_goal_counts_while_the_law_explores():
    law = Planner(set())
    law.exploring = True
    run = RunLifecycle(COURSE, law)
    assert kinds(run.observe(0, (1.0, 0.0, 0.0))) == ['STARTED']
    law.exploring = False
    assert kinds(run.observe(20 * MS, (1.0, 0.0, 0.0))) == ['WAYPOINT']


def test_each_law_declares_what_more_than_commands_it_gives():
    """The lifecycle asks a law only what its protocols declare (lifecycle.py)."""
    goals = [Waypoint(1.0, 0.0, 0.0)]
    route, explorer = RouteLaw(goals, 0.1, 0.1), ExplorerLaw(goals, 0.1, 0.1)
    assert isinstance(route, PlanningLaw) and isinstance(route, RoutingLaw)
    assert not isinstance(route, ExploringLaw) and isinstance(explorer, ExploringLaw)
    answer = PlannedLaw(goals)
    assert isinstance(answer, ControlLaw)
    assert not any(isinstance(answer, kind) for kind in (PlanningLaw, RoutingLaw, ExploringLaw))

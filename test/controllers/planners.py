"""
Planning submissions that break the planning coursework's rules, written for grade_lab's tests.

    python3 planners.py @ WAYPOINT_FILE     (the behaviour: the first word of ./behaviour)

pushes_on never gives a goal up: with no route it drives straight at the goal, into the wall,
until the lab's stall watch ends the run; gives_up reports every goal unreachable at once. Each
is the reference planner-controller with that one rule changed.
"""

from pathlib import Path
import sys

from coursework_answers.planner_controller import PlannerController
from coursework_answers.route_law import RouteLaw
from simple_robot_control.node_runtime import build_parser, run


class PushingLaw(RouteLaw):
    """Never says a goal is unreachable: with no route, it heads straight for the goal."""

    def _plan(self, pose):
        super()._plan(pose)
        if not self.reachable:
            goal = self.goals[self._index]
            self.route, self.reachable = [(goal.x, goal.y, goal.theta)], True


class GivingUpLaw(RouteLaw):
    """Says every goal is unreachable."""

    def _plan(self, pose):
        super()._plan(pose)
        self.reachable = False


LAWS = {'pushes_on': PushingLaw, 'gives_up': GivingUpLaw}


def main():
    behaviour = Path('behaviour').read_text().split()[0] if sys.argv[1] == '@' else sys.argv[1]
    law_type = LAWS[behaviour]

    class Planner(PlannerController):
        def build_law(self, params, waypoints):
            law, rules = super().build_law(params, waypoints)
            law.__class__ = law_type
            return law, rules

    parser = build_parser('planners', 'a planning submission that breaks a rule', ())
    parser.add_argument('waypoint_file')
    sys.exit(run('planners', parser, lambda options: Planner(options.waypoint_file),
                 [sys.argv[0]] + sys.argv[2:]))


if __name__ == '__main__':
    main()

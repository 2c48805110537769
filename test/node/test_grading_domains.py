"""grade_lab takes a ROS domain only when nobody is in it, lock files or not."""

import threading

from conftest import DOMAIN
from lab_grader import course_run
from lab_grader.domains import DomainClaim
from lab_grader.sandbox import SandboxPolicy
from rclpy.node import Node
from waypoint_lab.course import Course
from waypoint_lab.waypoints import Waypoint


def test_a_domain_where_another_program_runs_is_passed_over(ros_context, executor, tmp_path,
                                                            monkeypatch, capsys):
    neighbour = Node('students_demo', context=ros_context)
    executor.add_node(neighbour)
    claims = []
    real_claim = course_run.claim_domain

    def claim_ours_first(avoid=()):
        """Claim this worker's domain first, which lock files call free and a node is in."""
        claim = DomainClaim(DOMAIN.domain_id, None) if not claims else real_claim(avoid)
        claims.append((claim.domain_id, tuple(avoid)))
        return claim
    monkeypatch.setattr(course_run, 'claim_domain', claim_ours_first)
    (tmp_path / 'here.txt').write_text('1 2 0\n')
    run = course_run._Run(Course('here', (Waypoint(1.0, 2.0, 0.0),),
                                 waypoint_file=tmp_path / 'here.txt'),
                          threading.Event(), tmp_path, SandboxPolicy())
    try:
        run.course_robot = 'robot0'
        run._take_empty_domain()
        assert run.claim is not None and run.claim.domain_id != DOMAIN.domain_id
        assert claims[1][1] == (DOMAIN.domain_id,)
        said = capsys.readouterr().out
        assert (f'grade_lab: ROS domain {DOMAIN.domain_id} is in use by another program '
                '(nodes /students_demo)') in said
    finally:
        run.close()

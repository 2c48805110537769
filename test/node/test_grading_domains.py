"""grade_lab takes a ROS domain only when nobody is in it, lock files or not."""

from conftest import DOMAIN
from lab_grader import course_domain
from lab_grader.course_domain import CourseDomain
from lab_grader.domains import DomainClaim
from rclpy.node import Node
from waypoint_lab.course import Course
from waypoint_lab.waypoints import Waypoint


def test_a_domain_where_another_program_runs_is_passed_over(ros_context, executor, tmp_path,
                                                            monkeypatch, capsys):
    neighbour = Node('students_demo', context=ros_context)
    executor.add_node(neighbour)
    claims = []
    real_claim = course_domain.claim_domain

    def claim_ours_first(avoid=()):
        """Claim this worker's domain first, which lock files call free and a node is in."""
        claim = DomainClaim(DOMAIN.domain_id, None) if not claims else real_claim(avoid)
        claims.append((claim.domain_id, tuple(avoid)))
        return claim
    monkeypatch.setattr(course_domain, 'claim_domain', claim_ours_first)
    (tmp_path / 'here.txt').write_text('1 2 0\n')
    domain = CourseDomain(tmp_path / 'run.mcap', 'robot0',
                          Course('here', (Waypoint(1.0, 2.0, 0.0),),
                                 waypoint_file=tmp_path / 'here.txt'))
    try:
        domain.take_empty()
        assert domain.claim is not None and domain.domain_id != DOMAIN.domain_id
        assert claims[1][1] == (DOMAIN.domain_id,)
        said = capsys.readouterr().out
        assert (f'grade_lab: ROS domain {DOMAIN.domain_id} is in use by another program '
                '(nodes /students_demo)') in said
    finally:
        domain.close()

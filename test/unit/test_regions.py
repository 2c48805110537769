"""Circles against the standard's bounds: sphere, box and convex hull, seen from above."""

import pytest

from stdr_lite.core.regions import overlaps_box, overlaps_circle, overlaps_hull

SQUARE = [(0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 2.0, 0.0), (0.0, 2.0, 0.0), (1.0, 1.0, 0.0)]


@pytest.mark.parametrize('centre, radius, expected', [
    ((1.0, 1.0), 0.1, True), ((2.5, 1.0), 0.6, True), ((2.5, 1.0), 0.4, False),
    ((2.4, 2.4), 0.5, False), ((2.3, 2.3), 0.5, True)])
def test_circle_against_a_square(centre, radius, expected):
    assert overlaps_box(centre, radius, (2.0, 2.0, 0.0), (0.0, 0.0, 0.0)) == expected
    assert overlaps_hull(centre, radius, SQUARE) == expected


def test_circles_touching_overlap():
    assert overlaps_circle((0.0, 0.0), 1.0, (3.0, 0.0), 2.0)
    assert not overlaps_circle((0.0, 0.0), 1.0, (3.01, 0.0), 2.0)


def test_a_hull_of_points_on_one_line_is_refused():
    with pytest.raises(ValueError, match='three points not all on one line'):
        overlaps_hull((0.0, 0.0), 1.0, [(0, 0, 0), (1, 1, 0), (2, 2, 0)])

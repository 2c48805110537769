"""Circles against the standard's bounds: sphere, box and convex hull, seen from above."""

import math

import pytest
from stdr_lite.core.regions import (convex_hull, MAX_HULL_POINTS, overlaps_box, overlaps_circle,
                                    overlaps_hull, region_test)

SQUARE = [(0.0, 0.0, 0.0), (2.0, 0.0, 0.0), (2.0, 2.0, 0.0), (0.0, 2.0, 0.0), (1.0, 1.0, 0.0)]


@pytest.mark.parametrize('centre, radius, expected', [
    ((1.0, 1.0), 0.1, True), ((2.5, 1.0), 0.6, True), ((2.5, 1.0), 0.4, False),
    ((2.4, 2.4), 0.5, False), ((2.3, 2.3), 0.5, True)])
def test_circle_against_a_square(centre, radius, expected):
    assert overlaps_box(centre, radius, (2.0, 2.0, 0.0), (0.0, 0.0, 0.0)) == expected
    assert overlaps_hull(centre, radius, convex_hull(SQUARE)) == expected
    assert region_test('hull', SQUARE)(centre, radius) == expected
    assert region_test('box', [(2.0, 2.0, 0.0), (0.0, 0.0, 0.0)])(centre, radius) == expected


def test_circles_touching_overlap():
    assert overlaps_circle((0.0, 0.0), 1.0, (3.0, 0.0), 2.0)
    assert not overlaps_circle((0.0, 0.0), 1.0, (3.01, 0.0), 2.0)


def test_a_hull_of_points_on_one_line_is_refused():
    with pytest.raises(ValueError, match='three points not all on one line'):
        convex_hull([(0, 0, 0), (1, 1, 0), (2, 2, 0)])


@pytest.mark.parametrize('kind, points, message', [
    ('box', [(0.0, 0.0, 0.0), (math.nan, 1.0, 0.0)], 'not finite'),
    ('sphere', [(0.0, 0.0, 0.0), (math.inf, 0.0, 0.0)], 'not finite'),
    ('sphere', [(0.0, 0.0, 0.0), (-1.0, 0.0, 0.0)], 'a sphere radius must be >= 0'),
    ('hull', [(float(k), float(k * k), 0.0) for k in range(MAX_HULL_POINTS + 1)],
     f'at most {MAX_HULL_POINTS:,}'),
    ('box', [(0.0, 0.0, 0.0)], 'define no volume'),
])
def test_a_region_that_means_nothing_is_refused(kind, points, message):
    with pytest.raises(ValueError, match=message):
        region_test(kind, points)


def test_a_sphere_takes_its_radius_from_the_second_point():
    inside = region_test('sphere', [(1.0, 1.0, 0.0), (0.5, 0.0, 0.0)])
    assert inside((1.6, 1.0), 0.2) and not inside((1.8, 1.0), 0.2)

"""When a run of the lab may start: discovery's grace, then the map when the law plans."""

from waypoint_lab.start import MAP_WAIT, StartConditions


class _Clock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def test_odometry_is_held_until_discovery_has_had_its_grace():
    start = StartConditions('/map', None, warn=print)
    start.hold('odometry 1')
    start.hold('odometry 2')
    assert start.release() is None
    start.discovered()
    assert start.release() == 'odometry 2'
    assert start.release() is None


def test_a_planning_law_waits_for_a_published_map_then_gives_up_with_one_line():
    clock, said, publishers = _Clock(), [], [1]
    start = StartConditions('/map', lambda: publishers[0], said.append, clock)
    start.discovered()
    start.hold('odometry')
    clock.now = MAP_WAIT - 0.1
    assert start.release() is None and said == []
    clock.now = MAP_WAIT
    assert start.release() == 'odometry'
    assert len(said) == 1 and said[0].startswith('/map has a publisher but no map came in 10 s')
    assert start.may_start() and len(said) == 1


def test_a_map_that_came_or_cannot_come_lets_the_run_start_at_once():
    publishers = [1]
    start = StartConditions('/map', lambda: publishers[0], warn=print)
    start.discovered()
    assert not start.may_start()
    start.map_came()
    assert start.has_map and start.may_start()
    unreadable = StartConditions('/map', lambda: 1, warn=print)
    unreadable.discovered()
    unreadable.map_unreadable()
    assert unreadable.may_start()
    unpublished = StartConditions('/map', lambda: 0, warn=print)
    unpublished.discovered()
    assert unpublished.may_start()

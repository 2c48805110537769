"""Stall detection."""

from waypoint_lab.lifecycle import StallDetector


def test_stall_is_reported_after_the_timeout_without_progress():
    detector = StallDetector(timeout=2.0)
    assert not detector.stalled(0.0, 3.0, 0.5)
    assert not detector.stalled(1.9, 3.0, 0.5)
    assert detector.stalled(2.1, 3.0, 0.5)


def test_progress_in_distance_or_heading_resets_the_clock():
    detector = StallDetector(timeout=2.0)
    detector.stalled(0.0, 3.0, 0.5)
    assert not detector.stalled(1.5, 2.9, 0.5)
    assert not detector.stalled(3.0, 2.9, 0.4)
    assert not detector.stalled(4.9, 2.9, 0.4)
    assert detector.stalled(5.1, 2.9, 0.4)


def test_creeping_below_the_margin_is_a_stall():
    detector = StallDetector(timeout=1.0)
    for step in range(30):
        stalled = detector.stalled(step * 0.1, 1.0 - step * 1e-4, 0.3)
    assert stalled


def test_restart_watches_a_new_waypoint_afresh():
    detector = StallDetector(timeout=1.0)
    detector.stalled(0.0, 1.0, 0.1)
    detector.restart(5.0)
    assert not detector.stalled(5.5, 9.0, 3.0)

"""Stall detection."""

from waypoint_controller.progress import ProgressMonitor


def test_stall_is_reported_after_the_timeout_without_progress():
    monitor = ProgressMonitor(timeout=2.0)
    assert not monitor.stalled(0.0, 3.0, 0.5)
    assert not monitor.stalled(1.9, 3.0, 0.5)
    assert monitor.stalled(2.1, 3.0, 0.5)


def test_progress_in_distance_or_heading_resets_the_clock():
    monitor = ProgressMonitor(timeout=2.0)
    monitor.stalled(0.0, 3.0, 0.5)
    assert not monitor.stalled(1.5, 2.9, 0.5)
    assert not monitor.stalled(3.0, 2.9, 0.4)
    assert not monitor.stalled(4.9, 2.9, 0.4)
    assert monitor.stalled(5.1, 2.9, 0.4)


def test_creeping_below_the_margin_is_a_stall():
    monitor = ProgressMonitor(timeout=1.0)
    for step in range(30):
        stalled = monitor.stalled(step * 0.1, 1.0 - step * 1e-4, 0.3)
    assert stalled


def test_restart_watches_a_new_waypoint_afresh():
    monitor = ProgressMonitor(timeout=1.0)
    monitor.stalled(0.0, 1.0, 0.1)
    monitor.restart(5.0)
    assert not monitor.stalled(5.5, 9.0, 3.0)

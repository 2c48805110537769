"""The simulator's pace warning: measured between checks, never over the node's own start."""

from types import SimpleNamespace

from stdr_lite.node import health
from stdr_lite.node.health import HealthWatch


class FakeNode:
    """What HealthWatch uses of a node: a timer, a logger, the graph."""

    def __init__(self):
        self.warnings = []
        self.logger = SimpleNamespace(warn=lambda text, **_: self.warnings.append(text))

    def create_timer(self, *args, **kwargs):
        return None

    def get_logger(self):
        return self.logger


def test_the_start_is_not_taken_for_falling_behind(monkeypatch):
    now = [100.0]
    monkeypatch.setattr(health.time, 'monotonic', lambda: now[0])
    simulation = SimpleNamespace(sim_time=0.0, names=['robot0'])
    node = FakeNode()
    watch = HealthWatch(node, simulation, {}, 1.0, lambda: True)
    now[0] += 5.0                      # a slow start: 5 s built, nothing stepped yet
    watch.check()
    assert node.warnings == []
    now[0] += 1.0
    simulation.sim_time = 0.5          # then half pace: that is behind
    watch.check()
    assert len(node.warnings) == 1 and 'running at 0.50x real time' in node.warnings[0]

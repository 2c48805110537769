"""
What the simulation services act on, handed to them by the stdr_lite node.

The services (control_services.py, entity_services.py) receive the simulation, its stepper,
the frames and the node's few world-changing steps here, rather than reaching back into the
node for them; the node itself they use only to serve requests, log and read the graph.
"""

from collections.abc import Callable, Iterator
from dataclasses import dataclass

from stdr_lite.core.simulation import Simulation
from stdr_lite.node.parameters import Frames
from stdr_lite.node.stepper import Stepper


@dataclass(frozen=True)
class Served:
    """
    The simulation and the node's steps a service may take.

    refresh_topics and restart are generators, run within a request's job: refresh_topics
    makes the topics, frames and markers follow the entities; restart does that after a reset
    or a new world (new_time: the clock went back to 0; grid: a new map message).
    """

    simulation: Simulation
    stepper: Stepper
    frames: Frames
    search_path: tuple
    refresh_topics: Callable[[], Iterator]
    restart: Callable[..., Iterator]
    show_state: Callable[[], None]
    note_description: Callable[[str, object], None]
    quit_soon: Callable[[], None]

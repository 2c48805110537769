"""A map and what the simulation derives from it: made once per map, off the loop if need be."""

from dataclasses import dataclass

from simple_robot_control.occupancy_map import OccupancyMap
from stdr_lite.core.collision import FootprintChecker, wall_distances
from stdr_lite.core.sensors import RangeFinder


@dataclass(frozen=True)
class Terrain:
    """
    A map with its footprint checker and range finder.

    Their distance transform is the costly part of a world (seconds for 16 M cells), so it is
    computed once per map, shared by both, and can be computed away from the simulation loop:
    survey() touches nothing of a running simulation.
    """

    occupancy_map: OccupancyMap
    checker: FootprintChecker
    finder: RangeFinder


def survey(occupancy_map: OccupancyMap, max_radius: float) -> Terrain:
    """Derive a Terrain from a map, for robots and obstacles up to max_radius."""
    distances = wall_distances(occupancy_map.occupied)
    return Terrain(occupancy_map, FootprintChecker(occupancy_map, max_radius, distances),
                   RangeFinder(occupancy_map, distances))

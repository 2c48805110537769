"""
Draw the courseworks' maps (maps/factory, maps/simple_walls, maps/plus_room) from their plans.

Each map is written in map_server's format: a PGM image (black walls, white floor, 5 cm cells)
and its YAML. The plans below are the maps' one source: test/unit/test_coursework_maps.py
draws them again and checks the bundled files match, so change a plan here, run
`python scripts/make_coursework_maps.py`, and commit both.
"""

import argparse
from pathlib import Path

import numpy as np
from PIL import Image

RESOLUTION = 0.05
WALL = 0.3

# Each plan: the map's size in metres, and its walls as rectangles (x0, y0, x1, y1) in metres.
# A factory floor: a corridor across the middle, three rooms below and four above, each with
# a door onto the corridor but the last room above (a store room no robot can reach), and
# machines standing in the rooms.
FACTORY = ((24.0, 16.0), (
    # The corridor's walls (y 6.5 and 9.5), with 1.4 m doors.
    (0.0, 6.5, 3.3, 6.5 + WALL), (4.7, 6.5, 11.3, 6.5 + WALL), (12.7, 6.5, 19.3, 6.5 + WALL),
    (20.7, 6.5, 24.0, 6.5 + WALL),
    (0.0, 9.5 - WALL, 2.3, 9.5), (3.7, 9.5 - WALL, 8.3, 9.5), (9.7, 9.5 - WALL, 14.3, 9.5),
    (15.7, 9.5 - WALL, 24.0, 9.5),
    # The rooms' walls.
    (8.0, 0.0, 8.0 + WALL, 6.5), (16.0, 0.0, 16.0 + WALL, 6.5),
    (6.0, 9.5, 6.0 + WALL, 16.0), (12.0, 9.5, 12.0 + WALL, 16.0), (18.0, 9.5, 18.0 + WALL, 16.0),
    # Machines.
    (2.0, 2.0, 4.0, 3.0), (5.0, 1.0, 6.0, 4.0), (10.0, 2.5, 14.0, 3.5), (19.0, 1.5, 20.5, 3.0),
    (21.5, 3.5, 23.0, 5.0), (2.0, 12.0, 3.5, 13.5), (8.0, 11.5, 10.0, 12.5),
    (14.0, 12.5, 15.0, 15.0), (20.0, 11.0, 22.0, 14.0),
))
# An open room with four free-standing walls, one a dead end the robot must back out of.
SIMPLE_WALLS = ((16.0, 12.0), (
    (4.0, 0.0, 4.0 + WALL, 7.0), (8.0, 5.0, 8.0 + WALL, 12.0), (11.0, 3.0, 16.0, 3.0 + WALL),
    (11.0, 3.0, 11.0 + WALL, 8.0),
))
# A plus-shaped room: four arms 5 m wide meeting in a square with a pillar in its middle.
PLUS_ROOM = ((15.0, 15.0), (
    (0.0, 0.0, 5.0, 5.0), (10.0, 0.0, 15.0, 5.0), (0.0, 10.0, 5.0, 15.0),
    (10.0, 10.0, 15.0, 15.0),
    (7.0, 7.0, 8.0, 8.0),
))
PLANS = {'factory': FACTORY, 'simple_walls': SIMPLE_WALLS, 'plus_room': PLUS_ROOM}

_YAML = """# {name}: drawn by scripts/make_coursework_maps.py from its plan
# ({width:g} m x {height:g} m, {columns} x {rows} cells of {resolution:g} m, walls {wall:g} m).
image: {name}.pgm
mode: trinary
resolution: {resolution}
origin: [0.0, 0.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.25
"""


def draw(plan: tuple) -> np.ndarray:
    """Return the plan's image: uint8 rows top first, 0 for walls, 254 for floor."""
    (width, height), walls = plan
    columns, rows = round(width / RESOLUTION), round(height / RESOLUTION)
    floor = np.ones((rows, columns), dtype=bool)
    border = round(WALL / RESOLUTION)
    floor[:border, :] = floor[-border:, :] = False
    floor[:, :border] = floor[:, -border:] = False
    for x0, y0, x1, y1 in walls:
        # Row 0 of the grid is y = 0, the image's bottom row.
        floor[round(y0 / RESOLUTION):round(y1 / RESOLUTION),
              round(x0 / RESOLUTION):round(x1 / RESOLUTION)] = False
    return np.where(np.flipud(floor), 254, 0).astype(np.uint8)


def write(name: str, folder: Path) -> None:
    """Write name's PGM and YAML into folder."""
    plan = PLANS[name]
    image = draw(plan)
    Image.fromarray(image).save(folder / f'{name}.pgm')
    (width, height), _ = plan
    (folder / f'{name}.yaml').write_text(_YAML.format(
        name=name, width=width, height=height, columns=image.shape[1], rows=image.shape[0],
        resolution=RESOLUTION, wall=WALL), encoding='utf-8')


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--folder', type=Path, default=Path(__file__).parents[1] / 'maps')
    arguments = parser.parse_args()
    for name in PLANS:
        write(name, arguments.folder)
        print(f'wrote {arguments.folder / name}.pgm and .yaml')


if __name__ == '__main__':
    main()

"""
A coursework's cells as its judge read them, drawn as task.png beside a course's run.png.

For mapping, each of the world's cells coloured by the judge's reading of the submission's last
map (agreed, false wall, missed wall, known beyond sight, ...); for exploration, the reachable
free space seen along the true path and the part never seen; the true path over either; a
mapping submission's map, as published, beside its reading. Like run_picture.py,
matplotlib's object API on the Agg canvas, imported only to draw. No ROS here.
"""

import os

from lab_grader.task_checks import TaskPicture
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch
import numpy as np
from waypoint_lab.run_picture import draw_map

FIGURE_SIZE = (10.0, 7.5)
DPI = 100


def render_task_picture(picture: TaskPicture, path_xy: np.ndarray,
                        output_path: str | os.PathLike) -> None:
    """Write a PNG of the judge's reading of each cell, the true path (x, y rows) over it."""
    submitted = picture.submitted
    figure = Figure(figsize=(FIGURE_SIZE[0] * (1.6 if submitted else 1.0), FIGURE_SIZE[1]),
                    dpi=DPI, layout='constrained')
    FigureCanvasAgg(figure)
    if submitted is not None:
        shown, axes = figure.subplots(1, 2, gridspec_kw={'width_ratios': (1, 1.6)})
        draw_map(shown, submitted)
        shown.set_aspect('equal')
        shown.set_title(f'as published: {submitted.width}x{submitted.height} cells of '
                        f'{submitted.resolution:g} m')
        shown.set_xlabel('x [m]')
        shown.set_ylabel('y [m]')
    else:
        axes = figure.subplots()
    codes = [code for code, _, _ in picture.meanings]
    colours = ListedColormap([colour for _, _, colour in picture.meanings])
    index = np.searchsorted(codes, picture.codes)
    world = picture.world
    width, height = world.extent
    left, bottom = world.origin[:2]
    axes.imshow(index, cmap=colours, vmin=0, vmax=len(codes) - 1, origin='lower',
                interpolation='nearest', extent=(left, left + width, bottom, bottom + height))
    walls = np.ma.masked_where(~world.occupied, np.ones(world.cells.shape))
    axes.imshow(walls, cmap=ListedColormap(['black']), origin='lower', alpha=0.35,
                interpolation='nearest', extent=(left, left + width, bottom, bottom + height))
    if len(path_xy):
        axes.plot(path_xy[:, 0], path_xy[:, 1], color='black', linewidth=1.0,
                  label='true path')
    counts = {code: int(np.count_nonzero(picture.codes == code)) for code in codes}
    handles = [Patch(color=colour, label=f'{label} ({counts[code]:,} cells)')
               for code, label, colour in picture.meanings if counts[code]]
    axes.legend(handles=handles + ([axes.lines[0]] if axes.lines else []), loc='upper right',
                fontsize='small')
    axes.set_aspect('equal')
    axes.set_xlabel('x [m]')
    axes.set_ylabel('y [m]')
    axes.set_title(picture.title)
    figure.savefig(output_path, dpi=DPI, format='png')

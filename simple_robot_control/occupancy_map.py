"""Maps in the standard map_server format: a YAML file naming an image and its geometry."""

import array
from dataclasses import dataclass
import os

import numpy as np
from PIL import Image
from simple_robot_control.input_files import check_file, read_yaml
from simple_robot_control.pose import yaw_from_quaternion
from simple_robot_control.validation import Bounds, describe, is_finite_number

OCCUPIED = 100
FREE = 0
UNKNOWN = -1

# A map is held as several arrays of its cells (occupancy, clearance, masks): 16 M cells, such as
# 4096 x 4096 or 200 m x 200 m at 5 cm, keep them within a few hundred megabytes.
MAX_CELLS = 1 << 24
MAX_IMAGE_BYTES = 256 << 20
RESOLUTION = Bounds(0.001, 100.0)

_DEFAULTS = {'mode': 'trinary', 'negate': 0, 'occupied_thresh': 0.65, 'free_thresh': 0.25}
_REQUIRED = ('image', 'resolution', 'origin')
_MODES = ('trinary', 'scale', 'raw')


class MapError(ValueError):
    """A map that cannot be loaded; the message is one line naming the file and the problem."""


class MapImageError(MapError):
    """A map whose image is missing, unreadable or empty."""


class MapTooLargeError(MapImageError):
    """A map whose image holds more cells than the simulator takes."""


@dataclass(frozen=True)
class OccupancyMap:
    """An occupancy grid: row 0 is the bottom of the image, as in nav_msgs/OccupancyGrid."""

    cells: np.ndarray
    resolution: float
    origin: tuple
    source: str = ''

    @property
    def occupied(self):
        """Cells a robot may not touch."""
        return self.cells == OCCUPIED

    @property
    def height(self):
        return self.cells.shape[0]

    @property
    def width(self):
        return self.cells.shape[1]

    @property
    def extent(self):
        """Return the map's (width, height) in metres."""
        return self.width * self.resolution, self.height * self.resolution

    @classmethod
    def from_grid_message(cls, message, source='/map') -> 'OccupancyMap':
        """
        Read a nav_msgs/OccupancyGrid (duck-typed: no ROS import here).

        A grid from another node is input like a file: one whose size, resolution or origin
        makes no map raises MapError saying why.
        """
        info = message.info
        width, height = info.width, info.height
        if not 0 < width * height <= MAX_CELLS:
            raise MapError(f'{source}: a grid of {width}x{height} cells (at most {MAX_CELLS:,}, '
                           'none empty)')
        if len(message.data) != width * height:
            raise MapError(f'{source}: {width}x{height} cells, but {len(message.data):,} values')
        problem = RESOLUTION.problem('resolution', info.resolution)
        if problem is not None:
            raise MapError(f'{source}: {problem} (metres per cell)')
        origin = info.origin
        corner = (origin.position.x, origin.position.y, yaw_from_quaternion(origin.orientation))
        if not all(map(is_finite_number, corner)):
            raise MapError(f'{source}: the origin is not finite')
        data = message.data
        cells = (np.frombuffer(data, dtype=np.int8) if isinstance(data, array.array)
                 else np.asarray(data, dtype=np.int8))
        return cls(cells.reshape(height, width), float(info.resolution), corner, source)


def load_map(yaml_path):
    """Load a map_server YAML file and its image; raise MapError on any problem."""
    yaml_path = os.fspath(yaml_path)
    description = read_yaml(yaml_path, 'map file', MapError)
    if not isinstance(description, dict):
        raise MapError(f'{yaml_path}: expected a mapping of map fields, got '
                       f'{describe(description)}')
    fields = _validated_fields(yaml_path, description)
    image_path = fields['image']
    if not os.path.isabs(image_path):
        image_path = os.path.join(os.path.dirname(yaml_path), image_path)
    channel_sums, alpha = _read_image(image_path)
    # A pixel's grey level is the mean of its three colour channels: a table of the cell for
    # each of the 766 possible sums decides every pixel by the same arithmetic, at a byte each.
    by_sum = image_to_cells(np.arange(3 * 255 + 1) / 3.0, None, fields)
    cells = by_sum[channel_sums]
    if alpha is not None and fields['mode'] != 'raw':
        cells[alpha < 255] = UNKNOWN
    return OccupancyMap(cells=np.ascontiguousarray(np.flipud(cells)),
                        resolution=fields['resolution'], origin=fields['origin'],
                        source=yaml_path)


def image_to_cells(pixels, alpha, fields):
    """Convert grey levels (0..255, any shape) to occupancy values as map_server does."""
    shade = pixels / 255.0
    occupancy = shade if fields['negate'] else 1.0 - shade
    occupied_thresh = fields['occupied_thresh']
    free_thresh = fields['free_thresh']
    if fields['mode'] == 'raw':
        cells = np.where(pixels <= OCCUPIED, pixels, UNKNOWN)
    else:
        cells = np.full(pixels.shape, UNKNOWN)
        if fields['mode'] == 'scale':
            fraction = (occupancy - free_thresh) / (occupied_thresh - free_thresh)
            cells = np.rint(99.0 * fraction).astype(int)
        cells = np.where(occupancy > occupied_thresh, OCCUPIED, cells)
        cells = np.where(occupancy < free_thresh, FREE, cells)
        if alpha is not None:
            cells = np.where(alpha < 255, UNKNOWN, cells)
    return cells.astype(np.int8)


def _validated_fields(yaml_path, description):
    unknown = sorted(set(description) - set(_REQUIRED) - set(_DEFAULTS))
    if unknown:
        allowed = ', '.join(_REQUIRED + tuple(_DEFAULTS))
        raise MapError(f'{yaml_path}: unknown field {describe(unknown[0])} (allowed: {allowed})')
    missing = [key for key in _REQUIRED if key not in description]
    if missing:
        raise MapError(f'{yaml_path}: missing required field {missing[0]!r}')
    fields = dict(_DEFAULTS, **description)
    if not isinstance(fields['image'], str) or not fields['image']:
        raise MapError(f'{yaml_path}: image must be a file name, got {describe(fields["image"])}')
    fields['resolution'] = _number(yaml_path, 'resolution', fields['resolution'])
    problem = RESOLUTION.problem('resolution', fields['resolution'])
    if problem is not None:
        raise MapError(f'{yaml_path}: {problem} (metres per cell)')
    origin = fields['origin']
    if not isinstance(origin, list) or len(origin) != 3:
        raise MapError(f'{yaml_path}: origin must be [x, y, yaw], got {describe(origin)}')
    fields['origin'] = tuple(_number(yaml_path, 'origin', value) for value in origin)
    if fields['negate'] not in (0, 1) or isinstance(fields['negate'], float):
        raise MapError(f'{yaml_path}: negate must be 0 or 1, got {describe(fields["negate"])}')
    for key in ('occupied_thresh', 'free_thresh'):
        fields[key] = _number(yaml_path, key, fields[key])
        if not 0.0 <= fields[key] <= 1.0:
            raise MapError(f'{yaml_path}: {key} must lie in [0, 1], got {fields[key]}')
    if fields['free_thresh'] >= fields['occupied_thresh']:
        raise MapError(f'{yaml_path}: free_thresh {fields["free_thresh"]} must be below '
                       f'occupied_thresh {fields["occupied_thresh"]}')
    if fields['mode'] not in _MODES:
        raise MapError(f'{yaml_path}: mode must be one of {", ".join(_MODES)}, '
                       f'got {describe(fields["mode"])}')
    return fields


def _number(yaml_path, key, value):
    if not is_finite_number(value):
        raise MapError(f'{yaml_path}: {key} must be a finite number, got {describe(value)}')
    return float(value)


def _read_image(image_path):
    """
    Return the sum of the three colour channels of every pixel, and the alpha channel if any.

    The image's size is read from its header and judged before any pixel is decoded, so a
    compressed file that would unpack to gigabytes is refused in a moment; pixels stay bytes,
    so a map of 16 M cells is read in well under a gigabyte.
    """
    check_file(image_path, 'map image', MapImageError, MAX_IMAGE_BYTES)
    too_large = f'(at most {MAX_CELLS:,} cells, e.g. 4096x4096)'
    try:
        with Image.open(image_path) as image:
            width, height = image.size
            if width * height > MAX_CELLS:
                raise MapTooLargeError(f'{image_path}: map image of {width}x{height} pixels is '
                                       f'too large {too_large}')
            image.load()
            has_alpha = image.mode in ('RGBA', 'LA', 'PA') or 'transparency' in image.info
            if image.mode == 'L':
                channel_sums = 3 * np.asarray(image, dtype=np.uint16)
                alpha = None
            else:
                rgba = np.asarray(image.convert('RGBA'))
                channel_sums = rgba[..., :3].sum(axis=2, dtype=np.uint16)
                alpha = rgba[..., 3] if has_alpha else None
    except MapTooLargeError:
        raise
    except Image.DecompressionBombError:
        raise MapTooLargeError(f'{image_path}: map image is too large {too_large}') from None
    except (OSError, SyntaxError, ValueError) as error:
        raise MapImageError(f'{image_path}: cannot read map image: {error}') from None
    if channel_sums.size == 0:
        raise MapImageError(f'{image_path}: map image is empty')
    return channel_sums, alpha

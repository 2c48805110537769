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
    def occupied(self) -> np.ndarray:
        """Cells a robot may not touch."""
        return self.cells == OCCUPIED

    @property
    def height(self) -> int:
        return self.cells.shape[0]

    @property
    def width(self) -> int:
        return self.cells.shape[1]

    @property
    def extent(self) -> tuple[float, float]:
        """Return the map's (width, height) in metres."""
        return self.width * self.resolution, self.height * self.resolution

    @classmethod
    def from_grid_message(cls, message: object, source: str = '/map') -> 'OccupancyMap':
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


def load_map(yaml_path: str | os.PathLike) -> OccupancyMap:
    """Load a map_server YAML file and its image as ROS 1 map_server does; MapError if not."""
    yaml_path = os.fspath(yaml_path)
    description = read_yaml(yaml_path, 'map file', MapError)
    if not isinstance(description, dict):
        raise MapError(f'{yaml_path}: expected a mapping of map fields, got '
                       f'{describe(description)}')
    fields = _validated_fields(yaml_path, description)
    image_path = fields['image']
    if not os.path.isabs(image_path):
        image_path = os.path.join(os.path.dirname(yaml_path), image_path)
    pixels = _read_image(image_path)
    return OccupancyMap(cells=np.ascontiguousarray(np.flipud(pixels_to_cells(pixels, fields))),
                        resolution=fields['resolution'], origin=fields['origin'],
                        source=yaml_path)


def pixels_to_cells(pixels: np.ndarray, fields: dict) -> np.ndarray:
    """
    Return the cells of an image's pixels (rows, columns, channels as map_server got them).

    ROS 1 map_server's rules (image_loader.cpp), which STDR's maps were made for, to the cell:
    a pixel's level is the mean of its channels: all of them for one or three channels, and for
    four (with alpha) in trinary mode; the colour channels alone for four in scale and raw.
    Negated, the level is 255 minus that. Raw: the cell is the level, cut to a whole number and
    stored as a signed byte. Otherwise occupancy is (255 - level) / 255; above occupied_thresh
    the cell is occupied, else below free_thresh free (so thresholds the wrong way round, such
    as 0.0 and 1.0, read white as free and any other pixel as occupied), else unknown in trinary
    mode or where the pixel's last channel is 0 (its alpha, or the blue of a colour image: the
    loader reads the last channel whatever it is), else 1 + 98 * (occupancy - free_thresh) /
    (occupied_thresh - free_thresh), cut to a whole number. The mean of at most four channels
    is one of 1021 sums: a table of the cell for each decides every pixel at a byte each.
    """
    channels = pixels.shape[2]
    averaged = channels if fields['mode'] == 'trinary' or channels != 4 else 3
    sums = pixels[..., :averaged].sum(axis=2, dtype=np.uint16)
    level = np.arange(255 * averaged + 1) / averaged
    if fields['negate']:
        level = 255.0 - level
    if fields['mode'] == 'raw':
        return level.astype(np.uint8).view(np.int8)[sums]
    occupancy = (255.0 - level) / 255.0
    occupied, free = fields['occupied_thresh'], fields['free_thresh']
    between = np.full(level.shape, UNKNOWN, dtype=np.int8)
    if fields['mode'] == 'scale':
        with np.errstate(divide='ignore', invalid='ignore'):
            graded = 1.0 + 98.0 * (occupancy - free) / (occupied - free)
        between = np.where(np.isfinite(graded), np.clip(graded, 0, 255), 0).astype(
            np.uint8).view(np.int8)

    def decided(otherwise):
        return np.where(occupancy > occupied, np.int8(OCCUPIED),
                        np.where(occupancy < free, np.int8(FREE), otherwise)).astype(np.int8)
    cells = decided(between)[sums]
    if fields['mode'] == 'scale' and channels > 1:
        transparent = pixels[..., -1] == 0
        cells[transparent] = decided(np.int8(UNKNOWN))[sums[transparent]]
    return cells


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
    # Any finite thresholds, in any order, as map_server takes them (pixels_to_cells).
    for key in ('occupied_thresh', 'free_thresh'):
        fields[key] = _number(yaml_path, key, fields[key])
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
    Return the image's pixels as map_server's loader (SDL_image) hands them over: channels last.

    One channel for a grey image (16-bit greys cut to their high byte, as the loader does) and
    for a palette image (its indices, as the loader gives them); three for colour; four for
    colour with alpha, and for grey with alpha (the grey in three). The image's size is read
    from its header and judged before any pixel is decoded, so a compressed file that would
    unpack to gigabytes is refused in a moment; pixels stay bytes.
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
            if image.mode in ('L', 'P'):
                pixels = np.asarray(image, dtype=np.uint8)[..., np.newaxis]
            elif image.mode in ('I;16', 'I;16B', 'I;16L', 'I'):
                pixels = (np.asarray(image).astype(np.uint32) >> 8).astype(np.uint8)[
                    ..., np.newaxis]
            elif image.mode in ('RGBA', 'LA', 'PA'):
                pixels = np.asarray(image.convert('RGBA'), dtype=np.uint8)
            else:
                pixels = np.asarray(image.convert('RGB'), dtype=np.uint8)
    except MapTooLargeError:
        raise
    except Image.DecompressionBombError:
        raise MapTooLargeError(f'{image_path}: map image is too large {too_large}') from None
    except (OSError, SyntaxError, ValueError) as error:
        raise MapImageError(f'{image_path}: cannot read map image: {error}') from None
    if pixels.size == 0:
        raise MapImageError(f'{image_path}: map image is empty')
    return pixels

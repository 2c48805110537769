"""Helpers that write small map_server maps for tests."""

import struct
import zlib

import numpy as np
from PIL import Image
import yaml


def write_map(directory, pixels, name='world', image_format='pgm', **fields):
    """Write pixels (grey levels or RGBA, image row order) and a YAML file; return its path."""
    pixels = np.asarray(pixels, dtype=np.uint8)
    image_name = f'{name}.{image_format}'
    Image.fromarray(pixels).save(directory / image_name)
    description = {'image': image_name, 'resolution': 0.05, 'origin': [0.0, 0.0, 0.0],
                   'negate': 0, 'occupied_thresh': 0.65, 'free_thresh': 0.25}
    description.update(fields)
    yaml_path = directory / f'{name}.yaml'
    yaml_path.write_text(yaml.safe_dump(description))
    return yaml_path


def walled_room(width_cells, height_cells, wall_cells=1):
    """Grey levels of an empty room: black border, white inside."""
    pixels = np.full((height_cells, width_cells), 255, dtype=np.uint8)
    pixels[:wall_cells, :] = 0
    pixels[-wall_cells:, :] = 0
    pixels[:, :wall_cells] = 0
    pixels[:, -wall_cells:] = 0
    return pixels


def png_header(width, height):
    """Return a PNG that declares a size in its header but holds no pixels."""
    def chunk(kind, data):
        return (struct.pack('>I', len(data)) + kind + data
                + struct.pack('>I', zlib.crc32(kind + data)))
    header = struct.pack('>IIBBBBB', width, height, 8, 0, 0, 0, 0)
    return b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', header) + chunk(b'IEND', b'')

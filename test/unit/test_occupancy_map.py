"""Loading map_server maps: every YAML field, and a clear error for each kind of bad file."""

from map_fixtures import png_header, walled_room, write_map
import numpy as np
from PIL import Image
import pytest
from simple_robot_control.occupancy_map import FREE, load_map, MapError, OCCUPIED, UNKNOWN
from simple_robot_control.share import shared_file


def test_geometry_fields_are_read(tmp_path):
    occupancy_map = load_map(write_map(tmp_path, walled_room(6, 4), resolution=0.25,
                                       origin=[-1.5, 2.0, 0.3]))
    assert occupancy_map.resolution == 0.25
    assert occupancy_map.origin == (-1.5, 2.0, 0.3)
    assert (occupancy_map.height, occupancy_map.width) == (4, 6)


def test_image_top_row_becomes_the_last_grid_row(tmp_path):
    pixels = np.full((3, 4), 255)
    pixels[0, 1] = 0
    cells = load_map(write_map(tmp_path, pixels)).cells
    assert cells[2, 1] == OCCUPIED
    assert np.count_nonzero(cells == OCCUPIED) == 1


@pytest.mark.parametrize('negate, black, white', [(0, OCCUPIED, FREE), (1, FREE, OCCUPIED)])
def test_negate_swaps_black_and_white(tmp_path, negate, black, white):
    cells = load_map(write_map(tmp_path, [[0, 255]], negate=negate)).cells
    assert cells.tolist() == [[black, white]]


def ros1_cell(channels, mode, negate, occupied_thresh, free_thresh):
    """
    Return the cell ROS 1 map_server makes of one pixel (its channels as SDL_image gives them).

    The rules of map_server/src/image_loader.cpp (noetic-devel), one pixel at a time, as
    plainly as they read there: the judge of load_map's vectorised reading.
    """
    count = len(channels)
    averaged = count if mode == 'trinary' or count != 4 else count - 1
    level = sum(channels[:averaged]) / averaged
    alpha = 1 if count == 1 else channels[-1]
    if negate:
        level = 255 - level
    if mode == 'raw':
        return np.array(int(level), dtype=np.uint8).view(np.int8).item()
    occupancy = (255 - level) / 255.0
    if occupancy > occupied_thresh:
        return 100
    if occupancy < free_thresh:
        return 0
    if mode == 'trinary' or alpha < 1.0:
        return -1
    ratio = (occupancy - free_thresh) / (occupied_thresh - free_thresh)
    return int(1 + 98 * ratio)


def crafted_images():
    """Images of every grey, colours (blue 0 among them), greys and colours with alpha."""
    rng = np.random.default_rng(7)
    grey = np.arange(256, dtype=np.uint8).reshape(16, 16)
    edge = np.full((16, 16), 255, dtype=np.uint8)
    edge[4:12, 4:12] = 0
    edge[3, 3:13] = 128  # an anti-aliased edge
    edge[12, 3:13] = 254
    colour = rng.integers(0, 256, (16, 16, 3), dtype=np.uint8)
    colour[0, :, 2] = 0
    colour_alpha = rng.integers(0, 256, (16, 16, 4), dtype=np.uint8)
    colour_alpha[:4, :, 3] = 0
    colour_alpha[4:8, :, 3] = 255
    grey_alpha = np.stack([grey, rng.integers(0, 256, (16, 16), dtype=np.uint8)], axis=2)
    grey_alpha[:, :3, 1] = 0
    return {'grey.pgm': grey, 'edge.png': edge, 'colour.png': colour,
            'colour_alpha.png': colour_alpha, 'grey_alpha.png': grey_alpha}


def as_sdl_gives(pixels):
    """Return the channels map_server's loader hands over: grey with alpha as colour with it."""
    pixels = np.asarray(pixels)
    if pixels.ndim == 2:
        return pixels[..., np.newaxis]
    if pixels.shape[2] == 2:
        return np.concatenate([np.repeat(pixels[..., :1], 3, axis=2), pixels[..., 1:]], axis=2)
    return pixels


@pytest.mark.parametrize('mode', ['trinary', 'scale', 'raw'])
@pytest.mark.parametrize('negate', [0, 1])
@pytest.mark.parametrize('occupied_thresh, free_thresh', [
    (0.65, 0.25), (0.0, 1.0), (0.001, 0.0005), (0.5, 0.5), (0.9, 0.1)])
def test_every_pixel_reads_as_ros1_map_server_reads_it(tmp_path, mode, negate, occupied_thresh,
                                                       free_thresh):
    for name, pixels in crafted_images().items():
        stem, image_format = name.split('.')
        cells = load_map(write_map(tmp_path, pixels, name=stem, image_format=image_format,
                                   mode=mode, negate=negate, occupied_thresh=occupied_thresh,
                                   free_thresh=free_thresh)).cells
        channels = as_sdl_gives(pixels)
        expected = [[ros1_cell(tuple(int(value) for value in channels[row, column]), mode,
                               negate, occupied_thresh, free_thresh)
                     for column in range(channels.shape[1])]
                    for row in reversed(range(channels.shape[0]))]
        assert cells.tolist() == expected, (name, mode, negate)


def test_thresholds_the_wrong_way_round_read_white_as_free_and_all_else_occupied(tmp_path):
    """A course's maps say occupied_thresh 0.0, free_thresh 1.0: ROS 1 loads them so."""
    cells = load_map(write_map(tmp_path, [[255, 254, 128, 0]], occupied_thresh=0.0,
                               free_thresh=1.0)).cells
    assert cells.tolist() == [[FREE, OCCUPIED, OCCUPIED, OCCUPIED]]


def test_sixteen_bit_greys_are_read_by_their_high_byte(tmp_path):
    pixels = np.array([[0, 0x7FFF, 0xFFFF]], dtype=np.uint16)
    Image.fromarray(pixels).save(tmp_path / 'deep.png')
    (tmp_path / 'deep.yaml').write_text('image: deep.png\nresolution: 0.05\n'
                                        'origin: [0, 0, 0]\n')
    assert load_map(tmp_path / 'deep.yaml').cells.tolist() == [[OCCUPIED, UNKNOWN, FREE]]


def test_scale_mode_grades_the_unknown_band(tmp_path):
    cells = load_map(write_map(tmp_path, [[0, 114, 255]], mode='scale')).cells
    occupancy = 1.0 - 114 / 255.0
    assert cells.tolist() == [[OCCUPIED, int(1 + 98 * (occupancy - 0.25) / 0.4), FREE]]


def test_bundled_lab_room_is_a_walled_20_by_15_metre_room():
    occupancy_map = load_map(shared_file('maps', 'lab_room.yaml'))
    assert (occupancy_map.width * occupancy_map.resolution,
            occupancy_map.height * occupancy_map.resolution) == pytest.approx((20.0, 15.0))
    occupied = occupancy_map.occupied
    assert occupied[:, :7].all() and occupied[:7, :].all()
    assert not occupied[7:-7, 7:-7].any()


BAD_YAML = {
    'not_yaml': ('image: [unclosed', 'map file is not valid YAML'),
    'not_a_mapping': ('- just\n- a list\n', 'expected a mapping'),
    'missing_field': ('image: x.pgm\nresolution: 0.05\n', "missing required field 'origin'"),
    'unknown_field': ('image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nocupied_thresh: 1\n',
                      "unknown field 'ocupied_thresh'"),
    'zero_resolution': ('image: x.pgm\nresolution: 0\norigin: [0, 0, 0]\n',
                        'resolution must be in [0.001, 100], got 0 (metres per cell)'),
    'text_resolution': ('image: x.pgm\nresolution: fine\norigin: [0, 0, 0]\n',
                        "resolution must be a finite number, got 'fine'"),
    'short_origin': ('image: x.pgm\nresolution: 0.05\norigin: [0, 0]\n',
                     'origin must be [x, y, yaw]'),
    'nan_origin': ('image: x.pgm\nresolution: 0.05\norigin: [0, .nan, 0]\n',
                   'origin must be a finite number'),
    'bad_negate': ('image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 2\n',
                   'negate must be 0 or 1'),
    'threshold_text': ('image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n'
                       'occupied_thresh: high\n', 'occupied_thresh must be a finite number'),
    'bad_mode': ('image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nmode: fancy\n',
                 'mode must be one of trinary, scale, raw'),
    'missing_image': ('image: nowhere.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n',
                      'nowhere.pgm: cannot read map image: No such file or directory'),
}


@pytest.mark.parametrize('case', sorted(BAD_YAML))
def test_bad_map_files_raise_one_line_errors_naming_the_file(tmp_path, case):
    text, expected = BAD_YAML[case]
    yaml_path = tmp_path / f'{case}.yaml'
    yaml_path.write_text(text)
    with pytest.raises(MapError) as raised:
        load_map(yaml_path)
    message = str(raised.value)
    assert expected in message
    assert str(tmp_path) in message
    assert '\n' not in message


def test_missing_yaml_file_is_named(tmp_path):
    with pytest.raises(MapError, match='nothing.yaml: cannot read map file'):
        load_map(tmp_path / 'nothing.yaml')


@pytest.mark.parametrize('side', [5000, 14000])
def test_a_decompression_bomb_is_refused_from_its_header(tmp_path, side):
    (tmp_path / 'huge.png').write_bytes(png_header(side, side))
    yaml_path = tmp_path / 'huge.yaml'
    yaml_path.write_text('image: huge.png\nresolution: 0.05\norigin: [0, 0, 0]\n')
    with pytest.raises(MapError, match='huge.png: map image .*is too large'):
        load_map(yaml_path)


def test_a_device_is_no_map_image(tmp_path):
    yaml_path = tmp_path / 'zero.yaml'
    yaml_path.write_text('image: /dev/zero\nresolution: 0.05\norigin: [0, 0, 0]\n')
    with pytest.raises(MapError, match='^/dev/zero: map image is not a regular file$'):
        load_map(yaml_path)


def test_numbers_may_be_written_with_an_exponent(tmp_path):
    yaml_path = write_map(tmp_path, walled_room(20, 10), resolution='5e-2')
    yaml_path.write_text(yaml_path.read_text().replace("'5e-2'", '5e-2'))
    assert load_map(yaml_path).resolution == 0.05


def test_corrupt_image_is_named(tmp_path):
    (tmp_path / 'broken.pgm').write_bytes(b'P5\n4 4\n255\n\x00')
    yaml_path = tmp_path / 'broken.yaml'
    yaml_path.write_text('image: broken.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n')
    with pytest.raises(MapError, match='broken.pgm: cannot read map image'):
        load_map(yaml_path)

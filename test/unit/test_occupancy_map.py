"""Loading map_server maps: every YAML field, and a clear error for each kind of bad file."""

from map_fixtures import png_header, walled_room, write_map
import numpy as np
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


def test_thresholds_split_grey_levels_into_three_classes(tmp_path):
    # Occupancy probability is 1 - grey/255: 0.8, 0.5 and 0.1 for these grey levels.
    pixels = [[51, 127, 229]]
    default = load_map(write_map(tmp_path, pixels, name='default')).cells
    assert default.tolist() == [[OCCUPIED, UNKNOWN, FREE]]
    strict = load_map(write_map(tmp_path, pixels, name='strict', occupied_thresh=0.9,
                                free_thresh=0.6)).cells
    assert strict.tolist() == [[UNKNOWN, FREE, FREE]]


def test_scale_mode_grades_the_unknown_band(tmp_path):
    cells = load_map(write_map(tmp_path, [[0, 114, 255]], mode='scale')).cells
    occupancy = 1.0 - 114 / 255.0
    assert cells.tolist() == [[OCCUPIED, round(99 * (occupancy - 0.25) / 0.4), FREE]]


def test_transparent_pixels_are_unknown(tmp_path):
    rgba = np.zeros((1, 2, 4))
    rgba[..., 3] = [255, 0]
    cells = load_map(write_map(tmp_path, rgba, image_format='png')).cells
    assert cells.tolist() == [[OCCUPIED, UNKNOWN]]


def test_colour_images_use_the_mean_of_their_channels(tmp_path):
    rgb = np.array([[[255, 255, 0], [255, 255, 153]]])
    cells = load_map(write_map(tmp_path, rgb, image_format='png')).cells
    assert cells.tolist() == [[UNKNOWN, FREE]]


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
    'threshold_range': ('image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n'
                        'occupied_thresh: 1.5\n', 'occupied_thresh must lie in [0, 1]'),
    'threshold_order': ('image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n'
                        'free_thresh: 0.7\n', 'must be below occupied_thresh'),
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

"""Robot lists: defaults for names, poses and descriptions, and one-line errors."""

from pathlib import Path

import pytest
from simple_robot_control.share import BUNDLED_ROBOT, shared_file
from stdr_lite.core.robot_description import load_robot, RobotFileError
from stdr_lite.core.robot_list import load_robot_list

SMALL_ROBOT = 'initial_pose: {x: 1.5, y: 2.5, theta: 0.5}\nfootprint: {radius: 0.15}\n'
# A robot in STDR's XML that includes its footprint from a resource folder of its own.
XML_ROBOT = ('<robot><robot_specifications><footprint><filename>footprints/box.xml</filename>'
             '</footprint></robot_specifications></robot>')
BOX = ('<footprint><footprint_specifications><points>' + ''.join(
    f'<point><x>{x}</x><y>{y}</y></point>' for x, y in ((-0.1, -0.1), (0.1, -0.1), (0.1, 0.1),
                                                        (-0.1, 0.1)))
       + '</points></footprint_specifications></footprint>')


def test_robot_list_defaults_names_poses_and_descriptions(tmp_path):
    (tmp_path / 'small.yaml').write_text(SMALL_ROBOT)
    robots = tmp_path / 'robots.yaml'
    robots.write_text('robots:\n  - {}\n  - {name: scout, description: small.yaml}\n'
                      '  - {pose: [3, 4, 0.5]}\n')
    default = load_robot(shared_file(*BUNDLED_ROBOT))
    entries = load_robot_list(robots, default)
    assert [entry.name for entry in entries] == ['robot0', 'scout', 'robot2']
    assert entries[0].description == default and entries[0].pose == default.initial_pose
    assert entries[1].description.radius == 0.15 and entries[1].pose == (1.5, 2.5, 0.5)
    assert entries[2].pose == (3.0, 4.0, 0.5)


def test_listed_robot_files_find_their_includes_on_the_search_path(tmp_path):
    resources = tmp_path / 'course_resources'
    (resources / 'footprints').mkdir(parents=True)
    (resources / 'footprints' / 'box.xml').write_text(BOX)
    (tmp_path / 'boxy.xml').write_text(XML_ROBOT)
    robots = tmp_path / 'robots.yaml'
    robots.write_text('robots:\n  - {name: boxy, description: boxy.xml, pose: [1, 1, 0]}\n')
    default = load_robot(shared_file(*BUNDLED_ROBOT))
    with pytest.raises(RobotFileError, match='footprint.filename footprints/box.xml: no such'):
        load_robot_list(robots, default)
    entry, = load_robot_list(robots, default, (Path(resources),))
    assert len(entry.description.points) == 4


def test_an_empty_robot_list_is_an_empty_world(tmp_path):
    robots = tmp_path / 'robots.yaml'
    robots.write_text('robots: []\n')
    assert load_robot_list(robots, load_robot(shared_file(*BUNDLED_ROBOT))) == []


@pytest.mark.parametrize('text, message', [
    ('robot: []\n', 'robots: missing (a world that starts empty says robots: [])'),
    ('robots:\n  - {name: a}\n  - {name: a}\n', 'names must be unique; repeated: a'),
    ('robots:\n  - {pose: [1, 2]}\n', 'robots[0].pose: expected [x, y, theta]'),
    ('robots:\n  - {speed: 3}\n', "robots[0]: unknown keys ['speed']"),
    ('robots:\n  - {description: nowhere.yaml}\n', 'nowhere.yaml: cannot read robot file'),
])
def test_bad_robot_list_is_one_line(tmp_path, text, message):
    robots = tmp_path / 'robots.yaml'
    robots.write_text(text)
    with pytest.raises(RobotFileError) as raised:
        load_robot_list(robots, load_robot(shared_file(*BUNDLED_ROBOT)))
    assert message in str(raised.value) and '\n' not in str(raised.value)

"""Finding what is installed: the package's own files, and the ROS packages a launch needs."""

from simple_robot_control.share import missing_packages


def test_packages_missing_from_the_ament_index_are_named(tmp_path, monkeypatch):
    markers = tmp_path / 'share' / 'ament_index' / 'resource_index' / 'packages'
    markers.mkdir(parents=True)
    (markers / 'simple_robot_control').write_text('')
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(tmp_path))
    assert missing_packages(['rviz2', 'simple_robot_control']) == ['rviz2']
    assert missing_packages([]) == []


def test_without_an_ament_index_every_package_is_missing(monkeypatch):
    monkeypatch.delenv('AMENT_PREFIX_PATH', raising=False)
    assert missing_packages(['rviz2']) == ['rviz2']

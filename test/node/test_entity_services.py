"""The standard simulation API's entities: spawn, delete, query and move, in-process."""

import math

from geometry_msgs.msg import Twist, Vector3
from map_fixtures import walled_room, write_map
from nav_msgs.msg import Odometry
import pytest
from rclpy.node import Node
from ros_helpers import (overrides, pose_stamped, ServiceCaller, spin_for, spin_until,
                         wait_for_subscribers)
from sensor_msgs.msg import LaserScan
from simple_robot_control.pose import pose_from_message
from simulation_interfaces.msg import (Bounds, EntityCategory, EntityFilters, EntityState,
                                       Resource, Result, SimulationState,
                                       SpawnEntity as SpawnRequest, SpawnResult, TagsFilter)
from simulation_interfaces.srv import (DeleteEntity, GetEntities, GetEntitiesStates,
                                       GetEntityBounds, GetEntityInfo, GetEntityState,
                                       GetSpawnables, SetEntityState, SpawnEntities, SpawnEntity)
from stdr_lite.node.stdr_lite import StdrLite

OK = Result.RESULT_OK
FAST_ROBOT = ('footprint: {radius: 0.2}\nsensors:\n  lasers:\n    - {frame_id: laser_0, '
              'min_angle: -1, max_angle: 1, min_range: 0.1, max_range: 4, num_rays: 5, '
              'frequency: 1000}\n')

# Robots in STDR's XML: one includes the bundled 360-degree laser, one carries an RFID reader.
TURTLE_LIKE = ('<robot><robot_specifications><laser><filename>laser_sensors/lds_01.xml'
               '</filename></laser></robot_specifications></robot>')
TAGGING = ('<robot><robot_specifications><rfid_reader><rfid_reader_specifications>'
           '<frame_id>tags</frame_id></rfid_reader_specifications></rfid_reader>'
           '</robot_specifications></robot>')


@pytest.fixture
def world(ros_context, executor):
    """Give (simulator, client node, call): stdr_lite with robot0 at (1, 2, 0), paused."""
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        real_time_factor=0.0))
    client = Node('client', context=ros_context)
    for node in (simulator, client):
        executor.add_node(node)
    simulator.stepper.set_state(SimulationState.STATE_PAUSED)
    return simulator, client, ServiceCaller(executor, client)


def spawn(call, name='rock', uri='obstacle', x=8.0, y=8.0, theta=0.0, **fields):
    return call(SpawnEntity, 'spawn_entity', name=name, uri=uri,
                initial_pose=pose_stamped(x, y, theta), **fields)


def test_a_bundled_robot_spawns_with_its_topics(world, executor):
    simulator, client, call = world
    answer = spawn(call, 'scout', 'lab_robot', 5.0, 5.0, 0.5)
    assert (answer.result.result, answer.entity_name) == (OK, 'scout')
    assert simulator.simulation.pose('scout') == pytest.approx((5.0, 5.0, 0.5))
    spin_until(executor, lambda: client.count_publishers('/scout/odom') == 1,
               what="the robot's odometry topic")
    info = call(GetEntityInfo, 'get_entity_info', entity='scout').info
    assert info.category.category == EntityCategory.CATEGORY_ROBOT
    assert set(info.tags) == {'robot', 'spawned'}
    assert 'laser_0' in info.description and '/scout' in info.description


def test_robots_spawn_from_text_and_uris_under_their_namespace(world, executor, tmp_path):
    simulator, client, call = world
    text = 'footprint: {radius: 0.3}\n'
    odometry = []
    client.create_subscription(Odometry, '/team_a/round/odom', odometry.append, 10)
    assert call(SpawnEntity, 'spawn_entity', name='round', resource_string=text,
                initial_pose=pose_stamped(5.0, 5.0),
                entity_namespace='team_a/round').result.result == OK
    simulator.stepper.set_state(SimulationState.STATE_PLAYING)
    spin_until(executor, lambda: odometry, what="the namespaced robot's odometry")
    assert (odometry[-1].header.frame_id, odometry[-1].child_frame_id) == (
        'team_a/round/odom', 'team_a/round/base_link')
    assert client.count_publishers('/round/odom') == 0
    (tmp_path / 'round.yaml').write_text(text)
    assert spawn(call, 'by_path', str(tmp_path / 'round.yaml'), 7.0, 5.0).result.result == OK
    assert spawn(call, 'by_uri', (tmp_path / 'round.yaml').as_uri(), 9.0, 5.0).result.result == OK
    assert simulator.simulation.entity('by_uri').radius == 0.3


def test_renaming_gives_a_free_name(world):
    _, _, call = world
    assert spawn(call, 'robot0', allow_renaming=True).entity_name == 'robot0_0'
    assert spawn(call, '', allow_renaming=True, x=6.0).entity_name == 'obstacle0'


@pytest.mark.parametrize('fields, code, words', [
    ({'name': 'robé'}, SpawnResult.NAME_INVALID, 'robé'),
    *(({'name': name}, SpawnResult.NAME_INVALID, f'got a text of {len(name)} characters')
      for name in ('a\x01b', 'a\nb', 'a\x1b[2Jb', 'a\x7fb')),
    ({'name': ''}, SpawnResult.NAME_INVALID, 'allow renaming'),
    ({'name': 'robot0'}, SpawnResult.NAME_NOT_UNIQUE, 'robot0'),
    ({'uri': ''}, SpawnResult.NO_RESOURCE, 'resource_string'),
    ({'uri': 'https://example.com/robot.yaml'}, SpawnResult.UNSUPPORTED_FORMAT, 'file paths'),
    ({'uri': '/tmp/robot.sdf'}, SpawnResult.UNSUPPORTED_FORMAT, 'stdr_robot_yaml'),
    ({'uri': '/no/such/robot.yaml'}, SpawnResult.MISSING_ASSETS, 'no such file'),
    ({'uri': '', 'text': 'obstacle: {radius: 2}'}, SpawnResult.RESOURCE_PARSE_ERROR, 'radius'),
    ({'uri': '', 'text': 'footprint: [unclosed'}, SpawnResult.RESOURCE_PARSE_ERROR, 'YAML'),
    ({'x': 0.1, 'y': 0.1}, SpawnResult.INVALID_POSE, 'wall'),
    ({'x': 100.0}, SpawnResult.INVALID_POSE, 'map'),
    ({'x': 1.2, 'y': 2.0}, SpawnResult.INVALID_POSE, 'robot0'),
    ({'x': math.nan}, SpawnResult.INVALID_POSE, 'finite'),
    ({'frame': 'robot0/odom'}, SpawnResult.INVALID_POSE, 'robot0/odom'),
    ({'tilt': True}, SpawnResult.INVALID_POSE, 'plane'),
    ({'namespace': 'ns'}, SpawnResult.NAMESPACE_INVALID, 'obstacle'),
    ({'uri': 'lab_robot', 'namespace': '1bad'}, SpawnResult.NAMESPACE_INVALID, '1bad'),
    ({'uri': 'lab_robot', 'namespace': 'robot0'}, SpawnResult.NAMESPACE_INVALID, 'taken'),
    ({'uri': '', 'text': FAST_ROBOT}, Result.RESULT_OPERATION_FAILED, 'faster'),
])
def test_a_refused_spawn_changes_nothing(world, executor, fields, code, words):
    simulator, client, call = world
    pose = pose_stamped(fields.get('x', 8.0), fields.get('y', 8.0),
                        frame_id=fields.get('frame', ''))
    if fields.get('tilt'):
        pose.pose.orientation.x = pose.pose.orientation.w = math.sqrt(0.5)
    answer = call(SpawnEntity, 'spawn_entity', name=fields.get('name', 'newcomer'),
                  uri=fields.get('uri', 'obstacle'),
                  resource_string=fields.get('text', ''),
                  entity_namespace=fields.get('namespace', ''), initial_pose=pose).result
    assert answer.result == code
    assert words in answer.error_message
    assert simulator.simulation.names == ['robot0']
    spin_for(executor, 0.1)
    assert sorted(name for name, _ in client.get_topic_names_and_types()
                  if name.endswith('/odom')) == ['/robot0/odom']


def test_spawning_many_reports_each_and_fails_as_a_whole(world):
    simulator, _, call = world
    requests = [SpawnRequest(name=name, entity_resource=Resource(uri='obstacle'),
                             initial_pose=pose_stamped(x, 8.0))
                for name, x in (('a', 5.0), ('b', 0.1), ('c', 7.0), ('a', 9.0))]
    answer = call(SpawnEntities, 'spawn_entities', spawn_requests=requests)
    assert answer.result.result == SpawnEntities.Response.ENTITIES_SPAWN_FAILED
    assert '2 of 4' in answer.result.error_message
    assert [outcome.result.result for outcome in answer.results] == [
        OK, SpawnResult.INVALID_POSE, OK, SpawnResult.NAME_NOT_UNIQUE]
    assert simulator.simulation.names == ['robot0', 'a', 'c']
    assert call(SpawnEntities, 'spawn_entities', spawn_requests=[SpawnRequest(
        name='d', entity_resource=Resource(resource_string='obstacle: {radius: 0.1}'),
        initial_pose=pose_stamped(11.0, 8.0))]).result.result == OK
    assert simulator.simulation.entity('d').radius == 0.1


def test_a_thousand_requests_in_a_burst_are_all_answered_right(ros_context, executor, tmp_path):
    big = write_map(tmp_path, walled_room(1000, 700), name='big')
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        map_yaml=str(big), real_time_factor=0.0, initial_pose=[0.5, 0.5, 0.0]))
    client = Node('client', context=ros_context)
    for node in (simulator, client):
        executor.add_node(node)
    call = ServiceCaller(executor, client)
    expected, futures, spawned = [], [], []
    for index in range(1000):
        name, x, y = f'rock{index}', 1.5 + index % 40, 1.5 + index // 40
        code = OK
        if index % 10 == 9:
            name, code = spawned[-1], SpawnResult.NAME_NOT_UNIQUE
        elif index % 7 == 6:
            x, code = 80.0, SpawnResult.INVALID_POSE
        else:
            spawned.append(name)
        expected.append((code, name if code == OK else ''))
        request = SpawnEntity.Request(name=name, uri='obstacle',
                                      initial_pose=pose_stamped(x, y))
        futures.append(call.client(SpawnEntity, 'spawn_entity').call_async(request))
    spin_until(executor, lambda: all(future.done() for future in futures), timeout=120.0,
               what='1000 answers')
    answers = [(future.result().result.result, future.result().entity_name)
               for future in futures]
    assert answers == expected
    assert simulator.simulation.names == ['robot0'] + spawned


def test_delete_takes_an_entity_out(world, executor):
    simulator, client, call = world
    spawn(call, 'scout', 'lab_robot', 5.0, 5.0)
    assert call(DeleteEntity, 'delete_entity', entity='scout').result.result == OK
    assert simulator.simulation.names == ['robot0']
    spin_until(executor, lambda: client.count_publishers('/scout/odom') == 0,
               what='the topics gone')
    missing = call(DeleteEntity, 'delete_entity', entity='scout').result
    assert missing.result == Result.RESULT_NOT_FOUND and 'scout' in missing.error_message


def a_few_entities(call):
    spawn(call, 'scout', 'lab_robot', 5.0, 5.0)
    spawn(call, 'rock', 'obstacle', 8.0, 8.0)
    spawn(call, 'ball', 'moving_obstacle', 12.0, 4.0)


def box(low, high):
    return Bounds(type=Bounds.TYPE_BOX, points=[Vector3(x=low[0], y=low[1], z=-1.0),
                                                Vector3(x=high[0], y=high[1], z=1.0)])


def category(value):
    return EntityCategory(category=value)


@pytest.mark.parametrize('filters, names', [
    (EntityFilters(), ['robot0', 'scout', 'rock', 'ball']),
    (EntityFilters(filter='^r'), ['robot0', 'rock']),
    (EntityFilters(categories=[category(EntityCategory.CATEGORY_ROBOT)]), ['robot0', 'scout']),
    (EntityFilters(categories=[category(EntityCategory.CATEGORY_DYNAMIC_OBJECT),
                               category(EntityCategory.CATEGORY_STATIC_OBJECT)]),
     ['rock', 'ball']),
    (EntityFilters(tags=TagsFilter(tags=['obstacle', 'moving'],
                                   filter_mode=TagsFilter.FILTER_MODE_ALL)), ['ball']),
    (EntityFilters(tags=TagsFilter(tags=['robot', 'moving'])), ['robot0', 'scout', 'ball']),
    (EntityFilters(bounds=box((4.0, 4.0), (9.0, 9.0))), ['scout', 'rock']),
    (EntityFilters(bounds=box((8.1, 8.1), (9.0, 9.0))), ['rock']),
    (EntityFilters(bounds=box((8.2, 8.2), (9.0, 9.0))), []),
    (EntityFilters(bounds=Bounds(type=Bounds.TYPE_SPHERE, points=[Vector3(x=1.0, y=2.0),
                                                                  Vector3(x=0.5)])), ['robot0']),
    (EntityFilters(filter='o', bounds=Bounds(type=Bounds.TYPE_CONVEX_HULL, points=[
        Vector3(x=0.0, y=0.0), Vector3(x=10.0, y=0.0), Vector3(x=10.0, y=10.0)])),
     ['scout', 'rock']),
])
def test_entities_are_found_by_every_filter(world, filters, names):
    _, _, call = world
    a_few_entities(call)
    answer = call(GetEntities, 'get_entities', filters=filters)
    assert answer.result.result == OK
    assert list(answer.entities) == names


@pytest.mark.parametrize('filters, words', [
    (EntityFilters(filter='(unclosed'), 'regular expression'),
    (EntityFilters(bounds=Bounds(type=Bounds.TYPE_BOX, points=[Vector3()])), 'no volume'),
    (EntityFilters(bounds=Bounds(type=Bounds.TYPE_CONVEX_HULL, points=[
        Vector3(), Vector3(x=1.0), Vector3(x=2.0)])), 'hull'),
    (EntityFilters(tags=TagsFilter(tags=['robot'], filter_mode=7)),
     'tags filter_mode 7 is neither FILTER_MODE_ANY (0) nor FILTER_MODE_ALL (1)'),
    (EntityFilters(categories=[category(3)]), 'category 3 is none of'),
])
def test_a_filter_that_means_nothing_is_refused(world, filters, words):
    _, _, call = world
    answer = call(GetEntities, 'get_entities', filters=filters)
    assert answer.result.result == Result.RESULT_OPERATION_FAILED
    assert words in answer.result.error_message and not answer.entities


def test_states_info_and_bounds_describe_each_entity(world):
    simulator, _, call = world
    a_few_entities(call)
    states = call(GetEntitiesStates, 'get_entities_states',
                  filters=EntityFilters(filter='o'))
    assert list(states.entities) == ['robot0', 'scout', 'rock']
    assert [pose_from_message(state.pose)[:2] for state in states.states] == [
        (1.0, 2.0), (5.0, 5.0), (8.0, 8.0)]
    assert {state.header.frame_id for state in states.states} == {'map'}
    single = call(GetEntityState, 'get_entity_state', entity='scout').state
    assert pose_from_message(single.pose) == pytest.approx((5.0, 5.0, 0.0))
    info = call(GetEntityInfo, 'get_entity_info', entity='ball').info
    assert info.category.category == EntityCategory.CATEGORY_DYNAMIC_OBJECT
    assert set(info.tags) == {'obstacle', 'moving', 'spawned'}
    bounds = call(GetEntityBounds, 'get_entity_bounds', entity='rock').bounds
    assert bounds.type == Bounds.TYPE_BOX
    assert [(point.x, point.y) for point in bounds.points] == [(0.25, 0.25), (-0.25, -0.25)]
    assert simulator.simulation.names == ['robot0', 'scout', 'rock', 'ball']


@pytest.mark.parametrize('kind, service', [
    (GetEntityInfo, 'get_entity_info'), (GetEntityState, 'get_entity_state'),
    (GetEntityBounds, 'get_entity_bounds'), (DeleteEntity, 'delete_entity'),
    (SetEntityState, 'set_entity_state'),
])
def test_an_unknown_entity_is_not_found(world, kind, service):
    _, _, call = world
    answer = call(kind, service, entity='nobody').result
    assert answer.result == Result.RESULT_NOT_FOUND and 'nobody' in answer.error_message


def entity_state(x, y, theta=0.0, velocity=(0.0, 0.0, 0.0), frame_id=''):
    pose = pose_stamped(x, y, theta, frame_id)
    return EntityState(header=pose.header, pose=pose.pose, twist=Twist(
        linear=Vector3(x=velocity[0], y=velocity[1]), angular=Vector3(z=velocity[2])))


def test_set_state_teleports_and_sets_a_robot_moving(world, executor):
    simulator, _, call = world
    answer = call(SetEntityState, 'set_entity_state', entity='robot0',
                  state=entity_state(4.0, 4.0, math.pi / 2, (0.0, 0.5, 0.1)))
    assert answer.result.result == OK
    assert simulator.simulation.pose('robot0') == pytest.approx((4.0, 4.0, math.pi / 2))
    for _ in range(50):
        simulator.stepper.step_now()
    x, y, _ = simulator.simulation.pose('robot0')
    assert y == pytest.approx(4.5, abs=0.05) and x < 4.0
    state = call(GetEntityState, 'get_entity_state', entity='robot0').state
    assert state.twist.angular.z == pytest.approx(0.1)


@pytest.mark.parametrize('entity, state, code, words', [
    ('robot0', entity_state(0.1, 0.1), SetEntityState.Response.INVALID_POSE, 'wall'),
    ('robot0', entity_state(5.0, 5.0, frame_id='robot0/odom'),
     SetEntityState.Response.INVALID_POSE, 'robot0/odom'),
    ('robot0', entity_state(5.0, 5.0, 0.0, (0.0, 0.5, 0.0)), Result.RESULT_OPERATION_FAILED,
     'unicycle'),
    ('robot0', entity_state(5.0, 5.0, 0.0, (500.0, 0.0, 0.0)), Result.RESULT_OPERATION_FAILED,
     'limits'),
    ('robot0', entity_state(5.0, 5.0, 0.0, (math.inf, 0.0, 0.0)),
     Result.RESULT_OPERATION_FAILED, 'finite'),
    ('rock', entity_state(5.0, 5.0, 0.0, (0.1, 0.0, 0.0)), Result.RESULT_OPERATION_FAILED,
     'static'),
])
def test_a_refused_state_changes_nothing(world, entity, state, code, words):
    simulator, _, call = world
    spawn(call, 'rock', 'obstacle', 8.0, 8.0)
    before = simulator.simulation.pose(entity)
    answer = call(SetEntityState, 'set_entity_state', entity=entity, state=state).result
    assert answer.result == code and words in answer.error_message
    assert simulator.simulation.pose(entity) == before
    simulator.stepper.step_now()
    assert simulator.simulation.pose(entity) == before


def test_a_state_in_three_dimensions_is_refused(world):
    simulator, _, call = world
    state = entity_state(5.0, 5.0)
    state.twist.angular.x = 0.3
    answer = call(SetEntityState, 'set_entity_state', entity='robot0', state=state).result
    assert answer.result == Result.RESULT_OPERATION_FAILED and 'plane' in answer.error_message
    assert simulator.simulation.pose('robot0') == (1.0, 2.0, 0.0)


def test_spawnables_list_the_bundled_files_and_any_folder(world, tmp_path):
    _, _, call = world
    (tmp_path / 'pillar.yaml').write_text('obstacle: {radius: 0.4}\n')
    (tmp_path / 'notes.yaml').write_text('just: words\n')
    answer = call(GetSpawnables, 'get_spawnables', sources=[str(tmp_path), '/no/such'])
    assert answer.result.result == OK and '/no/such' in answer.result.error_message
    (tmp_path / 'scanner.xml').write_text(TURTLE_LIKE)
    uris = [spawnable.uri for spawnable in answer.spawnables]
    assert uris[:5] == ['lab_robot', 'moving_obstacle', 'obstacle', 'small_laser_robot',
                        'turtlebot3_burger']
    assert uris[5:] == [str(tmp_path / 'pillar.yaml')]
    pillar = answer.spawnables[5]
    assert pillar.spawn_bounds.type == Bounds.TYPE_SPHERE
    assert pillar.spawn_bounds.points[1].x == 0.4
    answer = call(GetSpawnables, 'get_spawnables', sources=[str(tmp_path)])
    assert [spawnable.uri for spawnable in answer.spawnables][5:] == [
        str(tmp_path / 'pillar.yaml'), str(tmp_path / 'scanner.xml')]


def test_stdr_robot_files_spawn_with_their_includes(world, executor, tmp_path, capfd):
    simulator, client, call = world
    (tmp_path / 'scanner.xml').write_text(TURTLE_LIKE)
    answer = spawn(call, 'turtle', str(tmp_path / 'scanner.xml'), 5.0, 5.0)
    assert answer.result.result == OK, answer.result.error_message
    laser, = simulator.simulation.robot('turtle').description.lasers
    assert (laser.num_rays, laser.min_angle, laser.max_range) == (360, 0.0, 3.5)
    answer = spawn(call, 'tagger', '', 8.0, 5.0, resource_string=TAGGING)
    assert answer.result.result == OK, answer.result.error_message
    spin_until(executor, lambda: 'not simulated' in capfd.readouterr().err or None,
               what='the unsimulated RFID reader named in the log')
    answer = spawn(call, 'lost', '', 8.0, 8.0, resource_string=TURTLE_LIKE.replace(
        'lds_01', 'lds_99'))
    assert answer.result.result == SpawnResult.RESOURCE_PARSE_ERROR
    assert 'laser.filename laser_sensors/lds_99.xml: no such file' in (
        answer.result.error_message)


def test_a_moving_obstacle_stops_a_robot_and_shows_in_its_laser(ros_context, executor):
    simulator = StdrLite(context=ros_context, parameter_overrides=overrides(
        real_time_factor=0.0, initial_pose=[2.0, 7.5, 0.0]))
    client = Node('client', context=ros_context)
    scans, odometry = [], []
    client.create_subscription(LaserScan, '/robot0/laser_0', scans.append, 10)
    client.create_subscription(Odometry, '/robot0/odom', odometry.append, 10)
    driver = client.create_publisher(Twist, '/robot0/cmd_vel', 10)
    for node in (simulator, client):
        executor.add_node(node)
    call = ServiceCaller(executor, client)
    spawn(call, 'ball', 'moving_obstacle', 6.0, 7.5)
    scans.clear()
    spin_until(executor, lambda: scans, what='a laser scan')
    ahead = len(scans[-1].ranges) // 2
    assert scans[-1].ranges[ahead] == pytest.approx(6.0 - 0.25 - 2.0 - 0.1, abs=0.03)
    assert call(SetEntityState, 'set_entity_state', entity='ball',
                state=entity_state(6.0, 7.5, 0.0, (-0.5, 0.0, 0.0))).result.result == OK
    wait_for_subscribers(executor, driver)
    driver.publish(Twist(linear=Vector3(x=0.5)))
    spin_until(executor, lambda: simulator.simulation.sim_time > 6.0, timeout=30.0,
               what='six simulated seconds')
    robot_x = simulator.simulation.pose('robot0')[0]
    ball_x = simulator.simulation.pose('ball')[0]
    assert ball_x - robot_x == pytest.approx(0.45, abs=0.03)
    assert simulator.simulation.applied_velocity('robot0') == (0.0, 0.0, 0.0)
    assert scans[-1].ranges[ahead] < 0.2
    assert pose_from_message(odometry[-1].pose.pose)[0] == pytest.approx(robot_x)


def test_requests_to_different_services_are_served_in_the_order_they_came(world, executor):
    """Sent at once: each answer sees exactly the requests sent before it."""
    _, _, call = world
    futures = []
    for round_ in range(5):
        futures.append(call.client(SpawnEntity, 'spawn_entity').call_async(SpawnEntity.Request(
            name=f'rock{round_}', uri='obstacle', initial_pose=pose_stamped(8.0, 3.0 + round_))))
        futures.append(call.client(GetEntities, 'get_entities').call_async(
            GetEntities.Request()))
        futures.append(call.client(DeleteEntity, 'delete_entity').call_async(
            DeleteEntity.Request(entity=f'rock{round_}')))
        futures.append(call.client(GetEntities, 'get_entities').call_async(
            GetEntities.Request()))
    spin_until(executor, lambda: all(future.done() for future in futures),
               what='every answer')
    seen = [list(future.result().entities) for future in futures[1::2]]
    assert seen == [entities for round_ in range(5)
                    for entities in (['robot0', f'rock{round_}'], ['robot0'])]

"""
The standard simulation API's entities, served under the node's name.

SpawnEntity, SpawnEntities, DeleteEntity, GetEntities, GetEntitiesStates, GetEntityInfo,
GetEntityState, SetEntityState, GetEntityBounds and GetSpawnables. Entities are the robots
(from STDR robot files) and circular obstacles, static or moving; every answer carries a
standard result code and, on a refusal, a message saying why; a refused call changes nothing.
A name filter is a regular expression matched with a time limit per name, so no pattern can
run away; folders of spawnables are read a file at a time (requests.py).
"""

import os

from geometry_msgs.msg import Vector3
import regex
from simple_robot_control.input_files import yaml_files
from simple_robot_control.pose import planar_pose, set_pose
from simple_robot_control.share import bundled_files, shared_file
from simple_robot_control.validation import compact, is_ros_name, ros_name_problem, shorten
from simulation_interfaces.msg import (Bounds, EntityCategory, EntityInfo, EntityState, Result,
                                       SimulationState, Spawnable, SpawnResult, TagsFilter)
from simulation_interfaces.srv import (DeleteEntity, GetEntities, GetEntitiesStates,
                                       GetEntityBounds, GetEntityInfo, GetEntityState,
                                       GetSpawnables, SetEntityState, SpawnEntities, SpawnEntity)
from stdr_lite.core.bodies import PlacementError
from stdr_lite.core.entities import Category, NamespaceError, RequestError
from stdr_lite.core.footprints import convex_hull
from stdr_lite.core.regions import count_problem, region_test
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from stdr_lite.core.spawnables import load_resource, SpawnResourceError
from stdr_lite.node.messages import set_stamp
from stdr_lite.node.naming import check_robot_names, NamingProblem
from stdr_lite.node.results import Refusal, result
from stdr_lite.node.served import Served

CATEGORIES = {Category.ROBOT: EntityCategory.CATEGORY_ROBOT,
              Category.STATIC_OBSTACLE: EntityCategory.CATEGORY_STATIC_OBJECT,
              Category.MOVING_OBSTACLE: EntityCategory.CATEGORY_DYNAMIC_OBJECT}
KNOWN_CATEGORIES = {EntityCategory.CATEGORY_OBJECT, EntityCategory.CATEGORY_ROBOT,
                    EntityCategory.CATEGORY_HUMAN, EntityCategory.CATEGORY_DYNAMIC_OBJECT,
                    EntityCategory.CATEGORY_STATIC_OBJECT}
TAG_MODES = (TagsFilter.FILTER_MODE_ANY, TagsFilter.FILTER_MODE_ALL)
REGIONS = {Bounds.TYPE_SPHERE: 'sphere', Bounds.TYPE_BOX: 'box',
           Bounds.TYPE_CONVEX_HULL: 'hull'}
# A name filter: its length, and the wall time it may take on one name (names are at most a
# few hundred characters: any sane pattern takes microseconds).
MAX_FILTER_LENGTH = 1000
MATCH_TIME = 0.002
RESOURCE_CODES = {'no_resource': SpawnResult.NO_RESOURCE,
                  'unsupported_format': SpawnResult.UNSUPPORTED_FORMAT,
                  'missing_assets': SpawnResult.MISSING_ASSETS,
                  'parse_error': SpawnResult.RESOURCE_PARSE_ERROR}


class EntityServices:
    """Serves spawning, deleting, querying and moving entities on a StdrLite node."""

    def __init__(self, node, served: Served, world_changing: bool = True):
        """Serve the queries, and unless world_changing is False spawn, delete and move."""
        self._node, self._served = node, served
        self._simulation = served.simulation
        services = [(GetEntities, 'get_entities', self._entities),
                    (GetEntitiesStates, 'get_entities_states', self._entities_states),
                    (GetEntityInfo, 'get_entity_info', self._info),
                    (GetEntityState, 'get_entity_state', self._get_state),
                    (GetEntityBounds, 'get_entity_bounds', self._bounds),
                    (GetSpawnables, 'get_spawnables', self._spawnables)]
        if world_changing:
            services += [(SpawnEntity, 'spawn_entity', self._spawn_one),
                         (SpawnEntities, 'spawn_entities', self._spawn_many),
                         (DeleteEntity, 'delete_entity', self._delete),
                         (SetEntityState, 'set_entity_state', self._set_state)]
        for kind, name, callback in services:
            node.requests.serve(kind, name, callback)

    def _spawn_one(self, request, response):
        response.entity_name = self._spawn(request.name, request.allow_renaming, request.uri,
                                           request.resource_string, request.entity_namespace,
                                           request.initial_pose)
        yield from self._served.refresh_topics()

    def _spawn_many(self, request, response):
        """Spawn each request on its own, one per slice; a failed one fails the call as a whole."""
        response.results = []
        for spawn in request.spawn_requests:
            outcome = SpawnResult(result=result())
            try:
                outcome.entity_name = self._spawn(
                    spawn.name, spawn.allow_renaming, spawn.entity_resource.uri,
                    spawn.entity_resource.resource_string, spawn.entity_namespace,
                    spawn.initial_pose)
            except Refusal as refusal:
                outcome.result = result(refusal.code, str(refusal))
            response.results.append(outcome)
            yield from self._served.refresh_topics()
            yield
        failed = [index for index, outcome in enumerate(response.results)
                  if outcome.result.result != Result.RESULT_OK]
        if failed:
            raise Refusal(response.ENTITIES_SPAWN_FAILED,
                          f'{len(failed)} of {len(response.results)} failed; see results')

    def _spawn(self, name, allow_renaming, uri, resource_string, namespace, pose):
        """Spawn one entity; return the name it got, or raise Refusal with the spawn code."""
        if self._served.stepper.state == SimulationState.STATE_NO_WORLD:
            raise Refusal(Result.RESULT_INCORRECT_STATE, 'no world is loaded')
        try:
            spec = load_resource(uri, resource_string, bundled_files('robots', 'obstacles'),
                                 self._served.search_path)
        except SpawnResourceError as error:
            raise Refusal(RESOURCE_CODES[error.kind], str(error)) from None
        is_robot = isinstance(spec, RobotDescription)
        name = self._spawn_name(name, allow_renaming, 'robot' if is_robot else 'obstacle')
        start = self._pose(pose.header.frame_id, pose.pose, SpawnResult.INVALID_POSE)
        try:
            if is_robot:
                self._check_names(namespace.strip('/') or name, spec, bool(namespace))
                self._simulation.add_robot(RobotEntry(name, spec, start), spawned=True,
                                           namespace=namespace)
                self._served.note_description(name, spec)
            elif namespace:
                raise Refusal(SpawnResult.NAMESPACE_INVALID, 'an obstacle has no topics to '
                              'put under a namespace')
            else:
                self._simulation.add_obstacle(name, spec.radius, start, spec.moving)
        except PlacementError as error:
            raise Refusal(SpawnResult.INVALID_POSE, str(error)) from None
        except NamespaceError as error:
            raise Refusal(SpawnResult.NAMESPACE_INVALID, str(error)) from None
        except RequestError as error:
            raise Refusal(Result.RESULT_OPERATION_FAILED, str(error)) from None
        return name

    def _check_names(self, namespace, description, namespace_given):
        """Refuse a robot whose topics or frames could not exist (see naming.py)."""
        try:
            check_robot_names(self._node, self._served.frames, namespace, description)
        except NamingProblem as problem:
            code = {'sensor': SpawnResult.RESOURCE_PARSE_ERROR,
                    'name': SpawnResult.NAMESPACE_INVALID if namespace_given
                    else SpawnResult.NAME_INVALID}[problem.part]
            raise Refusal(code, str(problem)) from None

    def _spawn_name(self, name, allow_renaming, kind):
        if not name:
            if not allow_renaming:
                raise Refusal(SpawnResult.NAME_INVALID, 'give a name, or allow renaming')
            return self._simulation.default_name(kind)
        if not is_ros_name(name):
            raise Refusal(SpawnResult.NAME_INVALID, ros_name_problem(name, 'the name'))
        if name in self._simulation:
            if not allow_renaming:
                raise Refusal(SpawnResult.NAME_NOT_UNIQUE,
                              f'an entity named {shorten(name)} exists')
            return self._simulation.default_name(f'{name}_')
        return name

    def _pose(self, frame_id, pose, invalid):
        if frame_id not in ('', 'world', self._served.frames.map_frame):
            raise Refusal(invalid, f'poses are in the {self._served.frames.map_frame} frame '
                          f'(or world), not {shorten(repr(frame_id))}')
        try:
            return planar_pose(pose)
        except ValueError as error:
            raise Refusal(invalid, str(error)) from None

    def _delete(self, request, response):
        self._entity(request.entity)
        self._simulation.remove(request.entity)
        self._served.stepper.release()
        self._served.stepper.step_if_answered()
        yield from self._served.refresh_topics()

    def _entity(self, name):
        if name not in self._simulation:
            raise Refusal(Result.RESULT_NOT_FOUND, f'no entity named {shorten(repr(name))}')
        return self._simulation.entity(name)

    def _entities(self, request, response):
        response.entities = yield from self._matching(request.filters)

    def _entities_states(self, request, response):
        response.entities = yield from self._matching(request.filters)
        response.states = [self._state_of(name) for name in response.entities]

    def _matching(self, filters):
        """Yield between slices; return the names of the entities that pass every filter."""
        matches_name = _name_filter(filters.filter)
        overlaps = _region_filter(filters.bounds)
        categories = {category.category for category in filters.categories}
        unknown = sorted(categories - KNOWN_CATEGORIES)
        if unknown:
            raise Refusal(Result.RESULT_OPERATION_FAILED, f'category {unknown[0]} is none of '
                          f'EntityCategory\'s ({", ".join(map(str, sorted(KNOWN_CATEGORIES)))})')
        wanted = set(filters.tags.tags)
        if filters.tags.filter_mode not in TAG_MODES:
            raise Refusal(Result.RESULT_OPERATION_FAILED, f'tags filter_mode '
                          f'{filters.tags.filter_mode} is neither FILTER_MODE_ANY (0) nor '
                          'FILTER_MODE_ALL (1)')
        every_tag = filters.tags.filter_mode == TagsFilter.FILTER_MODE_ALL
        matching = []
        for name in self._simulation.names:
            entity = self._simulation.entity(name)
            tags = set(_tags(entity))
            if (matches_name(name)
                    and not (categories and CATEGORIES[entity.category] not in categories)
                    and not (wanted and not (wanted <= tags if every_tag else wanted & tags))
                    and overlaps(self._simulation.pose(name)[:2], entity.radius)):
                matching.append(name)
            yield
        return matching

    def _info(self, request, response):
        entity = self._entity(request.entity)
        response.info = EntityInfo(category=EntityCategory(category=CATEGORIES[entity.category]),
                                   description=_description(entity, self._simulation.settings),
                                   tags=_tags(entity))

    def _get_state(self, request, response):
        self._entity(request.entity)
        response.state = self._state_of(request.entity)

    def _state_of(self, name):
        state = EntityState()
        state.header.frame_id = self._served.frames.map_frame
        set_stamp(state.header.stamp, self._simulation.time_ns)
        set_pose(state.pose, *self._simulation.pose(name))
        state.twist.linear.x, state.twist.linear.y, state.twist.angular.z = (
            self._simulation.velocity(name))
        return state

    def _set_state(self, request, response):
        self._entity(request.entity)
        state = request.state
        pose = self._pose(state.header.frame_id, state.pose, response.INVALID_POSE)
        twist = state.twist
        if twist.linear.z or twist.angular.x or twist.angular.y:
            raise Refusal(Result.RESULT_OPERATION_FAILED, 'the world is a plane: only linear '
                          'x, y and angular z can be set')
        try:
            self._simulation.set_state(request.entity, pose,
                                       (twist.linear.x, twist.linear.y, twist.angular.z))
        except PlacementError as error:
            raise Refusal(response.INVALID_POSE, str(error)) from None
        except RequestError as error:
            raise Refusal(Result.RESULT_OPERATION_FAILED, str(error)) from None
        self._served.show_state()

    def _bounds(self, request, response):
        """Give a round entity's square box, or a polygonal robot's convex hull, in its frame."""
        entity = self._entity(request.entity)
        if entity.shape is not None:
            response.bounds = Bounds(type=Bounds.TYPE_CONVEX_HULL, points=[
                Vector3(x=x, y=y) for x, y in convex_hull(entity.shape)])
            return
        radius = entity.radius
        response.bounds = Bounds(type=Bounds.TYPE_BOX, points=[
            Vector3(x=radius, y=radius), Vector3(x=-radius, y=-radius)])

    def _spawnables(self, request, response):
        paths = list(bundled_files('robots', 'obstacles').values())
        unknown, notes = [], []
        for source in request.sources:
            if os.path.isdir(source):
                found, note = yaml_files(source, ('.yaml', '.yml', '.xml'))
                paths += found
                notes += [note] if note else []
            else:
                unknown.append(source)
        response.spawnables = []
        for path in paths:
            spawnable = _spawnable(path, self._served.search_path)
            if spawnable is not None:
                response.spawnables.append(spawnable)
            yield
        if unknown:
            notes.append(f'not folders, not searched: {", ".join(unknown)}')
        return '; '.join(notes)


def _name_filter(pattern):
    """Return matches(name) for a name filter, or raise Refusal for one that cannot run."""
    if len(pattern) > MAX_FILTER_LENGTH:
        raise Refusal(Result.RESULT_OPERATION_FAILED, f'a filter of {len(pattern)} characters; '
                      f'at most {MAX_FILTER_LENGTH}')
    shown = shorten(repr(pattern))
    try:
        compiled = regex.compile(pattern)
    except regex.error as error:
        raise Refusal(Result.RESULT_OPERATION_FAILED,
                      f'filter {shown} is no regular expression: {error}') from None

    def matches(name):
        try:
            return compiled.search(name, timeout=MATCH_TIME) is not None
        except TimeoutError:
            raise Refusal(Result.RESULT_OPERATION_FAILED,
                          f'filter {shown} took over {MATCH_TIME * 1e3:g} ms to match one name '
                          f'({shorten(name)}): it backtracks without end; simplify it') from None
    return matches


def _region_filter(bounds):
    """Return overlaps(centre, radius) for the filters' bounds, or raise Refusal."""
    if bounds.type == Bounds.TYPE_EMPTY:
        return lambda centre, radius: True
    # Refused before anything is made of each point: rclpy has already spent 2 us on each.
    problem = count_problem(len(bounds.points))
    if problem is not None:
        raise Refusal(Result.RESULT_OPERATION_FAILED, problem)
    points = [(point.x, point.y, point.z) for point in bounds.points]
    try:
        return region_test(REGIONS.get(bounds.type, f'type {bounds.type}'), points)
    except ValueError as error:
        raise Refusal(Result.RESULT_OPERATION_FAILED, str(error)) from None


def _tags(entity):
    return {Category.ROBOT: ['robot'], Category.STATIC_OBSTACLE: ['obstacle', 'static'],
            Category.MOVING_OBSTACLE: ['obstacle', 'moving']}[entity.category] + (
        ['spawned'] if entity.spawned else [])


def _description(entity, settings):
    if not entity.is_robot:
        return f'{entity.category.value} of radius {compact(entity.radius)} m'
    sensors = ', '.join(sensor.spec.frame_id for sensor in entity.sensors) or 'no sensors'
    shape = (f'of radius {compact(entity.radius)} m' if entity.shape is None
             else f'of {len(entity.shape)} corners (within {compact(entity.radius)} m)')
    kinematic = entity.description.kinematic
    kind = 'omni-directional robot' if kinematic.model == 'omni' else 'robot'
    noise = ''.join(f', {note}' for note in (
        'noisy motion' if kinematic.noisy else '',
        settings.sensor_noise_note(entity.description)) if note)
    return f'{kind} {shape} with {sensors}{noise}; topics under /{entity.namespace}'


def _spawnable(path, search_path):
    """Describe a robot or obstacle file as a standard Spawnable, or None if it is neither."""
    try:
        spec = load_resource(path, '', {}, search_path)
    except SpawnResourceError:
        return None
    name = os.path.splitext(os.path.basename(path))[0]
    kind = 'robot' if isinstance(spec, RobotDescription) else (
        'moving obstacle' if spec.moving else 'obstacle')
    bounds = Bounds(type=Bounds.TYPE_SPHERE, points=[Vector3(), Vector3(x=spec.radius)])
    return Spawnable(uri=name if path.startswith(shared_file()) else path,
                     description=f'{kind} of radius {compact(spec.radius)} m ({path})',
                     spawn_bounds=bounds)

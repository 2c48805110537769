"""
The standard simulation API's entities, served under the node's name.

SpawnEntity, SpawnEntities, DeleteEntity, GetEntities, GetEntitiesStates, GetEntityInfo,
GetEntityState, SetEntityState, GetEntityBounds and GetSpawnables. Entities are the robots
(from STDR robot files) and circular obstacles, static or moving; every answer carries a
standard result code and, on a refusal, a message saying why; a refused call changes nothing.
"""

import glob
import os
import re

from geometry_msgs.msg import Vector3
from simple_robot_control.pose import planar_pose, set_pose
from simple_robot_control.share import bundled_files, shared_file
from simple_robot_control.validation import compact, is_ros_name, ros_name_problem
from simulation_interfaces.msg import (Bounds, EntityCategory, EntityInfo, EntityState, Result,
                                       SimulationState, Spawnable, SpawnResult, TagsFilter)
from simulation_interfaces.srv import (DeleteEntity, GetEntities, GetEntitiesStates,
                                       GetEntityBounds, GetEntityInfo, GetEntityState,
                                       GetSpawnables, SetEntityState, SpawnEntities, SpawnEntity)
from stdr_lite.core.entities import Category, NamespaceError, RequestError
from stdr_lite.core.regions import overlaps_box, overlaps_circle, overlaps_hull
from stdr_lite.core.robot_description import RobotDescription, RobotEntry
from stdr_lite.core.spawnables import load_resource, SpawnResourceError
from stdr_lite.core.world import PlacementError
from stdr_lite.node.answers import answering, Refusal, result, SERVICE_QOS
from stdr_lite.node.messages import set_stamp

CATEGORIES = {Category.ROBOT: EntityCategory.CATEGORY_ROBOT,
              Category.STATIC_OBSTACLE: EntityCategory.CATEGORY_STATIC_OBJECT,
              Category.MOVING_OBSTACLE: EntityCategory.CATEGORY_DYNAMIC_OBJECT}
RESOURCE_CODES = {'no_resource': SpawnResult.NO_RESOURCE,
                  'unsupported_format': SpawnResult.UNSUPPORTED_FORMAT,
                  'missing_assets': SpawnResult.MISSING_ASSETS,
                  'parse_error': SpawnResult.RESOURCE_PARSE_ERROR}


class EntityServices:
    """Serves spawning, deleting, querying and moving entities on a StdrLite node."""

    def __init__(self, node):
        self._node = node
        self._simulation = node.simulation
        for kind, name, callback in (
                (SpawnEntity, 'spawn_entity', self._spawn_one),
                (SpawnEntities, 'spawn_entities', self._spawn_many),
                (DeleteEntity, 'delete_entity', self._delete),
                (GetEntities, 'get_entities', self._entities),
                (GetEntitiesStates, 'get_entities_states', self._entities_states),
                (GetEntityInfo, 'get_entity_info', self._info),
                (GetEntityState, 'get_entity_state', self._get_state),
                (SetEntityState, 'set_entity_state', self._set_state),
                (GetEntityBounds, 'get_entity_bounds', self._bounds),
                (GetSpawnables, 'get_spawnables', self._spawnables)):
            node.create_service(kind, f'~/{name}', answering(callback), qos_profile=SERVICE_QOS)

    def _spawn_one(self, request, response):
        response.entity_name = self._spawn(request.name, request.allow_renaming, request.uri,
                                           request.resource_string, request.entity_namespace,
                                           request.initial_pose)
        self._node.sync_entities()

    def _spawn_many(self, request, response):
        """Spawn each request on its own; a failed one fails the call as a whole."""
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
        self._node.sync_entities()
        failed = [index for index, outcome in enumerate(response.results)
                  if outcome.result.result != Result.RESULT_OK]
        if failed:
            raise Refusal(response.ENTITIES_SPAWN_FAILED,
                          f'{len(failed)} of {len(response.results)} failed; see results')

    def _spawn(self, name, allow_renaming, uri, resource_string, namespace, pose):
        """Spawn one entity; return the name it got, or raise Refusal with the spawn code."""
        if self._node.stepper.state == SimulationState.STATE_NO_WORLD:
            raise Refusal(Result.RESULT_INCORRECT_STATE, 'no world is loaded')
        try:
            spec = load_resource(uri, resource_string, bundled_files('robots', 'obstacles'))
        except SpawnResourceError as error:
            raise Refusal(RESOURCE_CODES[error.kind], str(error)) from None
        is_robot = isinstance(spec, RobotDescription)
        name = self._spawn_name(name, allow_renaming, 'robot' if is_robot else 'obstacle')
        start = self._pose(pose.header.frame_id, pose.pose, SpawnResult.INVALID_POSE)
        try:
            if is_robot:
                self._simulation.add_robot(RobotEntry(name, spec, start), spawned=True,
                                           namespace=namespace)
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

    def _spawn_name(self, name, allow_renaming, kind):
        if not name:
            if not allow_renaming:
                raise Refusal(SpawnResult.NAME_INVALID, 'give a name, or allow renaming')
            return self._simulation.default_name(kind)
        if not is_ros_name(name):
            raise Refusal(SpawnResult.NAME_INVALID, ros_name_problem(name, 'the name'))
        if name in self._simulation:
            if not allow_renaming:
                raise Refusal(SpawnResult.NAME_NOT_UNIQUE, f'an entity named {name} exists')
            return self._simulation.default_name(f'{name}_')
        return name

    def _pose(self, frame_id, pose, invalid):
        if frame_id not in ('', 'world', self._node.frames.map_frame):
            raise Refusal(invalid, f'poses are in the {self._node.frames.map_frame} frame '
                          f'(or world), not {frame_id!r}')
        try:
            return planar_pose(pose)
        except ValueError as error:
            raise Refusal(invalid, str(error)) from None

    def _delete(self, request, response):
        self._entity(request.entity)
        self._simulation.remove(request.entity)
        self._node.sync_entities()
        self._node.stepper.step_if_answered()

    def _entity(self, name):
        if name not in self._simulation:
            raise Refusal(Result.RESULT_NOT_FOUND, f'no entity named {name!r}')
        return self._simulation.entity(name)

    def _entities(self, request, response):
        response.entities = self._matching(request.filters)

    def _entities_states(self, request, response):
        response.entities = self._matching(request.filters)
        response.states = [self._state_of(name) for name in response.entities]

    def _matching(self, filters):
        """Return the names of the entities that pass every part of the filters."""
        try:
            pattern = re.compile(filters.filter)
        except re.error as error:
            raise Refusal(Result.RESULT_OPERATION_FAILED,
                          f'filter {filters.filter!r} is no regular expression: {error}') from None
        categories = {category.category for category in filters.categories}
        matching = []
        for name in self._simulation.names:
            entity = self._simulation.entity(name)
            tags = set(_tags(entity))
            wanted = set(filters.tags.tags)
            if not pattern.search(name) or (categories and CATEGORIES[entity.category]
                                            not in categories):
                continue
            if wanted and not (wanted <= tags if filters.tags.filter_mode
                               == TagsFilter.FILTER_MODE_ALL else wanted & tags):
                continue
            if self._overlaps(filters.bounds, self._simulation.pose(name)[:2], entity.radius):
                matching.append(name)
        return matching

    @staticmethod
    def _overlaps(bounds, centre, radius):
        points = [(point.x, point.y, point.z) for point in bounds.points]
        if bounds.type == Bounds.TYPE_EMPTY:
            return True
        if bounds.type == Bounds.TYPE_SPHERE and len(points) == 2:
            return overlaps_circle(centre, radius, points[0][:2], points[1][0])
        if bounds.type == Bounds.TYPE_BOX and len(points) == 2:
            return overlaps_box(centre, radius, points[0], points[1])
        if bounds.type == Bounds.TYPE_CONVEX_HULL and len(points) >= 3:
            try:
                return overlaps_hull(centre, radius, points)
            except ValueError as error:
                raise Refusal(Result.RESULT_OPERATION_FAILED, str(error)) from None
        raise Refusal(Result.RESULT_OPERATION_FAILED, f'bounds of type {bounds.type} with '
                      f'{len(points)} points define no volume')

    def _info(self, request, response):
        entity = self._entity(request.entity)
        response.info = EntityInfo(category=EntityCategory(category=CATEGORIES[entity.category]),
                                   description=_description(entity), tags=_tags(entity))

    def _get_state(self, request, response):
        self._entity(request.entity)
        response.state = self._state_of(request.entity)

    def _state_of(self, name):
        state = EntityState()
        state.header.frame_id = self._node.frames.map_frame
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
        self._node.show_state()

    def _bounds(self, request, response):
        radius = self._entity(request.entity).radius
        response.bounds = Bounds(type=Bounds.TYPE_BOX, points=[
            Vector3(x=radius, y=radius), Vector3(x=-radius, y=-radius)])

    def _spawnables(self, request, response):
        paths = list(bundled_files('robots', 'obstacles').values())
        unknown = []
        for source in request.sources:
            if os.path.isdir(source):
                paths += sorted(glob.glob(os.path.join(source, '*.yaml')))
            else:
                unknown.append(source)
        response.spawnables = [spawnable for spawnable in map(_spawnable, paths) if spawnable]
        return f'not folders, not searched: {", ".join(unknown)}' if unknown else ''


def _tags(entity):
    return {Category.ROBOT: ['robot'], Category.STATIC_OBSTACLE: ['obstacle', 'static'],
            Category.MOVING_OBSTACLE: ['obstacle', 'moving']}[entity.category] + (
        ['spawned'] if entity.spawned else [])


def _description(entity):
    if not entity.is_robot:
        return f'{entity.category.value} of radius {compact(entity.radius)} m'
    sensors = ', '.join(sensor.spec.frame_id for sensor in entity.sensors) or 'no sensors'
    return (f'robot of radius {compact(entity.radius)} m with {sensors}; topics under '
            f'/{entity.namespace}')


def _spawnable(path):
    """Describe a robot or obstacle file as a standard Spawnable, or None if it is neither."""
    try:
        spec = load_resource(path, '', {})
    except SpawnResourceError:
        return None
    name = os.path.splitext(os.path.basename(path))[0]
    kind = 'robot' if isinstance(spec, RobotDescription) else (
        'moving obstacle' if spec.moving else 'obstacle')
    bounds = Bounds(type=Bounds.TYPE_SPHERE, points=[Vector3(), Vector3(x=spec.radius)])
    return Spawnable(uri=name if path.startswith(shared_file()) else path,
                     description=f'{kind} of radius {compact(spec.radius)} m ({path})',
                     spawn_bounds=bounds)

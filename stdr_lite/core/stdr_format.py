"""
STDR's own robot files: its nested YAML and its XML, and the files they include by name.

STDR reads both into one tree of tagged elements: a `filename` element is replaced by what
the file it names holds (found against a search path); elements that may come once are merged
when they come again (robots, sensors and points stay apart); where two values meet, the file's
own wins over the one it includes; what is missing takes STDR's default. This module does the
same, then writes the result in the flat layout of robot_description, whose rules check every
format alike. Elements STDR knows but stdr_lite does not simulate (RFID readers, CO2, thermal
and sound sensors) are kept by name. No ROS here.
"""

from dataclasses import dataclass, field
import os
import xml.parsers.expat

from simple_robot_control.input_files import (is_regular_file, MAX_DESCRIPTION_BYTES,
                                              MAX_NESTING, parse_yaml, read_text)
from simple_robot_control.validation import parse_decimal, shorten

# A robot and everything it includes, however deep: bounds on the files and the chain.
MAX_INCLUDES = 64
MAX_INCLUDE_DEPTH = 8
# Elements that stay apart however many there are (STDR's stdr_multiple_allowed.xml).
SEPARATE = frozenset({'robot', 'laser', 'sonar', 'rfid_reader', 'point', 'co2_sensor',
                      'thermal_sensor', 'sound_sensor'})
UNSIMULATED = ('rfid_reader', 'co2_sensor', 'thermal_sensor', 'sound_sensor')
# STDR's defaults (stdr_specifications.xml), in its units: metres, radians, hertz.
LASER_DEFAULTS = {'max_angle': '1.57', 'min_angle': '-1.57', 'max_range': '4', 'min_range': '0',
                  'num_rays': '180', 'frequency': '10'}
SONAR_DEFAULTS = {'cone_angle': '1.0', 'max_range': '4', 'min_range': '0', 'frequency': '10'}
DEFAULT_RADIUS = '0.3'
KINEMATIC_PARAMETERS = tuple(f'a_{row}_{column}' for row in ('ux', 'uy', 'w', 'g')
                             for column in ('ux', 'uy', 'w'))
# What each element may hold (STDR's stdr_specifications.xml, the robot's part).
ALLOWED = {
    'robot': {'robot_specifications'},
    'robot_specifications': {'initial_pose', 'footprint', 'laser', 'sonar', 'kinematic',
                             *UNSIMULATED},
    'initial_pose': {'x', 'y', 'theta'},
    'pose': {'x', 'y', 'theta'},
    'footprint': {'footprint_specifications'},
    'footprint_specifications': {'radius', 'points'},
    'points': {'point'},
    'point': {'x', 'y'},
    'laser': {'laser_specifications'},
    'laser_specifications': {*LASER_DEFAULTS, 'frame_id', 'pose', 'noise'},
    'sonar': {'sonar_specifications'},
    'sonar_specifications': {*SONAR_DEFAULTS, 'frame_id', 'pose', 'noise'},
    'noise': {'noise_specifications'},
    'noise_specifications': {'noise_mean', 'noise_std'},
    'kinematic': {'kinematic_specifications'},
    'kinematic_specifications': {'kinematic_model', 'kinematic_parameters'},
    'kinematic_parameters': set(KINEMATIC_PARAMETERS),
}


class StdrFileError(ValueError):
    """A robot file in STDR's layouts that cannot be read: one line naming file and element."""


@dataclass
class Element:
    """A tagged element of STDR's tree, or a value (tag None); priority grows with inclusion."""

    tag: str | None
    value: str | None = None
    children: list = field(default_factory=list)
    source: str = ''
    line: int | None = None
    priority: int = 0

    def where(self) -> str:
        return f'{self.source}:{self.line}' if self.line else self.source

    def tagged(self, tag: str) -> list:
        return [child for child in self.children if child.tag == tag]


def is_stdr_layout(data: object) -> bool:
    """Whether YAML already read holds a robot in STDR's nested layout (robot: ...)."""
    return isinstance(data, dict) and set(data) == {'robot'}


def flat_from_xml(text: str, source: str, search_path: list, in_file: bool) -> dict:
    """
    Read an STDR robot XML text into the flat layout of robot_description.

    Included files are looked for as STDR looks for them: in its resources folder, which is
    the folder above a robot file's own (robots/ stands beside laser_sensors/, footprints/,
    ...) when the text is a file's (in_file), then beside the file that includes them, then in
    the folders of search_path.
    """
    reader = _Reader(search_path, _resources_of(source) if in_file else None)
    root = reader.document(text, source, 'xml')
    return _flat(root)


def flat_from_yaml(data: object, source: str, search_path: list, in_file: bool) -> dict:
    """Read an STDR nested-YAML robot (already parsed) into the flat layout, as flat_from_xml."""
    reader = _Reader(search_path, _resources_of(source) if in_file else None)
    root = reader.from_yaml(data, source, 0)
    reader.expand(root, (source,))
    return _flat(root)


def _resources_of(path):
    return os.path.dirname(os.path.dirname(os.path.abspath(path)))


class _Reader:
    """Reads a document and every file it includes, within MAX_INCLUDES and MAX_INCLUDE_DEPTH."""

    def __init__(self, search_path, resources):
        self._resources = [resources] if resources else []
        self._search_path = [os.fspath(folder) for folder in search_path]
        self._included = 0

    def document(self, text, source, kind, priority=0, chain=()):
        root = (self.from_xml(text, source, priority) if kind == 'xml'
                else self.from_yaml(parse_yaml(text, source, 'robot file', StdrFileError),
                                    source, priority))
        self.expand(root, chain + (source,))
        return root

    def from_xml(self, text, source, priority):
        """Build the tree of an XML text with expat, each element with its line."""
        parser = xml.parsers.expat.ParserCreate()
        stack = [Element('document', source=source, priority=priority)]
        texts = [[]]

        def start(tag, attributes):
            if len(stack) > MAX_NESTING:
                raise StdrFileError(f'{source}:{parser.CurrentLineNumber}: robot file is nested '
                                    f'more than {MAX_NESTING} levels deep')
            element = Element(tag, source=source, line=parser.CurrentLineNumber,
                              priority=priority)
            stack[-1].children.append(element)
            stack.append(element)
            texts.append([])

        def end(tag):
            words = ''.join(texts.pop()).strip()
            element = stack.pop()
            if words:
                element.children.append(Element(None, words, source=source, line=element.line,
                                                priority=priority))

        def refuse_doctype(*_):
            raise StdrFileError(f'{source}:{parser.CurrentLineNumber}: robot file declares a '
                                'DOCTYPE: STDR robot files have none, and none is read')
        parser.StartElementHandler, parser.EndElementHandler = start, end
        parser.CharacterDataHandler = lambda data: texts[-1].append(data)
        parser.StartDoctypeDeclHandler = refuse_doctype
        try:
            parser.Parse(text, True)
        except xml.parsers.expat.ExpatError as error:
            raise StdrFileError(f'{source}:{error.lineno}: robot file is not valid XML '
                                f'({xml.parsers.expat.ErrorString(error.code)})') from None
        return stack[0]

    def from_yaml(self, data, source, priority, tag='document'):
        """Build the tree of parsed YAML as STDR does: keys are tags, lists are flattened."""
        element = Element(tag, source=source, priority=priority)
        self._add_yaml(element, data, source, priority)
        return element

    def _add_yaml(self, element, data, source, priority):
        if isinstance(data, dict):
            for key, value in data.items():
                child = Element(str(key), source=source, priority=priority)
                element.children.append(child)
                self._add_yaml(child, value, source, priority)
        elif isinstance(data, list):
            for item in data:
                self._add_yaml(element, item, source, priority)
        elif data is not None:
            element.children.append(Element(None, str(data), source=source, priority=priority))

    def expand(self, element, chain):
        """Replace every filename element below element by what its file holds."""
        for child in list(element.children):
            if child.tag == 'filename':
                index = element.children.index(child)
                element.children[index:index + 1] = self._included_children(element, child,
                                                                            chain)
            elif child.tag is not None:
                self.expand(child, chain)

    def _included_children(self, parent, filename, chain):
        values = [child.value for child in filename.children if child.tag is None]
        if len(values) != 1:
            raise StdrFileError(f'{filename.where()}: {parent.tag}.filename: expected a file '
                                'name')
        name = values[0]
        if len(chain) > MAX_INCLUDE_DEPTH:
            raise StdrFileError(f'{filename.where()}: {parent.tag}.filename {shorten(name)}: '
                                f'files include each other more than {MAX_INCLUDE_DEPTH} deep')
        self._included += 1
        if self._included > MAX_INCLUDES:
            raise StdrFileError(f'{filename.where()}: more than {MAX_INCLUDES} files included')
        folders = self._search(filename.source)
        path = next((candidate for candidate in (
            [name] if os.path.isabs(name) else [os.path.join(folder, name) for folder in folders])
            if is_regular_file(candidate)), None)
        if path is None:
            looked = ', '.join(folders) or 'nowhere'
            raise StdrFileError(f'{filename.where()}: {parent.tag}.filename {shorten(name)}: no '
                                f'such file (looked in {looked})')
        kind = 'xml' if path.endswith('.xml') else 'yaml'
        text = read_text(path, 'included robot file', StdrFileError, MAX_DESCRIPTION_BYTES)
        root = self.document(text, path, kind, filename.priority + 1, chain)
        tops = [child for child in root.children if child.tag is not None]
        if len(tops) != 1 or tops[0].tag != parent.tag:
            found = ', '.join(child.tag for child in tops) or 'nothing'
            raise StdrFileError(f'{filename.where()}: {parent.tag}.filename {shorten(name)}: '
                                f'that file holds {found}, not a {parent.tag}')
        return tops[0].children

    def _search(self, including):
        """Return where an include is looked for: STDR's resources, its file's folder, the rest."""
        own = [os.path.dirname(os.path.abspath(including))] if os.path.exists(including) else []
        return list(dict.fromkeys(self._resources + own + self._search_path))


def _merged(element):
    """Merge repeated elements into their first, and keep the winning one of repeated values."""
    kept = []
    for child in element.children:
        if child.tag is None or child.tag in SEPARATE:
            kept.append(child)
            continue
        first = next((other for other in kept if other.tag == child.tag), None)
        if first is None:
            kept.append(child)
        else:
            first.children.extend(child.children)
            first.priority = min(first.priority, child.priority)
    values = [child for child in kept if child.tag is None]
    if values and len(values) == len(kept):
        kept = [min(values, key=lambda value: value.priority)]
    element.children = kept
    for child in kept:
        if child.tag is not None:
            _merged(child)
    return element


def _flat(root):
    """Write the merged tree of a robot in robot_description's flat layout."""
    root = _merged(root)
    robots = root.tagged('robot')
    if len(robots) != 1 or len(root.children) != 1:
        raise StdrFileError(f'{root.where()}: expected one robot element at the top, got '
                            f'{", ".join(str(child.tag) for child in root.children) or "none"}')
    _check_allowed(robots[0], 'robot')
    specs = _one(robots[0], 'robot_specifications', 'robot')
    if specs is None:
        raise StdrFileError(f'{robots[0].where()}: robot: robot_specifications is missing')
    flat = {'initial_pose': _pose(_one(specs, 'initial_pose', 'robot_specifications'),
                                  'initial_pose'),
            'footprint': _footprint(specs),
            'sensors': {'lasers': [], 'sonars': []},
            'unsimulated': []}
    for kind, defaults, label in (('laser', LASER_DEFAULTS, 'lasers'),
                                  ('sonar', SONAR_DEFAULTS, 'sonars')):
        for index, sensor in enumerate(specs.tagged(kind)):
            flat['sensors'][label].append(_sensor(sensor, kind, index, defaults))
    for kind in UNSIMULATED:
        for index, sensor in enumerate(specs.tagged(kind)):
            inner = _one(sensor, f'{kind}_specifications', kind)
            frame = _value(inner, 'frame_id', f'{kind}[{index}]') if inner else None
            flat['unsimulated'].append(f'{kind} {frame or f"{kind}_{index}"}')
    kinematic = _one(specs, 'kinematic', 'robot_specifications')
    if kinematic is not None:
        flat['kinematic'] = _kinematic(kinematic)
    return flat


def _check_allowed(element, path):
    allowed = ALLOWED.get(element.tag)
    for child in element.children:
        if child.tag is None:
            if allowed:
                raise StdrFileError(f'{child.where()}: {path}: a value where elements belong')
            continue
        if allowed is not None and child.tag not in allowed:
            raise StdrFileError(f'{child.where()}: {path}: unknown element {shorten(child.tag)} '
                                f'(allowed: {", ".join(sorted(allowed))})')
        _check_allowed(child, f'{path}.{child.tag}')


def _one(element, tag, path):
    found = element.tagged(tag) if element is not None else []
    if len(found) > 1:
        raise StdrFileError(f'{found[1].where()}: {path}.{tag}: given more than once')
    return found[0] if found else None


def _value(element, tag, path, default=None):
    """Return the text of element's child tag, or default when absent."""
    child = _one(element, tag, path) if element is not None else None
    if child is None:
        return default
    values = [item.value for item in child.children if item.tag is None]
    if len(values) != 1 or any(item.tag is not None for item in child.children):
        raise StdrFileError(f'{child.where()}: {path}.{tag}: expected a value')
    return values[0]


def _number(element, tag, path, default):
    text = _value(element, tag, path, default)
    value = parse_decimal(text) if text is not None else None
    if value is None:
        child = _one(element, tag, path)
        raise StdrFileError(f'{child.where() if child else element.where()}: {path}.{tag}: '
                            f'expected a number, got {shorten(repr(text))}')
    return value


def _pose(element, path):
    return {axis: _number(element, axis, path, '0') if element is not None else 0.0
            for axis in ('x', 'y', 'theta')}


def _footprint(specs):
    footprint = _one(specs, 'footprint', 'robot_specifications')
    inner = _one(footprint, 'footprint_specifications', 'footprint') if footprint else None
    radius = _number(inner, 'radius', 'footprint', DEFAULT_RADIUS) if inner else float(
        DEFAULT_RADIUS)
    points = _one(inner, 'points', 'footprint') if inner else None
    corners = [[_number(point, 'x', f'footprint.points.point[{index}]', '0'),
                _number(point, 'y', f'footprint.points.point[{index}]', '0')]
               for index, point in enumerate(points.tagged('point') if points else [])]
    return {'radius': radius, 'points': corners}


def _sensor(sensor, kind, index, defaults):
    path = f'{kind}[{index}]'
    inner = _one(sensor, f'{kind}_specifications', path)
    if inner is None:
        raise StdrFileError(f'{sensor.where()}: {path}: {kind}_specifications is missing')
    spec = {name: _number(inner, name, path, default) for name, default in defaults.items()}
    spec['frame_id'] = _value(inner, 'frame_id', path, f'{kind}_{index}')
    spec['pose'] = _pose(_one(inner, 'pose', path), f'{path}.pose')
    noise = _one(inner, 'noise', path)
    noise = _one(noise, 'noise_specifications', f'{path}.noise') if noise else None
    spec['noise'] = {'mean': _number(noise, 'noise_mean', f'{path}.noise', '0') if noise else 0.0,
                     'std': _number(noise, 'noise_std', f'{path}.noise', '0') if noise else 0.0}
    return spec


def _kinematic(kinematic):
    inner = _one(kinematic, 'kinematic_specifications', 'kinematic')
    if inner is None:
        raise StdrFileError(f'{kinematic.where()}: kinematic: kinematic_specifications is '
                            'missing')
    parameters = _one(inner, 'kinematic_parameters', 'kinematic')
    return {'model': _value(inner, 'kinematic_model', 'kinematic', 'ideal'),
            'parameters': {name: _number(parameters, name, 'kinematic.kinematic_parameters', '0')
                           if parameters else 0.0 for name in KINEMATIC_PARAMETERS}}

"""
Node parameters: declared with their ranges, checked at start and whenever they are set.

Every parameter a node takes is a ParameterSpec; a value given on the command line or in a
parameters file is judged by the same rule as one set at run time, a whole number is taken for a
double (users type `3`, `ros2 param set x 3` sends an INTEGER), and a parameter the node does not
know is refused with the name of the closest one it does.
"""

from dataclasses import dataclass
import difflib

from rcl_interfaces.msg import ParameterDescriptor, ParameterType, SetParametersResult
from rclpy.exceptions import ParameterException, ParameterUninitializedException
from rclpy.parameter import Parameter
from simple_robot_control.node_runtime import ConfigError
from simple_robot_control.validation import Bounds, compact, is_finite_number, ros_name_problem

# A list default is a list of doubles, a tuple one of strings (an empty one has no type of its
# own in rclpy, so a string-array parameter is declared by its type and read as empty unset).
_TYPES = {bool: ParameterType.PARAMETER_BOOL, int: ParameterType.PARAMETER_INTEGER,
          float: ParameterType.PARAMETER_DOUBLE, str: ParameterType.PARAMETER_STRING,
          list: ParameterType.PARAMETER_DOUBLE_ARRAY, tuple: ParameterType.PARAMETER_STRING_ARRAY}
# What rclpy itself declares or reads on every node, besides the node's own parameters.
_RCLPY_PARAMETERS = ('use_sim_time', 'start_type_description_service')
_RCLPY_PREFIXES = ('qos_overrides.',)


@dataclass(frozen=True)
class ParameterSpec:
    """
    One node parameter: its default, a description with units, and what values it accepts.

    bounds limits a number, choices a string, ros_name makes a string a ROS name (a robot or
    frame name that goes into topics); constraints adds words for what none of those can say.
    A parameter is read-only unless tunable, in which case `ros2 param set` may change it while
    the node runs, under the same checks as at start.
    """

    name: str
    default: object
    description: str
    bounds: Bounds | None = None
    choices: tuple = ()
    ros_name: bool = False
    constraints: str = ''
    tunable: bool = False

    def constraint_text(self) -> str:
        words = [self.bounds.text()] if self.bounds else []
        if self.choices:
            words.append(' | '.join(self.choices))
        if self.ros_name:
            words.append('a ROS name')
        if self.constraints:
            words.append(self.constraints)
        return '; '.join(words)

    def descriptor(self) -> ParameterDescriptor:
        return ParameterDescriptor(name=self.name, type=_TYPES[type(self.default)],
                                   description=self.description,
                                   additional_constraints=self.constraint_text(),
                                   read_only=not self.tunable)

    def problem(self, value) -> str | None:
        """Return one line saying why value is not acceptable, or None."""
        if self.bounds is not None:
            return self.bounds.problem(self.name, value)
        if self.choices and value not in self.choices:
            return f'{self.name} must be one of {", ".join(self.choices)}, got {value!r}'
        if self.ros_name:
            return ros_name_problem(value, self.name)
        if isinstance(self.default, list) and not all(is_finite_number(item) for item in value):
            return f'{self.name} must hold finite numbers, got {[compact(v) for v in value]}'
        return None

    def as_declared_type(self, parameter: Parameter) -> Parameter:
        """Return parameter as a double (or doubles) where it is a whole number for one."""
        if isinstance(self.default, float) and parameter.type_ == Parameter.Type.INTEGER:
            return Parameter(parameter.name, Parameter.Type.DOUBLE, float(parameter.value))
        if isinstance(self.default, list) and parameter.type_ == Parameter.Type.INTEGER_ARRAY:
            return Parameter(parameter.name, Parameter.Type.DOUBLE_ARRAY,
                             [float(value) for value in parameter.value])
        return parameter

    def help_line(self) -> str:
        default = (list(self.default) if isinstance(self.default, tuple)
                   else self.default if self.default != '' else "''")
        constraints = self.constraint_text()
        extra = ', '.join(part for part in (constraints, 'tunable' if self.tunable else '')
                          if part)
        return f'  {self.name} [default {default}]: {self.description}' + (
            f' ({extra})' if extra else '')


def declare_parameters(node, specs):
    """
    Declare specs on node and return their checked values by name; problems are ConfigErrors.

    Values given to the node for parameters it does not declare are refused too.
    """
    # rclpy keeps the values given on the command line and in parameter files here, and has
    # no public accessor: they are read once, to take whole numbers for doubles and to find
    # names the node does not know.
    overrides = getattr(node, '_parameter_overrides', {})
    values = {}
    for spec in specs:
        if spec.name in overrides:
            overrides[spec.name] = spec.as_declared_type(overrides[spec.name])
        try:
            value = _declared(node, spec)
        except ParameterException as error:
            raise ConfigError(f'parameter {spec.name}: {error} (expected a '
                              f'{type(spec.default).__name__})') from None
        value = type(spec.default)(value) if isinstance(spec.default, (list, tuple)) else value
        problem = spec.problem(value)
        if problem is not None:
            raise ConfigError(problem)
        values[spec.name] = value
    _refuse_unknown(node.get_name(), overrides, [spec.name for spec in specs])
    return values


def _declared(node, spec):
    """Declare spec on node and return its value."""
    if isinstance(spec.default, tuple):
        node.declare_parameter(spec.name, Parameter.Type.STRING_ARRAY, spec.descriptor())
        try:
            value = node.get_parameter(spec.name).value
        except ParameterUninitializedException:
            return spec.default
        return spec.default if value is None else value
    node.declare_parameter(spec.name, spec.default, spec.descriptor())
    return node.get_parameter(spec.name).value


def _refuse_unknown(node_name, given, known):
    unknown = sorted(name for name in given if name not in known
                     and name not in _RCLPY_PARAMETERS and not name.startswith(_RCLPY_PREFIXES))
    if not unknown:
        return
    name = unknown[0]
    close = difflib.get_close_matches(name, known, n=1, cutoff=0.6)
    hint = f'; did you mean {close[0]}?' if close else f'; {node_name} takes {", ".join(known)}'
    raise ConfigError(f'unknown parameter {name!r} for {node_name}{hint}')


def accept_tuning(node, specs, apply):
    """
    Let `ros2 param set` change the tunable specs while node runs.

    A request is checked whole, by the same rules as at start: if every value is acceptable,
    apply(values by name) receives them all; otherwise none is taken and the reply names the
    first problem. Read-only parameters are refused by rclpy itself. A whole number given for
    a double is taken as that double.
    """
    by_name = {spec.name: spec for spec in specs}
    tunable = {spec.name: spec for spec in specs if spec.tunable}

    def as_declared_types(parameters):
        return [by_name[parameter.name].as_declared_type(parameter)
                if parameter.name in by_name else parameter for parameter in parameters]

    def on_set(parameters):
        changes = {}
        for parameter in parameters:
            spec = tunable.get(parameter.name)
            if spec is None:
                continue
            problem = spec.problem(parameter.value)
            if problem is not None:
                node.get_logger().warn(f'refused: {problem}')
                return SetParametersResult(successful=False, reason=problem)
            changes[parameter.name] = parameter.value
        if changes:
            apply(changes)
            node.get_logger().info('tuned: ' + ', '.join(
                f'{name} = {compact(value)}' for name, value in changes.items()))
        return SetParametersResult(successful=True)

    node.add_pre_set_parameters_callback(as_declared_types)
    node.add_on_set_parameters_callback(on_set)

"""
Node parameters: declared with their ranges, checked at start and whenever they are set.

Every parameter a node takes is a ParameterSpec (parameter_specs.py); a value given on the
command line or in a parameters file is judged by the same rule as one set at run time, a whole
number is taken for a double (users type `3`, `ros2 param set x 3` sends an INTEGER), and a
parameter the node does not know is refused with the name of the closest one it does.
"""

from collections.abc import Callable, Sequence

from rcl_interfaces.msg import ParameterDescriptor, ParameterType, SetParametersResult
from rclpy.exceptions import ParameterException, ParameterUninitializedException
from rclpy.node import Node
from rclpy.parameter import Parameter
from simple_robot_control.parameter_specs import ParameterSpec, unknown_problem
from simple_robot_control.validation import compact, ConfigError

# A list default is a list of doubles, a tuple one of strings (an empty one has no type of its
# own in rclpy, so a string-array parameter is declared by its type and read as empty unset).
_TYPES = {bool: ParameterType.PARAMETER_BOOL, int: ParameterType.PARAMETER_INTEGER,
          float: ParameterType.PARAMETER_DOUBLE, str: ParameterType.PARAMETER_STRING,
          list: ParameterType.PARAMETER_DOUBLE_ARRAY, tuple: ParameterType.PARAMETER_STRING_ARRAY}
# Whole numbers given for a double, or a list of doubles, are taken as such.
_WIDENED = {Parameter.Type.INTEGER: Parameter.Type.DOUBLE,
            Parameter.Type.INTEGER_ARRAY: Parameter.Type.DOUBLE_ARRAY}


def descriptor(spec: ParameterSpec) -> ParameterDescriptor:
    """Return the descriptor `ros2 param describe` shows for spec."""
    return ParameterDescriptor(name=spec.name, type=_TYPES[type(spec.default)],
                               description=spec.description,
                               additional_constraints=spec.constraint_text(),
                               read_only=not spec.tunable)


def as_declared_type(spec: ParameterSpec, parameter: Parameter) -> Parameter:
    """Return parameter as a double (or doubles) where it is a whole number for one."""
    widened = _WIDENED.get(parameter.type_)
    if widened is None or widened.value != _TYPES[type(spec.default)]:
        return parameter
    return Parameter(parameter.name, widened, spec.as_declared_type(parameter.value))


def declare_parameters(node: Node, specs: Sequence[ParameterSpec]) -> dict:
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
            overrides[spec.name] = as_declared_type(spec, overrides[spec.name])
        try:
            value = _declared(node, spec)
        except ParameterException as error:
            given = overrides.get(spec.name)
            raise ConfigError(spec.type_problem(given.value) if given is not None
                              else f'parameter {spec.name}: {error}') from None
        value = type(spec.default)(value) if isinstance(spec.default, (list, tuple)) else value
        problem = spec.problem(value)
        if problem is not None:
            raise ConfigError(problem)
        values[spec.name] = value
    problem = unknown_problem(node.get_name(), overrides, specs)
    if problem is not None:
        raise ConfigError(problem)
    return values


def _declared(node, spec):
    """Declare spec on node and return its value."""
    if isinstance(spec.default, tuple):
        node.declare_parameter(spec.name, Parameter.Type.STRING_ARRAY, descriptor(spec))
        try:
            value = node.get_parameter(spec.name).value
        except ParameterUninitializedException:
            return spec.default
        return spec.default if value is None else value
    node.declare_parameter(spec.name, spec.default, descriptor(spec))
    return node.get_parameter(spec.name).value


def accept_tuning(node: Node, specs: Sequence[ParameterSpec], apply: Callable[[dict], None]
                  ) -> None:
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
        return [as_declared_type(by_name[parameter.name], parameter)
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

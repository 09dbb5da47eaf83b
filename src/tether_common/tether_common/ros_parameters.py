"""Declare a node's :class:`~tether_common.parameters.ParamSpec` tuple with rclpy.

Each parameter gets a descriptor (description with unit, range, read-only flag) and an
on-set callback rejects values outside the specification with the reason.
"""

from __future__ import annotations

from rcl_interfaces.msg import FloatingPointRange
from rcl_interfaces.msg import IntegerRange
from rcl_interfaces.msg import ParameterDescriptor
from rcl_interfaces.msg import SetParametersResult
from rclpy.exceptions import ParameterUninitializedException
from rclpy.node import Node
from rclpy.parameter import Parameter

from tether_common.parameters import ParamSpec
from tether_common.parameters import spec_table


def declare_parameters(node: Node, specs: tuple[ParamSpec, ...]) -> dict[str, object]:
    """Declare every parameter of ``specs`` on ``node`` and return their current values."""
    table = spec_table(specs)
    for spec in specs:
        initial = spec.default if spec.default != [] else _ARRAY_TYPES[spec.element_type]
        node.declare_parameter(spec.name, initial, _descriptor(spec))

    def on_set(parameters):
        for parameter in parameters:
            spec = table.get(parameter.name)
            if spec is None:
                continue
            reason = spec.check(parameter.value)
            if reason:
                return SetParametersResult(successful=False, reason=f'{parameter.name}: {reason}')
        return SetParametersResult(successful=True)

    node.add_on_set_parameters_callback(on_set)
    values = {}
    for spec in specs:
        try:
            value = node.get_parameter(spec.name).value
        except ParameterUninitializedException:
            value = []
        reason = spec.check(value)
        if reason:
            raise ValueError(f'parameter {spec.name}: {reason}')
        values[spec.name] = spec.coerce(value)
    return values


_ARRAY_TYPES = {
    bool: Parameter.Type.BOOL_ARRAY,
    int: Parameter.Type.INTEGER_ARRAY,
    float: Parameter.Type.DOUBLE_ARRAY,
    str: Parameter.Type.STRING_ARRAY,
}


def _descriptor(spec: ParamSpec) -> ParameterDescriptor:
    description = spec.description + (f' [{spec.unit}]' if spec.unit else '')
    descriptor = ParameterDescriptor(
        description=description,
        read_only=spec.read_only,
        additional_constraints=spec.expected(),
    )
    if spec.kind is float and (spec.low is not None or spec.high is not None):
        descriptor.floating_point_range = [FloatingPointRange(
            from_value=float(spec.low if spec.low is not None else -1e308),
            to_value=float(spec.high if spec.high is not None else 1e308),
        )]
    elif spec.kind is int and (spec.low is not None or spec.high is not None):
        descriptor.integer_range = [IntegerRange(
            from_value=int(spec.low if spec.low is not None else -(2**62)),
            to_value=int(spec.high if spec.high is not None else 2**62),
            step=1,
        )]
    return descriptor

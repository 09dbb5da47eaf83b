"""Declare a node's :class:`~tether_common.parameters.ParamSpec` tuple with rclpy.

Each parameter gets a descriptor (description with unit, range, read-only flag) and an
on-set callback rejects values outside the specification with the reason.

A value given at start (``--ros-args -p``, a parameters file) is checked against the
specification before rclpy applies the descriptor: a wrong type, an out-of-range value,
an unknown choice or a missing file raises :class:`ConfigurationError` naming the
parameter, the value and what is expected (the shared node main prints it as one line
and exits with status 2). An integer given for a floating-point parameter
(``state_rate:=50``) is accepted as that number.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rcl_interfaces.msg import FloatingPointRange
from rcl_interfaces.msg import IntegerRange
from rcl_interfaces.msg import ParameterDescriptor
from rcl_interfaces.msg import SetParametersResult
from rclpy.node import Node
from rclpy.parameter import Parameter

from tether_common.node_main import ConfigurationError
from tether_common.parameters import ParamSpec
from tether_common.parameters import spec_table


def declare_parameters(node: Node, specs: tuple[ParamSpec, ...],
                       on_change: Callable[[str, object], None] | None = None) -> dict[str, Any]:
    """Declare every parameter of ``specs`` on ``node`` and return their checked values.

    Each parameter is first declared dynamically typed, so that rclpy takes any value
    given at start; the value is checked against its specification, converted to the
    parameter's type, and only then is the final descriptor (static type, range,
    read-only) applied.

    A writable parameter (``read_only=False``) must take effect: ``on_change(name,
    value)`` is called with each accepted new value, and declaring a writable parameter
    without it is refused.
    """
    table = spec_table(specs)
    writable = [spec.name for spec in specs if not spec.read_only]
    if writable and on_change is None:
        raise ValueError(f'{node.get_name()}: writable parameter(s) {", ".join(writable)} need an on_change '
                         'that applies them; declare them read_only otherwise')
    values = {}
    for spec in specs:
        node.declare_parameter(spec.name, None if spec.default == [] else spec.default,
                               ParameterDescriptor(dynamic_typing=True))
        value = node.get_parameter(spec.name).value
        if value is None:
            value = []
        reason = spec.check(value)
        if reason:
            raise ConfigurationError(f'parameter {spec.name}: {reason}')
        values[spec.name] = spec.coerce(value)
        typed = Parameter(spec.name, _parameter_type(spec), values[spec.name])
        node.set_descriptor(spec.name, _descriptor(spec), typed.get_parameter_value())

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
    if writable:
        def on_accepted(parameters):
            for parameter in parameters:
                if parameter.name in writable:
                    on_change(parameter.name, table[parameter.name].coerce(parameter.value))

        node.add_post_set_parameters_callback(on_accepted)
    return values


_SCALAR_TYPES = {
    bool: Parameter.Type.BOOL,
    int: Parameter.Type.INTEGER,
    float: Parameter.Type.DOUBLE,
    str: Parameter.Type.STRING,
}
_ARRAY_TYPES: dict[type | None, Parameter.Type] = {
    bool: Parameter.Type.BOOL_ARRAY,
    int: Parameter.Type.INTEGER_ARRAY,
    float: Parameter.Type.DOUBLE_ARRAY,
    str: Parameter.Type.STRING_ARRAY,
}


def _parameter_type(spec: ParamSpec) -> Parameter.Type:
    if spec.kind is list:
        return _ARRAY_TYPES[spec.element_type]
    return _SCALAR_TYPES[spec.kind]


def _descriptor(spec: ParamSpec) -> ParameterDescriptor:
    description = spec.description + (f' [{spec.unit}]' if spec.unit else '')
    descriptor = ParameterDescriptor(
        description=description,
        type=_parameter_type(spec).value,
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

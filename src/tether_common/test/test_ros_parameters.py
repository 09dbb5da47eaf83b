"""declare_parameters: values checked at start, read-only refused, writable applied."""

from __future__ import annotations

import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter

from tether_common.node_main import ConfigurationError
from tether_common.parameters import ParamSpec
from tether_common.ros_parameters import declare_parameters

SPECS = (
    ParamSpec('gain', 1.0, 'controller gain', low=0.0, high=10.0, read_only=False),
    ParamSpec('rate', 50.0, 'control rate', 'Hz', low=1.0, high=1000.0),
    ParamSpec('names', [], 'names', item_type=str),
)


def _node(context, *overrides):
    return Node('params', context=context, parameter_overrides=list(overrides))


def test_integers_for_doubles_are_doubles_and_bad_values_are_configuration_errors(ros_context):
    node = _node(ros_context, Parameter('rate', value=20), Parameter('gain', value=2))
    values = declare_parameters(node, SPECS, on_change=lambda name, value: None)
    assert values == {'gain': 2.0, 'rate': 20.0, 'names': []}
    assert isinstance(values['rate'], float)
    assert node.get_parameter('rate').type_ == Parameter.Type.DOUBLE
    assert node.get_parameter('names').type_ == Parameter.Type.STRING_ARRAY
    bad = _node(ros_context, Parameter('rate', value=5000.0))
    with pytest.raises(ConfigurationError, match=r'^parameter rate: expected a number in \[1, 1000\] \(Hz\), got 5000.0$'):
        declare_parameters(bad, SPECS, on_change=lambda name, value: None)


def test_writable_parameter_takes_effect_and_read_only_is_refused(ros_context):
    node = _node(ros_context)
    changes = []
    declare_parameters(node, SPECS, on_change=lambda name, value: changes.append((name, value)))
    assert node.set_parameters([Parameter('gain', value=2.5)])[0].successful
    assert changes == [('gain', 2.5)]
    refused = node.set_parameters([Parameter('gain', value=20.0), Parameter('rate', value=10.0)])
    assert [r.successful for r in refused] == [False, False]
    assert 'read-only' in refused[1].reason
    assert changes == [('gain', 2.5)]
    assert node.get_parameter('rate').value == 50.0


def test_writable_parameter_without_a_way_to_apply_it_is_refused(ros_context):
    with pytest.raises(ValueError, match='writable parameter.* gain need an on_change'):
        declare_parameters(_node(ros_context), SPECS)

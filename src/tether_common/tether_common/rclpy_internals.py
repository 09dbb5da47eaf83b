"""The only place tethersim reaches below rclpy's public API, with the assumption each use makes.

rclpy (Jazzy) has no public way to do these three things; each is kept here, small, so that an
rclpy upgrade that breaks one breaks it here, and ``src/tether_common/test/test_rclpy_internals.py``
checks every assumption below against the installed rclpy and fails naming it.

1. :data:`RCLError`: the exception ``rclpy.init`` raises for arguments rcl refuses (a bad
   ``--ros-args``), from rclpy's private C extension; rclpy re-exports it nowhere public.
   Assumption: ``rclpy.impl.implementation_singleton.rclpy_implementation.RCLError`` is an
   ``Exception`` subclass and is what ``rclpy.init`` raises for bad arguments.
2. :func:`idle_reader`: a DDS reader of a topic that the node's executor never sees (it keeps
   a linked subscription matched in the graph, :mod:`tether_common.lockstep`). A public
   ``create_subscription`` registers it with the node, which the executor waits on and takes
   from. Assumption: ``rclpy_implementation.Subscription(node.handle, msg_type, topic,
   c_qos_profile)`` makes such a reader, counted by the publisher's ``get_subscription_count``,
   absent from ``node.subscriptions``, freed by ``destroy_when_not_in_use()``.
3. :func:`as_subclass`: turning a publisher a node already made into a subclass of
   ``rclpy.publisher.Publisher`` (the public way, ``create_publisher(..., publisher_class=)``,
   works only where the publisher is made, inside every node). Assumption: ``Publisher`` is a
   plain Python class without ``__slots__``, so an instance's class can be set to a subclass
   that only adds instance attributes and overrides ``publish``, and the node's own list of
   publishers (``node.publishers``) holds that same object.
"""

from __future__ import annotations

from typing import TypeVar, cast

from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile

RCLError = _rclpy.RCLError
"""The exception of rcl's refusals (rclpy's private ``_rclpy_pybind11.RCLError``)."""

P = TypeVar('P', bound=Publisher)


def idle_reader(node: Node, msg_type: type, topic: str, qos: QoSProfile):
    """A DDS reader of ``topic`` on ``node``'s rcl node that no executor sees; the caller destroys it
    with ``destroy_when_not_in_use()`` before the node.
    """
    with node.handle:
        return _rclpy.Subscription(node.handle, msg_type, topic, qos.get_c_qos_profile())


def as_subclass(publisher: Publisher, cls: type[P]) -> P:
    """The same publisher object, now of ``cls`` (a subclass of ``Publisher`` that adds only instance
    attributes, which the caller sets).
    """
    if not issubclass(cls, type(publisher)):
        msg = f'{cls.__name__} is not a subclass of {type(publisher).__name__}'
        raise TypeError(msg)
    publisher.__class__ = cls
    return cast(P, publisher)

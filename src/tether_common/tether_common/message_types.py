"""Message classes by their ROS type names or field types."""

from __future__ import annotations

import importlib


def message_class(type_name: str) -> type:
    """Import the Python class of ``pkg/msg/Type`` (or ``pkg/Type``)."""
    package, *_, name = type_name.split('/')
    return getattr(importlib.import_module(f'{package}.msg'), name)


def field_class(slot_type) -> type:
    """The Python class of a message field's type (a ``rosidl_parser`` ``NamespacedType``)."""
    return getattr(importlib.import_module('.'.join(slot_type.namespaces)), slot_type.name)

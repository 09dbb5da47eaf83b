"""Message classes by their ROS type names."""

from __future__ import annotations

import importlib


def message_class(type_name: str) -> type:
    """Import the Python class of ``pkg/msg/Type`` (or ``pkg/Type``)."""
    package, *_, name = type_name.split('/')
    return getattr(importlib.import_module(f'{package}.msg'), name)

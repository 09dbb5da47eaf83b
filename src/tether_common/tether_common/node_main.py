"""The one ``main`` every tethersim node uses: init, spin, clean exit.

Ctrl-C, SIGTERM and an external shutdown end the node normally (exit status 0). A
:class:`ConfigurationError` raised while the node is built (a bad parameter, a missing
file) is logged as one line and ends the process with status 2, without a traceback.
"""

from __future__ import annotations

import sys
from collections.abc import Callable

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


class ConfigurationError(Exception):
    """A node cannot start with the parameters or files it was given."""


def run_node(factory: Callable[[], Node], args: list[str] | None = None) -> int:
    """Build the node with ``factory`` and spin it until shutdown; return the exit status."""
    rclpy.init(args=args)
    node = None
    status = 0
    try:
        node = factory()
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except ConfigurationError as error:
        print(f'error: {error}', file=sys.stderr, flush=True)
        status = 2
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return status

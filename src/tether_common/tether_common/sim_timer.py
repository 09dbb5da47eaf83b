"""A sim-time timer that never drops a tick.

An rclpy timer driven by ``/clock`` fires once when sim time jumps over several periods
(a busy machine, a high real-time factor), silently skipping the ticks in between. This
timer runs its callback once for every period that has elapsed, in order, each time with
the tick's own sim time, so a node publishes the same messages with the same stamps however
late its process gets to run.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from rclpy.node import Node
from rclpy.time import Time


class SimTimer:
    """Call ``callback(tick_time)`` at every multiple of ``period`` of the node's clock.

    The first tick is the first multiple of ``period`` after the clock's time at creation
    (``period`` itself for a node created before ``/clock`` starts).
    """

    def __init__(self, node: Node, period: float, callback: Callable[[Time], None]) -> None:
        if not period > 0:
            raise ValueError(f'period must be positive, got {period}')
        self.period_ns = round(period * 1e9)
        self._node = node
        self._callback = callback
        start_ns = node.get_clock().now().nanoseconds
        self._next_ns = max(1, math.ceil(start_ns / self.period_ns)) * self.period_ns
        self.timer = node.create_timer(period, self._on_timer)

    def _on_timer(self) -> None:
        now_ns = self._node.get_clock().now().nanoseconds
        while self._next_ns <= now_ns:
            self._callback(Time(nanoseconds=self._next_ns, clock_type=self._node.get_clock().clock_type))
            self._next_ns += self.period_ns

"""What the machine's cores did during a run, from the kernel's ``/proc/stat``.

A run's real-time factor depends on the cores it gets. On a virtual machine the hypervisor
may run other guests on them (*steal*: time the guest's cores were ready to run but not
running), and other processes on the machine take their share; both lower the achieved
factor while leaving a process's CPU per simulated second as it was. The run summary splits
the cores' time between its marks into this run's processes, the machine's other processes,
idle and stolen, so a slow run says why.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

STAT = Path('/proc/stat')


@dataclass(frozen=True)
class CoreTimes:
    """Core-seconds of all cores since boot: busy (user, nice, system, irq, softirq), idle (with
    I/O wait), stolen by the hypervisor, and their sum.
    """

    busy: float
    idle: float
    steal: float
    total: float


def parse_stat(text: str, ticks_per_second: float) -> CoreTimes | None:
    """The aggregate ``cpu`` line of ``/proc/stat`` (proc(5): user nice system idle iowait irq
    softirq steal guest guest_nice, in clock ticks; guest time is already in user and nice),
    or None if the text has none.
    """
    fields = text.split('\n', 1)[0].split()
    if len(fields) < 9 or fields[0] != 'cpu':
        return None
    user, nice, system, idle, iowait, irq, softirq, steal = (int(value) for value in fields[1:9])
    total = user + nice + system + idle + iowait + irq + softirq + steal
    busy = total - idle - iowait - steal
    return CoreTimes(busy / ticks_per_second, (idle + iowait) / ticks_per_second, steal / ticks_per_second,
                     total / ticks_per_second)


def core_times() -> CoreTimes | None:
    """This machine's :class:`CoreTimes` now; None where ``/proc/stat`` cannot be read."""
    try:
        text = STAT.read_text()
    except OSError:
        return None
    return parse_stat(text, os.sysconf('SC_CLK_TCK'))


def shares(start: CoreTimes, end: CoreTimes, ours: float) -> dict[str, float] | None:
    """Fractions of the cores' time between ``start`` and ``end``: this run (``ours``, the CPU
    seconds its processes used meanwhile, at most what the cores were busy), other processes,
    idle, stolen; None over an interval too short for the kernel's counters to move.
    """
    total = end.total - start.total
    if total <= 0:
        return None
    busy = end.busy - start.busy
    run = min(max(ours, 0.0), busy)
    return {'this run': run / total, 'other processes': (busy - run) / total,
            'idle': (end.idle - start.idle) / total, 'stolen by the hypervisor': (end.steal - start.steal) / total}

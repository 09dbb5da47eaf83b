"""Test doubles of run reports (``module:function`` in a scene's ``reports``), for the bringup's report phase.

``plot_report`` writes one PNG and a line; ``slow_report`` writes the file named by
``$SLOW_REPORT_STARTED`` and then sleeps, so a test can signal the bringup while a report runs.
"""

import os
import time
from pathlib import Path

PNG = bytes.fromhex('89504e470d0a1a0a')


def plot_report(bag: str, out: str) -> list[str]:
    """Write ``plot_report.png`` into the run directory."""
    (Path(out) / 'plot_report.png').write_bytes(PNG)
    return ['plot report: done']


def slow_report(bag: str, out: str) -> list[str]:
    """Announce the start, then take far longer than any test waits."""
    Path(os.environ['SLOW_REPORT_STARTED']).write_text('started')
    time.sleep(600)
    return ['slow report: done']

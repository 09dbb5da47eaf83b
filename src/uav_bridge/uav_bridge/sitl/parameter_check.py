"""Confirm that SITL took the parameters a scene sets (no rclpy import).

SITL reads a scene's ``parameters`` from its defaults file and skips a name its ArduPilot
version does not have without a word (ArduCopter 4.7 renamed ``WPNAV_SPEED_UP`` to
``WP_SPD_UP``: the old name left the climb at 2.5 m/s, outrunning the reel). This check asks
SITL for each name on its second MAVLink port (SERIAL1, TCP 5762 + 10 x instance; the bridge
keeps 5760) with PARAM_REQUEST_READ and compares the PARAM_VALUE it answers. ArduPilot answers
nothing for a name it lacks, so a name still unanswered after ``patience`` of SITL's 1 Hz
HEARTBEATs (SITL time: SITL on the JSON physics runs only as fast as the graph) is unknown.
Reading parameters changes nothing in the autopilot, and the check closes its link once it is
done, during ArduCopter's wait for its EKF. A SITL that sends no HEARTBEAT for ``silence``
seconds of wall time ends the check with that reason (the whole graph may take minutes to
start, and SITL on the JSON physics is silent until the graph runs; a dead SITL is the sitl
node's watch's to report).
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass
from dataclasses import field

from pymavlink import mavutil

SYSTEM_ID = 254
"""The check's MAVLink system id: not the bridge's (255), so the autopilot keeps them apart."""
REQUEST_EVERY = 2
"""HEARTBEATs between requests of a name still unanswered (a request sent before SITL's link was up is lost)."""


@dataclass
class CheckResult:
    """What SITL answered: the names it confirmed, the unknown ones, those it holds at another value."""

    confirmed: dict[str, float] = field(default_factory=dict)
    unknown: list[str] = field(default_factory=list)
    different: dict[str, tuple[float, float]] = field(default_factory=dict)
    error: str = ''

    def problem(self) -> str:
        """One line naming what is wrong, or '' when SITL took every parameter."""
        parts = []
        if self.unknown:
            parts.append(f'SITL has no parameter {", ".join(self.unknown)} (it skips such a name in its defaults '
                         'file; check the name for this ArduPilot version)')
        if self.different:
            parts.append('SITL holds ' + ', '.join(f'{name} = {held:g}, not {wanted:g}'
                                                   for name, (wanted, held) in self.different.items()))
        if self.error:
            parts.append(self.error)
        return '; '.join(parts)


def _same(wanted: float, held: float) -> bool:
    """PARAM_VALUE carries a float32: equal to float32 precision."""
    return math.isclose(wanted, held, rel_tol=1e-6, abs_tol=1e-6)


def check_parameters(url: str, wanted: dict[str, float], patience: int = 10, stop: threading.Event | None = None,
                     connect_timeout: float = 600.0, silence: float = 600.0) -> CheckResult:
    """Ask the autopilot at ``url`` for each of ``wanted`` (name: value) and compare.

    ``patience`` HEARTBEATs without an answer make a name unknown; ``stop`` ends the check early
    (the names not yet answered are then neither confirmed nor unknown).
    """
    result = CheckResult()
    stop = stop or threading.Event()
    try:
        link = mavutil.mavlink_connection(url, source_system=SYSTEM_ID, source_component=1, autoreconnect=False,
                                          retries=int(connect_timeout))
    except OSError as error:
        result.error = f'parameter check on {url}: {error}'
        return result
    try:
        pending = {name.upper(): float(value) for name, value in wanted.items()}
        beats = 0
        heard = time.monotonic()
        while pending and not stop.is_set():
            msg = link.recv_match(type=['HEARTBEAT', 'PARAM_VALUE'], blocking=True, timeout=0.5)
            if msg is None:
                if time.monotonic() - heard > silence:
                    result.error = (f'parameter check on {url}: no HEARTBEAT for {silence:g} s; '
                                    f'{", ".join(sorted(pending))} not confirmed')
                    break
                continue
            heard = time.monotonic()
            if msg.get_type() == 'PARAM_VALUE':
                name = msg.param_id.rstrip('\x00')
                if name in pending:
                    wanted_value = pending.pop(name)
                    if _same(wanted_value, msg.param_value):
                        result.confirmed[name] = wanted_value
                    else:
                        result.different[name] = (wanted_value, float(msg.param_value))
                continue
            if msg.get_srcComponent() != mavutil.mavlink.MAV_COMP_ID_AUTOPILOT1:
                continue
            if beats >= patience:
                result.unknown = sorted(pending)
                break
            if beats % REQUEST_EVERY == 0:
                for name in pending:
                    link.mav.param_request_read_send(msg.get_srcSystem(), msg.get_srcComponent(), name.encode(), -1)
            beats += 1
    finally:
        link.close()
    return result

"""After-run report of a UAV flight: station keeping during the mission's hold phase, from a bag.

Reads ``/uav/pose`` (world, ENU), ``/mission/state`` (phases, station) and ``/uav/state``
(link staleness, reconnects, reboots). During ``hold``, from ``SETTLE`` after the UAV's
arrival within ``ARRIVAL`` of the station, it computes the altitude's peak-to-peak
range and standard deviation and the horizontal radius about the mean position, the numbers
the thesis gives for its indoor flights (Sec. 6.3: 1.08 m peak-to-peak, 0.18 m standard
deviation, within a 0.60 m radius; untethered 0.99 m, 0.18 m, 0.48 m), plus the largest
distance from the station. The summary says whether a tether acted on the UAV in this run
(a ``/tether/state`` topic in the bag), since the thesis's numbers are for a tethered UAV
flown by an RC pilot and are only comparable then.

The autopilot's link losses (``/uav/state`` neither connected nor fresh, after it first
was), its reboots (the bridge's reboot count growing) and gaps in ``/uav/pose`` longer than
:data:`POSE_GAP` are listed (:func:`link_outages`), and the station-keeping window ends at the
first of them (:func:`clip_to_outages`): a hold statistic, or a cross-correlation on
interpolated poses, must not span an autopilot that was not there.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_bringup.bag_reader import read_bag  # noqa: E402

THESIS_INDOOR = {'peak_to_peak': 1.08, 'std': 0.18, 'radius': 0.60}
THESIS_UNTETHERED = {'peak_to_peak': 0.99, 'std': 0.18, 'radius': 0.48}
ARRIVAL = 0.5
"""m: the UAV has arrived at the station when it first comes this close."""
SETTLE = 5.0
"""s after the arrival at which the station-keeping window opens (the end of the approach)."""
POSE_GAP = 3.0
"""s of sim time: ``/uav/pose`` stamps further apart than this are a gap, as long as the bridge's ``link_timeout``
(3 s) that marks the link stale. The bridge streams poses at 10-50 Hz stamped on arrival: on the shared 2-core
machine, SITL at 10x under a graph at 5x delivered them with gaps of 1.2-2.2 s of sim time (0.24-0.44 s of wall
time) throughout a flight, the load's jitter and no loss of the autopilot."""


@dataclass(frozen=True)
class Outage:
    """A stretch of the run without the autopilot: a link loss, a reboot (start = end), a gap in the poses."""

    start: float        # s, sim time
    end: float          # s; inf: to the end of the bag
    kind: str           # 'link lost', 'reboot', 'pose gap'

    def text(self) -> str:
        """The outage in words."""
        if self.kind == 'reboot':
            return f'autopilot reboot seen at {self.start:.1f} s'
        what = 'link lost' if self.kind == 'link lost' else '/uav/pose gap'
        if np.isinf(self.end):
            return f'{what} from {self.start:.1f} s to the end'
        return f'{what} {self.start:.1f}-{self.end:.1f} s ({self.end - self.start:.1f} s)'


def link_outages(t: np.ndarray, up: np.ndarray, reboots: np.ndarray, pose_t: np.ndarray,
                 gap: float = POSE_GAP, end: float = -np.inf) -> list[Outage]:
    """The run's outages, by start time: from ``/uav/state`` (stamps ``t``, link ``up`` = connected and not
    stale, the bridge's ``reboots`` count) after the link was first up, and from the ``/uav/pose`` stamps (a gap
    also from the last pose to ``end``, the recording's end, when that is longer than ``gap``). None starting at
    ``end``: the run's nodes stop there, SITL (its node) before the bridge when the scene lists it first, and the
    bridge's last ``/uav/state``, stamped with the last ``/clock``, then shows a closed link.
    """
    outages = []
    up = np.asarray(up, dtype=bool)
    first = int(np.argmax(up)) if up.any() else len(up)
    for i in range(first + 1, len(up)):
        if up[i - 1] and not up[i]:
            back = np.flatnonzero(up[i:])
            outages.append(Outage(float(t[i]), float(t[i + back[0]]) if len(back) else np.inf, 'link lost'))
    for i in np.flatnonzero(np.diff(np.asarray(reboots, dtype=float)) > 0):
        outages.append(Outage(float(t[i + 1]), float(t[i + 1]), 'reboot'))
    for i in np.flatnonzero(np.diff(pose_t) > gap):
        outages.append(Outage(float(pose_t[i]), float(pose_t[i + 1]), 'pose gap'))
    if len(pose_t) and end - pose_t[-1] > gap:
        outages.append(Outage(float(pose_t[-1]), np.inf, 'pose gap'))
    return sorted((o for o in outages if o.start < end or not np.isfinite(end)), key=lambda o: (o.start, o.kind))


def clip_to_outages(interval: tuple[float, float] | None, outages: list[Outage],
                    pose_t: np.ndarray) -> tuple[float, float] | None:
    """The station-keeping window ended at the first outage that reaches into it; None if fewer than two of the
    poses (stamps ``pose_t``) are left in it.
    """
    if interval is None:
        return None
    starts = [o.start for o in outages if o.end >= interval[0] and o.start < interval[1]]
    if not starts:
        return interval
    end = min(starts)
    left = int(np.count_nonzero((pose_t >= interval[0]) & (pose_t < end)))
    return (interval[0], end) if left >= 2 else None


def outage_lines(outages: list[Outage], interval: tuple[float, float] | None) -> list[str]:
    """The outages in one line, and where they cut the station keeping."""
    if not outages:
        return [f'  autopilot: no link loss, no reboot, no /uav/pose gap over {POSE_GAP:g} s']
    line = '  autopilot: ' + '; '.join(o.text() for o in outages)
    if interval is not None and not np.isinf(interval[1]) and any(o.start == interval[1] for o in outages):
        line += f'; the station-keeping figures stop at {interval[1]:.1f} s, before the first in the hold'
    return [line]


def _stamp(header) -> float:
    return header.stamp.sec + header.stamp.nanosec * 1e-9


def read_flight(bag_path: Path) -> dict:
    """Poses (t, x, y, z), mission phases (t, phase, reason, station), UAV states, topic names of a bag."""
    poses, phases, states = [], [], []
    wanted = {'/uav/pose', '/mission/state', '/uav/state'}
    bag = read_bag(Path(bag_path))
    topics = set(bag.topics)
    for topic in sorted(wanted & topics):
        for _, m in bag.decoded(topic):
            if topic == '/uav/pose':
                p = m.pose.position
                poses.append((_stamp(m.header), p.x, p.y, p.z))
            elif topic == '/mission/state':
                phases.append((_stamp(m.header), m.phase, m.reason, (m.station.x, m.station.y, m.station.z)))
            else:
                states.append((_stamp(m.header), m.stale, m.reconnects, m.reboots, m.connected))
    return {'poses': np.array(poses, dtype=float).reshape(-1, 4), 'phases': phases, 'states': states,
            'topics': topics}


def hold_interval(phases: list, poses: np.ndarray, arrival: float = ARRIVAL,
                  settle: float = SETTLE) -> tuple[float, float] | None:
    """Start and end (s) of the station-keeping window; None when the UAV never held station.

    The window opens ``settle`` s after the first pose of the first ``hold`` phase within
    ``arrival`` m of the station (the mission enters ``hold`` when the take-off altitude is
    reached, before the UAV has crossed to the station) and closes when the phase ends (inf
    while it lasted to the end of the bag); None if it would not open before that.
    """
    start = next(((t, station) for t, phase, _, station in phases if phase == 'hold'), None)
    if start is None:
        return None
    end = next((t for t, phase, _, _ in phases if t > start[0] and phase != 'hold'), np.inf)
    during = (poses[:, 0] >= start[0]) & (poses[:, 0] < end)
    near = during & (np.linalg.norm(poses[:, 1:4] - np.asarray(start[1]), axis=1) <= arrival)
    if not near.any():
        return None
    opens = float(poses[np.argmax(near), 0]) + settle
    return (opens, end) if opens < min(end, poses[-1, 0]) else None


def station_keeping(positions: np.ndarray, station) -> dict:
    """Altitude peak-to-peak and std, horizontal radius about the mean and largest distance from ``station``."""
    horizontal = positions[:, :2]
    return {'peak_to_peak': float(np.ptp(positions[:, 2])), 'std': float(np.std(positions[:, 2])),
            'radius': float(np.max(np.linalg.norm(horizontal - horizontal.mean(axis=0), axis=1))),
            'from_station': float(np.max(np.linalg.norm(positions - np.asarray(station), axis=1)))}


def flight_report(bag_path: str, out_dir: str) -> list[str]:
    """Plot the UAV's altitude and track with the mission phases; return the station-keeping lines.

    Raises:
        ValueError: the bag cannot be read.
    """
    flight = read_flight(Path(bag_path))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    poses, phases = flight['poses'], flight['phases']
    if poses.shape[0] == 0:
        return ['uav: no /uav/pose messages in the bag'
                + (f' (mission phase at the end: {phases[-1][1]}: {phases[-1][2]})' if phases else '')]
    lines = [f'uav: {poses.shape[0]} poses over {poses[-1, 0] - poses[0, 0]:.1f} s; mission phases: '
             + (' → '.join(dict.fromkeys(phase for _, phase, _, _ in phases)) if phases else 'no /mission/state')]
    states = flight['states']
    outages = link_outages(np.array([s[0] for s in states]), np.array([s[4] and not s[1] for s in states]),
                           np.array([s[3] for s in states]), poses[:, 0], end=states[-1][0] if states else -np.inf)
    interval = clip_to_outages(hold_interval(phases, poses), outages, poses[:, 0])
    station = phases[-1][3] if phases else None
    if interval is not None:
        inside = (poses[:, 0] >= interval[0]) & (poses[:, 0] < interval[1])
        if inside.sum() >= 2:
            stats = station_keeping(poses[inside, 1:], station)
            tether = '/tether/state' in flight['topics']
            lines.append(f'uav hold {interval[0]:.1f}-{min(interval[1], poses[-1, 0]):.1f} s ({inside.sum()} poses), '
                         f'station {station[2]:g} m up, {np.hypot(station[0], station[1]):g} m radial: altitude '
                         f'peak-to-peak {stats["peak_to_peak"]:.3f} m, std {stats["std"]:.3f} m, horizontal radius '
                         f'{stats["radius"]:.3f} m, largest distance from the station {stats["from_station"]:.3f} m')
            lines.append(f'  thesis Sec. 6.3 (indoor, tethered, RC pilot): {THESIS_INDOOR["peak_to_peak"]} m, '
                         f'{THESIS_INDOOR["std"]} m, {THESIS_INDOOR["radius"]} m; untethered '
                         f'{THESIS_UNTETHERED["peak_to_peak"]} m, {THESIS_UNTETHERED["std"]} m, '
                         f'{THESIS_UNTETHERED["radius"]} m'
                         + ('' if tether else ' — no tether acted on this UAV (no /tether/state): not comparable'))
    else:
        lines.append(f'uav: the mission never held station (hold phase within {ARRIVAL:g} m of the station)'
                     + (f' (last phase {phases[-1][1]}: {phases[-1][2]})' if phases else ''))
    if phases and phases[-1][2]:
        lines.append(f'uav mission end: {phases[-1][1]}: {phases[-1][2]}')
    lines += [line.replace('  autopilot:', 'uav autopilot:', 1) for line in outage_lines(outages, interval)]
    if states:
        stale_edges = sum(1 for a, b in zip(states, states[1:]) if b[1] and not a[1])
        lines.append(f'uav link: {stale_edges} stale periods after the first message, {states[-1][2]} '
                     f'connections, {states[-1][3]} autopilot reboots detected')
    _plot(poses, phases, interval, station, out / 'uav_flight.png')
    lines.append('uav: plot uav_flight.png')
    return lines


def _plot(poses, phases, interval, station, path: Path) -> None:
    t0 = poses[0, 0]
    fig, (ax_z, ax_xy) = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw={'width_ratios': [2, 1]})
    ax_z.plot(poses[:, 0] - t0, poses[:, 3], lw=1.0, color='tab:blue', label='UAV altitude (world z)')
    if station is not None:
        ax_z.axhline(station[2], color='k', ls=':', lw=0.8, label='station')
    if interval is not None:
        ax_z.axvspan(interval[0] - t0, min(interval[1], poses[-1, 0]) - t0, color='tab:green', alpha=0.1,
                     label='hold')
    for t, phase, _, _ in phases:
        ax_z.axvline(t - t0, color='0.7', lw=0.5)
        ax_z.text(t - t0, ax_z.get_ylim()[1], phase, rotation=90, va='top', fontsize=7)
    ax_z.set_xlabel('time (s, sim)')
    ax_z.set_ylabel('m')
    ax_z.legend(loc='lower right', fontsize=8)
    ax_xy.plot(poses[:, 1], poses[:, 2], lw=0.8, color='tab:blue')
    if station is not None:
        ax_xy.plot(station[0], station[1], 'k+', ms=12, label='station')
    ax_xy.plot(0.0, 0.0, 'rs', ms=6, label='guide way (world origin)')
    ax_xy.set_xlabel('x east (m)')
    ax_xy.set_ylabel('y north (m)')
    ax_xy.set_aspect('equal', adjustable='datalim')
    ax_xy.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)

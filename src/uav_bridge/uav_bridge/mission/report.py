"""Mission report (thesis Sec. 6.3, 6.4, Table 6.3) from runs of the flight scenes.

``tethersim report mission BAG...`` reads runs of ``indoor_flight``, ``outdoor_flight`` and
their ``*_no_control`` variants (run directories, bag directories or ``.mcap`` files) and
writes, per run, ``<run>_flight.png`` (UAV altitude with the platform heave, their
cross-correlation, the horizontal track), ``<run>_tether.png`` (tether snapshots against
the catenary reference, the shape error), ``<run>_errors.png`` (estimator and length
errors) and ``<run>_clearance.png`` (lowest point above deck and sea), and a table of the
figures beside the thesis's.

Definitions. Every statistic is taken over the station-keeping window: from
:data:`uav_bridge.mission.flight_report.SETTLE` after the UAV's first arrival within
:data:`uav_bridge.mission.flight_report.ARRIVAL` of the station during the mission's ``hold`` phase to the
phase's end (:func:`uav_bridge.mission.flight_report.hold_interval`), where the landing starts: the return
over the pad at the end of the scene (``/mission/state`` phase ``return``), or the descent
at once on a reel trip (phase ``land``), or the first loss of the autopilot's link, reboot
or gap in ``/uav/pose`` in it (:func:`uav_bridge.mission.flight_report.clip_to_outages`; each is listed).
The fouling figures and the reel's safety trips cover the flight up to the landing: a UAV
landing beside the boat lays its tether on the sea. The landing's own trips, peak tensions
and fouled time are given on a line of their own.

* station keeping (Sec. 6.3): peak-to-peak and standard deviation of the UAV altitude
  (``/uav/pose`` z) and the largest horizontal distance from its mean position;
* decoupling (Fig. 6.10b): normalised cross-correlation of the UAV altitude with the
  platform heave (``/platform/state``), both on the platform's stamps, means removed, beside
  both standard deviations and the altitude's part that follows the heave (the largest
  correlation times the altitude's std: a high correlation of mm-scale errors is still mm),
  ``c(k) = Σ x_i y_(i+k) / (N σ_x σ_y)`` at every lag k; the largest ``|c|``;
* tether shape (Sec. 6.3, Fig. 6.9): at each ``/tether/nodes`` message, 11 points evenly
  spaced in unstretched arc length strictly between the reel and the UAV (the thesis's
  11 markers) against the points at the same arc fractions of the catenary of the
  reference length (Eq. 4.4/4.5) between the same ends
  (:func:`tether_dynamics.plant_markers.reference_shape`); the mean distance and its std;
* Table 6.3: estimator error = ``/estimate/relative`` Δz minus ``/truth/relative`` Δz at
  equal stamps (initialised estimates only); length error = encoder length
  (``/reel/state``) minus the reference length of the true relative position, as the
  surrogate report defines it; mean of the absolute error and RMSE;
* fouling: the lowest point on or below the deck (``clearance_deck`` plus the reel's
  ``guide_height``) or the sea (``fouling``); events are rising edges; also the time the
  lowest point hangs more than :data:`SAG` below the guide way.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from dataclasses import field
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_bringup.bag_reader import Bag  # noqa: E402
from tether_bringup.bag_reader import BagError  # noqa: E402
from tether_bringup.bag_reader import read_bag  # noqa: E402
from tether_bringup.run_directory import node_parameter  # noqa: E402
from tether_common.command_line import Command  # noqa: E402
from tether_common.command_line import UsageError  # noqa: E402
from tether_common.command_line import analysis  # noqa: E402
from tether_common.correlation import cross_correlation  # noqa: E402
from tether_common.report_figures import ReportLines  # noqa: E402
from tether_common.rotation import quaternion_rotation  # noqa: E402
from tether_dynamics.clearance import guide_height  # noqa: E402
from tether_dynamics.plant_markers import reference_shape  # noqa: E402
from tether_dynamics.statics.reference_length import reference_lengths  # noqa: E402
from uav_bridge.mission.flight_report import ARRIVAL  # noqa: E402
from uav_bridge.mission.flight_report import SETTLE  # noqa: E402
from uav_bridge.mission.flight_report import THESIS_INDOOR  # noqa: E402
from uav_bridge.mission.flight_report import clip_to_outages  # noqa: E402
from uav_bridge.mission.flight_report import hold_interval  # noqa: E402
from uav_bridge.mission.flight_report import link_outages  # noqa: E402
from uav_bridge.mission.flight_report import outage_lines  # noqa: E402
from uav_bridge.mission.flight_report import station_keeping  # noqa: E402

THESIS = {
    'xcorr': 0.2,                    # Sec. 6.3, Fig. 6.10b: under 0.2 at all lags
    'shape_mean': 0.076, 'shape_std': 0.0378,     # Sec. 6.3: 11 nodes, eight trials
    'dz_mean': (0.0054, 0.0082), 'dz_rmse': (0.0080, 0.012),     # Table 6.3, range over the four profiles
    'length_mean': (0.0096, 0.0118), 'length_rmse': (0.0132, 0.0163),
    'test_time': 512.4,              # s, Table 6.3: the shortest trial
}
SHAPE_POINTS = 11
"""Tether points compared with the reference shape (the thesis's 11 motion-capture markers)."""
PAD_RADIUS = 0.5
"""m, a touchdown this close to the pad's centre, horizontally, is on the pad (the mission's return tolerance)."""
SAG = 0.1
"""m: the lowest point this far below the guide way counts as the tether sagging below the reel."""


@dataclass
class Run:
    """The recorded series of one flight run (times in s of sim time)."""

    path: Path
    name: str
    poses: np.ndarray          # (t, x, y, z), UAV in world
    phases: list               # (t, phase, reason, station)
    heave: np.ndarray          # (t, heave)
    nodes: list                # (t, positions (n, 3), arc length (n,))
    tether: dict               # t, clearance_deck, clearance_sea, fouling, length
    truth: dict                # t, dr, dz
    estimate: dict             # t, dz, initialized
    reel: dict                 # t, length, mode
    trips: dict                # t, count (the reel's trip_count)
    guide_height: float
    force: dict = field(default_factory=lambda: {c: np.zeros(0) for c in 'txyz'})   # tether on the UAV, N, world
    tether_model: str = 'none'  # the JSON physics' tether_model, or the plant's
    max_tension: float = math.nan   # N, the reel's reel-in trip limit (params/reel.yaml), NaN when unknown
    pad: np.ndarray | None = None   # (t, x, y, z): the built-in UAV's pad in world at each /platform/reel_pose
    uav_state: dict = field(default_factory=lambda: {c: np.zeros(0) for c in ('t', 'up', 'reboots')})   # /uav/state



def _t(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def _series(bag: Bag, topic: str, fields: dict) -> dict:
    rows = [(_t(m), *(f(m) for f in fields.values())) for _, m in bag.decoded(topic)] if topic in bag.topics else []
    array = np.array(rows, dtype=float).reshape(-1, len(fields) + 1)
    return {'t': array[:, 0], **{name: array[:, i + 1] for i, name in enumerate(fields)}}


def load_run(path: str | Path) -> Run:
    """Read one flight run's bag.

    Raises:
        UsageError: the bag cannot be read or holds no UAV poses or mission phases.
    """
    path = Path(path)
    try:
        bag = read_bag(path)
        missing = [t for t in ('/uav/pose', '/mission/state', '/platform/state') if t not in bag.topics]
        if missing:
            raise UsageError(f'{path}: not a flight run: no {", ".join(missing)} in the bag')
        poses = np.array([(_t(m), m.pose.position.x, m.pose.position.y, m.pose.position.z)
                          for _, m in bag.decoded('/uav/pose')], dtype=float).reshape(-1, 4)
        phases = [(_t(m), m.phase, m.reason, (m.station.x, m.station.y, m.station.z))
                  for _, m in bag.decoded('/mission/state')]
        heave = _series(bag, '/platform/state', {'heave': lambda m: m.heave})
        nodes = [(_t(m), np.array([(p.x, p.y, p.z) for p in m.positions]), np.array(m.arc_length))
                 for _, m in bag.decoded('/tether/nodes')] if '/tether/nodes' in bag.topics else []
        tether = _series(bag, '/tether/state', {
            'clearance_deck': lambda m: m.clearance_deck, 'clearance_sea': lambda m: m.clearance_sea,
            'fouling': lambda m: float(m.fouling), 'length': lambda m: m.deployed_length,
            'tension_reel': lambda m: m.tension_reel, 'tension_uav': lambda m: m.tension_uav})
        truth = _series(bag, '/truth/relative', {'dr': lambda m: math.hypot(m.position.x, m.position.y),
                                                 'dz': lambda m: m.position.z})
        estimate = _series(bag, '/estimate/relative', {'dz': lambda m: m.dz, 'initialized': lambda m: m.initialized})
        reel = _series(bag, '/reel/state', {'length': lambda m: m.deployed_length, 'mode': lambda m: m.mode})
        trips = _series(bag, '/reel/diagnostics', {'count': lambda m: m.trip_count})
        uav_state = _series(bag, '/uav/state', {'up': lambda m: float(m.connected and not m.stale),
                                                'reboots': lambda m: m.reboots})
        force_topic = '/uav/tether_force' if '/uav/tether_force' in bag.topics else '/tether/uav_wrench'
        force = _series(bag, force_topic, {'x': lambda m: m.wrench.force.x, 'y': lambda m: m.wrench.force.y,
                                           'z': lambda m: m.wrench.force.z})
        pad = _pad_track(bag, path)
    except BagError as error:
        raise UsageError(f'{path}: cannot read the bag: {error}') from None
    directory = path.resolve() if path.is_dir() else path.resolve().parent
    name = directory.parent.name if directory.name == 'bag' else directory.name
    model = node_parameter(path, 'json_physics', 'tether_model') or ('plant' if len(force['t']) else 'none')
    limit = node_parameter(path, 'reel', 'max_tension', ('smart_reel', 'reel'))
    return Run(path, name, poses, phases, np.column_stack([heave['t'], heave['heave']]), nodes, tether, truth,
               estimate, reel, trips, guide_height(path), force, str(model),
               math.nan if limit is None else float(limit), pad, uav_state)


def _pad_track(bag: Bag, path: Path) -> np.ndarray | None:
    """(t, x, y, z) of the built-in UAV's landing pad in world: its ``pad`` offset in ``boat`` carried by
    ``/platform/reel_pose``; None when the run has no pad (another UAV, or ``ground`` not ``pad``).
    """
    if node_parameter(path, 'uav', 'ground', ('uav_bridge', 'builtin_uav')) != 'pad' or '/platform/reel_pose' not in bag.topics:
        return None
    offset = np.asarray(node_parameter(path, 'uav', 'pad', ('uav_bridge', 'builtin_uav')), dtype=float)
    rows = []
    for _, m in bag.decoded('/platform/reel_pose'):
        p, q = m.pose.position, m.pose.orientation
        rotation = quaternion_rotation(np.array([q.x, q.y, q.z, q.w]), '/platform/reel_pose orientation')
        rows.append((_t(m), *(np.array([p.x, p.y, p.z]) + rotation.apply(offset))))
    return np.array(rows, dtype=float).reshape(-1, 4)


def shape_errors(positions: np.ndarray, arc_length: np.ndarray, n: int = SHAPE_POINTS) -> tuple[np.ndarray,
                                                                                                    np.ndarray]:
    """Distances (m) of ``n`` tether points from the reference catenary's, and those tether points.

    The points lie at arc fractions ``k / (n + 1)``, k = 1..n, of the tether (by unstretched arc
    length) and of the reference catenary between the same two ends.
    """
    fractions = np.arange(1, n + 1) / (n + 1)
    s = fractions * arc_length[-1]
    points = np.column_stack([np.interp(s, arc_length, positions[:, i]) for i in range(3)])
    reference = reference_shape(positions[0], positions[-1], n + 2)[1:-1]
    return np.linalg.norm(points - reference, axis=1), points


def _window(t: np.ndarray, interval: tuple[float, float]) -> np.ndarray:
    return (t >= interval[0]) & (t < interval[1])


def _events(flag: np.ndarray) -> int:
    return int(np.sum(flag[1:] & ~flag[:-1]) + (1 if len(flag) and flag[0] else 0))


def _touchdown(run: Run) -> tuple[float, float] | None:
    """(time, horizontal distance from the pad in m) where the mission's phase became ``landed``; the distance
    is NaN without a pad track, and None when the mission never landed.
    """
    landed = next((t for t, phase, _, _ in run.phases if phase == 'landed'), None)
    if landed is None or not run.poses.shape[0]:
        return None
    if run.pad is None or not run.pad.shape[0]:
        return landed, math.nan
    i = min(int(np.searchsorted(run.poses[:, 0], landed)), run.poses.shape[0] - 1)
    j = min(int(np.searchsorted(run.pad[:, 0], landed)), run.pad.shape[0] - 1)
    return landed, float(np.hypot(*(run.poses[i, 1:3] - run.pad[j, 1:3])))


def analyse(run: Run) -> dict:
    """The figures of one run (see the module docstring for the definitions)."""
    result: dict = {'run': run}
    interval = hold_interval(run.phases, run.poses) if run.poses.shape[0] else None
    result['outages'] = link_outages(run.uav_state['t'], run.uav_state['up'] > 0.5, run.uav_state['reboots'],
                                     run.poses[:, 0], end=max(run.heave[:, 0].max(initial=-math.inf),
                                                              run.uav_state['t'].max(initial=-math.inf)))
    interval = clip_to_outages(interval, result['outages'], run.poses[:, 0])
    result['interval'] = interval
    result['phases'] = list(dict.fromkeys(phase for _, phase, _, _ in run.phases))
    result['end'] = run.phases[-1][2] if run.phases else ''
    result['landing'] = next((t for t, phase, _, _ in run.phases if phase in ('return', 'land')), math.inf)
    flying = run.tether['t'] < result['landing']
    trips = int(run.trips['count'][run.trips['t'] < result['landing']].max(initial=0))
    landing = ~flying
    result['landing_figures'] = None if not landing.any() else {
        'trips': int(run.trips['count'].max(initial=0)) - trips,
        'tension_reel': float(run.tether['tension_reel'][landing].max()),
        'tension_uav': float(run.tether['tension_uav'][landing].max()),
        'fouled_time': float(np.sum((run.tether['clearance_deck'][landing] + run.guide_height <= 0.0)
                                    | (run.tether['fouling'][landing] > 0.5)) * np.median(np.diff(run.tether['t'])))}
    result['touchdown'] = _touchdown(run)
    tt = run.tether['t'][flying]
    deck = run.tether['clearance_deck'][flying] + run.guide_height
    fouled = (deck <= 0.0) | (run.tether['fouling'][flying] > 0.5)
    sag = run.tether['clearance_deck'][flying] < -SAG
    dt = float(np.median(np.diff(tt))) if len(tt) > 1 else 0.0
    result.update(fouling_events=_events(fouled), fouled_time=float(fouled.sum() * dt),
                  sag_time=float(sag.sum() * dt), min_deck=float(deck.min()) if len(tt) else math.nan,
                  min_sea=float(run.tether['clearance_sea'][flying].min()) if len(tt) else math.nan,
                  first_fouled=float(tt[np.argmax(fouled)]) if fouled.any() else math.nan, trips=trips,
                  duration=float(run.poses[-1, 0] - run.poses[0, 0]) if run.poses.shape[0] else 0.0)
    if interval is None:
        return result
    end = min(interval[1], run.poses[-1, 0])
    result['window'] = (interval[0], end)
    inside = _window(run.poses[:, 0], interval)
    station = run.phases[-1][3]
    result['station'] = station
    result['keeping'] = station_keeping(run.poses[inside, 1:], station)
    result['hold_error'] = np.linalg.norm(run.poses[inside, 1:3] - np.asarray(station)[:2], axis=1)
    force_in = _window(run.force['t'], interval)
    if force_in.sum() >= 2:
        result['force'] = np.column_stack([run.force[c][force_in] for c in 'xyz'])
    heave_in = _window(run.heave[:, 0], interval)
    th, heave = run.heave[heave_in, 0], run.heave[heave_in, 1]
    if len(th) > 10:
        altitude = np.interp(th, run.poses[:, 0], run.poses[:, 3])
        lags, corr = cross_correlation(altitude, heave)
        result['xcorr'] = (lags * float(np.median(np.diff(th))), corr)
        k = int(np.argmax(np.abs(corr)))
        result['xcorr_max'] = (float(abs(corr[k])), float(lags[k] * np.median(np.diff(th))))
        result['xcorr_std'] = (float(np.std(altitude)), float(np.std(heave)))
    snapshots = [(t, p, a) for t, p, a in run.nodes if interval[0] <= t < interval[1] and len(p) >= 2]
    if snapshots:
        errors = np.array([shape_errors(p, a)[0] for _, p, a in snapshots])
        result['shape'] = (np.array([t for t, _, _ in snapshots]), errors)
        result['shape_mean'], result['shape_std'] = float(errors.mean()), float(errors.std())
        result['snapshots'] = snapshots
    est_in = _window(run.estimate['t'], interval) & (run.estimate['initialized'] > 0.5)
    if est_in.any() and len(run.truth['t']):
        common, i_est, i_truth = np.intersect1d(run.estimate['t'][est_in].round(6), run.truth['t'].round(6),
                                                return_indices=True)
        error = run.estimate['dz'][est_in][i_est] - run.truth['dz'][i_truth]
        result['dz_error'] = (common, error)
    reel_in = _window(run.reel['t'], interval)
    if reel_in.any() and len(run.truth['t']):
        tr = run.reel['t'][reel_in]
        dr = np.interp(tr, run.truth['t'], run.truth['dr'])
        dz = np.interp(tr, run.truth['t'], run.truth['dz'])
        model, _ = reference_lengths(dr, dz, 'poly')
        result['length_error'] = (tr, run.reel['length'][reel_in] - model)
    return result


def _stats(error: np.ndarray) -> tuple[float, float]:
    return float(np.mean(np.abs(error))), float(np.sqrt(np.mean(error ** 2)))


def summary_lines(r: dict) -> list[str]:
    """The text of one run's figures beside the thesis's (every number from the run)."""
    run = r['run']
    lines = [f'{run.name}: {r["duration"]:.1f} s recorded; mission phases: {" → ".join(r["phases"]) or "none"}'
             + (f'; ended: {r["end"]}' if r['end'] else '')]
    lines += outage_lines(r['outages'], r['interval'])
    if r['interval'] is None:
        lines.append(f'  the UAV never held station (came within {ARRIVAL:g} m of it in the hold phase, then '
                     f'{SETTLE:g} s): no station-keeping, decoupling, shape or error figures')
    else:
        start, end = r['window']
        k, station = r['keeping'], r['station']
        until = ' to the landing' if end == r['landing'] else ''
        lines.append(f'  station {station[2]:g} m up, {math.hypot(station[0], station[1]):g} m radial; held '
                     f'{start:.1f}-{end:.1f} s ({end - start:.1f} s, from {SETTLE:g} s after the arrival within {ARRIVAL:g} m'
                     f'{until})'
                     + ('; shorter than the thesis\'s trials (Table 6.3: 512-669 s)'
                        if end - start < THESIS['test_time'] else ''))
        lines.append(f'  UAV altitude peak-to-peak {k["peak_to_peak"]:.3f} m (thesis indoor '
                     f'{THESIS_INDOOR["peak_to_peak"]} m), std {k["std"]:.3f} m ({THESIS_INDOOR["std"]} m), '
                     f'horizontal radius {k["radius"]:.3f} m ({THESIS_INDOOR["radius"]} m)')
        if 'xcorr_max' in r:
            value, lag = r['xcorr_max']
            verdict = 'under' if value < THESIS['xcorr'] else 'not under'
            lines.append(f'  |normalised cross-correlation| of UAV altitude and platform heave: largest {value:.3f} '
                         f'at lag {lag:+.2f} s, {verdict} the thesis\'s {THESIS["xcorr"]} at all lags')
            altitude_std, heave_std = r['xcorr_std']
            coupled = value * altitude_std
            lines.append(f'    normalised by the amplitudes: UAV altitude std {altitude_std:.4f} m, heave std '
                         f'{heave_std:.4f} m; the part of the altitude that follows the heave at that lag is '
                         f'{coupled:.4f} m rms, {100 * coupled / heave_std:.2f} % of the heave' if heave_std > 0 else
                         f'    the platform did not heave (std {heave_std:.4f} m): the correlation says nothing')
        if 'shape_mean' in r:
            lines.append(f'  tether shape vs catenary reference: mean node error {r["shape_mean"]:.3f} m, std '
                         f'{r["shape_std"]:.3f} m over {SHAPE_POINTS} nodes x {len(r["shape"][0])} snapshots '
                         f'(thesis {THESIS["shape_mean"]} m, std {THESIS["shape_std"]} m)')
        if 'dz_error' in r:
            mean, rmse = _stats(r['dz_error'][1])
            lines.append(f'  estimator Δz: mean |error| {mean:.4f} m, RMSE {rmse:.4f} m over {len(r["dz_error"][1])} '
                         f'estimates (Table 6.3: {THESIS["dz_mean"][0]}-{THESIS["dz_mean"][1]} m, '
                         f'{THESIS["dz_rmse"][0]}-{THESIS["dz_rmse"][1]} m)')
        if 'length_error' in r:
            mean, rmse = _stats(r['length_error'][1])
            lines.append(f'  length L: mean |error| {mean:.4f} m, RMSE {rmse:.4f} m (Table 6.3: '
                         f'{THESIS["length_mean"][0]}-{THESIS["length_mean"][1]} m, '
                         f'{THESIS["length_rmse"][0]}-{THESIS["length_rmse"][1]} m)')
    if not len(run.tether['t']):
        lines.append('  no tether plant in this run (no /tether/state): no shape, length or fouling figures')
        return lines
    first = f', first at {r["first_fouled"]:.1f} s' if r['fouling_events'] else ''
    until = f' until the landing at {r["landing"]:.1f} s' if math.isfinite(r['landing']) else ''
    lines.append(f'  fouling{until}: {r["fouling_events"]} events (lowest point on the deck or in the sea), '
                 f'{r["fouled_time"]:.1f} s fouled{first}; lowest point more than {SAG:g} m below the guide way for '
                 f'{r["sag_time"]:.1f} s; least clearance above deck {r["min_deck"]:.2f} m, above sea '
                 f'{r["min_sea"]:.2f} m; reel safety trips {r["trips"]}')
    landing = r['landing_figures']
    if landing is not None:
        limit = run.max_tension
        beside = '' if math.isnan(limit) else (f' ({"under" if landing["tension_reel"] <= limit else "OVER"} the '
                                               f'reel\'s {limit:g} N reel-in trip limit)')
        lines.append(f'  the landing from {r["landing"]:.1f} s: reel safety trips {landing["trips"]}, peak tension '
                     f'{landing["tension_reel"]:.1f} N at the reel{beside} and {landing["tension_uav"]:.1f} N at the '
                     f'UAV, {landing["fouled_time"]:.1f} s fouled')
    touchdown = r['touchdown']
    if touchdown is not None:
        where = ('' if math.isnan(touchdown[1])
                 else f', {touchdown[1]:.2f} m from the pad ({"on" if touchdown[1] <= PAD_RADIUS else "OFF"} the pad)')
        lines.append(f'  landed at {touchdown[0]:.1f} s{where}')
    return lines


def plot(r: dict, out: Path) -> list[str]:
    """Write the run's PNGs; return their names."""
    run = r['run']
    names = []
    t0 = run.poses[0, 0] if run.poses.shape[0] else 0.0
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), gridspec_kw={'width_ratios': [2, 1.2, 1]})
    ax = axes[0]
    ax.plot(run.poses[:, 0] - t0, run.poses[:, 3], color='tab:blue', lw=1.0, label='UAV altitude (m)')
    ax.set_xlabel('t (s)')
    ax.set_ylabel('UAV altitude (m)')
    twin = ax.twinx()
    twin.plot(run.heave[:, 0] - t0, run.heave[:, 1], color='tab:orange', lw=0.8, label='platform heave (m)')
    twin.set_ylabel('platform heave (m)')
    if r['interval'] is not None:
        ax.axvspan(r['window'][0] - t0, r['window'][1] - t0, color='tab:green', alpha=0.1, label='station kept')
    ax.legend(loc='upper left', fontsize=8)
    twin.legend(loc='upper right', fontsize=8)
    ax.set_title('UAV altitude and platform heave')
    if 'xcorr' in r:
        lags, corr = r['xcorr']
        axes[1].plot(lags, corr, lw=0.8)
        for level, label in ((THESIS['xcorr'], f'thesis: |c| < {THESIS["xcorr"]} (Fig. 6.10b)'), (-THESIS['xcorr'], None)):
            axes[1].axhline(level, color='k', ls=':', lw=0.8, label=label)
        axes[1].set_ylim(-1, 1)
        axes[1].legend(loc='upper right', fontsize=8)
    axes[1].set_xlabel('lag (s)')
    axes[1].set_title('UAV altitude vs platform heave: normalised cross-correlation')
    axes[2].plot(run.poses[:, 1], run.poses[:, 2], lw=0.8)
    if r['interval'] is not None:
        station = r['station']
        axes[2].plot(station[0], station[1], 'k+', ms=12, label='station')
        axes[2].legend(fontsize=8)
    axes[2].set_xlabel('x east (m)')
    axes[2].set_ylabel('y north (m)')
    axes[2].set_aspect('equal', adjustable='datalim')
    axes[2].set_title('UAV track')
    fig.tight_layout()
    names.append(f'{run.name}_flight.png')
    fig.savefig(out / names[-1], dpi=100)
    plt.close(fig)

    if 'snapshots' in r:
        fig, (ax_s, ax_e) = plt.subplots(1, 2, figsize=(13, 4.5))
        snaps = r['snapshots']
        for index, color in zip((0, len(snaps) // 2, len(snaps) - 1), ('tab:blue', 'tab:green', 'tab:red')):
            t, positions, arc = snaps[index]
            _, points = shape_errors(positions, arc)
            radial = np.hypot(positions[:, 0] - positions[0, 0], positions[:, 1] - positions[0, 1])
            reference = reference_shape(positions[0], positions[-1])
            ref_r = np.hypot(reference[:, 0] - positions[0, 0], reference[:, 1] - positions[0, 1])
            ax_s.plot(radial, positions[:, 2], color=color, lw=1.2, label=f'tether {t - t0:.1f} s')
            ax_s.plot(ref_r, reference[:, 2], color=color, ls='--', lw=0.8, label='catenary reference')
            ax_s.plot(np.hypot(points[:, 0] - positions[0, 0], points[:, 1] - positions[0, 1]), points[:, 2], 'o',
                      color=color, ms=3)
        ax_s.set_xlabel('horizontal distance from the guide way (m)')
        ax_s.set_ylabel('z (m, world)')
        ax_s.legend(fontsize=7)
        ax_s.set_title('tether against the catenary of the reference length')
        times, errors = r['shape']
        ax_e.plot(times - t0, errors.mean(axis=1), lw=0.8, label='mean over the 11 nodes')
        ax_e.axhline(THESIS['shape_mean'], color='k', ls=':', label=f'thesis {THESIS["shape_mean"]} m')
        ax_e.set_xlabel('t (s)')
        ax_e.set_ylabel('node error (m)')
        ax_e.legend(fontsize=8)
        fig.tight_layout()
        names.append(f'{run.name}_tether.png')
        fig.savefig(out / names[-1], dpi=100)
        plt.close(fig)

    if 'dz_error' in r or 'length_error' in r:
        fig, ax = plt.subplots(figsize=(11, 4))
        if 'dz_error' in r:
            ax.plot(r['dz_error'][0] - t0, r['dz_error'][1], lw=0.6, label='estimator Δz error')
        if 'length_error' in r:
            ax.plot(r['length_error'][0] - t0, r['length_error'][1], lw=0.8, label='length error (encoder - reference)')
        ax.set_xlabel('t (s)')
        ax.set_ylabel('m')
        ax.legend(fontsize=8)
        ax.set_title('Table 6.3 errors over the station-keeping window')
        fig.tight_layout()
        names.append(f'{run.name}_errors.png')
        fig.savefig(out / names[-1], dpi=100)
        plt.close(fig)

    tt = run.tether['t']
    if len(tt):
        fig, ax = plt.subplots(figsize=(11, 4))
        ax.plot(tt - t0, run.tether['clearance_deck'] + run.guide_height, lw=0.8,
                label=f'lowest point above the deck (guide way {run.guide_height:.2f} m above it)')
        ax.plot(tt - t0, run.tether['clearance_sea'], lw=0.8, label='lowest point above sea')
        ax.axhline(0.0, color='k', lw=0.8, label='deck / sea: fouled at or below')
        if math.isfinite(r['landing']):
            ax.axvline(r['landing'] - t0, color='0.5', ls='--', lw=0.8, label='landing starts')
        ax.set_xlabel('t (s)')
        ax.set_ylabel('m')
        ax.legend(fontsize=8)
        until = f'before the landing at {r["landing"] - t0:.1f} s' if math.isfinite(r['landing']) else 'in the run'
        landing = r['landing_figures']
        after = f'; {landing["fouled_time"]:.1f} s fouled in the landing' if landing is not None else ''
        ax.set_title(f'lowest tether point: {r["fouling_events"]} fouling events (on the deck or in the sea) {until}'
                     f'{after}')
        fig.tight_layout()
        names.append(f'{run.name}_clearance.png')
        fig.savefig(out / names[-1], dpi=100)
        plt.close(fig)
    return names


def comparison_lines(results: list[dict]) -> list[str]:
    """The runs side by side over their hold windows: tether model, position-hold error, force on the UAV
    (issue: the plant's tether against a straight line like ArduPilot's SIM_Tether on the same mission).
    """
    held = [r for r in results if 'hold_error' in r]
    if len(held) < 2:
        return []
    lines = ['side by side (hold windows): tether model | horizontal error from the station rms / max (m) | '
             'altitude peak-to-peak (m) | tether force on the UAV down / sideways mean, |F| peak-to-peak (N)']
    for r in held:
        error = r['hold_error']
        text = (f'  {r["run"].name}: {r["run"].tether_model} | {np.sqrt(np.mean(error ** 2)):.3f} / '
                f'{error.max():.3f} | {r["keeping"]["peak_to_peak"]:.3f} | ')
        if 'force' in r:
            f = r['force']
            text += (f'{-f[:, 2].mean():.2f} / {np.linalg.norm(f[:, :2], axis=1).mean():.2f}, '
                     f'{np.ptp(np.linalg.norm(f, axis=1)):.2f}')
        else:
            text += 'no tether force recorded'
        lines.append(text)
    return lines


def report(paths: list[str], out: Path) -> str:
    """Analyse and plot each run; with several, a side-by-side table; return the summary text."""
    lines = []
    results = []
    for path in paths:
        r = analyse(load_run(path))
        results.append(r)
        lines += summary_lines(r)
        lines.append('  plots: ' + ', '.join(plot(r, out)))
    return '\n'.join(lines + comparison_lines(results))


def outcome(r: dict) -> tuple[str, str | None]:
    """How the mission of a run ended, and the abort's reason (None without one).

    ``landed_on_pad``: landed at the end of the mission, touching down within :data:`PAD_RADIUS`
    of the built-in UAV's pad (:func:`_touchdown`); ``landed``: landed elsewhere or with no pad
    to land on; ``aborted``: a reel trip aborted it (whether it then returned and landed on the
    pad is in ``touchdown_distance``); ``incomplete``: the recording ended before it landed.
    """
    run = r['run']
    reasons = [reason for _, _, reason, _ in run.phases if reason.startswith('aborted')]
    abort = reasons[0].removeprefix('aborted: ') if reasons else None
    if abort is not None:
        return 'aborted', abort
    if r['touchdown'] is None:
        return 'incomplete', None
    return ('landed_on_pad' if r['touchdown'][1] <= PAD_RADIUS else 'landed'), None


def figures(r: dict) -> dict:
    """The run's figures as data (:func:`analyse`'s, by the module docstring's definitions; None where the run
    has none): outcome, hold time, peak tensions, fouling, clearance, trips, estimator and length errors.
    """
    run = r['run']
    ended, abort = outcome(r)
    keeping = r.get('keeping', {})
    landing = r['landing_figures'] or {}
    tension = run.tether

    def peak(name: str):
        return float(tension[name].max()) if len(tension['t']) else None

    def rmse(key: str):
        return _stats(r[key][1])[1] if key in r and len(r[key][1]) else None

    return {
        'outcome': ended, 'success': ended == 'landed_on_pad', 'abort_reason': abort,
        'touchdown_distance': r['touchdown'][1] if r['touchdown'] is not None else None,
        'reel_trip_limit': run.max_tension,
        'hold_time': r['window'][1] - r['window'][0] if 'window' in r else 0.0,
        'landing_time': r['landing'] if math.isfinite(r['landing']) else None,
        'peak_tension_reel': peak('tension_reel'), 'peak_tension_uav': peak('tension_uav'),
        'fouled_time': r['fouled_time'], 'fouling_events': r['fouling_events'], 'sag_time': r['sag_time'],
        'least_clearance_deck': r['min_deck'], 'least_clearance_sea': r['min_sea'],
        'reel_trips': r['trips'] + landing.get('trips', 0), 'reel_trips_flying': r['trips'],
        'landing_peak_tension_reel': landing.get('tension_reel'), 'landing_peak_tension_uav': landing.get('tension_uav'),
        'landing_fouled_time': landing.get('fouled_time'),
        'altitude_peak_to_peak': keeping.get('peak_to_peak'), 'altitude_std': keeping.get('std'),
        'horizontal_radius': keeping.get('radius'), 'xcorr_max': r['xcorr_max'][0] if 'xcorr_max' in r else None,
        'shape_mean': r.get('shape_mean'), 'dz_rmse': rmse('dz_error'), 'length_rmse': rmse('length_error'),
    }


def mission_report(bag_path: str, out_dir: str) -> ReportLines:
    """Scene report: the mission figures of one run, as text and as data (:func:`figures`)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    r = analyse(load_run(bag_path))
    return ReportLines(summary_lines(r) + ['  plots: ' + ', '.join(plot(r, out))], figures(r))


def _arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument('bags', nargs='+', help='run directories, bag directories or .mcap files')
    parser.add_argument('--out', type=Path, default=Path('runs/report-mission'), help='output directory')


def _command(args: argparse.Namespace) -> str:
    return report(args.bags, args.out)


COMMAND = Command('UAV missions (Sec. 6.3, 6.4, Table 6.3): station keeping, decoupling from the heave, tether '
                  'shape, estimator and length errors, fouling', _arguments, analysis('tethersim report mission',
                                                                                      _command))

"""After-run report of a tethered flight: the tether's force on the UAV and the autopilot's estimate, from a bag.

Reads ``/uav/tether_force`` (the force the JSON physics applied to the UAV, world; else the
plant's ``/tether/uav_wrench``), ``/uav/pose`` (the true
UAV), ``/autopilot/pose`` (the autopilot's estimate, when the bridge publishes there) and
``/mission/state``. Over the flight report's station-keeping window
(:func:`uav_bridge.mission.flight_report.hold_interval`) it gives the force's mean downward and
sideways pull and its peak-to-peak magnitude, the hover load the rotors must carry on top of
the weight, and how far the autopilot's estimate lies from the true position. With the JSON
physics' ``/uav/rotor_thrust``, the hover balance: the mean rotor thrust against the mean
|m g e_z − f| (weight plus the tether's pull; m the json_physics ``mass``). Plots
``uav_tether_force.png``.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_bringup.bag_reader import read_bag  # noqa: E402
from tether_bringup.run_directory import node_parameter  # noqa: E402
from tether_models.constants import GRAVITY  # noqa: E402
from uav_bridge.json_physics.params import PARAMETERS as PHYSICS_PARAMETERS  # noqa: E402
from uav_bridge.mission.flight_report import hold_interval  # noqa: E402
from uav_bridge.mission.flight_report import read_flight  # noqa: E402


def _stamp(header) -> float:
    return header.stamp.sec + header.stamp.nanosec * 1e-9


def _series(bag, topic: str, values) -> np.ndarray:
    if topic not in bag.topics:
        return np.zeros((0, 4))
    return np.array([(_stamp(m.header), *values(m)) for _, m in bag.decoded(topic)], dtype=float).reshape(-1, 4)


def tether_flight_report(bag_path: str, out_dir: str) -> list[str]:
    """The tether's force on the UAV and the estimate's error during the hold; plot; summary lines.

    Raises:
        ValueError: the bag cannot be read.
    """
    bag = read_bag(Path(bag_path))
    topic = '/uav/tether_force' if '/uav/tether_force' in bag.topics else '/tether/uav_wrench'
    force = _series(bag, topic, lambda m: (m.wrench.force.x, m.wrench.force.y, m.wrench.force.z))
    if force.shape[0] == 0:
        return ['tether on the UAV: no /uav/tether_force or /tether/uav_wrench in the bag']
    flight = read_flight(Path(bag_path))
    truth = flight['poses']
    estimate = _series(bag, '/autopilot/pose', lambda m: (m.pose.position.x, m.pose.position.y, m.pose.position.z))
    interval = hold_interval(flight['phases'], truth) if truth.shape[0] else None
    lines = []
    if interval is None:
        lines.append('tether on the UAV: the UAV never held station; the whole run follows')
        inside = np.ones(force.shape[0], dtype=bool)
    else:
        inside = (force[:, 0] >= interval[0]) & (force[:, 0] < interval[1])
    if inside.sum() >= 2:
        f = force[inside, 1:]
        magnitude = np.linalg.norm(f, axis=1)
        lines.append(f'tether on the UAV ({"hold" if interval else "whole run"}, {inside.sum()} samples): '
                     f'{-f[:, 2].mean():.2f} N down, {np.linalg.norm(f[:, :2], axis=1).mean():.2f} N sideways '
                     f'(mean), |F| {magnitude.mean():.2f} N mean, {np.ptp(magnitude):.2f} N peak-to-peak')
        thrust = _series(bag, '/uav/rotor_thrust', lambda m: (0.0, 0.0, m.wrench.force.z))
        if thrust.shape[0] >= 2:
            held = thrust[(thrust[:, 0] >= force[inside, 0][0]) & (thrust[:, 0] <= force[inside, 0][-1]), 3]
            lines.append(hover_balance_line(held, f, _mass(Path(bag_path))))
    if estimate.shape[0] >= 2 and truth.shape[0] >= 2:
        chosen = estimate[(estimate[:, 0] >= interval[0]) & (estimate[:, 0] < interval[1])] if interval else estimate
        if chosen.shape[0] >= 2:
            true_at = np.column_stack([np.interp(chosen[:, 0], truth[:, 0], truth[:, c]) for c in (1, 2, 3)])
            error = np.linalg.norm(chosen[:, 1:] - true_at, axis=1)
            lines.append(f'autopilot estimate (/autopilot/pose) against the true UAV: mean {error.mean():.3f} m, '
                         f'max {error.max():.3f} m over {chosen.shape[0]} poses')
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    _plot(force, interval, out / 'uav_tether_force.png')
    lines.append('tether on the UAV: plot uav_tether_force.png')
    return lines


def _mass(path: Path) -> float:
    value = node_parameter(path, 'json_physics', 'mass')
    return float(value) if value is not None else float(next(p.default for p in PHYSICS_PARAMETERS
                                                              if p.name == 'mass'))


def hover_balance(thrust: np.ndarray, force: np.ndarray, mass: float) -> tuple[float, float, float]:
    """Mean rotor thrust (N), mean |m g e_z − f| (N) and their relative difference over a hold."""
    load = np.linalg.norm(np.array([0.0, 0.0, mass * GRAVITY]) - force, axis=1)
    return float(thrust.mean()), float(load.mean()), float((thrust.mean() - load.mean()) / load.mean())


def hover_balance_line(thrust: np.ndarray, force: np.ndarray, mass: float) -> str:
    """The hover balance as a report line."""
    mean_thrust, load, balance = hover_balance(thrust, force, mass)
    return (f'hover: rotor thrust {mean_thrust:.2f} N against weight {mass * GRAVITY:.2f} N plus the tether\'s pull: '
            f'|m g e_z - f| {load:.2f} N ({100 * balance:+.2f} %)')


def _plot(force: np.ndarray, interval, path: Path) -> None:
    t0 = force[0, 0]
    fig, ax = plt.subplots(figsize=(10, 4))
    ax.plot(force[:, 0] - t0, -force[:, 3], lw=0.8, label='down (−f_z)')
    ax.plot(force[:, 0] - t0, np.linalg.norm(force[:, 1:3], axis=1), lw=0.8, label='sideways |f_xy|')
    ax.plot(force[:, 0] - t0, np.linalg.norm(force[:, 1:], axis=1), lw=0.8, color='k', label='|f|')
    if interval is not None:
        ax.axvspan(interval[0] - t0, min(interval[1], force[-1, 0]) - t0, color='tab:green', alpha=0.1, label='hold')
    ax.set_xlabel('time (s, sim)')
    ax.set_ylabel('tether force on the UAV (N)')
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)

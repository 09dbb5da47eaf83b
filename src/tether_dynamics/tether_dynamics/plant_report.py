"""After-run report of the tether plant from a bag: shapes, end loads, angles, clearance.

Reads ``/tether/state`` (every plant step) and ``/tether/nodes`` (node positions, lower
rate) and writes

* ``tether_snapshots.png``: the tether at six times in 3-D and in the vertical plane
  through its ends, beside the catenary of the reference length for the same ends
  (Eq. 3.2 with Eq. 4.4/4.5), i.e. the shape a perfect smart reel would hold;
* ``tether_loads.png``: tension at the reel and at the UAV, departure and arrival angles
  against time, each beside the reference catenary's value;
* ``tether_clearance.png``: deployed against reference length, and the lowest point's
  clearance above the deck and the sea with the fouling steps marked.

Clearances are above the deck, the datum of every report (:mod:`tether_dynamics.clearance`:
the plant's ``clearance_deck`` plus the run's reel ``guide_height``). The element count is
the plant's ``elements`` parameter; with the moving reel the FEM splits the element at the
guide way as it pays out and merges it as it reels in, so the count varies about it, and
the summary gives its range.

The summary lines put the run's numbers beside the thesis's UAV-surrogate results
(Sec. 6.1: length error, arrival-angle error, tension 2.38 ± 0.27 N).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_bringup.bag_reader import read_bag  # noqa: E402
from tether_bringup.run_directory import node_parameter  # noqa: E402
from tether_dynamics.clearance import above_deck  # noqa: E402
from tether_dynamics.clearance import guide_height  # noqa: E402
from tether_dynamics.statics.catenary import solve  # noqa: E402
from tether_dynamics.plant_markers import reference_shape  # noqa: E402
from tether_dynamics.statics.reference_length import reference_lengths  # noqa: E402

STATE = '/tether/state'
NODES = '/tether/nodes'
SNAPSHOTS = 6
THESIS_TENSION = (2.38, 0.27, 2.21)
"""UAV-surrogate tension with catenary control: mean, std, peak-to-peak (N), Sec. 6.1."""
THESIS_LENGTH_ERROR = (0.022, 0.028)
"""UAV-surrogate length error: mean, RMSE (m), Sec. 6.1."""
THESIS_ARRIVAL_ERROR = 2.1
"""UAV-surrogate arrival-angle error against the catenary theory, mean (deg), Sec. 6.1."""


@dataclass
class TetherRun:
    """Time series of /tether/state and the node snapshots of /tether/nodes."""

    t: np.ndarray
    reel_end: np.ndarray
    uav_end: np.ndarray
    length: np.ndarray
    tension_reel: np.ndarray
    tension_uav: np.ndarray
    departure: np.ndarray
    arrival: np.ndarray
    deck: np.ndarray
    clearance_sea: np.ndarray
    fouling: np.ndarray
    fidelity: str
    elements: int
    element_range: tuple[int, int]
    guide_height: float
    node_t: np.ndarray
    nodes: list[np.ndarray]


def _seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


def read_run(bag_path: Path) -> TetherRun:
    """Read the plant's topics of a bag.

    Raises:
        tether_bringup.errors.BagError: the bag cannot be read.
    """
    rows, node_t, nodes, fidelity, counts = [], [], [], '', set()
    bag = read_bag(bag_path)
    for _, m in bag.decoded(NODES, required=False):
        node_t.append(_seconds(m.header.stamp))
        nodes.append(np.array([(p.x, p.y, p.z) for p in m.positions]).reshape(-1, 3))
    for _, m in bag.decoded(STATE, required=False):
        fidelity = m.fidelity
        counts.add(m.element_count)
        rows.append((_seconds(m.header.stamp), m.reel_end.x, m.reel_end.y, m.reel_end.z,
                     m.uav_end.x, m.uav_end.y, m.uav_end.z, m.deployed_length, m.tension_reel,
                     m.tension_uav, m.departure_angle, m.arrival_angle, m.clearance_deck,
                     m.clearance_sea, float(m.fouling)))
    a = np.array(rows, dtype=float).reshape(-1, 15)
    height = guide_height(bag_path)
    elements = node_parameter(bag_path, 'plant', 'elements')
    element_range = (min(counts), max(counts)) if counts else (0, 0)
    return TetherRun(t=a[:, 0], reel_end=a[:, 1:4], uav_end=a[:, 4:7], length=a[:, 7], tension_reel=a[:, 8],
                     tension_uav=a[:, 9], departure=a[:, 10], arrival=a[:, 11], deck=above_deck(a[:, 12], height),
                     clearance_sea=a[:, 13], fouling=a[:, 14] > 0.5, fidelity=fidelity,
                     elements=int(elements) if isinstance(elements, int) else element_range[1],
                     element_range=element_range, guide_height=height, node_t=np.array(node_t), nodes=nodes)


def _reference(run: TetherRun):
    """Reference length of each state's ends and the catenary of that length (Eq. 3.2-3.12, 4.4/4.5)."""
    d = run.uav_end - run.reel_end
    dr = np.hypot(d[:, 0], d[:, 1])
    length, _ = reference_lengths(dr, d[:, 2])
    return length, solve(dr, d[:, 2], length)


def _plane(points: np.ndarray, origin: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Horizontal distance along origin -> end and height above origin of each point."""
    d = end[:2] - origin[:2]
    norm = np.hypot(*d)
    direction = d / norm if norm > 0 else np.array([1.0, 0.0])
    return (points[:, :2] - origin[:2]) @ direction, points[:, 2] - origin[2]


def _model(run: TetherRun) -> str:
    """The fidelity and element count; a count that varied is given as the range the moving reel made."""
    if not run.elements or run.fidelity == 'quasi_static':
        return run.fidelity
    low, high = run.element_range
    if low == high == run.elements:
        return f'{run.fidelity}, {run.elements} elements'
    return (f'{run.fidelity}, {run.elements} elements set, {low}-{high} over the run as the moving reel splits '
            'and merges the element at the guide way')


def _plot_snapshots(run: TetherRun, out: Path) -> None:
    picks = np.unique(np.linspace(0, len(run.nodes) - 1, SNAPSHOTS).round().astype(int))
    fig = plt.figure(figsize=(13, 6))
    ax3 = fig.add_subplot(1, 2, 1, projection='3d')
    ax2 = fig.add_subplot(1, 2, 2)
    colors = plt.cm.viridis(np.linspace(0.0, 0.9, picks.size))
    for color, i in zip(colors, picks):
        nodes = run.nodes[i]
        ref = reference_shape(nodes[0], nodes[-1])
        label = f't = {run.node_t[i]:.1f} s'
        ax3.plot(nodes[:, 0], nodes[:, 1], nodes[:, 2], color=color, lw=1.6, label=label)
        ax3.plot(ref[:, 0], ref[:, 1], ref[:, 2], color=color, lw=1.0, ls='--')
        r, z = _plane(nodes, nodes[0], nodes[-1])
        rr, zr = _plane(ref, nodes[0], nodes[-1])
        ax2.plot(r, z, color=color, lw=1.6, marker='.', ms=3, label=label)
        ax2.plot(rr, zr, color=color, lw=1.0, ls='--')
    every = np.concatenate([run.nodes[i] for i in picks])
    centre = 0.5 * (every.max(axis=0) + every.min(axis=0))
    half = 0.5 * float(np.max(every.max(axis=0) - every.min(axis=0)))
    for setter, c in zip((ax3.set_xlim, ax3.set_ylim, ax3.set_zlim), centre):
        setter(c - half, c + half)
    ax3.set_box_aspect((1.0, 1.0, 1.0))
    ax3.set_xlabel('x east (m)')
    ax3.set_ylabel('y north (m)')
    ax3.set_zlabel('z up (m)')
    ax3.set_title('tether (solid) and reference catenary (dashed), world')
    ax3.legend(loc='upper left', fontsize=8)
    ax2.set_xlabel('horizontal distance from the guide way (m)')
    ax2.set_ylabel('height above the guide way (m)')
    ax2.set_title('in the vertical plane through the ends')
    ax2.set_aspect('equal', adjustable='datalim')
    ax2.grid(alpha=0.3)
    fig.suptitle(f'tether snapshots ({_model(run)}) beside the catenary of the reference length (Eq. 3.2, 4.4/4.5)')
    fig.tight_layout()
    fig.savefig(out / 'tether_snapshots.png', dpi=110)
    plt.close(fig)


def _plot_loads(run: TetherRun, ref, out: Path) -> None:
    t = run.t
    fig, axes = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    axes[0].plot(t, run.tension_reel, color='tab:red', lw=1.0, label='reel end $T_A$')
    axes[0].plot(t, run.tension_uav, color='tab:blue', lw=1.0, label='UAV end $T_B$')
    axes[0].plot(t, ref.tension_a, color='tab:red', lw=0.8, ls='--', label='reference catenary $T_A$')
    axes[0].plot(t, ref.tension_b, color='tab:blue', lw=0.8, ls='--', label='reference catenary $T_B$')
    axes[0].set_ylabel('tension (N)')
    axes[1].plot(t, np.degrees(run.departure), color='tab:red', lw=1.0, label=r'departure $\alpha$')
    axes[1].plot(t, np.degrees(run.arrival), color='tab:blue', lw=1.0, label=r'arrival $\beta$')
    axes[1].plot(t, np.degrees(ref.alpha), color='tab:red', lw=0.8, ls='--', label=r'reference $\alpha$')
    axes[1].plot(t, np.degrees(ref.beta), color='tab:blue', lw=0.8, ls='--', label=r'reference $\beta$')
    axes[1].set_ylabel('angle above horizontal (deg)')
    axes[1].set_xlabel('time (s)')
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(loc='upper right', fontsize=8, ncol=2)
    fig.suptitle('end tensions and angles (cf. Fig. 6.2, 6.4)')
    fig.tight_layout()
    fig.savefig(out / 'tether_loads.png', dpi=110)
    plt.close(fig)


def _plot_clearance(run: TetherRun, reference_length: np.ndarray, out: Path) -> None:
    t = run.t
    fig, axes = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    axes[0].plot(t, run.length, color='tab:orange', lw=1.2, label='deployed')
    axes[0].plot(t, reference_length, color='k', lw=0.8, ls='--', label='reference (Eq. 4.4/4.5)')
    axes[0].set_ylabel('tether length (m)')
    axes[1].plot(t, run.deck, color='tab:brown', lw=1.0,
                 label=f'lowest point above the deck (guide way {run.guide_height:.2f} m above it)')
    axes[1].plot(t, run.clearance_sea, color='tab:cyan', lw=1.0, label='lowest point above the sea')
    axes[1].axhline(0.0, color='k', lw=0.6)
    if run.fouling.any():
        axes[1].fill_between(t, 0, 1, where=run.fouling, color='tab:red', alpha=0.25,
                             transform=axes[1].get_xaxis_transform(), label='fouling')
    axes[1].set_ylabel('clearance (m)')
    axes[1].set_xlabel('time (s)')
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(loc='upper right', fontsize=8)
    fig.suptitle('deployed length and fouling clearance')
    fig.tight_layout()
    fig.savefig(out / 'tether_clearance.png', dpi=110)
    plt.close(fig)


def tether_report(bag_path: str, out_dir: str) -> list[str]:
    """Plot the plant's run from a bag; return summary lines beside the thesis's Sec. 6.1 numbers.

    Args:
        bag_path: the run's rosbag2 MCAP file (or its directory).
        out_dir: where the PNGs are written.

    Raises:
        ValueError: the bag cannot be read.
    """
    run = read_run(Path(bag_path))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if run.t.size == 0:
        return [f'tether: no {STATE} messages in the bag']
    reference_length, ref = _reference(run)
    if run.nodes:
        _plot_snapshots(run, out)
    _plot_loads(run, ref, out)
    _plot_clearance(run, reference_length, out)
    length_error = run.length - reference_length
    arrival_error = np.degrees(run.arrival - ref.beta)
    tb = run.tension_uav
    lines = [
        f'tether: {run.t.size} plant steps over {run.t[-1] - run.t[0]:.1f} s ({_model(run)}), '
        f'{len(run.nodes)} node snapshots',
        f'tether: UAV-end tension {tb.mean():.2f} ± {tb.std():.2f} N, peak-to-peak {np.ptp(tb):.2f} N '
        f'(thesis, UAV surrogate with catenary control: {THESIS_TENSION[0]} ± {THESIS_TENSION[1]} N, '
        f'peak-to-peak {THESIS_TENSION[2]} N); reel-end tension {run.tension_reel.mean():.2f} ± '
        f'{run.tension_reel.std():.2f} N, max {run.tension_reel.max():.2f} N',
        f'tether: deployed minus reference length mean {length_error.mean() * 1000:+.1f} mm, RMSE '
        f'{np.sqrt(np.mean(length_error**2)) * 1000:.1f} mm (thesis smart reel: mean '
        f'{THESIS_LENGTH_ERROR[0] * 1000:.0f} mm, RMSE {THESIS_LENGTH_ERROR[1] * 1000:.0f} mm)',
        f'tether: arrival angle minus reference catenary mean {arrival_error.mean():+.2f} deg, mean |error| '
        f'{np.abs(arrival_error).mean():.2f} deg (thesis, measured against theory: {THESIS_ARRIVAL_ERROR} deg); '
        f'departure angle {np.degrees(run.departure.min()):+.1f}..{np.degrees(run.departure.max()):+.1f} deg',
        f'tether: lowest point at least {run.deck.min():.2f} m above the deck (the guide way is '
        f'{run.guide_height:.2f} m above it) and '
        f'{run.clearance_sea.min():.2f} m above the sea; fouling in {run.fouling.mean() * 100:.1f} % of steps',
    ]
    return lines

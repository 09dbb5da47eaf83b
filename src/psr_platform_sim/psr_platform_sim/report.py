"""After-run report of the platform: commanded vs. achieved roll, pitch and heave from a bag.

PlatformState carries both achieved and commanded roll and pitch as REP-103 angles of the
FLU ``boat`` frame in ``world`` (see :mod:`psr_platform_sim.simulator`), so they are
compared directly; the differences include the effect of the mechanism's coupled yaw.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tether_bringup.bag_reader import read_bag  # noqa: E402
from tether_common.report_figures import ReportLines  # noqa: E402

TOPIC = '/platform/state'


def _read_states(bag_path: Path) -> np.ndarray:
    """Rows of (stamp, heave, roll, pitch, commanded heave, roll, pitch, in_workspace)."""
    bag = read_bag(bag_path)
    if TOPIC not in bag.topics:
        return np.zeros((0, 8))
    rows = [(m.header.stamp.sec + m.header.stamp.nanosec * 1e-9, m.heave, m.roll, m.pitch,
             m.commanded_heave, m.commanded_roll, m.commanded_pitch, float(m.in_workspace))
            for _, m in bag.decoded(TOPIC)]
    return np.array(rows, dtype=float).reshape(-1, 8)


def tracking_report(bag_path: str, out_dir: str) -> ReportLines:
    """Plot commanded vs. achieved roll, pitch (REP-103), heave from /platform/state and the error; return RMS error
    lines, and as figures (data) the RMS errors (m, rad), the fraction of states clipped and the achieved heave's range (m).

    Args:
        bag_path: the run's rosbag2 MCAP file (or its directory).
        out_dir: where ``platform_tracking.png`` is written.

    Raises:
        tether_bringup.errors.BagError: the bag cannot be read.
    """
    data = _read_states(Path(bag_path))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if data.shape[0] == 0:
        return ReportLines([f'platform: no {TOPIC} messages in the bag'], {})
    t = data[:, 0] - data[0, 0]
    error = data[:, 1:4] - data[:, 4:7]
    rms = np.sqrt(np.mean(error**2, axis=0))
    fig, axes = plt.subplots(3, 2, figsize=(13, 8), sharex=True)
    rows = ((0, 'heave', 'm', 1.0, 'mm', 1000.0), (1, 'roll', 'deg, REP-103', np.degrees(1.0), 'deg', np.degrees(1.0)),
            (2, 'pitch', 'deg, REP-103', np.degrees(1.0), 'deg', np.degrees(1.0)))
    for i, name, unit, scale, error_unit, error_scale in rows:
        ax, ax_error = axes[i]
        ax.plot(t, data[:, 4 + i] * scale, color='tab:blue', lw=1.2, label='commanded')
        ax.plot(t, data[:, 1 + i] * scale, color='tab:red', lw=0.8, ls='--', label='achieved')
        ax.set_ylabel(f'{name} ({unit})')
        ax_error.plot(t, error[:, i] * error_scale, color='tab:purple', lw=0.8)
        ax_error.axhline(0.0, color='k', lw=0.6)
        ax_error.set_ylabel(f'{name} error ({error_unit})')
        for a in (ax, ax_error):
            a.grid(alpha=0.3)
    axes[0, 0].legend(loc='upper right')
    axes[0, 0].set_title('commanded and achieved')
    axes[0, 1].set_title('achieved minus commanded')
    for a in axes[-1]:
        a.set_xlabel('time (s)')
    fig.suptitle('3-PSR platform tracking (cf. Fig. 2.7)')
    fig.tight_layout()
    fig.savefig(out / 'platform_tracking.png', dpi=110)
    plt.close(fig)
    clipped = (1.0 - data[:, 7].mean()) * 100.0
    figures = {'tracking_rmse_heave': rms[0], 'tracking_rmse_roll': rms[1], 'tracking_rmse_pitch': rms[2],
               'clipped_fraction': clipped / 100.0, 'heave_min': data[:, 1].min(), 'heave_max': data[:, 1].max()}
    return ReportLines([f'platform: {data.shape[0]} states over {t[-1]:.1f} s; RMS tracking error heave '
            f'{rms[0] * 1000:.1f} mm, roll {np.degrees(rms[1]):.3f} deg, pitch {np.degrees(rms[2]):.3f} deg',
            f'platform: {clipped:.1f} % of states had the command clipped to the workspace; '
            f'commanded roll range {np.degrees(data[:, 5].min()):+.1f}..{np.degrees(data[:, 5].max()):+.1f} deg, '
            f'pitch {np.degrees(data[:, 6].min()):+.1f}..{np.degrees(data[:, 6].max()):+.1f} deg, '
            f'heave {data[:, 4].min():+.2f}..{data[:, 4].max():+.2f} m'], figures)

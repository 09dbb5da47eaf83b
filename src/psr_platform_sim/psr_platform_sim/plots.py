"""PNG figures of the workspace, the design study and the path tracking (Agg backend)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from psr_platform_sim.optimize import StudyResult  # noqa: E402
from psr_platform_sim.workspace import Region  # noqa: E402
from psr_platform_sim.workspace import WorkspaceTable  # noqa: E402


def _slider_curves(ax, table: WorkspaceTable, region: Region, count: int = 3) -> None:
    """Draw S1, S2, S3 curves: one slider moves, the other two stay (Fig. 2.3a)."""
    n = table.steps
    roll, pitch = np.degrees(table.roll), np.degrees(table.pitch)
    mask = table.feasible
    offsets = np.linspace(-0.25, 0.25, count) * n
    colours = {'S1': 'tab:red', 'S2': 'tab:green', 'S3': 'tab:blue'}
    for offset in offsets.astype(int):
        mid = n // 2 + offset
        paths = {
            'S2': (np.arange(n), np.full(n, mid)),
            'S3': (np.full(n, mid), np.arange(n)),
            'S1': (np.clip(np.arange(n), 0, n - 1), np.clip(np.arange(n) + offset, 0, n - 1)),
        }
        for name, (j, k) in paths.items():
            keep = mask[j, k]
            ax.plot(np.where(keep, roll[j, k], np.nan), np.where(keep, pitch[j, k], np.nan),
                    color=colours[name], lw=0.8, label=name if offset == offsets.astype(int)[0] else None)


def workspace_figure(table: WorkspaceTable, region: Region, path: Path, title: str) -> None:
    """Fig. 2.3: slider curves over the workspace (a) and yaw coupling as colour (b)."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2))
    roll, pitch, yaw = (np.degrees(a) for a in (table.roll, table.pitch, table.yaw))
    ax = axes[0]
    ax.scatter(roll[table.feasible], pitch[table.feasible], s=0.3, color='0.8', label='feasible (Eq. 2.14-2.15)')
    _slider_curves(ax, table, region)
    ax.set_title('a) slider curves')
    ax.legend(loc='upper right', fontsize=8)
    ax = axes[1]
    keep = region.points
    sc = ax.scatter(roll[keep], pitch[keep], c=yaw[keep], s=0.5, cmap='viridis')
    fig.colorbar(sc, ax=ax, label='yaw (deg)')
    ax.set_title(f'b) usable workspace {region.area:.0f} deg$^2$, yaw coupling')
    for a in axes:
        a.set_xlabel('roll $\\phi$ (deg)')
        a.set_ylabel('pitch $\\theta$ (deg)')
        a.set_aspect('equal')
        a.grid(alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def optimized_figure(regions: list[tuple[WorkspaceTable, Region, str]], path: Path) -> None:
    """Fig. 2.4: the optimal workspaces overlaid, the larger one first."""
    fig, ax = plt.subplots(figsize=(6.5, 6))
    colours = ('tab:blue', 'tab:orange', 'tab:green')
    for (table, region, label), colour in zip(regions, colours):
        keep = region.points
        ax.scatter(np.degrees(table.roll[keep]), np.degrees(table.pitch[keep]), s=0.5,
                   color=colour, label=f'{label}: {region.area:.0f} deg$^2$')
    ax.set_xlabel('roll $\\phi$ (deg)')
    ax.set_ylabel('pitch $\\theta$ (deg)')
    ax.set_aspect('equal')
    ax.grid(alpha=0.3)
    ax.legend(loc='upper right', fontsize=8, markerscale=10)
    ax.set_title('Optimized roll-pitch workspaces (cf. Fig. 2.4)')
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def study_figure(result: StudyResult, path: Path) -> None:
    """Workspace area over (l, d) without and with the ball-joint limit."""
    ratios = result.settings.ratios
    nominal = np.where(result.components == 1, result.nominal_area, np.nan)
    ball = np.where(result.ball_components == 1, result.ball_area, np.nan)
    ball = np.nanmax(np.where(np.isnan(ball), -1.0, ball), axis=-1)
    ball = np.where(ball < 0, np.nan, ball)
    fig, axes = plt.subplots(1, 2, figsize=(12, 5))
    extent = (ratios[0], ratios[-1], ratios[0], ratios[-1])
    for ax, data, title in ((axes[0], nominal, 'a) area, Eq. 2.14-2.16'),
                            (axes[1], ball, 'b) with ball-joint limit, best $\\gamma$')):
        im = ax.imshow(data.T, origin='lower', extent=extent, aspect='equal', cmap='magma')
        fig.colorbar(im, ax=ax, label='deg$^2$')
        ax.set_xlabel('l / r')
        ax.set_ylabel('d / r')
        ax.set_title(title + '\n(blank: disjoint or empty)', fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def profiles_figure(profiles, path: Path) -> None:
    """Fig. 5.5: amplitude spectra of the profiles' heave (a) and the last profile's time series (b)."""
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8))
    for profile in profiles:
        dt = profile.t[1] - profile.t[0]
        freq = np.fft.rfftfreq(profile.t.size, dt)
        amplitude = 2.0 * np.abs(np.fft.rfft(profile.heave)) / profile.t.size
        axes[0].plot(freq[1:], amplitude[1:], lw=0.9, label=profile.name)
    axes[0].set_xlim(0.0, 0.5)
    axes[0].set_xlabel('frequency (Hz)')
    axes[0].set_ylabel('heave amplitude (m)')
    axes[0].legend(fontsize=7)
    axes[0].set_title('a) heave spectra')
    last = profiles[-1]
    ax = axes[1]
    ax.plot(last.t, last.heave, color='k', lw=1.0, label='heave (m)')
    ax2 = ax.twinx()
    ax2.plot(last.t, np.degrees(last.roll), color='tab:red', lw=0.8, label='roll (deg)')
    ax2.plot(last.t, np.degrees(last.pitch), color='tab:blue', lw=0.8, label='pitch (deg)')
    ax.set_xlabel('time (s)')
    ax.set_ylabel('heave (m)')
    ax2.set_ylabel('angle (deg)')
    ax2.legend(loc='upper right', fontsize=8)
    ax.set_title(f'b) {last.name}')
    for a in axes:
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def tracking_figure(sim, path: Path) -> None:
    """Fig. 2.7b: commanded vs. achieved roll, pitch and heave of a played profile."""
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    heave, roll, pitch = sim.achieved_hrp()
    achieved = (heave, np.degrees(roll), np.degrees(pitch))
    commanded = (sim.command[:, 0], np.degrees(sim.command[:, 1]), np.degrees(sim.command[:, 2]))
    for ax, a, c, label in zip(axes, achieved, commanded, ('heave (m)', 'roll (deg)', 'pitch (deg)')):
        ax.plot(sim.command_t, c, color='tab:blue', lw=1.2, label='commanded')
        ax.plot(sim.t, a, color='tab:red', lw=0.8, ls='--', label='achieved (exact kinematics)')
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(loc='upper right', fontsize=8)
    axes[-1].set_xlabel('time (s)')
    fig.suptitle(f'{sim.profile_name}: commanded vs. achieved (cf. Fig. 2.7b)')
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)

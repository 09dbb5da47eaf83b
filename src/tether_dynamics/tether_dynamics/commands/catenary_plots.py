"""PNG plots of the flying-space analysis (thesis Fig. 3.3-3.8) and of Fig. 4.3."""

from __future__ import annotations

from typing import TYPE_CHECKING

import matplotlib as mpl

mpl.use('Agg')
import matplotlib.pyplot as plt
import numpy as np

from tether_dynamics.statics import catenary, flying_space, heave_robustness, reference_length

if TYPE_CHECKING:
    from pathlib import Path

_ROB_COLORS = ('tab:orange', 'tab:purple', 'tab:brown')


def _save(fig: plt.Figure, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def shapes(path: Path, dx: float = 44.0, dy: float = 55.0) -> Path:
    """Fig. 3.3: the swept catenary shapes for one position, taut/slack/T_min/max marked."""
    lengths = flying_space.sweep_lengths(np.array([dx]), np.array([dy]))[0]
    sol = catenary.solve(dx, dy, lengths)
    r, z = sol.shape(201)
    k_min = int(np.argmin(sol.tension_b))
    k_slack = int(np.sum(sol.alpha >= 0.0) - 1)
    fig, ax = plt.subplots(figsize=(6, 6))
    for k in range(0, lengths.size, 8):
        ax.plot(r[k], z[k], color='0.8', lw=0.5)
    for k, color, label in ((0, 'c', 'taut'), (k_slack, 'r', 'slack'), (k_min, 'g', 'min tension'),
                            (lengths.size - 1, 'b', 'max length')):
        ax.plot(r[k], z[k], color=color, lw=2, label=f'{label}, L = {lengths[k]:.1f} m')
    ax.set(xlabel='Δx (m)', ylabel='Δy (m)', aspect='equal',
           title=f'Catenary shapes, Δy = {dy:g} m, Δx = {dx:g} m, {lengths.size} lengths')
    ax.legend(fontsize=8)
    return _save(fig, path)


def tension_vs_length(path: Path, dy: float = 55.0, offsets: tuple[float, ...] = (5.0, 30.0, 55.0),
                      linear_density: float = catenary.THESIS_LINEAR_DENSITY) -> Path:
    """Fig. 3.4: UAV tension vs tether length with slack and minimum-tension markers."""
    fig, axes = plt.subplots(1, len(offsets), figsize=(4 * len(offsets), 3.6))
    for ax, dx in zip(axes, offsets, strict=True):
        lengths = flying_space.sweep_lengths(np.array([dx]), np.array([dy]))[0][1:]
        sol = catenary.solve(dx, dy, lengths, linear_density)
        k_min = int(np.argmin(sol.tension_b))
        l_slack = float(heave_robustness.slack_length(dx, dy))
        t_slack = float(catenary.solve(dx, dy, l_slack, linear_density).tension_b)
        ax.plot(lengths, sol.tension_b, 'k')
        ax.plot(l_slack, t_slack, 'ro', label='slack')
        ax.plot(lengths[k_min], sol.tension_b[k_min], 'go', label='min tension')
        ax.set(xlabel='L (m)', ylabel='T_B (N)', title=f'Δy = {dy:g} m, Δx = {dx:g} m',
               ylim=(0.0, 3.0 * sol.tension_b[k_min]))
        ax.legend(fontsize=8)
    return _save(fig, path)


def _row(result: flying_space.SweepResult, dy: float) -> np.ndarray:
    return np.flatnonzero(np.isclose(result.dy, dy))


def margins(path: Path, result: flying_space.SweepResult, dy: float = 55.0) -> Path:
    """Fig. 3.5: heave tolerance (up and down) for Δy = 55 m and nondimensionalized."""
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4))
    row = _row(result, dy)
    x = np.linspace(0.005, 1.2, 300)
    for rise, heave, color in zip(flying_space.RISES, result.rob_heave, _ROB_COLORS, strict=True):
        label = f'{round(100 * rise)} % rise'
        order = np.argsort(result.dx[row])
        ax_a.plot(result.dx[row][order], heave[row][order], color=color, label=label)
        ax_a.plot(result.dx[row][order], -heave[row][order], color=color)
        use = result.ratio <= 1.2
        ax_b.plot(result.ratio[use], heave[use] / result.dy[use], '.', ms=1, color=color)
        exact = flying_space.heave_tolerance_curve(x, rise)
        ax_b.plot(x, exact, color=color, label=f'{label} (exact)')
        ax_b.plot(x, -exact, color=color)
    ax_a.set(xlabel='Δx (m)', ylabel='heave tolerance Δy₁ = Δy₂ (m)', title=f'Δy = {dy:g} m')
    ax_b.set(xlabel='Δx/Δy', ylabel='Δy₁/Δy', title='nondimensional (dots: sweep)')
    for ax in (ax_a, ax_b):
        ax.axhline(0.0, color='k', lw=0.5)
        ax.legend(fontsize=8)
    return _save(fig, path)


def fitted_quantity(path: Path, result: flying_space.SweepResult, table: str,
                    fits: dict[str, dict[str, flying_space.Fit]], linear_density: float,
                    dy: float = 55.0) -> Path:
    """Fig. 3.6-3.8: one table's quantities for Δy = 55 m and nondimensionalized with fits."""
    data = flying_space.curve_data(result, linear_density)[table]
    scale = {'tension': linear_density * result.dy, 'length': result.dy,
             'angle': np.ones_like(result.dy)}[table]
    unit = {'tension': ('T_B (N)', 'T_B/(λ Δy)'), 'length': ('L (m)', 'L/Δy'),
            'angle': ('α (deg)', 'α (deg)')}[table]
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4))
    row = _row(result, dy)
    order = np.argsort(result.dx[row])
    x = np.linspace(0.0, 1.2, 300)
    use = result.ratio <= 1.2
    for i, (name, values) in enumerate(data.items()):
        color = f'C{i}'
        ax_a.plot(result.dx[row][order], (values * scale)[row][order], color=color, label=name)
        ax_b.plot(result.ratio[use], values[use], '.', ms=1, color=color)
        ax_b.plot(x, fits[table][name](x), color=color, label=f'{name} fit')
        ax_b.plot(x, flying_space.thesis_fit(table, name)(x), '--', color=color, lw=1)
    ax_a.set(xlabel='Δx (m)', ylabel=unit[0], title=f'Δy = {dy:g} m')
    ax_b.set(xlabel='Δx/Δy', ylabel=unit[1],
             title='nondimensional: dots sweep, solid project fit, dashed thesis')
    ax_a.legend(fontsize=7)
    ax_b.legend(fontsize=7)
    return _save(fig, path)


def reference_model(path: Path, dz: float = 30.0) -> Path:
    """Fig. 4.3: Eq. 4.4, Eq. 4.5, the safeguarded model and the exact L_rob5 vs Δr/Δz."""
    ratio = np.linspace(0.0, 2.5, 501)
    dr = ratio * dz
    poly3 = np.polynomial.polynomial.polyval(ratio, reference_length.POLY3)
    poly2 = np.polynomial.polynomial.polyval(ratio, reference_length.POLY2)
    model, _ = reference_length.reference_lengths(dr, np.full_like(dr, dz))
    exact = heave_robustness.robust_length(dr, dz, reference_length.RISE).length
    slack = heave_robustness.slack_length(dr, dz)
    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(11, 4))
    ax_a.plot(ratio, poly3, label='Eq. 4.4 (3rd order)')
    ax_a.plot(ratio, poly2, label='Eq. 4.5 (2nd order)')
    ax_a.plot(ratio, model / dz, 'k', lw=2, label='reference model (blend 1.1-1.3, safeguards)')
    ax_a.plot(ratio, exact / dz, 'g--', label='exact L_rob5')
    ax_a.plot(ratio, slack / dz, 'r:', label='L_slack')
    ax_a.plot(ratio, np.hypot(ratio, 1.0), 'c:', label='taut (chord)')
    ax_a.set(xlabel='Δr/Δz', ylabel='L/Δz', ylim=(0.9, 3.0), title='Reference length models')
    ax_a.legend(fontsize=7)
    ax_b.plot(ratio, model - exact, 'k')
    ax_b.set(xlabel='Δr/Δz', ylabel='model - exact (m)', title=f'Δz = {dz:g} m')
    ax_b.axhline(0.0, color='0.5', lw=0.5)
    return _save(fig, path)


def reference_error_map(path: Path, dz: np.ndarray, ratio: np.ndarray, error: np.ndarray) -> Path:
    """Heat map of reference-model minus exact length (m) over the operating envelope."""
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    limit = float(np.max(np.abs(error)))
    mesh = ax.pcolormesh(ratio, dz, error, cmap='coolwarm', vmin=-limit, vmax=limit,
                         shading='auto')
    fig.colorbar(mesh, ax=ax, label='model - exact L_rob5 (m)')
    ax.set(xlabel='Δr/Δz', ylabel='Δz (m)', title='Reference length error over the envelope')
    return _save(fig, path)

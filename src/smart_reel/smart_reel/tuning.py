"""How the catenary controller's gains are found: ``tethersim reel tune``.

The procedure, reproducible by the command:

1. **Design model.** From the motor and winch parameters, the voltage-to-length transfer
   function of the drive, ``G(s) = k/(s (τ s + 1))`` with ``k = r N K/(R c)``,
   ``τ = J/c``, ``c = (N K)²/R + b`` (back-EMF and viscous damping, drum radius ``r`` and
   inertia ``J`` at the tuning length), sampled with a zero-order hold at the control
   period, in a loop with the discrete PD ``C(z) = K_p + K_d (1 - z⁻¹)/T``.
2. **Robustness constraints** on that sampled loop: phase margin ≥ ``MIN_PHASE_MARGIN`` and
   gain margin ≥ ``MIN_GAIN_MARGIN``; and on the closed-loop step response of the full
   nonlinear drive (:func:`closed_loop_response`): overshoot ≤ ``MAX_OVERSHOOT``.
3. **Objective:** the length RMSE against the catenary reference model on the tuning
   profile (UAV-surrogate geometry of Sec. 5.1, the thesis's JONSWAP heave-only profile),
   simulated with :class:`~smart_reel.reel.ReelCore` exactly as the node runs it (winch
   with friction and stiction, encoder, 4 Hz radial distance, scheduled filter, one-step
   input delay) against the quasi-static catenary tension of the tether
   (:mod:`tether_dynamics.statics.catenary`).
4. **Search:** Nelder-Mead over ``(log K_p, log K_d)`` from the gains that put the crossover
   at a tenth of the sampling frequency, constraints as penalties.
5. **Check** on the held-out HPR 3 profile, reported beside the tuning result.

The step and ramp responses of the tuned loop are stated in the summary (settling time,
overshoot, ramp following error) and asserted by the tests.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import minimize

from smart_reel.controller import DiscretePid
from smart_reel.reel import ReelInputs
from smart_reel.reel import build_core
from smart_reel.reel_params import PARAMETERS
from tether_common.command_line import positive
from tether_dynamics.statics.catenary import tension_b_point
from tether_dynamics.statics.reference_length import reference_length
from tether_models.constants import GRAVITY
from tether_models.waves import named_profile

MIN_PHASE_MARGIN = 45.0
"""deg, of the sampled linear loop."""
MIN_GAIN_MARGIN = 6.0
"""dB, of the sampled linear loop."""
MAX_OVERSHOOT = 0.10
"""Fraction of a 0.1 m reference step."""
SETTLING_BAND = 0.02
"""Settling band, fraction of the step."""


def default_parameters() -> dict:
    """The reel node's default parameter values."""
    return {p.name: p.default for p in PARAMETERS}


@dataclass(frozen=True)
class SurrogateRig:
    """UAV-surrogate geometry of Sec. 5.1: UAV end fixed, reel on the replicator.

    ``height`` is the UAV above the guide way with the platform at the bottom of its heave
    range, where the relative position is at the recommended ``ratio`` Δr/Δz.
    """

    height: float = 7.0
    ratio: float = 0.46
    heave_limit: float = 1.1

    @property
    def radial(self) -> float:
        """Δr (m), constant: the reel sits at the platform centre."""
        return self.ratio * self.height

    @property
    def uav_z(self) -> float:
        """World z of the UAV end (m), guide way at z = heave."""
        return self.height - self.heave_limit


def heave_profile(name: str, duration: float, rate: float, seed: int = 1, ramp: float = 5.0):
    """Platform heave (m) and heave rate (m/s) of a named profile at ``rate`` Hz."""
    profile = named_profile(name, seed=seed, duration=duration).ramped(ramp)
    t = np.arange(0.0, duration, 1.0 / rate)
    heave = np.interp(t, profile.t, profile.heave)
    return t, heave, np.gradient(heave, t)


def reel_tension(dr: float, dz: float, length: float, linear_density: float) -> float:
    """Quasi-static tension at the reel end (N) of the catenary, ``T_A = T_B - λ g Δz``."""
    chord = math.hypot(dr, dz)
    tb = tension_b_point(dr, dz, max(length, chord * (1.0 + 1e-9)), linear_density)
    return min(tb, 1e4) - linear_density * GRAVITY * dz


def simulate(params: dict, t: np.ndarray, heave: np.ndarray, heave_rate: np.ndarray,
             rig: SurrogateRig = SurrogateRig()) -> dict[str, np.ndarray]:
    """Closed loop of :class:`ReelCore` against the quasi-static catenary on a heave profile.

    Inputs at tick ``k`` are those of tick ``k - 1`` (the node's one-step ``input_delay``).
    Returns arrays: t, deployed and reference length, voltage, tension, payout rate.
    """
    dr = rig.radial
    dz = rig.uav_z - heave
    initial = reference_length(dr, dz[0], params['reference_mode']).length
    core = build_core(params, initial)
    lam = params['linear_density']
    n = len(t)
    out = {key: np.zeros(n) for key in ('deployed', 'reference', 'voltage', 'tension', 'payout')}
    inputs = ReelInputs(dr, dz[0], -heave_rate[0], reel_tension(dr, dz[0], initial, lam))
    for k in range(n):
        result = core.step(float(t[k]), inputs)
        tension = reel_tension(dr, dz[k], result.deployed_length, lam)
        inputs = ReelInputs(dr, float(dz[k]), float(-heave_rate[k]), tension)
        out['deployed'][k] = result.deployed_length
        out['reference'][k] = reference_length(dr, float(dz[k]), params['reference_mode']).length
        out['voltage'][k] = result.voltage
        out['tension'][k] = tension
        out['payout'][k] = result.payout_rate
    out['t'] = t
    return out


def design_plant(params: dict, length: float) -> tuple[float, float]:
    """Gain ``k`` (m/(V s)) and time constant ``τ`` (s) of ``G(s) = k/(s(τs+1))`` at ``length``."""
    core = build_core(params, length)
    w = core.winch
    m = w.motor
    c = m.back_emf_damping + w.friction.viscous
    r = w.spool.radius(length)
    return r * m.shaft_constant / (m.resistance * c), w.inertia() / c


def loop_margins(kp: float, kd: float, k: float, tau: float, period: float) -> tuple[float, float, float]:
    """Phase margin (deg), gain margin (dB) and crossover (rad/s) of the sampled PD loop."""
    a = math.exp(-period / tau)
    # ZOH equivalent of k/(s(τs+1)): k [(T - τ(1-a)) z + (τ(1-a) - aT)] / ((z - 1)(z - a))
    b1 = k * (period - tau * (1.0 - a))
    b0 = k * (tau * (1.0 - a) - a * period)
    w = np.logspace(-2, math.log10(math.pi / period * 0.999), 4000)
    z = np.exp(1j * w * period)
    loop = (kp + kd * (1.0 - 1.0 / z) / period) * (b1 * z + b0) / ((z - 1.0) * (z - a))
    mag = np.abs(loop)
    phase = np.unwrap(np.angle(loop))
    cross = np.nonzero((mag[:-1] >= 1.0) & (mag[1:] < 1.0))[0]
    if len(cross) == 0:
        return -180.0, -math.inf, 0.0
    i = cross[0]
    pm = 180.0 + math.degrees(phase[i])
    below = np.nonzero(phase <= -math.pi)[0]
    # the phase of the sampled integrator reaches -180 deg only at the Nyquist frequency
    gm = -20.0 * math.log10(mag[below[0]] if len(below) else mag[-1])
    return pm, gm, float(w[i])


def closed_loop_response(params: dict, reference, duration: float, length: float = 8.0):
    """The drive under the discrete PD following ``reference(t)`` (m, offset from ``length``).

    No tether load; friction, stiction, limits and the encoder as in the node.
    Returns (t, deployed offset, reference offset) at the winch step.
    """
    core = build_core(params, length)
    step = params['step']
    pid = DiscretePid(params['kp'], params['kd'], params['ki'], 1.0 / params['control_rate'],
                      min(params['voltage_limit'], params['supply_voltage']), core.winch.motor.voltage_step)
    per_tick = round(1.0 / params['control_rate'] / step)
    n = round(duration / step)
    t = np.arange(n) * step
    y = np.zeros(n)
    ref = np.array([reference(tk) for tk in t])
    voltage = 0.0
    for k in range(n):
        if k % per_tick == 0:
            voltage = pid.step(core.measured_length() - length - ref[k]).output
        core.winch.step(step, 'voltage', voltage, 0.0)
        y[k] = core.winch.deployed - length
    return t, y, ref


def step_metrics(t: np.ndarray, y: np.ndarray, size: float) -> tuple[float, float]:
    """Overshoot (fraction) and settling time (s, into ±SETTLING_BAND) of a step of ``size`` at t = 0."""
    overshoot = max(0.0, (np.max(y) - size) / size)
    outside = np.nonzero(np.abs(y - size) > SETTLING_BAND * size)[0]
    settling = float(t[outside[-1] + 1]) if len(outside) and outside[-1] + 1 < len(t) else float(t[-1])
    return overshoot, settling


def _rmse(sim: dict[str, np.ndarray], skip: float) -> float:
    keep = sim['t'] >= skip
    return float(np.sqrt(np.mean((sim['deployed'][keep] - sim['reference'][keep]) ** 2)))


def tune(params: dict, tuning: tuple, evaluations: int = 60, log=print) -> dict:
    """Search (K_p, K_d) as the module docstring describes; return gains and figures."""
    rig = SurrogateRig()
    k, tau = design_plant(params, reference_length(rig.radial, rig.height).length)
    period = 1.0 / params['control_rate']
    kp0 = 2.0 * math.pi / period / 10.0 / k
    start = np.log([kp0, kp0 * period])
    cache: dict[tuple, float] = {}

    def cost(x: np.ndarray) -> float:
        kp, kd = (float(v) for v in np.exp(x))
        key = (round(kp, 6), round(kd, 6))
        if key in cache:
            return cache[key]
        pm, gm, _ = loop_margins(kp, kd, k, tau, period)
        penalty = max(0.0, MIN_PHASE_MARGIN - pm) * 0.01 + max(0.0, MIN_GAIN_MARGIN - gm) * 0.01
        trial = dict(params, kp=kp, kd=kd)
        if penalty == 0.0:
            t, y, _ = closed_loop_response(trial, lambda _t: 0.1, 2.0)
            penalty += max(0.0, step_metrics(t, y, 0.1)[0] - MAX_OVERSHOOT)
        value = _rmse(simulate(trial, *tuning), 10.0) + penalty
        cache[key] = value
        log(f'  kp {kp:8.1f} V/m  kd {kd:7.2f} V s/m  PM {pm:5.1f} deg  GM {gm:5.1f} dB  cost {value:.5f}')
        return value

    result = minimize(cost, start, method='Nelder-Mead',
                      options={'maxfev': evaluations, 'xatol': 0.02, 'fatol': 1e-5, 'initial_simplex': [
                          start, start + [0.7, 0.0], start + [0.0, 0.7]]})
    kp, kd = (float(v) for v in np.exp(result.x))
    pm, gm, wc = loop_margins(kp, kd, k, tau, period)
    return {'kp': kp, 'kd': kd, 'phase_margin': pm, 'gain_margin': gm, 'crossover': wc, 'k': k, 'tau': tau,
            'kp0': kp0, 'evaluations': len(cache)}


def _command(args: argparse.Namespace) -> str:
    params = default_parameters()
    rate = 1.0 / params['step']
    tuning = heave_profile('jonswap', args.duration, rate, seed=1)
    held_out = heave_profile('hpr3', args.duration, rate)
    print(f'tuning on the JONSWAP heave-only profile, {args.duration:g} s (held out: HPR 3)', file=sys.stderr)
    gains = tune(params, tuning, args.evaluations, log=lambda s: print(s, file=sys.stderr))
    tuned = dict(params, kp=round(gains['kp'], 1), kd=round(gains['kd'], 2))
    sims = {'tuning (JONSWAP)': simulate(tuned, *tuning), 'held out (HPR 3)': simulate(tuned, *held_out)}
    t, y, _ = closed_loop_response(tuned, lambda _t: 0.1, 2.0)
    overshoot, settling = step_metrics(t, y, 0.1)
    tr, yr, rr = closed_loop_response(tuned, lambda tk: 0.5 * tk, 3.0)
    ramp_error = float(np.max(np.abs(yr - rr)[tr >= 1.0]))
    lines = [
        'Catenary-controller gains (tethersim reel tune)',
        f'design model G(s) = k/(s(tau s + 1)): k = {gains["k"]:.4f} m/(V s), tau = {gains["tau"] * 1000:.2f} ms',
        f'start: kp = {gains["kp0"]:.1f} V/m (crossover at 1/10 of the 50 Hz sampling), kd = kp T',
        f'result after {gains["evaluations"]} evaluations: kp = {tuned["kp"]:.1f} V/m, kd = {tuned["kd"]:.2f} V s/m',
        f'sampled loop: phase margin {gains["phase_margin"]:.1f} deg (>= {MIN_PHASE_MARGIN:g}), gain margin '
        f'{gains["gain_margin"]:.1f} dB (>= {MIN_GAIN_MARGIN:g}), crossover {gains["crossover"]:.1f} rad/s',
        f'0.1 m step: overshoot {overshoot * 100:.1f} % (<= {MAX_OVERSHOOT * 100:g} %), '
        f'{SETTLING_BAND * 100:g} % settling time {settling:.3f} s',
        f'0.5 m/s ramp: largest following error after 1 s {ramp_error * 1000:.1f} mm',
    ]
    for name, sim in sims.items():
        err = sim['deployed'] - sim['reference']
        keep = sim['t'] >= 10.0
        lines.append(f'{name}: length error mean {np.mean(err[keep]):+.4f} m, RMSE {_rmse(sim, 10.0):.4f} m '
                     f'(thesis, UAV surrogate: mean 0.022 m, RMSE 0.028 m)')
    _plot(args.out, sims, (t, y), (tr, yr, rr))
    lines.append(f'plots: {args.out / "tuning.png"}')
    return '\n'.join(lines)


def _plot(out: Path, sims: dict, step: tuple, ramp: tuple) -> None:
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 2, figsize=(12, 7))
    for ax, (name, sim) in zip(axes[0], sims.items()):
        ax.plot(sim['t'], sim['reference'], label='reference (model)')
        ax.plot(sim['t'], sim['deployed'], '--', label='deployed')
        ax.set_title(name)
        ax.set_xlabel('t (s)')
        ax.set_ylabel('length (m)')
        ax.legend()
    axes[1, 0].plot(step[0], step[1] * 1000, label='deployed length change')
    axes[1, 0].axhline(100.0, color='k', lw=0.5, label='the step: 100 mm')
    axes[1, 0].legend(fontsize=8)
    axes[1, 0].set_title('0.1 m reference step')
    axes[1, 0].set_xlabel('t (s)')
    axes[1, 0].set_ylabel('length change (mm)')
    axes[1, 1].plot(ramp[0], (ramp[1] - ramp[2]) * 1000)
    axes[1, 1].set_title('0.5 m/s reference ramp: following error')
    axes[1, 1].set_xlabel('t (s)')
    axes[1, 1].set_ylabel('error (mm)')
    fig.tight_layout()
    fig.savefig(out / 'tuning.png', dpi=100)
    plt.close(fig)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``tethersim reel tune``."""
    parser.add_argument('--duration', type=positive(), default=60.0, help='profile length, s (default 60)')
    parser.add_argument('--evaluations', type=positive(int), default=40, help='simulations at most (default 40)')
    parser.add_argument('--out', type=Path, default=Path('runs/reel-tune'), help='output directory')


def command(args: argparse.Namespace) -> str:
    """Run the procedure; return the summary text."""
    return _command(args)

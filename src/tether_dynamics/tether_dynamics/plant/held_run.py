"""The whole-run stepper of the finite-element tether under held inputs, compiled.

A scene steps the plant once per tick through :meth:`~tether_dynamics.plant.plant.TetherPlant.step`;
a fixed-length case whose inputs do not change (the Chapter 9 pendulum: the guide way still, the reel
held, the end body free) needs no node between its samples. :func:`run_held` makes the same calls of
:func:`~tether_dynamics.plant.fem_kernels.advance`, the same watchdog judgement
(:func:`~tether_dynamics.plant.watchdog.watch`) and the same report
(:func:`~tether_dynamics.plant.fem_kernels.report`) at each sample, in one compiled loop, so its
samples equal the per-call stepper's bit for bit (``test_plant_held_run.py``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from tether_dynamics.laws import STATUS_NONFINITE, STATUS_OK
from tether_dynamics.plant import fem_kernels as fk
from tether_dynamics.plant.bodies import RS_RATE
from tether_dynamics.plant.watchdog import watch

# What stopped a run early (besides a fem_kernels status): the watchdog.
STOP_WATCHDOG = -1


@njit(cache=True)
def sub_steps(t_a, t_b, dt):
    """Internal steps of a call from t_a to t_b at most dt long (what the per-call stepper takes)."""
    return max(1, int(np.ceil((t_b - t_a) / dt - 1e-9)))


@njit(cache=True)
def run_held(x, v, rest, st, fp, rs, rp, g_tab, u_tab, times, dt, bs, inertia, inertia_inv, rho, torque, acc,
             energy0, marks, verdict, values, bodies):
    """Step from times[0] through every later sample with the ends' tables, commands and thrust held;
    after each, the ``fem_kernels.RV_`` report into values[k] and the UAV body state into bodies[k].

    Returns the number of samples done (len(times) when the run finished); when it stopped early,
    st[ST_STATUS] holds the kernel's status, or STOP_WATCHDOG with the watchdog's ``verdict``.
    """
    order, kv_on, torque_input = st[fk.ST_ORDER], st[fk.ST_KV] == 1, st[fk.ST_TORQUE] == 1
    cap = x.shape[0]
    nodes, velocities = np.empty((cap, 3)), np.empty((cap, 3))
    arc, lumps, seg = np.empty(cap), np.empty(cap), np.empty(cap)
    reel, uav, lowest, row = np.empty(3), np.empty(3), np.empty(3), np.empty(fk.RV_SIZE)
    for k in range(1, times.size):
        t_a, t_b = times[k - 1], times[k]
        fp[fk.FP_COMMAND_PREV] = fp[fk.FP_COMMAND] if torque_input else rs[RS_RATE]
        fk.advance(x, v, rest, st, fp, rs, rp, g_tab, u_tab, t_a, t_b, sub_steps(t_a, t_b, dt), bs, inertia,
                   inertia_inv, rho, torque, acc)
        if st[fk.ST_STATUS] != STATUS_OK:
            return k
        if not watch(x, v, rest, st, fp, acc, energy0, t_b, marks, verdict):
            st[fk.ST_STATUS] = STOP_WATCHDOG
            return k
        n = st[fk.ST_NODES]
        feed = fp[fk.FP_PAYOUT] if st[fk.ST_METHOD] == fk.METHOD_ALE else 0.0
        fk.report(x, v, rest, n, fp, order, kv_on, feed, nodes[:n], velocities[:n], arc[:n], lumps[:n], seg[:n - 1],
                  reel, uav, lowest, row)
        if not fk.report_finite(seg, n, reel, uav, lowest, row):
            st[fk.ST_STATUS] = STATUS_NONFINITE
            return k
        values[k, :] = row
        bodies[k, :] = bs
    return times.size

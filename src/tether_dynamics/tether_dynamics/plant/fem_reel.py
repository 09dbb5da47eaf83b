"""Finite-element tether with a deployed length that changes at the reel (thesis Sec. 7.3-7.4, 10.4).

Method ('ale', the default)
---------------------------
The tether is cut into lumped-mass linear (or quadratic, below) elements. Node 0 is the guide way (it follows the
platform); every other node is a material point of the tether, except that the element at
the reel - the reel element, between the guide way and node 1 - is an arbitrary
Lagrangian-Eulerian element: its rest length is the deployed length minus the rest lengths
of all the others, so material enters (payout) or leaves (reel-in) the deployed tether
through it, continuously, with the spool (the ALE treatment Sec. 10.4 proposes, applied
to the one element where the mesh and the material differ). Three rules make it exact
where it can be and conservative where it cannot:

1. Momentum of the moving material. Material crossing the guide way moves with
   u0 = v_guide + Ldot (x1 - x0) / l_r: the guide way's velocity plus the payout along the
   departing tether (stretched). Node 1's lump gains or loses mass at mu Ldot / 2 and with it
   the momentum of that material, m1 dv1/dt = F1 + (mu Ldot / 2)(u0 - v1), so payout and
   reel-in add no spurious force, and the jump in velocity between drum and tether is the
   Carnot loss of Sec. 7.3 (counted in the energy balance, not hidden).
2. Split. When the reel element grows past 1.5 h (h the nominal element length), a node
   is put at rest length l_r - h from the guide way, on the element's chord (the shape is
   unchanged), with the material velocity interpolated at that mass fraction (mass and
   momentum unchanged); where on the chord is chosen so the two new elements carry the
   tension gradient of the tether's weight and inertia with the mean strain kept, so the
   exit tension (the reel element's tension carried to the guide way over its half-length,
   which is what the winch feels and the plant reports) has no step.
3. Strain-keeping merge. When it shrinks below 0.35 h (``MERGE``), node 1 is removed and node 2's
   velocity is set so the momentum of the three lumps involved is unchanged. The joined
   element keeps the rest-length-weighted mean strain of the two it replaces: where node 1
   was a kink (a curved tether), the straight element needs less rest length at that
   strain than the two had; the difference (millimetres) is taken out of the reel element
   and fed back into it over the next 0.25 s (counted meanwhile as deployed mass at the
   guide way). Joining at equal rest length instead leaves the joined element slack on a
   curved stiff tether (measured: the reel tension fell from 2.2 N to 0 at each merge of a
   sagging 20 m, 20 kN tether) and it snaps back. Merges go on down to a single element
   from the guide way to the UAV (no free node left to limit the step), so a UAV landing
   over the guide way can be reeled in to a fraction of h.

The reel element's rest length therefore stays in [0.35 h, 3 h / 2] whenever there is more
than one element, and every other element has rest length h: the element sizes stay within
a ratio of 4.3. The count follows the deployed length (L / h + 1 at most). Total tether mass,
drum (mu (total - L)) plus deployed (mu times the sum of rest lengths), is conserved to
rounding: the rest length added to the reel element each step is the deployed length the
winch added in that step (plus the merge's pay-back, already counted as deployed).

Alternatives measured (``bench/reel_payout``, same profile, same step): 'last_element' -
only the reel element's rest length changes, no split or merge (MoorDyn-F's DeltaL): the
element grows without bound; 'uniform' - every element reset to L / N each step
(MoorDyn-C, KiteModels): every element's strain changes without the material moving, and
node masses change without momentum; 'insert' - whole elements inserted or removed at the
reel end once the paid-out length reaches h, the undeployed remainder massless (OrcaFlex's
line feeding): each insertion changes the reel element's strain at once.

Quadratic elements ('quadratic', Sec. 8.4, Appendix D.3-D.4): three-node elements with
2-point Gauss quadrature of the strain energy, lumped masses mu l (1/6, 2/3, 1/6) (the row
sums of Eq. D.12, so Simpson's rule gives the momentum of a quadratic velocity field
exactly). The same three rules, with what quadratic elements change:

1. Momentum. Material entering the reel element joins its middle node's lump at 2/3 and
   its far node's at 1/6 of mu Ldot, with the velocity u0 = v_guide + Ldot r'(0) (r' = dr/ds,
   s the rest-length coordinate). The middle node's velocity is the material velocity
   there, and the node moves through the material at -Ldot / 2 along r', so it stays at the
   element's middle (a Lagrangian middle node drifts off it, and splitting such an element
   put a 15 N wave into a 12 N tether); the forces' work on that motion is counted with
   the rest-length flow of the energy balance.
2. Split (above 1.6 h, at l_0 - h from the guide way): the new nodes lie on the old
   element's parabola, where the material points would be if the stretch were what the
   element's quadrature sees (linear through its Gauss points): an exact subdivision where
   that is so (a straight or hanging element; shape, strain field and exit force
   unchanged), and no sudden strain on a coarse, deeply curved element, whose ends can be
   stretched while both Gauss points are slack (exact subdivision there put 2.3 kJ and a
   7.5 kN snap into a slack 6 m element). Where one Gauss point is slack, the stretch is held
   between the two Gauss values instead of extrapolated past the taut one (extrapolated, a
   split of a 0.889 / 1.000 element put 569 N into a tether carrying 3 N). Velocities from the velocity field at the same
   points, with a uniform correction that restores the momentum exactly.
3. Merge (below h / 2): the joined element runs through the guide way, the material point
   at its middle on the old shape (same reparametrisation), and its far node, with the
   middle node's velocity set by momentum; mass is exact, nothing is owed.

The reel element of quadratic elements stays in [h / 2, 1.6 h] (a size ratio of 3.2): its
middle node carries 2/3 of its mass, and the stable step of the shortest element sets the
step for all. The exit force is the elements' internal force on node 0 (the Gauss-point
tensions extrapolated, Eq. D.8) less the weight and inertia of node 0's lump: the length of
r'(0) itself overstates the stretch of a curved element by about (kappa l_0)^2 / 8 (measured:
325 N instead of 2.8 N on a 35 m catenary of 10 elements). Measured (tests): tension and
mass behaviour as the linear elements' (the same 2 m/s payout and reel-in of a hanging body
follows (m + mu L) g to 0.7 %); the energy balance closes to 1.6e-3 (100 m out and back) and
9e-3 of the throughput (sinusoidal payout that slackens and snaps the tether near the reel).

Time stepping is symplectic Euler with lumped masses (one force evaluation per step); the
stable step of linear elements is about 0.7 h / c (c = sqrt(EA / mu), the shortest reel
element 0.35 h); of quadratic elements it is computed from the highest mode of a short and
two full elements (about 0.28 h / c without damping). The plant accepts 0.9 of that estimate
where Kelvin-Voigt damping damps the highest mode, 0.5 without (:func:`accepted_step`), checked
at construction; an energy-balance watchdog stops a run that diverges anyway (:mod:`.watchdog`).
"""

from __future__ import annotations

import math

import numpy as np

from tether_dynamics.laws import GAUSS, STATUS_FULL, STATUS_NONFINITE, STATUS_OK, STATUS_SHORT, air_block, quadratic_slope
from tether_dynamics.layout import pack
from tether_dynamics.plant import fem_kernels as fk
from tether_dynamics.plant import held_run, quasi_static, watchdog
from tether_dynamics.plant.bodies import RS_RATE
from tether_dynamics.plant.config import PlantConfig, PlantConfigError

# The step the plant accepts, as a share of the estimate :func:`stable_step` (its margin): 0.9 when
# internal damping damps the highest axial mode by a ratio of at least DAMPED_RATIO, 0.5 without.
# Measured (bench/plant_stability: a stiff, light tether, EA 40 kN, 0.01 kg/m, on a heaving, paying-out
# reel with the far end driven sideways), with merges below h / 4: undamped, linear N = 40 peaks at 122,
# 201, 409 and 4,455 N at 0.3, 0.5, 0.7 and 0.9 of the estimate (energy residual 0.009, 0.022, 0.12 and
# 5.9 of the throughput), quadratic N = 40 at 0.9 reaches 430 N (residual 0.32); with c = 1 N s (ratio
# 0.07) linear N = 40 peaks at 139.8, 139.4, 139.0 and 139.9 N at the same steps. With merges below
# 0.35 h (fem_kernels.MERGE; the estimate 1.18 times longer): undamped 178 and 282 N at 0.3 and 0.5
# (residual 0.016, 0.055); c = 1 N s 118.9, 116.7, 118.3, 116.2 and 114.4 N at 0.3, 0.6, 0.7, 0.8 and
# 0.9 (residual 0.008 to 0.066): within 4 %, the scatter of the snaps, not a trend with the step.
STABLE_FRACTION = 0.9
UNDAMPED_FRACTION = 0.5
DAMPED_RATIO = 0.01

class PlantDivergenceError(RuntimeError):
    """The finite-element tether left the physical range; the message names how."""


def damping_ratio(config: PlantConfig) -> float:
    """Kelvin-Voigt damping ratio of the highest axial mode, c omega / (2 EA) (0 without damping),
    omega from the shortest reel element (:func:`stable_step`'s mode).
    """
    if 'damping' not in config.effects or config.damping <= 0.0:
        return 0.0
    h = config.nominal_element_length
    if config.fidelity == 'quadratic':
        omega = _quadratic_highest_omega(config, fk.MERGE_QUADRATIC * h, h)
    else:
        omega = math.sqrt(2.0 * config.ea / (config.mass_per_length * fk.MERGE * h * h))
    return config.damping * omega / (2.0 * config.ea)


def accepted_step(config: PlantConfig) -> float:
    """The largest internal step (s) the plant accepts: the stable-step estimate times its margin,
    STABLE_FRACTION when internal damping damps the highest mode (ratio >= DAMPED_RATIO),
    UNDAMPED_FRACTION otherwise (module constants: the measurements behind them).
    """
    damped = damping_ratio(config) >= DAMPED_RATIO
    return (STABLE_FRACTION if damped else UNDAMPED_FRACTION) * stable_step(config)


def stable_step(config: PlantConfig) -> float:
    """Largest stable internal step (s) of the moving-reel FEM for this configuration (the estimate
    of a fixed mesh; :func:`accepted_step` is what the plant accepts).
    """
    h = config.nominal_element_length
    c = math.sqrt(config.ea / config.mass_per_length)
    if config.fidelity == 'quadratic':
        return _quadratic_stable_step(config, fk.MERGE_QUADRATIC * h, h)
    shortest = fk.MERGE * h
    omega = math.sqrt(2.0 * config.ea / (config.mass_per_length * shortest * h))
    step = min(2.0 / omega, h / c)
    if 'damping' in config.effects and config.damping > 0.0:
        # Explicit Kelvin-Voigt: the dashpot c / l between two lumps of the shortest element.
        lump = 0.5 * config.mass_per_length * (shortest + h)
        step = min(step, lump * shortest / config.damping)
    return step


def _quadratic_stable_step(config: PlantConfig, shortest: float, h: float) -> float:
    """Symplectic Euler's limit on quadratic elements, from the highest axial mode of a chain
    of the shortest reel element and two full ones (lumped masses 1/6, 2/3, 1/6; 2-point
    Gauss stiffness, Eq. D.8): dt = 2 / omega (sqrt(1 + xi^2) - xi), with the Kelvin-Voigt
    damping ratio xi = c omega / (2 EA) of that mode.
    """
    omega = _quadratic_highest_omega(config, shortest, h)
    xi = config.damping * omega / (2.0 * config.ea) if 'damping' in config.effects else 0.0
    return 2.0 / omega * (math.sqrt(1.0 + xi * xi) - xi)


def _quadratic_highest_omega(config: PlantConfig, shortest: float, h: float) -> float:
    """Highest axial angular frequency (rad/s) of a chain of quadratic elements of rest lengths
    (shortest, h, h) with lumped masses 1/6, 2/3, 1/6 and 2-point Gauss stiffness (Eq. D.8).
    """
    ea, mu = config.ea, config.mass_per_length
    slope = 2.0 * np.array([quadratic_slope(z) for z in GAUSS])
    rests = (shortest, h, h)
    n = 2 * len(rests) + 1
    stiff, mass = np.zeros((n, n)), np.zeros(n)
    for e, l0 in enumerate(rests):
        idx = slice(2 * e, 2 * e + 3)
        stiff[idx, idx] += ea / (2.0 * l0) * slope.T @ slope
        mass[idx] += mu * l0 * np.array([1.0, 4.0, 1.0]) / 6.0
    scale = 1.0 / np.sqrt(mass)
    return math.sqrt(float(np.max(np.linalg.eigvalsh(scale[:, None] * stiff * scale[None, :]))))


def _strain_points(rest: np.ndarray, order: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where the discrete chain measures strain: node indices (P, order + 1), the coefficients
    of dr/ds on them (P, order + 1) and the rest length each point stands for (P,). Linear:
    one point per element; quadratic: its two Gauss points (Appendix D.3).
    """
    if order == 1:
        k = np.arange(rest.size)
        return (np.stack([k, k + 1], axis=1), np.stack([-1.0 / rest, 1.0 / rest], axis=1), rest.copy())
    slope = np.array([quadratic_slope(z) for z in GAUSS])
    e = np.repeat(np.arange(rest.size), 2)
    idx = 2 * e[:, None] + np.arange(3)[None, :]
    coef = 2.0 / rest[e][:, None] * np.tile(slope, (rest.size, 1))
    return idx, coef, 0.5 * rest[e]


def lumped_masses(rest: np.ndarray, order: int, mu: float) -> np.ndarray:
    """Lumped node masses (kg) of elements of ``order`` with rest lengths ``rest`` (:func:`fem_kernels.lump`)."""
    out = np.zeros(order * rest.size + 1)
    share = mu * rest / (2.0 if order == 1 else 6.0)
    out[:-1:order] += share
    out[order::order] += share
    if order == 2:
        out[1::2] = 2.0 / 3.0 * mu * rest
    return out


def _discrete_equilibrium(x: np.ndarray, rest: np.ndarray, order: int, ea: float, mu: float, g: float,
                          iterations: int = 60) -> np.ndarray:
    """Static equilibrium of the discrete chain with both end nodes held: damped Newton on the
    (convex) potential energy sum_p 1/2 EA w_p max(|r'_p| - 1, 0)^2 + sum m_i g z_i over the
    strain points p (:func:`_strain_points`) and the lumps.
    """
    x = x.copy()
    n = x.shape[0]
    if n < 3:
        return x
    idx, coef, weight = _strain_points(rest, order)
    lumps = lumped_masses(rest, order, mu)

    def energy(xx: np.ndarray) -> float:
        lam = np.linalg.norm(np.einsum('pk,pkc->pc', coef, xx[idx]), axis=1)
        return float(np.sum(0.5 * ea * weight * np.maximum(lam - 1.0, 0.0) ** 2) + g * np.sum(lumps * xx[:, 2]))

    for _ in range(iterations):
        r = np.einsum('pk,pkc->pc', coef, x[idx])
        lam = np.linalg.norm(r, axis=1)
        e = r / lam[:, None]
        stress = ea * weight * np.maximum(lam - 1.0, 0.0)
        grad_all = np.zeros((n, 3))
        np.add.at(grad_all, idx, (stress[:, None] * coef)[:, :, None] * e[:, None, :])
        grad_all[:, 2] += lumps * g
        grad = grad_all[1:-1].ravel()
        if np.max(np.abs(grad)) < 1e-10 * ea:
            break
        hess = np.zeros((3 * n, 3 * n))
        for p in range(idx.shape[0]):
            if lam[p] > 1.0:
                block = ea * weight[p] * ((1.0 - 1.0 / lam[p]) * np.eye(3) + np.outer(e[p], e[p]) / lam[p])
            else:
                block = 1e-9 * ea * weight[p] * np.eye(3)
            for a, ia in enumerate(idx[p]):
                for b, ib in enumerate(idx[p]):
                    hess[3 * ia:3 * ia + 3, 3 * ib:3 * ib + 3] += coef[p, a] * coef[p, b] * block
        h_free = hess[3:-3, 3:-3] + 1e-9 * ea / np.min(rest) * np.eye(3 * (n - 2))
        step = -np.linalg.solve(h_free, grad).reshape(-1, 3)
        e0, alpha = energy(x), 1.0
        while alpha > 1e-8:
            trial = x.copy()
            trial[1:-1] += alpha * step
            if energy(trial) <= e0:
                break
            alpha *= 0.5
        x = trial
    return x


class FemTether:
    """The deployed tether's finite elements, stepped by :func:`fem_kernels.advance`."""

    def __init__(self, config: PlantConfig) -> None:
        if config.fidelity not in ('linear', 'quadratic'):
            msg = f"fidelity {config.fidelity!r}: the moving-reel FEM has 'linear' or 'quadratic' elements"
            raise PlantConfigError(msg)
        if config.fidelity == 'quadratic' and config.reshape != 'ale':
            msg = f"reshape {config.reshape!r} is a linear-element method; quadratic elements use 'ale'"
            raise PlantConfigError(msg)
        self.config = config
        self.order = 2 if config.fidelity == 'quadratic' else 1
        cfg = config
        h = cfg.nominal_element_length
        limit = accepted_step(cfg)
        if cfg.dt > limit:
            msg = (f'dt {cfg.dt:.3g} s is above the stable step {limit:.3g} s of elements of {h:.3g} m '
                   f'(EA {cfg.ea:g} N, mu {cfg.mass_per_length:g} kg/m, damping ratio {damping_ratio(cfg):.3g}); '
                   'reduce dt or lengthen the elements')
            raise PlantConfigError(msg)
        if cfg.reshape == 'uniform':
            cap = cfg.elements + 1
        else:
            cap = self.order * (int(math.ceil(cfg.reel.max_length / h)) + 4) + 1
        self.x = np.zeros((cap, 3))
        self.v = np.zeros((cap, 3))
        self.rest = np.zeros(cap)
        kv_on = 'damping' in cfg.effects and cfg.damping > 0.0
        self.st = pack('st', fk.ST_FIELDS, {
            'nodes': 0, 'method': fk.METHODS[cfg.reshape], 'torque': 0, 'body': cfg.uav.mode == 'dynamic',
            'drag': 'drag' in cfg.effects, 'kv': kv_on, 'splits': 0, 'merges': 0, 'status': STATUS_OK,
            'order': self.order}, np.int64)
        wind = cfg.wind if 'wind' in cfg.effects else (0.0, 0.0, 0.0)
        self.fp = pack('fp', fk.FP_FIELDS, {
            'ea': cfg.ea, 'mu': cfg.mass_per_length, 'h': h, 'g': cfg.gravity, 'kv': cfg.damping, 'command': 0.0,
            'thrust': 0.0, 'pending': 0.0, 'uav_mass': cfg.uav.mass, 'payout': 0.0, 'command_prev': 0.0,
            'owed': 0.0, 'acc1': np.zeros(3), 'acc_uav': np.zeros(3),
            'air': air_block(cfg.air_density, cfg.diameter, cfg.drag_coefficient, 0.008, wind)})
        self.acc = pack('acc', fk.ACC_FIELDS, {name: np.nan if name == 'last_t' else 0.0 for name, _ in fk.ACC_FIELDS})
        self.energy0 = 0.0
        self._marks = watchdog.fresh_marks()
        self._verdict = np.zeros(3)
        self._no_table = np.zeros((4, 3))
        self._inertia = np.asarray(cfg.uav.inertia, float)
        self._inertia_inv = np.linalg.inv(self._inertia)
        self._rho = np.asarray(cfg.uav.attach_offset, float)

    def _rest_lengths(self, length: float) -> np.ndarray:
        cfg = self.config
        if cfg.reshape == 'uniform':
            return np.full(cfg.elements, length / cfg.elements)
        h = cfg.nominal_element_length
        n_full = max(0, int(math.floor(length / h - 0.5)))
        return np.concatenate([[length - n_full * h], np.full(n_full, h)])

    def initialise(self, a: np.ndarray, b: np.ndarray, length: float) -> None:
        """Nodes at rest on the elastic catenary of ``length`` from a (guide way) to b (UAV).

        Each node first sits at the stretched arc length its material reaches under the
        catenary's tension, s(s0) = integral of (1 + T / EA) ds0; then Newton's method moves
        the free nodes to the equilibrium of the discrete chain (:func:`_discrete_equilibrium`),
        which differs from the continuous catenary by the chords' shortening on a curved
        tether - enough, with a stiff tether, to leave elements slack or overloaded and start
        elastic waves.
        """
        cfg = self.config
        rest = self._rest_lengths(length)
        n = self.order * rest.size + 1
        shape = quasi_static.solve(a, b, length, cfg.mass_per_length, cfg.ea, cfg.gravity)
        sol = shape.solution
        dense = shape.points(a, 4001)
        arc = np.linspace(0.0, shape.stretched_length, dense.shape[0])
        horizontal = float(sol.horizontal_tension)
        if math.isfinite(horizontal):
            weight = cfg.mass_per_length * length / shape.stretched_length * cfg.gravity
            vertical = shape.tension_a * math.sin(float(sol.alpha))
            tension = np.sqrt(horizontal**2 + (vertical + weight * arc) ** 2)
        else:
            tension = np.full(arc.size, cfg.ea * (shape.stretched_length / length - 1.0))
        stretch = 1.0 / (1.0 + tension / cfg.ea)
        material = np.concatenate([[0.0], np.cumsum(0.5 * (stretch[1:] + stretch[:-1]) * np.diff(arc))])
        material *= length / material[-1]
        where = np.interp(self._node_arc(rest), material, arc)
        self.x[:n] = np.column_stack([np.interp(where, arc, dense[:, c]) for c in range(3)])
        self.x[n - 1] = b
        self.x[:n] = _discrete_equilibrium(self.x[:n], rest, self.order, cfg.ea, cfg.mass_per_length, cfg.gravity)
        self.v[:] = 0.0
        self.rest[:rest.size] = rest
        self.st[fk.ST_NODES] = n
        self.energy0 = self.energy()

    def _node_arc(self, rest: np.ndarray) -> np.ndarray:
        """Unstretched distance of each node from the guide way for element rest lengths ``rest``
        (a quadratic element's middle node halfway), m (:func:`fem_kernels.node_arc`).
        """
        out = np.empty(self.order * rest.size + 1)
        fk.node_arc(rest, self.order, out)
        return out

    def advance(self, t_a: float, t_b: float, n_sub: int, g_tab: np.ndarray, u_tab: np.ndarray | None,
                rs: np.ndarray, rp: np.ndarray, torque_input: bool, command: float, body: np.ndarray,
                thrust: float, torque: np.ndarray) -> None:
        """Advance from t_a to t_b in n_sub steps (see :func:`fem_kernels.advance`)."""
        self._hold(rs, torque_input, command, thrust)
        fk.advance(self.x, self.v, self.rest, self.st, self.fp, rs, rp, g_tab,
                   u_tab if u_tab is not None else self._no_table, t_a, t_b, n_sub, body,
                   self._inertia, self._inertia_inv, self._rho, torque, self.acc)
        self._raise_on_status(t_b)
        if not watchdog.watch(self.x, self.v, self.rest, self.st, self.fp, self.acc, self.energy0, t_b, self._marks,
                              self._verdict):
            self._raise_watchdog(t_b)

    def run_held(self, times: np.ndarray, g_tab: np.ndarray, rs: np.ndarray, rp: np.ndarray, torque_input: bool,
                 command: float, body: np.ndarray, thrust: float, torque: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Step through ``times`` with the guide way's table and the commands held and the UAV a dynamic
        body, in one compiled loop (:func:`held_run.run_held`); the ``fem_kernels.RV_`` report
        (len(times), RV_SIZE) and the UAV body state (len(times), BS_SIZE) after each sample (row 0
        left for the caller).
        """
        self._hold(rs, torque_input, command, thrust)
        values, bodies = np.zeros((times.size, fk.RV_SIZE)), np.zeros((times.size, body.size))
        done = held_run.run_held(self.x, self.v, self.rest, self.st, self.fp, rs, rp, g_tab, self._no_table, times, self.config.dt, body,
                                 self._inertia, self._inertia_inv, self._rho, torque, self.acc, self.energy0,
                                 self._marks, self._verdict, values, bodies)
        if done < times.size:
            if self.st[fk.ST_STATUS] == held_run.STOP_WATCHDOG:
                self._raise_watchdog(float(times[done]))
            self._raise_on_status(float(times[done]))
        return values, bodies

    def _hold(self, rs: np.ndarray, torque_input: bool, command: float, thrust: float) -> None:
        """The commands of the next call: a spool-rate command ramps from the spool's rate."""
        self.st[fk.ST_TORQUE] = torque_input
        self.fp[fk.FP_COMMAND_PREV] = rs[RS_RATE] if not torque_input else command
        self.fp[fk.FP_COMMAND] = command
        self.fp[fk.FP_THRUST] = thrust

    def _raise_on_status(self, t_b: float) -> None:
        status = int(self.st[fk.ST_STATUS])
        if status == STATUS_FULL:
            msg = 'the tether needs more elements than the reel max_length allows; raise reel.max_length'
            raise PlantDivergenceError(msg)
        if status == STATUS_NONFINITE:
            msg = f'the tether state became non-finite before t = {t_b:.6g} s: reduce dt'
            raise PlantDivergenceError(msg)
        if status == STATUS_SHORT:
            msg = f"the reel element's rest length reached zero before t = {t_b:.6g} s (method {self.config.reshape!r})"
            raise PlantDivergenceError(msg)

    def _raise_watchdog(self, t: float) -> None:
        """The energy-balance watchdog's verdict (:func:`watchdog.watch`) as an error."""
        made, flowed, since = self._verdict
        span = f' since t = {since:.6g} s' if math.isfinite(since) else ''
        msg = (f'energy balance residual {made:.3g} J exceeds {watchdog.SHARE:g} of the energy throughput '
               f'{flowed:.3g} J{span} at t = {t:.6g} s: the explicit step {self.config.dt:.3g} s diverged; reduce dt')
        raise PlantDivergenceError(msg)

    @property
    def n(self) -> int:
        """Nodes in use."""
        return int(self.st[fk.ST_NODES])

    @property
    def elements(self) -> int:
        """Elements in use."""
        return (self.n - 1) // self.order

    def report(self) -> tuple[np.ndarray, ...]:
        """What the plant reports after a step (:func:`fem_kernels.report`): (n, 3) node positions
        from the guide way to the UAV (m) and velocities (m/s; node 0: the guide way's), (n,)
        unstretched arc lengths from the guide way (m, with what a merge still owes the reel element)
        and lumped masses (kg), (n - 1,) tensions between consecutive nodes (N), the tether's forces
        on the guide way and on the UAV (N), its lowest point (m), and the ``fem_kernels.RV_``
        scalars (Kelvin-Voigt included when on).
        """
        n = self.n
        nodes, velocities, arc, lumps = np.empty((n, 3)), np.empty((n, 3)), np.empty(n), np.empty(n)
        seg, reel, uav, lowest, values = np.zeros(n - 1), np.empty(3), np.empty(3), np.empty(3), np.empty(fk.RV_SIZE)
        feed = float(self.fp[fk.FP_PAYOUT]) if self.config.reshape == 'ale' else 0.0
        fk.report(self.x, self.v, self.rest, n, self.fp, self.order, bool(self.st[fk.ST_KV]), feed, nodes, velocities,
                  arc, lumps, seg, reel, uav, lowest, values)
        if not fk.report_finite(seg, n, reel, uav, lowest, values):
            msg = 'the tether\'s tensions or energies became non-finite: reduce dt'
            raise PlantDivergenceError(msg)
        return nodes, velocities, arc, lumps, seg, reel, uav, lowest, values

    def deployed_rest_length(self) -> float:
        """Deployed tether mass over mu, m: the elements' rest lengths plus what a merge still
        owes the reel element (material at the guide way, fed back within a second).
        """
        return float(np.sum(self.rest[:self.elements])) + float(self.fp[fk.FP_OWED])

    def energy(self) -> float:
        """Mechanical energy the balance counts (:func:`fem_kernels.energy`), J."""
        return float(fk.energy(self.x, self.v, self.rest, self.n, self.fp, self.order))

    def balance(self) -> dict[str, float]:
        """Energy balance of the deployed tether since the start, J: the energy change, each
        inflow, the residual change - inflows - mesh-change energy, and the throughput (the
        time integral of the flows' absolute values, the scale the residual is judged on).
        """
        flows = {'ends': self.acc[fk.ACC_ENDS], 'rest_length': self.acc[fk.ACC_REST],
                 'mass_flux': self.acc[fk.ACC_MASS], 'drag': self.acc[fk.ACC_DRAG],
                 'damping': self.acc[fk.ACC_KV], 'reshape': self.acc[fk.ACC_RESHAPE]}
        change = self.energy() - self.energy0
        out = {'change': change, **{k: float(v) for k, v in flows.items()}}
        out['residual'] = change - sum(flows.values())
        out['throughput'] = float(self.acc[fk.ACC_THROUGHPUT])
        return out

    def largest_reel_tension_step(self) -> float:
        """Largest change of the reel-end tension from one internal step to the next, N."""
        return float(self.acc[fk.ACC_JUMP])

    def largest_reel_tension_step_time(self) -> float:
        """When the largest change of the reel-end tension happened, s."""
        return float(self.acc[fk.ACC_JUMP_T])

    def mesh_events(self) -> tuple[int, int]:
        """Splits and merges (or insertions and removals) so far."""
        return int(self.st[fk.ST_SPLITS]), int(self.st[fk.ST_MERGES])

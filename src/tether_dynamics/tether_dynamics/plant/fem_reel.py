"""Finite-element tether with a deployed length that changes at the reel (thesis Sec. 7.3-7.4, 10.4).

Method ('ale', the default)
---------------------------
The tether is cut into lumped-mass linear elements. Node 0 is the guide way (it follows the
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
3. Strain-keeping merge. When it shrinks below h / 4, node 1 is removed and node 2's
   velocity is set so the momentum of the three lumps involved is unchanged. The joined
   element keeps the rest-length-weighted mean strain of the two it replaces: where node 1
   was a kink (a curved tether), the straight element needs less rest length at that
   strain than the two had; the difference (millimetres) is taken out of the reel element
   and fed back into it over the next 0.25 s (counted meanwhile as deployed mass at the
   guide way). Joining at equal rest length instead leaves the joined element slack on a
   curved stiff tether (measured: the reel tension fell from 2.2 N to 0 at each merge of a
   sagging 20 m, 20 kN tether) and it snaps back.

The reel element's rest length therefore stays in [h / 4, 3 h / 2] whenever there is more
than one element, and every other element has rest length h: the element sizes stay within
a ratio of 6. The count follows the deployed length (L / h + 1 at most). Total tether mass,
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

Time stepping is symplectic Euler with lumped masses (one force evaluation per step); the
stable step is about 0.7 h / c (c = sqrt(EA / mu), the shortest reel element h / 4), checked
at construction.
"""

from __future__ import annotations

import math

import numpy as np

from tether_dynamics.plant import fem_kernels as fk
from tether_dynamics.plant import quasi_static
from tether_dynamics.plant.bodies import RS_RATE
from tether_dynamics.plant.config import PlantConfig, PlantConfigError

STABLE_FRACTION = 0.9


class PlantDivergenceError(RuntimeError):
    """The finite-element tether left the physical range; the message names how."""


def stable_step(config: PlantConfig) -> float:
    """Largest stable internal step (s) of the moving-reel FEM for this configuration."""
    h = config.nominal_element_length
    c = math.sqrt(config.ea / config.mass_per_length)
    shortest = fk.MERGE * h
    omega = math.sqrt(2.0 * config.ea / (config.mass_per_length * shortest * h))
    step = min(2.0 / omega, h / c)
    if 'damping' in config.effects and config.damping > 0.0:
        # Explicit Kelvin-Voigt: the dashpot c / l between two lumps of the shortest element.
        lump = 0.5 * config.mass_per_length * (shortest + h)
        step = min(step, lump * shortest / config.damping)
    return step


def _discrete_equilibrium(x: np.ndarray, rest: np.ndarray, ea: float, mu: float, g: float,
                          iterations: int = 60) -> np.ndarray:
    """Static equilibrium of the lumped chain with both end nodes held: damped Newton on the
    (convex) potential energy sum 1/2 EA l (|d| / l - 1)^2 (tension only) + sum m g z.
    """
    x = x.copy()
    n = x.shape[0]
    if n < 3:
        return x
    lumps = np.zeros(n)
    lumps[:-1] += 0.5 * mu * rest
    lumps[1:] += 0.5 * mu * rest

    def energy(xx: np.ndarray) -> float:
        d = np.linalg.norm(np.diff(xx, axis=0), axis=1)
        eps = np.maximum(d / rest - 1.0, 0.0)
        return float(np.sum(0.5 * ea * rest * eps**2) + g * np.sum(lumps * xx[:, 2]))

    for _ in range(iterations):
        diff = np.diff(x, axis=0)
        d = np.linalg.norm(diff, axis=1)
        e = diff / d[:, None]
        tension = ea * np.maximum(d / rest - 1.0, 0.0)
        force = np.zeros((n, 3))
        force[:-1] += tension[:, None] * e
        force[1:] -= tension[:, None] * e
        force[:, 2] -= lumps * g
        grad = -force[1:-1].ravel()
        if np.max(np.abs(grad)) < 1e-10 * ea:
            break
        hess = np.zeros((3 * n, 3 * n))
        for k in range(n - 1):
            taut = tension[k] > 0.0
            block = (ea / rest[k] * np.outer(e[k], e[k]) + tension[k] / d[k] * (np.eye(3) - np.outer(e[k], e[k]))
                     if taut else 1e-9 * ea / rest[k] * np.eye(3))
            i, j = 3 * k, 3 * k + 3
            hess[i:i + 3, i:i + 3] += block
            hess[j:j + 3, j:j + 3] += block
            hess[i:i + 3, j:j + 3] -= block
            hess[j:j + 3, i:i + 3] -= block
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
        if config.fidelity != 'linear':
            msg = f"fidelity {config.fidelity!r}: the moving-reel FEM has linear elements; use 'linear'"
            raise PlantConfigError(msg)
        self.config = config
        cfg = config
        h = cfg.nominal_element_length
        limit = STABLE_FRACTION * stable_step(cfg)
        if cfg.dt > limit:
            msg = (f'dt {cfg.dt:.3g} s is above the stable step {limit:.3g} s of elements of {h:.3g} m '
                   f'(EA {cfg.ea:g} N, mu {cfg.mass_per_length:g} kg/m); reduce dt or lengthen the elements')
            raise PlantConfigError(msg)
        if cfg.reshape == 'uniform':
            cap = cfg.elements + 1
        else:
            cap = int(math.ceil(cfg.reel.max_length / h)) + 4
        self.x = np.zeros((cap, 3))
        self.v = np.zeros((cap, 3))
        self.rest = np.zeros(cap)
        self.st = np.zeros(fk.ST_SIZE, np.int64)
        self.st[fk.ST_METHOD] = fk.METHODS[cfg.reshape]
        self.st[fk.ST_BODY] = cfg.uav.mode == 'dynamic'
        self.st[fk.ST_DRAG] = 'drag' in cfg.effects
        self.st[fk.ST_WIND] = 'wind' in cfg.effects
        self.st[fk.ST_KV] = 'damping' in cfg.effects and cfg.damping > 0.0
        self.fp = np.zeros(fk.FP_SIZE)
        self.fp[fk.FP_EA], self.fp[fk.FP_MU], self.fp[fk.FP_H] = cfg.ea, cfg.mass_per_length, h
        self.fp[fk.FP_G], self.fp[fk.FP_DIAMETER] = cfg.gravity, cfg.diameter
        self.fp[fk.FP_CDN], self.fp[fk.FP_CDT], self.fp[fk.FP_RHO] = cfg.drag_coefficient, 0.008, cfg.air_density
        self.fp[fk.FP_KV] = cfg.damping
        self.fp[fk.FP_WIND:fk.FP_WIND + 3] = cfg.wind
        self.fp[fk.FP_UAV_MASS] = cfg.uav.mass
        self.acc = np.zeros(fk.ACC_SIZE)
        self.acc[fk.ACC_LAST_T] = np.nan
        self.energy0 = 0.0
        self._no_table = np.zeros((4, 3))

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
        n = rest.size + 1
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
        where = np.interp(np.concatenate([[0.0], np.cumsum(rest)]), material, arc)
        self.x[:n] = np.column_stack([np.interp(where, arc, dense[:, c]) for c in range(3)])
        self.x[n - 1] = b
        self.x[:n] = _discrete_equilibrium(self.x[:n], rest, cfg.ea, cfg.mass_per_length, cfg.gravity)
        self.v[:] = 0.0
        self.rest[:n - 1] = rest
        self.st[fk.ST_NODES] = n
        self.energy0 = self.energy()

    def advance(self, t_a: float, t_b: float, n_sub: int, g_tab: np.ndarray, u_tab: np.ndarray | None,
                rs: np.ndarray, rp: np.ndarray, torque_input: bool, command: float, body: np.ndarray,
                thrust: float, torque: np.ndarray) -> None:
        """Advance from t_a to t_b in n_sub steps (see :func:`fem_kernels.advance`)."""
        cfg = self.config
        self.st[fk.ST_TORQUE] = torque_input
        self.fp[fk.FP_COMMAND_PREV] = rs[RS_RATE] if not torque_input else command
        self.fp[fk.FP_COMMAND] = command
        self.fp[fk.FP_THRUST] = thrust
        fk.advance(self.x, self.v, self.rest, self.st, self.fp, rs, rp, g_tab,
                   u_tab if u_tab is not None else self._no_table, t_a, t_b, n_sub, body,
                   np.asarray(cfg.uav.inertia, float), np.linalg.inv(np.asarray(cfg.uav.inertia, float)),
                   np.asarray(cfg.uav.attach_offset, float), np.asarray(torque, float), self.acc)
        status = int(self.st[fk.ST_STATUS])
        if status == fk.STATUS_FULL:
            msg = 'the tether needs more elements than the reel max_length allows; raise reel.max_length'
            raise PlantDivergenceError(msg)
        if status == fk.STATUS_NONFINITE:
            msg = f'the tether state became non-finite before t = {t_b:.6g} s: reduce dt'
            raise PlantDivergenceError(msg)
        if status == fk.STATUS_SHORT:
            msg = f"the reel element's rest length reached zero before t = {t_b:.6g} s (method {cfg.reshape!r})"
            raise PlantDivergenceError(msg)

    @property
    def n(self) -> int:
        """Nodes in use."""
        return int(self.st[fk.ST_NODES])

    def nodes(self) -> np.ndarray:
        """(n, 3) node positions from the guide way to the UAV, m."""
        return self.x[:self.n].copy()

    def velocities(self) -> np.ndarray:
        """(n, 3) node velocities, m/s (node 0: the guide way's)."""
        return self.v[:self.n].copy()

    def _guide_material_velocity(self) -> np.ndarray:
        u0 = self.v[0].copy()
        if self.config.reshape == 'ale':
            u0 += self.fp[fk.FP_PAYOUT] * (self.x[1] - self.x[0]) / self.rest[0]
        return u0

    def tensions(self) -> np.ndarray:
        """(n - 1,) element tensions, N (Kelvin-Voigt included when on)."""
        out = np.zeros(self.n - 1)
        fk.element_tensions(self.x, self.v, self.rest, self.n, self.fp, bool(self.st[fk.ST_KV]),
                            self._guide_material_velocity(), out)
        return out

    def end_forces(self, tensions: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Forces of the tether on the guide way and on the UAV, N (:func:`fem_kernels.end_forces`)."""
        reel, uav = np.empty(3), np.empty(3)
        fk.end_forces(self.x, self.rest, self.n, tensions, self.fp, reel, uav)
        return reel, uav

    def arc_length(self) -> np.ndarray:
        """(n,) unstretched distance of each node from the guide way along the deployed
        tether, m (including what a merge still owes the reel element).
        """
        return np.concatenate([[0.0], float(self.fp[fk.FP_OWED]) + np.cumsum(self.rest[:self.n - 1])])

    def deployed_rest_length(self) -> float:
        """Deployed tether mass over mu, m: the elements' rest lengths plus what a merge still
        owes the reel element (material at the guide way, fed back within a second).
        """
        return float(np.sum(self.rest[:self.n - 1])) + float(self.fp[fk.FP_OWED])

    def lowest_point(self) -> np.ndarray:
        """The lowest node (the lowest point of a piecewise-linear tether), m."""
        return self.x[int(np.argmin(self.x[:self.n, 2]))].copy()

    def energy(self) -> float:
        """Mechanical energy the balance counts (:func:`fem_kernels.energy`), J."""
        return float(fk.energy(self.x, self.v, self.rest, self.n, self.fp))

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

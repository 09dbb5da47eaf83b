"""The stepping object of the tether plant: ``TetherPlant(config).step(t, inputs) -> PlantOutputs``."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from tether_common.rotation import quaternion_rotation
from tether_dynamics.plant import bodies, quasi_static
from tether_dynamics.plant import fem_kernels as fk
from tether_dynamics.plant.config import PlantConfig
from tether_dynamics.plant.energies import tether_energies
from tether_dynamics.plant.fem_reel import FemTether, lumped_masses
from tether_dynamics.plant.held_run import sub_steps
from tether_dynamics.plant.ends import Sample, cross, hermite, hermite_table, point_on_body
from tether_dynamics.plant.io import PlantInputs, PlantOutputs


class PlantStepError(ValueError):
    """A step that cannot be taken (time going backwards, bad input); the message says why."""


def _finite(name: str, value: object, shape: tuple[int, ...]) -> np.ndarray:
    arr = np.asarray(value, float)
    if arr.shape != shape or not all(map(math.isfinite, arr.reshape(-1).tolist())):
        msg = f'input {name} must be finite with shape {shape}, got {value!r}'
        raise PlantStepError(msg)
    return arr


@dataclass(frozen=True)
class HeldRun:
    """What :meth:`TetherPlant.run_held` returns, one row per sample time: the times (s), the UAV's
    position and velocity (m, m/s; ENU world), the tether's tensions at the reel and at the UAV (N) and
    its kinetic, gravitational and strain energies (J; :attr:`PlantOutputs.kinetic_energy` and the rest).
    """

    t: np.ndarray
    uav_position: np.ndarray
    uav_velocity: np.ndarray
    tension_reel: np.ndarray
    tension_uav: np.ndarray
    kinetic_energy: np.ndarray
    potential_energy: np.ndarray
    strain_energy: np.ndarray


class TetherPlant:
    """The tether between the guide way on the platform and the UAV, with the winch.

    See the package docstring for the contract. One object per run; ``step`` is called
    with increasing times; the first call sets the initial state (tether at rest in the
    elastic catenary of ``config.initial_length``) and advances nothing.
    """

    def __init__(self, config: PlantConfig) -> None:
        self.config = config
        cfg = config
        self._rp = np.array([cfg.reel.spool_radius, cfg.reel.inertia, cfg.reel.viscous_friction,
                             cfg.mass_per_length, cfg.reel.total_length, cfg.reel.min_length,
                             cfg.reel.max_length])
        self._rs = np.zeros(6)
        self._rs[bodies.RS_LENGTH] = cfg.initial_length
        self._body = np.zeros(bodies.BS_SIZE)
        self._inertia = np.asarray(cfg.uav.inertia, float)
        self._inertia_inv = np.linalg.inv(self._inertia)
        self._rho = np.asarray(cfg.uav.attach_offset, float)
        self._offset = np.asarray(cfg.guide_way_offset, float)
        self._t: float | None = None
        self._guide: Sample | None = None
        self._uav: Sample | None = None
        self._command = 0.0
        self._thrust = 0.0
        self._torque = np.zeros(3)
        self._uav_rotation = quaternion_rotation(np.array([0.0, 0.0, 0.0, 1.0]), 'uav_quaternion')
        self._nodes_prev: np.ndarray | None = None
        self._fem = FemTether(cfg) if cfg.fidelity != 'quasi_static' else None

    # ----------------------------------------------------------------- inputs
    def _samples(self, t: float, inputs: PlantInputs) -> tuple[Sample, Sample | None, float]:
        """Guide way and (prescribed) UAV attachment point at t, and the platform's height."""
        rot = quaternion_rotation(inputs.platform_quaternion, 'platform_quaternion')
        pos = _finite('platform_position', inputs.platform_position, (3,))
        vel = _finite('platform_velocity', inputs.platform_velocity, (3,))
        omega = _finite('platform_angular_velocity', inputs.platform_angular_velocity, (3,))
        gp, gv = point_on_body(pos, rot, vel, omega, self._offset)
        uav = None
        if self.config.uav.mode == 'prescribed' or self._t is None:
            urot = quaternion_rotation(inputs.uav_quaternion, 'uav_quaternion')
            self._uav_rotation = urot
            upos = _finite('uav_position', inputs.uav_position, (3,))
            uvel = _finite('uav_velocity', inputs.uav_velocity, (3,))
            uom = urot.apply(_finite('uav_angular_velocity', inputs.uav_angular_velocity, (3,)))
            ap, av = point_on_body(upos, urot, uvel, uom, self._rho)
            uav = Sample(t, ap, av)
            if self._t is None:
                self._body[bodies.BS_POS:bodies.BS_POS + 3] = upos
                self._body[bodies.BS_VEL:bodies.BS_VEL + 3] = uvel
                self._body[bodies.BS_QUAT:bodies.BS_QUAT + 4] = urot.as_quat()
                self._body[bodies.BS_OMEGA:bodies.BS_OMEGA + 3] = inputs.uav_angular_velocity
        return Sample(t, gp, gv), uav, float(pos[2])

    def _hold_commands(self, inputs: PlantInputs) -> None:
        cfg = self.config
        value = inputs.reel_torque if cfg.reel.input == 'torque' else inputs.spool_rate
        if not math.isfinite(value):
            msg = f'input {"reel_torque" if cfg.reel.input == "torque" else "spool_rate"} must be finite, got {value!r}'
            raise PlantStepError(msg)
        self._command = float(value)
        self._thrust = float(_finite('uav_thrust', inputs.uav_thrust, ()))
        self._torque = _finite('uav_torque', inputs.uav_torque, (3,)).copy()

    def _attach(self) -> tuple[np.ndarray, np.ndarray]:
        pos, vel = np.empty(3), np.empty(3)
        bodies.body_attach(self._body, self._rho, pos, vel)
        return pos, vel

    # ------------------------------------------------------------------ step
    def step(self, t: float, inputs: PlantInputs) -> PlantOutputs:
        """Advance to time t (s) with the kinematic samples at t; apply the commands from t on."""
        if not math.isfinite(t):
            msg = f'time must be finite, got {t!r}'
            raise PlantStepError(msg)
        if self._t is not None and t < self._t:
            msg = f'time went backwards: {t} s after {self._t} s'
            raise PlantStepError(msg)
        guide, uav, deck = self._samples(t, inputs)
        if self._t is None:
            self._t = t
            self._guide, self._uav = guide, uav
            if self._fem is not None:
                end = uav.position if uav is not None else self._attach()[0]
                self._fem.initialise(guide.position, end, self._rs[bodies.RS_LENGTH])
        elif t > self._t:
            self._advance(self._t, t, guide, uav)
            self._t = t
            self._guide = guide
            if uav is not None:
                self._uav = uav
        self._hold_commands(inputs)
        return self._outputs(t, inputs, deck)

    def _advance(self, t_a: float, t_b: float, guide: Sample, uav: Sample | None) -> None:
        cfg = self.config
        n_sub = sub_steps(t_a, t_b, cfg.dt)
        dt = (t_b - t_a) / n_sub
        assert self._guide is not None and (uav is None or self._uav is not None), 'set by the first step'
        g_tab = hermite_table(self._guide, guide)
        u_tab = hermite_table(self._uav, uav) if uav is not None and self._uav is not None else None
        torque_input = cfg.reel.input == 'torque'
        if self._fem is not None:
            self._fem.advance(t_a, t_b, n_sub, g_tab, u_tab, self._rs, self._rp, torque_input, self._command,
                              self._body, self._thrust, self._torque)
            return
        rate0 = float(self._rs[bodies.RS_RATE])
        for k in range(1, n_sub + 1):
            t_k = t_a + k * dt
            command = self._command if torque_input else rate0 + (self._command - rate0) * k / n_sub
            a, _ = hermite(g_tab, t_a, t_b, t_k - dt)
            b = hermite(u_tab, t_a, t_b, t_k - dt)[0] if u_tab is not None else self._attach()[0]
            t_a, t_b, tangent_b = quasi_static.end_tensions(a, b, self._rs[bodies.RS_LENGTH], cfg.mass_per_length,
                                                            cfg.ea, cfg.gravity)
            bodies.reel_step(self._rs, self._rp, torque_input, command, t_a, dt)
            if u_tab is None:
                force = -t_b * tangent_b
                bodies.body_step(self._body, cfg.uav.mass, self._inertia, self._inertia_inv, self._rho,
                                 self._thrust, self._torque, force, cfg.gravity, dt)

    def run_held(self, times: np.ndarray, inputs: PlantInputs) -> HeldRun:
        """Step through ``times`` (s, increasing) with ``inputs`` held: the whole-run stepper of the
        fixed-length cases (the Chapter 9 pendulum), one compiled loop (:mod:`.held_run`) whose samples
        equal ``step(t, inputs)`` called at each time, bit for bit. The first time is a ``step`` (it
        starts the plant when it has not started); the UAV must be 'dynamic' (a prescribed one would
        not move) and the fidelity finite-element.
        """
        times = np.ascontiguousarray(times, float)
        if self._fem is None or self.config.uav.mode != 'dynamic':
            msg = "run_held steps a finite-element fidelity with a 'dynamic' UAV"
            raise PlantStepError(msg)
        if times.ndim != 1 or times.size == 0 or not np.all(np.isfinite(times)) or np.any(np.diff(times) <= 0.0):
            msg = f'times must be a non-empty, finite, increasing 1-D array, got {times!r}'
            raise PlantStepError(msg)
        first = self.step(float(times[0]), inputs)
        guide = self._samples(float(times[-1]), inputs)[0]
        assert self._guide is not None, 'set by the first step'
        values, body = self._fem.run_held(times, hermite_table(self._guide, guide), self._rs, self._rp,
                                          self.config.reel.input == 'torque', self._command, self._body,
                                          self._thrust, self._torque)
        self._t, self._guide = float(times[-1]), guide
        values[0, [fk.RV_T_REEL, fk.RV_T_UAV, fk.RV_KINETIC, fk.RV_POTENTIAL, fk.RV_STRAIN]] = [
            first.tension_reel, first.tension_uav, first.kinetic_energy, first.potential_energy, first.strain_energy]
        body[0, bodies.BS_POS:bodies.BS_POS + 3] = first.uav_position
        body[0, bodies.BS_VEL:bodies.BS_VEL + 3] = first.uav_velocity
        return HeldRun(t=times, uav_position=body[:, bodies.BS_POS:bodies.BS_POS + 3],
                       uav_velocity=body[:, bodies.BS_VEL:bodies.BS_VEL + 3],
                       tension_reel=values[:, fk.RV_T_REEL], tension_uav=values[:, fk.RV_T_UAV],
                       kinetic_energy=values[:, fk.RV_KINETIC], potential_energy=values[:, fk.RV_POTENTIAL],
                       strain_energy=values[:, fk.RV_STRAIN])

    # --------------------------------------------------------------- outputs
    def _uav_state(self) -> tuple[np.ndarray, ...]:
        b = self._body
        return (b[bodies.BS_POS:bodies.BS_POS + 3].copy(), b[bodies.BS_VEL:bodies.BS_VEL + 3].copy(),
                b[bodies.BS_ACC:bodies.BS_ACC + 3].copy(), b[bodies.BS_QUAT:bodies.BS_QUAT + 4].copy(),
                b[bodies.BS_OMEGA:bodies.BS_OMEGA + 3].copy())

    def _outputs(self, t: float, inputs: PlantInputs, deck: float) -> PlantOutputs:
        cfg = self.config
        guide, uav = self._guide, self._uav
        assert guide is not None and (cfg.uav.mode != 'prescribed' or uav is not None), 'set by the first step'
        if cfg.uav.mode == 'prescribed':
            rot = self._uav_rotation
            upos, uvel = np.asarray(inputs.uav_position, float), np.asarray(inputs.uav_velocity, float)
            uacc, uquat = np.zeros(3), rot.as_quat()
            uom = np.asarray(inputs.uav_angular_velocity, float)
            assert uav is not None
            end, end_velocity = uav.position, uav.velocity
        else:
            upos, uvel, uacc, uquat, uom = self._uav_state()
            end, end_velocity = self._attach()
        a = guide.position
        length = float(self._rs[bodies.RS_LENGTH])
        mu, g = cfg.mass_per_length, cfg.gravity
        if self._fem is None:
            shape = quasi_static.solve(a, end, length, mu, cfg.ea, g)
            n = cfg.elements + 1
            nodes = shape.points(a, n)
            dt_out = t - getattr(self, '_t_nodes', t)
            vel = ((nodes - self._nodes_prev) / dt_out if self._nodes_prev is not None and dt_out > 0
                   else np.zeros_like(nodes))
            self._nodes_prev, self._t_nodes = nodes, t
            arc = np.linspace(0.0, length, n)
            sol = shape.solution
            h_t = float(sol.horizontal_tension) if math.isfinite(float(sol.horizontal_tension)) else 0.0
            v_a = shape.tension_a * math.sin(float(sol.alpha))
            s_mid = 0.5 * (arc[1:] + arc[:-1])
            tensions = np.sqrt(h_t**2 + (v_a + mu * g * s_mid) ** 2)
            t_a, t_b = shape.tension_a, shape.tension_b
            f_reel = t_a * shape.tangent_a()
            f_uav = -t_b * shape.tangent_b()
            alpha, beta = float(sol.alpha), float(sol.beta)
            lowest = shape.lowest_point(a)
            lumps = lumped_masses(np.diff(arc), 1, mu)
            kinetic, potential, strain = tether_energies(nodes, vel, lumps, tensions, arc, g, cfg.ea)
            max_tension = float(np.max(tensions))
            deployed_rest = length
        else:
            nodes, vel, arc, _, tensions, f_reel, f_uav, lowest, values = self._fem.report()
            t_a, t_b = float(values[fk.RV_T_REEL]), float(values[fk.RV_T_UAV])
            alpha, beta = float(values[fk.RV_ALPHA]), float(values[fk.RV_BETA])
            kinetic, potential = float(values[fk.RV_KINETIC]), float(values[fk.RV_POTENTIAL])
            strain, max_tension = float(values[fk.RV_STRAIN]), float(values[fk.RV_MAX_TENSION])
            deployed_rest = float(values[fk.RV_REST])
        moment = cross(end - upos, f_uav)
        sea = float(inputs.sea_surface_height)
        return PlantOutputs(
            t=t, fidelity=cfg.fidelity, element_count=self._fem.elements if self._fem is not None else len(nodes) - 1,
            reel_end=a.copy(), uav_end=end.copy(), reel_end_velocity=guide.velocity.copy(),
            uav_end_velocity=end_velocity.copy(),
            deployed_length=length, payout_rate=cfg.reel.spool_radius * float(self._rs[bodies.RS_RATE]),
            spool_angle=float(self._rs[bodies.RS_ANGLE]), spool_rate=float(self._rs[bodies.RS_RATE]),
            reel_torque=float(self._rs[bodies.RS_TORQUE]), at_stop=bool(self._rs[bodies.RS_STOP]),
            tension_reel=t_a, tension_uav=t_b, force_on_reel=f_reel, force_on_uav=f_uav, moment_on_uav=moment,
            departure_angle=alpha, arrival_angle=beta, lowest_point=lowest,
            clearance_deck=float(lowest[2] - deck), clearance_sea=float(lowest[2] - sea),
            fouling=bool(lowest[2] <= sea), kinetic_energy=kinetic, potential_energy=potential,
            strain_energy=strain, reel_work=float(self._rs[bodies.RS_WORK]),
            total_tether_mass=self._tether_mass(deployed_rest), nodes=nodes, velocities=vel, tensions=tensions,
            arc_length=arc, max_strain=max_tension / cfg.ea, uav_position=upos, uav_velocity=uvel,
            uav_acceleration=uacc, uav_quaternion=uquat, uav_angular_velocity=uom)

    def total_tether_mass(self) -> float:
        """Drum + deployed tether mass, kg: mu (total - L) + sum of the elements' rest masses."""
        return self._tether_mass(self._fem.deployed_rest_length() if self._fem is not None
                                 else float(self._rs[bodies.RS_LENGTH]))

    def energy_balance(self) -> dict[str, float] | None:
        """The finite-element tether's energy balance since the start (J; :meth:`FemTether.balance`),
        or None for the quasi-static fidelity.
        """
        return self._fem.balance() if self._fem is not None else None

    def _tether_mass(self, deployed_rest: float) -> float:
        """mu (total - L) on the drum + mu ``deployed_rest`` deployed, kg."""
        mu = self.config.mass_per_length
        return mu * (self.config.reel.total_length - float(self._rs[bodies.RS_LENGTH])) + mu * deployed_rest


def warm_up(config: PlantConfig) -> None:
    """Step a scratch plant of ``config``'s fidelity, effects and reel drive once, so that numba
    compiles the kernels it runs (about 15 s in a fresh checkout; afterwards it loads them from its
    on-disk cache). A node calls it while it starts: compiled in the run's first tick, the kernels
    counted in the run's CPU per simulated second and slowed the first tick of a rate-max run.

    The scratch tether is the reel's full length (the longest elements, the most stable step)
    hanging between the guide way and a UAV 0.6 of it out and 0.6 of it up.
    """
    length = config.reel.max_length
    inputs = PlantInputs(uav_position=np.asarray(config.guide_way_offset, float) + [0.6 * length, 0.0, 0.6 * length])
    plant = TetherPlant(replace(config, initial_length=length))
    plant.step(0.0, inputs)
    plant.step(2.0 * config.dt, inputs)

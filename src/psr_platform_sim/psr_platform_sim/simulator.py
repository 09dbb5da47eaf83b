"""The replicator playing a motion profile, without ROS (thesis Sec. 2.6-2.8).

The profile is sampled at the firmware's command rate, turned into slider heights
through the lookup table (Eq. 2.17 refined on the exact kinematics) and clipped to the
workspace; the sliders follow it with bounded speed and acceleration, smoothly between
commands (cubic Hermite through the commanded positions and their fourth-order central
difference velocities). The ``actuator_effects`` parameter makes the prototype's
actuators visible: ``firmware`` moves each slider at a constant speed between commands
(the firmware's steps per clock tick, Sec. 2.2), ``microstep`` puts it on whole
microsteps (``microstep`` m, 16:1 microstepping of Sec. 2.8). The achieved pose comes from the exact forward kinematics
(Eq. 2.1-2.9) on a fine time grid; an IMU at the platform centre sees its angular
velocity and specific force; its errors come from the shared IMU model
(:class:`tether_models.imu.ImuModel`, seeded white noise and constant bias here).

Frames (REP-103, REP-105 names): the thesis's mechanism frame has rail 1 - the
platform's bow, corner 1 - on +y and the body axes x' (starboard), y' (bow, Eq. 2.5),
z' (up, Eq. 2.4) with x' = y' x z' (Eq. 2.6). Published poses use ``world`` (ENU) = the
mechanism frame turned by -90 deg about z (:data:`MECHANISM_TO_WORLD`), so that rail 1
and the level platform's bow lie on world +x, and the body frame ``boat`` = FLU: x the
bow (corner 1, thesis y'), y port (-x'), z the platform normal (z'); at the level neutral
pose ``boat`` is aligned with ``world``, whose origin is the reel mount there. Heave,
surge (world x) and sway (world y) are the platform centre's displacement from its
neutral position.

Angles: the kinematics, the lookup table, the path generator, the thesis reproductions
(:meth:`PlatformSimulator.tracking_error`, :meth:`PlatformSimulator.achieved_hrp`,
``command``) and the motion profiles keep the thesis's Eq. 2.7-2.9 angles, the
inverse of R' = Rx(pitch) Ry(roll) Rz(yaw) on [x', y', z'] (roll about the bow axis y',
starboard down positive; pitch about x', bow up positive). The published angles
(:meth:`PlatformSimulator.sample`, PlatformState) are REP-103's intrinsic Z-Y-X angles
of the ``boat`` rotation R = Rz(yaw) Ry(pitch) Rx(roll): roll about the bow (starboard
down positive), pitch about port (bow down positive), yaw about up (bow turning to port
positive). In FLU the thesis rotation reads R = Ry(-pitch') Rx(roll') Rz(yaw'), so with
zero thesis yaw - every commanded pose, including the boat profiles - REP roll = thesis
roll and REP pitch = -thesis pitch exactly. The mechanism's coupled yaw makes the
achieved REP angles differ from that at second order (a body-frame tilt turned by the
yaw: up to 0.16 deg on HPR #1, whose coupled yaw stays below 0.8 deg; 2.3 deg on the
workspace profile's outer loops, yaw up to 4.3 deg), so published commanded and achieved
angles, both REP-103, differ by that much beyond the tracking error of the thesis angles.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import CubicHermiteSpline
from scipy.spatial.transform import Rotation

from psr_platform_sim.kinematics import Design
from psr_platform_sim.kinematics import platform_pose
from psr_platform_sim.kinematics import rotation_from_angles
from psr_platform_sim.kinematics import solve_corners
from psr_platform_sim.path import PathGenerator
from psr_platform_sim.path import central_velocity
from psr_platform_sim.path import limit_motion
from psr_platform_sim.validation import workspace_profile
from psr_platform_sim.workspace import ball_region
from psr_platform_sim.workspace import cached_table
from psr_platform_sim.workspace import nominal_region
from tether_models.constants import GRAVITY
from tether_models.imu import ImuModel
from tether_models.imu import ImuSpec
from tether_models.waves import named_profile

MECHANISM_TO_WORLD = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
"""Rz(-90 deg): mechanism-frame vectors to ``world``; also thesis body axes to FLU."""


def thesis_to_boat(rotation: np.ndarray) -> np.ndarray:
    """Rotation of the FLU ``boat`` frame in ``world`` from the thesis body axes [x', y', z'] (Eq. 2.4-2.6).

    ``rotation`` (..., 3, 3) holds x', y', z' as columns in the mechanism frame; the FLU
    axes are (y', -x', z'), so both sides turn by :data:`MECHANISM_TO_WORLD`.
    """
    return MECHANISM_TO_WORLD @ rotation @ MECHANISM_TO_WORLD.T


def rep103_angles(rotation: np.ndarray) -> np.ndarray:
    """REP-103 roll, pitch, yaw (rad) of body-to-world rotations (..., 3, 3): R = Rz(yaw) Ry(pitch) Rx(roll)."""
    return Rotation.from_matrix(rotation).as_euler('ZYX')[..., ::-1]


def thesis_to_rep103(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """REP-103 roll, pitch, yaw of the ``boat`` frame posed by thesis Eq. 2.7-2.9 angles, shape (..., 3)."""
    return rep103_angles(thesis_to_boat(rotation_from_angles(roll, pitch, yaw)))


@dataclass
class PlatformSample:
    """State of the platform at one instant (SI units; REP-103 angles in rad; see PlatformState.msg)."""

    slider_height: np.ndarray
    slider_velocity: np.ndarray
    position: np.ndarray
    quaternion: np.ndarray
    heave: float
    roll: float
    pitch: float
    yaw: float
    surge: float
    sway: float
    heave_rate: float
    roll_rate: float
    pitch_rate: float
    yaw_rate: float
    commanded_heave: float
    commanded_roll: float
    commanded_pitch: float
    in_workspace: bool
    angular_velocity: np.ndarray
    specific_force: np.ndarray
    reel_velocity: np.ndarray
    world_angular_velocity: np.ndarray


@dataclass(frozen=True)
class PlatformConfig:
    """What :class:`PlatformSimulator` simulates (the platform node builds it from its parameters).

    Attributes:
        design: the mechanism; ``ball_limit`` of pi means no ball-joint constraint.
        profile: motion profile name or CSV path (:func:`tether_models.waves.named_profile`, ``workspace``).
        seed: seed of the generated wave phases.
        sea_state: Douglas sea state of the boat profile.
        boat_length: boat length of the boat profile, m.
        profile_duration: length of generated profiles, s.
        ramp_time: fade-in from the level neutral pose, s.
        command_rate: slider command rate of the firmware, Hz.
        sample_rate: rate of the fine time grid the state is sampled on, Hz.
        heave_limit: half the heave range of the rails, m.
        rail_length: rail length, m; the level neutral pose puts the sliders at mid-rail.
        max_slider_speed: slider speed limit, m/s.
        max_slider_accel: slider acceleration limit, m/s².
        table_steps: lookup-table grid steps per slider axis.
        cache_dir: lookup-table cache directory (None: the default cache).
        reel_offset: reel mount from the platform centre in the FLU ``boat`` frame, m.
        actuator_effects: ``firmware`` and/or ``microstep`` (see the module docstring).
        microstep: slider travel per microstep, m.
    """

    design: Design
    profile: str
    seed: int
    sea_state: int
    boat_length: float
    profile_duration: float
    ramp_time: float
    command_rate: float
    sample_rate: float
    heave_limit: float
    rail_length: float
    max_slider_speed: float
    max_slider_accel: float
    table_steps: int
    cache_dir: Path | None
    reel_offset: tuple[float, float, float]
    actuator_effects: tuple[str, ...] = ()
    microstep: float = 2.5e-5


class PlatformSimulator:
    """Precomputed motion of the replicator for one profile, sampled by time."""

    def __init__(self, config: PlatformConfig) -> None:
        c = config
        self.design = c.design
        table = cached_table(self.design, c.table_steps, c.cache_dir)
        limited = c.design.ball_limit < np.pi
        region = ball_region(table) if limited else nominal_region(table)
        if region.area <= 0:
            raise ValueError(f'design r={c.design.r}, l={c.design.l}, d={c.design.d} has no usable workspace')
        self.rail_base = -c.rail_length / 2.0
        generator = PathGenerator(table, region, self.rail_base)
        self.neutral_centre = generator.neutral_centre
        if c.profile == 'workspace':
            profile = workspace_profile(table, region, rate=c.command_rate)
        else:
            profile = named_profile(c.profile, c.seed, c.profile_duration, c.sea_state, c.boat_length,
                                    c.command_rate)
        profile = profile.resampled(c.command_rate).ramped(c.ramp_time)
        self.profile_name = profile.name
        dt = 1.0 / c.command_rate
        path = generator.sliders(profile.heave, profile.roll, profile.pitch, exact=True,
                                 heave_limit=c.heave_limit)
        achieved, _, self.limited_ticks = limit_motion(path.heights, dt, c.max_slider_speed, c.max_slider_accel)
        self.command_t = profile.t
        self.command_dt = dt
        self.command = np.stack([path.heave, path.roll, path.pitch], axis=-1)
        self.commanded_angles = thesis_to_rep103(path.roll, path.pitch, np.zeros_like(path.roll))[:, :2]
        self.requested = np.stack([profile.heave, profile.roll, profile.pitch], axis=-1)
        self.inside = path.inside
        self.rate = c.sample_rate
        t = np.arange(0.0, profile.t[-1] + 0.5 / self.rate, 1.0 / self.rate)
        self.t = t
        effects = set(c.actuator_effects)
        if 'firmware' in effects:
            # Sec. 2.2: the firmware commands a number of motor steps per clock tick, so each
            # slider runs at a constant speed between commands.
            segment = np.clip(np.searchsorted(profile.t, t, side='right') - 1, 0, profile.t.size - 2)
            slope = np.diff(achieved, axis=0) / np.diff(profile.t)[:, None]
            self.sliders = achieved[segment] + slope[segment] * (t - profile.t[segment])[:, None]
            self.slider_velocity = slope[segment]
        else:
            spline = CubicHermiteSpline(profile.t, achieved, central_velocity(achieved, dt))
            self.sliders = spline(t)
            self.slider_velocity = spline(t, 1)
        if 'microstep' in effects:
            # Sec. 2.8: 16:1 microstepping; a slider stands on whole microsteps.
            self.sliders = np.round(self.sliders / c.microstep) * c.microstep
        corners, _, converged = solve_corners(self.design, self.sliders + self.rail_base)
        self.converged = converged
        pose = platform_pose(corners)
        offset = np.array([0.0, 0.0, self.neutral_centre])
        self.rotation = thesis_to_boat(pose.rotation)  # FLU boat to world
        self.centre = (pose.p - offset) @ MECHANISM_TO_WORLD.T
        self.thesis_angles = np.stack([pose.roll, pose.pitch, pose.yaw], axis=-1)
        self.quaternion = Rotation.from_matrix(self.rotation).as_quat()
        self.angles = rep103_angles(self.rotation)
        self.angle_rates = np.gradient(np.unwrap(self.angles, axis=0), 1.0 / self.rate, axis=0)
        self.velocity = np.gradient(self.centre, 1.0 / self.rate, axis=0)
        self.reel_offset = np.asarray(c.reel_offset, dtype=float)
        self.reel_position = self.centre + self.rotation @ self.reel_offset - self.reel_offset
        self.reel_velocity = np.gradient(self.reel_position, 1.0 / self.rate, axis=0)
        # Body angular velocity from R^T dR/dt, specific force R^T (a + g z).
        rdot = np.gradient(self.rotation, 1.0 / self.rate, axis=0)
        omega = np.einsum('nki,nkj->nij', self.rotation, rdot)
        self.angular_velocity = 0.5 * np.stack([omega[:, 2, 1] - omega[:, 1, 2], omega[:, 0, 2] - omega[:, 2, 0],
                                                omega[:, 1, 0] - omega[:, 0, 1]], axis=-1)
        self.world_angular_velocity = np.einsum('nij,nj->ni', self.rotation, self.angular_velocity)
        accel = np.gradient(self.velocity, 1.0 / self.rate, axis=0) + np.array([0.0, 0.0, GRAVITY])
        self.specific_force = np.einsum('nki,nk->ni', self.rotation, accel)

    @property
    def duration(self) -> float:
        """Length of the precomputed motion (s); the last pose is held after it."""
        return float(self.t[-1])

    def sample(self, time: float) -> PlatformSample:
        """State at ``time`` seconds after the start (nearest fine-grid sample), angles in REP-103."""
        i = min(max(int(round(time * self.rate)), 0), self.t.size - 1)
        c = min(max(int(round(time / self.command_dt)), 0), self.command_t.size - 1)
        held = time * self.rate > self.t.size - 1
        zero3 = np.zeros(3)
        return PlatformSample(
            slider_height=self.sliders[i], slider_velocity=zero3 if held else self.slider_velocity[i],
            position=self.reel_position[i], quaternion=self.quaternion[i],
            heave=float(self.centre[i, 2]), roll=float(self.angles[i, 0]), pitch=float(self.angles[i, 1]),
            yaw=float(self.angles[i, 2]), surge=float(self.centre[i, 0]), sway=float(self.centre[i, 1]),
            heave_rate=0.0 if held else float(self.velocity[i, 2]),
            roll_rate=0.0 if held else float(self.angle_rates[i, 0]),
            pitch_rate=0.0 if held else float(self.angle_rates[i, 1]),
            yaw_rate=0.0 if held else float(self.angle_rates[i, 2]),
            commanded_heave=float(np.interp(time, self.command_t, self.command[:, 0])),
            commanded_roll=float(np.interp(time, self.command_t, self.commanded_angles[:, 0])),
            commanded_pitch=float(np.interp(time, self.command_t, self.commanded_angles[:, 1])),
            in_workspace=bool(self.inside[c]),
            angular_velocity=zero3 if held else self.angular_velocity[i],
            specific_force=np.array([0.0, 0.0, GRAVITY]) @ self.rotation[i] if held else self.specific_force[i],
            reel_velocity=zero3 if held else self.reel_velocity[i],
            world_angular_velocity=zero3 if held else self.world_angular_velocity[i])

    def achieved_hrp(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Achieved heave (m), roll and pitch (rad, Eq. 2.7-2.8) on the fine time grid."""
        return self.centre[:, 2], self.thesis_angles[:, 0], self.thesis_angles[:, 1]

    def tracking_error(self) -> dict[str, float]:
        """RMS of achieved minus commanded heave (m), roll and pitch (rad, Eq. 2.7-2.8) on the command grid."""
        achieved = np.stack([np.interp(self.command_t, self.t, a) for a in self.achieved_hrp()], axis=-1)
        rms = np.sqrt(np.mean((achieved - self.command) ** 2, axis=0))
        return {'heave': float(rms[0]), 'roll': float(rms[1]), 'pitch': float(rms[2])}


def platform_imu(seed: int, gyro_noise: float, accel_noise: float, gyro_bias: float, accel_bias: float,
                 rate: float = 100.0) -> ImuModel:
    """The IMU at the platform centre: seeded white noise (std per sample) and a constant bias per axis."""
    spec = ImuSpec(gyro_noise=gyro_noise, accel_noise=accel_noise, gyro_bias=gyro_bias, accel_bias=accel_bias)
    return ImuModel(spec, np.random.default_rng([seed, 7]), 1.0 / rate)

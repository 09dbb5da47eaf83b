"""Wave and boat-motion profiles for the replicator (thesis Sec. 2.7.2 and 5.6).

* Heave only: a JONSWAP spectrum [81] as a sum of sinusoids with seeded random phases;
  the thesis's profile lasts 4 min with a 10 s peak period and a 1.6 m peak wave
  amplitude, read here as the profile's crest-to-trough range (it has to fit the 2.2 m
  heave range and approximates Douglas sea state 3, whose significant height of
  0.5-1.25 m matches a 1.6 m range over ~25 waves).
* Heave, pitch and roll of a boat: a directional sea (JONSWAP in frequency, cos^2
  spreading about the mean direction) sampled at three points of the hull - bow and the
  two stern corners - so that the boat's plane is fixed to the surface (Sec. 2.7.2); roll
  and pitch come from the plane's normal as in Eq. 2.7-2.8, heave from its mean height.
  Parameterized by Douglas sea state (3: Hs 0.5-1.25 m, 4: 1.25-2.5 m), boat length and
  seed. HPR #1 and #2 (seeds 1, 2) are for tuning, HPR #3 (seed 3) is held out; like the
  thesis's, their heave is fitted into the replicator's 2.2 m range.

Angles use the thesis convention of :mod:`psr_platform_sim.kinematics`: the boat's bow
points along the body y axis, roll turns about it (starboard down positive), pitch about
the body x axis (bow up positive). The platform node publishes them as REP-103 angles of
the FLU ``boat`` frame (roll unchanged, pitch negated at zero yaw; see
:mod:`psr_platform_sim.simulator`).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from tether_models.constants import GRAVITY

SEA_STATES = {3: (0.5, 1.25), 4: (1.25, 2.5)}
"""Douglas sea scale: significant wave height range (m) per sea state."""

HPR_SEEDS = {'hpr1': 1, 'hpr2': 2, 'hpr3': 3}
"""Boat profiles for tuning (#1, #2) and held-out testing (#3), as in Sec. 5.6."""

HPR_HEAVE_RANGE = 2.2
"""Sec. 5.6: the HPR profiles' heave spans up to the replicator's 2.2 m range."""


class ProfileError(Exception):
    """A motion profile cannot be loaded or built."""


@dataclass
class MotionProfile:
    """Commanded platform motion over time.

    Attributes:
        t: time (s), increasing, from 0.
        heave: platform-centre heave (m).
        roll, pitch: platform angles (rad), Eq. 2.7-2.8 convention.
        name: label for plots and logs.
    """

    t: np.ndarray
    heave: np.ndarray
    roll: np.ndarray
    pitch: np.ndarray
    name: str

    def resampled(self, rate: float) -> MotionProfile:
        """The profile at a fixed sample rate (Hz), linearly interpolated."""
        t = np.arange(0.0, self.t[-1] + 0.5 / rate, 1.0 / rate)
        heave, roll, pitch = (np.interp(t, self.t, a) for a in (self.heave, self.roll, self.pitch))
        return MotionProfile(t, heave, roll, pitch, self.name)

    def ramped(self, ramp_time: float) -> MotionProfile:
        """The profile faded in from the level neutral pose over ``ramp_time`` (s), a cosine ramp."""
        if ramp_time <= 0:
            return self
        w = 0.5 - 0.5 * np.cos(np.pi * np.clip(self.t / ramp_time, 0.0, 1.0))
        return MotionProfile(self.t, w * self.heave, w * self.roll, w * self.pitch, self.name)

    def save_csv(self, path: Path) -> None:
        """Write ``time,heave,roll,pitch`` (s, m, rad) rows."""
        with open(path, 'w', newline='') as handle:
            writer = csv.writer(handle)
            writer.writerow(['time', 'heave', 'roll', 'pitch'])
            writer.writerows(zip(self.t, self.heave, self.roll, self.pitch))


def load_csv(path: str | Path) -> MotionProfile:
    """Read a ``time,heave,roll,pitch`` CSV (s, m, rad); ProfileError with one line if bad."""
    path = Path(path)
    try:
        with open(path, newline='') as handle:
            rows = list(csv.reader(handle))
    except OSError as error:
        raise ProfileError(f'{path}: {error.strerror}') from None
    if not rows or [c.strip() for c in rows[0]] != ['time', 'heave', 'roll', 'pitch']:
        raise ProfileError(f'{path}: first line must be the header time,heave,roll,pitch')
    try:
        data = np.array([[float(v) for v in row] for row in rows[1:] if row], dtype=float)
    except ValueError as error:
        raise ProfileError(f'{path}: not a number: {error}') from None
    if data.ndim != 2 or data.shape[0] < 2 or data.shape[1] != 4:
        raise ProfileError(f'{path}: needs at least two rows of four values')
    if not np.all(np.isfinite(data)):
        raise ProfileError(f'{path}: values must be finite')
    if np.any(np.diff(data[:, 0]) <= 0):
        raise ProfileError(f'{path}: time must increase strictly')
    t = data[:, 0] - data[0, 0]
    return MotionProfile(t, data[:, 1], data[:, 2], data[:, 3], path.stem)


def jonswap_spectrum(omega: np.ndarray, hs: float, tp: float, gamma: float = 3.3) -> np.ndarray:
    """JONSWAP wave spectrum S(omega) (m^2 s/rad) with significant height hs and peak period tp.

    The DNV-RP-C205 form: the Pierson-Moskowitz spectrum times the peak enhancement
    gamma^exp(-(omega-omega_p)^2 / (2 sigma^2 omega_p^2)), normalized by
    (1 - 0.287 ln gamma) so that 4 sqrt(m0) = hs.
    """
    omega = np.asarray(omega, dtype=float)
    wp = 2.0 * np.pi / tp
    sigma = np.where(omega <= wp, 0.07, 0.09)
    with np.errstate(divide='ignore', over='ignore', invalid='ignore'):
        pm = 5.0 / 16.0 * hs**2 * wp**4 * omega**-5.0 * np.exp(-1.25 * (omega / wp) ** -4.0)
        peak = gamma ** np.exp(-((omega - wp) ** 2) / (2.0 * sigma**2 * wp**2))
        s = (1.0 - 0.287 * np.log(gamma)) * pm * peak
    return np.where(omega > 0, np.nan_to_num(s), 0.0)


def _components(duration: float, hs: float, tp: float, omega_max_factor: float = 5.0):
    """Frequencies on the 2 pi / duration grid and their amplitudes sqrt(2 S dw)."""
    dw = 2.0 * np.pi / duration
    wp = 2.0 * np.pi / tp
    omega = np.arange(1, int(omega_max_factor * wp / dw) + 1) * dw
    return omega, np.sqrt(2.0 * jonswap_spectrum(omega, hs, tp) * dw)


def jonswap_heave(duration: float = 240.0, hs: float = 1.0, tp: float = 10.0, seed: int = 0,
                  rate: float = 30.0) -> MotionProfile:
    """Heave-only profile from the JONSWAP spectrum: sinusoids with seeded random phases.

    The frequencies lie on the grid 2 pi k / duration, so the profile's variance over its
    duration equals the discretized spectrum's m0 and its significant height 4 sqrt(m0)
    matches ``hs`` up to the spectrum's truncation at 5 omega_p.
    """
    if duration <= 0 or hs < 0 or tp <= 0 or rate <= 0:
        raise ProfileError('jonswap: duration, peak period and rate must be positive, hs >= 0')
    omega, amplitude = _components(duration, hs, tp)
    phase = np.random.default_rng(seed).uniform(0.0, 2.0 * np.pi, omega.size)
    t = np.arange(0.0, duration, 1.0 / rate)
    heave = np.sum(amplitude * np.cos(np.outer(t, omega) + phase), axis=1)
    zeros = np.zeros_like(t)
    return MotionProfile(t, heave, zeros, zeros.copy(), f'jonswap-hs{hs:g}-tp{tp:g}-seed{seed}')


def thesis_heave_profile(seed: int = 0, duration: float = 240.0, tp: float = 10.0,
                         heave_range: float = 1.6, rate: float = 30.0) -> MotionProfile:
    """The thesis's heave-only profile (Sec. 5.6): 4 min, 10 s peak period, scaled to a 1.6 m range."""
    profile = jonswap_heave(duration, 1.0, tp, seed, rate)
    span = np.ptp(profile.heave)
    profile.heave *= heave_range / span
    profile.name = f'jonswap-range{heave_range:g}-tp{tp:g}-seed{seed}'
    return profile


def sea_state_height(sea_state: int) -> float:
    """Significant wave height (m) used for a Douglas sea state: its range's midpoint."""
    if sea_state not in SEA_STATES:
        raise ProfileError(f'sea state must be one of {sorted(SEA_STATES)}, got {sea_state}')
    low, high = SEA_STATES[sea_state]
    return 0.5 * (low + high)


def boat_profile(sea_state: int = 4, boat_length: float = 5.0, seed: int = 1, duration: float = 240.0,
                 rate: float = 30.0, heading: float = np.radians(45.0), directions: int = 24,
                 beam_ratio: float = 0.4) -> MotionProfile:
    """Heave, roll, pitch of a boat whose plane is fixed to three points of a directional sea.

    Args:
        sea_state: Douglas sea state (3 or 4); Hs is the range's midpoint and the peak
            period that of a fully developed sea, Tp = 5 sqrt(Hs) s (Pierson-Moskowitz).
        boat_length: hull length (m), 3-7 m; the beam is ``beam_ratio`` of it.
        seed: seed of the random phases.
        duration, rate: profile length (s) and sample rate (Hz).
        heading: angle from the mean wave direction to the bow (rad).
        directions: number of wave directions over +-90 deg (cos^2 spreading).
    """
    if not 3.0 <= boat_length <= 7.0:
        raise ProfileError(f'boat length must be 3-7 m, got {boat_length}')
    hs = sea_state_height(sea_state)
    tp = 5.0 * np.sqrt(hs)
    omega, amplitude = _components(duration, hs, tp)
    spread = np.linspace(-np.pi / 2, np.pi / 2, directions + 2)[1:-1]
    weight = np.cos(spread) ** 2
    weight /= weight.sum()
    rng = np.random.default_rng(seed)
    amp = amplitude[:, None] * np.sqrt(weight)[None, :]
    phase = rng.uniform(0.0, 2.0 * np.pi, amp.shape)
    k = omega**2 / GRAVITY  # deep-water dispersion
    direction = spread[None, :] - heading  # wave direction in the boat frame, from the bow axis
    kx = (k[:, None] * np.sin(direction)).ravel()
    ky = (k[:, None] * np.cos(direction)).ravel()
    w = np.repeat(omega, spread.size)
    amp, phase = amp.ravel(), phase.ravel()
    half, beam = boat_length / 2.0, beam_ratio * boat_length / 2.0
    hull = np.array([[0.0, half], [beam, -half], [-beam, -half]])  # bow, stern starboard, stern port
    t = np.arange(0.0, duration, 1.0 / rate)
    heights = np.empty((t.size, 3))
    for i, (x, y) in enumerate(hull):
        heights[:, i] = np.cos(np.outer(t, w) - (kx * x + ky * y) + phase) @ amp
    points = np.broadcast_to(np.concatenate([hull, np.zeros((3, 1))], axis=1), (t.size, 3, 3)).copy()
    points[..., 2] = heights
    normal = np.cross(points[:, 0] - points[:, 2], points[:, 0] - points[:, 1])  # as Eq. 2.4
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    roll = np.arcsin(normal[:, 0])  # Eq. 2.7
    pitch = -np.arcsin(normal[:, 1] / np.cos(roll))  # Eq. 2.8
    return MotionProfile(t, heights.mean(axis=1), roll, pitch,
                         f'boat-ss{sea_state}-L{boat_length:g}-seed{seed}')


def fit_heave(profile: MotionProfile, heave_range: float) -> MotionProfile:
    """The profile with its heave centred and, if larger, scaled down to ``heave_range`` (m)."""
    low, high = profile.heave.min(), profile.heave.max()
    scale = min(1.0, heave_range / (high - low)) if high > low else 1.0
    heave = (profile.heave - 0.5 * (low + high)) * scale
    return MotionProfile(profile.t, heave, profile.roll, profile.pitch, profile.name)


def named_profile(name: str, seed: int = 1, duration: float = 240.0, sea_state: int = 4,
                  boat_length: float = 5.0, rate: float = 30.0) -> MotionProfile:
    """Profile by name: ``jonswap``, ``boat``, ``hpr1``..``hpr3``, ``still`` or a CSV path."""
    if name == 'jonswap':
        return thesis_heave_profile(seed, duration, rate=rate)
    if name == 'boat':
        return boat_profile(sea_state, boat_length, seed, duration, rate)
    if name in HPR_SEEDS:
        return fit_heave(boat_profile(4, 5.0, HPR_SEEDS[name], duration, rate), HPR_HEAVE_RANGE)
    if name == 'still':
        t = np.arange(0.0, duration, 1.0 / rate)
        zeros = np.zeros_like(t)
        return MotionProfile(t, zeros, zeros.copy(), zeros.copy(), 'still')
    if name.endswith('.csv'):
        return load_csv(name)
    raise ProfileError(f'unknown profile {name!r}: use jonswap, boat, hpr1, hpr2, hpr3, still, workspace '
                       'or a .csv file')

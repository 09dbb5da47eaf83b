"""Message logic and retrodiction of the estimator: each fault alone, a wild fix after a dropout, late fixes."""

from __future__ import annotations

import numpy as np
import pytest

from relpos_estimator.estimator import Estimator
from relpos_estimator.estimator_params import PARAMETERS
from relpos_estimator.estimator_params import configs
from relpos_estimator.offline import run
from tether_models.dgps import DgpsConfig
from tether_models.dgps import Fix
from tether_models.dgps import STATUS_RTK_FIXED
from tether_models.sensor_suite import SensorSuite
from tether_models.sensor_suite import SuiteConfig

CLEAN = DgpsConfig(miss_rate=0.0, wild_rate=0.0)
DURATION = 60.0

FAULTS = {
    'missed': dict(miss_rate=0.1, stale_after_miss=0.0, recovery_time=0.0),
    'stale': dict(miss_rate=0.1, stale_after_miss=1.0, recovery_time=0.3),
    'recovering': dict(miss_rate=0.1, stale_after_miss=0.0, recovery_time=1.0),
    'wild': dict(wild_rate=0.1),
    'late': dict(late_rate=0.1),
    'duplicate': dict(duplicate_rate=0.1),
    'nonfinite': dict(nonfinite_rate=0.05),
}
SHIFT_BOUND = 0.05
"""m: no single fault type may move the estimate further than this from the fault-free run (the issue's
target). With the tuned covariances the lost fixes of a miss and its 1 s of recovery let the
estimate drift 0.032 m at most while dead reckoning (measured here; 0.06 m with the thesis's values)."""


DEFAULTS = configs({**{spec.name: spec.default for spec in PARAMETERS}, 'covariances': 'tuned'})
"""The tuned covariances (config/estimator_tuned.yaml) and the default message logic."""


def _run(truth, dgps: DgpsConfig, suite: SuiteConfig = SuiteConfig(), seed: int = 2):
    return run(truth(DURATION, seed=1), SensorSuite(suite, dgps, seed), Estimator(*DEFAULTS))


@pytest.fixture
def clean(truth):
    return _run(truth, CLEAN)


@pytest.mark.parametrize('kind', sorted(FAULTS))
def test_each_fault_alone_stays_within_the_bound(truth, clean, kind):
    faulty = _run(truth, DgpsConfig(**{**CLEAN.__dict__, **FAULTS[kind]}))
    injected = [f for _, f in faulty.faults if f.kind == kind]
    assert len(injected) >= 5, f'only {len(injected)} {kind} faults injected'
    a, b = clean.arrays(), faulty.arrays()
    settled = a['t'] > 5.0
    shift = np.abs(b['dz'] - a['dz'])[settled]
    assert shift.max() < SHIFT_BOUND, f'{kind}: estimate moved {shift.max():.3f} m'
    if kind in ('stale', 'wild', 'duplicate', 'nonfinite', 'recovering'):
        reasons = {r.reason for r in faulty.rejections}
        assert reasons, f'{kind}: nothing rejected'
    # and the faulty run still tracks the truth
    err = (b['dz'] - b['truth'])[settled]
    assert np.sqrt(np.mean(err**2)) < 0.03


def test_imu_nan_is_a_fault_not_a_number(truth, clean):
    faulty = _run(truth, CLEAN, SuiteConfig(imu_nonfinite_rate=0.02))
    assert sum(1 for s, _ in faulty.faults if s.startswith('imu')) > 100
    dz = faulty.arrays()['dz']
    assert np.all(np.isfinite(dz))
    assert np.abs(dz - clean.arrays()['dz'])[500:].max() < SHIFT_BOUND
    assert any(e.rejected & 48 for e in faulty.estimate)


def _fix(t, dz, seq, arrival=None):
    return Fix(t + 0.05 if arrival is None else arrival, t, np.array([2.5, 0.0, dz]), np.full(3, 0.01),
               STATUS_RTK_FIXED, seq)


def _drive(estimator, truth_fn, t_end, fixes, t_start=0.0):
    """Step 100 Hz from t_start with exact IMU accelerations of dz(t) = truth_fn; fixes: list of Fix delivered
    by arrival.
    """
    out = []
    for k in range(int(round(t_start * 100)), int(round(t_end * 100)) + 1):
        t = k / 100
        accel = -(truth_fn(t + 0.01) - 2 * truth_fn(t) + truth_fn(t - 0.01)) / 1e-4
        due = [f for f in fixes if int(np.ceil(f.arrival * 100 - 1e-6)) == k]
        out.append(estimator.step(t, accel, 0.0, due))
    return out


def _wave(t):
    return 5.0 - 0.8 * np.sin(2 * np.pi * t / 8.0)


@pytest.mark.parametrize('error', [0.3, 1.5, 15.0])
def test_a_wild_fix_right_after_a_2s_dropout_is_rejected(error):
    fixes = [_fix(k * 0.25, _wave(k * 0.25), k) for k in range(0, 41)]  # 0..10 s
    fixes += [_fix(12.0, _wave(12.0) + error, 48)]                       # 2 s later, wrong
    fixes += [_fix(k * 0.25, _wave(k * 0.25), k) for k in range(49, 61)]
    est = Estimator()
    out = _drive(est, _wave, 15.0, fixes)
    rejected = [r for e in out for r in e.rejections]
    assert [r.sequence for r in rejected] == [48]
    assert rejected[0].reason in ('innovation', 'jump')
    reference = _drive(Estimator(), _wave, 15.0, [f for f in fixes if f.sequence != 48])
    shift = max(abs(a.x[0] - b.x[0]) for a, b in zip(out, reference))
    assert shift < 1e-12


def test_a_late_out_of_order_fix_gives_the_on_time_estimate():
    """A fix delayed by 0.4 s (after the next one): after it arrives, the estimate equals the on-time run's."""
    on_time = [_fix(k * 0.25, _wave(k * 0.25) + 0.01 * np.sin(k), k) for k in range(0, 60)]
    late = [_fix(f.fix_time, f.position[2], f.sequence, f.arrival + (0.4 if f.sequence == 30 else 0.0))
            for f in on_time]
    a = _drive(Estimator(), _wave, 14.0, on_time)
    b = _drive(Estimator(), _wave, 14.0, late)
    arrived = int(round((30 * 0.25 + 0.45 + Estimator().logic.fix_hold) * 100))  # considered after the hold
    diff = max(abs(x.x[0] - y.x[0]) for x, y in zip(a[arrived:], b[arrived:]))
    assert diff < 1e-9
    # before it arrived the two differ: the late run had not seen the fix yet
    assert max(abs(x.x[0] - y.x[0]) for x, y in zip(a[760:arrived], b[760:arrived])) > 1e-6


def test_a_fix_fused_as_if_current_would_be_worse():
    """The retrodicted fix beats fusing the same late fix at its arrival (robot_localization #262)."""
    on_time = [_fix(k * 0.25, _wave(k * 0.25), k, arrival=k * 0.25 + 0.3) for k in range(0, 60)]
    as_current = [_fix(f.arrival, f.position[2], f.sequence, f.arrival) for f in on_time]
    t = np.arange(0, 1401) / 100
    a = np.array([e.x[0] for e in _drive(Estimator(), _wave, 14.0, on_time)])
    b = np.array([e.x[0] for e in _drive(Estimator(), _wave, 14.0, as_current)])
    rms = [np.sqrt(np.mean((v[200:] - _wave(t[200:])) ** 2)) for v in (a, b)]
    assert rms[0] < 0.5 * rms[1]


def test_stale_duplicate_and_status_are_rejected_with_their_reason():
    fixes = [_fix(k * 0.25, _wave(k * 0.25), k) for k in range(0, 20)]
    fixes.append(_fix(2.0, _wave(2.0), 99, arrival=2.55))            # repeats time of fix 2.0 s: stale
    fixes.append(_fix(2.25, _wave(2.25), 9, arrival=2.31))           # same sequence and time: duplicate
    fixes.append(Fix(3.2, 3.1, np.array([0.0, 0.0, _wave(3.1)]), np.full(3, 0.3), 3, 200))  # RTK float
    fixes.append(_fix(3.6, np.nan, 201))
    fixes.append(_fix(1.0, _wave(1.0), 202, arrival=4.7))            # 3.7 s old: stale
    out = _drive(Estimator(), _wave, 5.0, fixes)
    reasons = {r.sequence: r.reason for e in out for r in e.rejections}
    assert reasons == {99: 'stale', 9: 'duplicate', 200: 'status', 201: 'nonfinite', 202: 'stale'}


def test_the_filter_reacquires_after_a_true_step_in_altitude():
    """A real 3 m step (e.g. a re-mounted antenna) is rejected at first, then re-acquired, not locked out."""
    def stepped(t):
        return _wave(t) + (3.0 if t >= 6.0 else 0.0)
    fixes = [_fix(k * 0.25, stepped(k * 0.25), k) for k in range(0, 60)]
    out = _drive(Estimator(), _wave, 14.0, fixes)
    assert np.abs(out[-1].x[0] - stepped(14.0)) < 0.05
    assert sum(len(e.rejections) for e in out) == Estimator().logic.reacquire_after - 1


def test_same_seed_same_estimates(truth):
    a = _run(truth, DgpsConfig()).arrays()
    b = _run(truth, DgpsConfig()).arrays()
    np.testing.assert_array_equal(a['dz'], b['dz'])


FLIGHT = configs({**{spec.name: spec.default for spec in PARAMETERS}, 'covariances': 'flight'})
"""The flight covariances (config/estimator_flight.yaml: sigma_dgps 1e-4 m^2, the RTK-fixed sigma)."""


def _rate_error(out, truth_fn):
    """Largest |rate error| (m/s) of the estimates after ``out``'s first one."""
    return max(abs(e.x[1] - (truth_fn(e.t + 1e-4) - truth_fn(e.t - 1e-4)) / 2e-4) for e in out[1:])


def test_a_fix_the_receiver_calls_coarse_is_weighed_as_coarse():
    """A status-4 fix 0.5 m off that reports a 0.3 m sigma passes the gate (its NIS is 2.8, as the
    receiver's sigma says it may be that far off); fused at the flight sigma_dgps (0.01 m) it pulled
    the altitude 0.37 m and its rate 0.29 m/s (a flight of the campaign); at its own 0.3 m it moves
    them by less than 1 cm and 1 cm/s.
    """
    fixes = [_fix(k * 0.25, _wave(k * 0.25), k) for k in range(0, 41)]
    coarse = Fix(10.25 + 0.05, 10.25, np.array([2.5, 0.0, _wave(10.25) + 0.5]), np.full(3, 0.3), STATUS_RTK_FIXED, 41)
    est = Estimator(*FLIGHT)
    out = _drive(est, _wave, 10.4, [*fixes, coarse])
    assert [f.sequence for f in out[-1].fused] == [] and any(41 in [f.sequence for f in e.fused] for e in out)
    assert abs(out[-1].x[0] - _wave(10.4)) < 0.01
    assert _rate_error(out[-5:], _wave) < 0.01


def test_a_reacquisition_learns_the_rate_again():
    """A filter whose rate drifted 0.5 m/s off (as a bad fix left it) is locked out by the gate until
    it re-acquires; the re-acquisition resets the altitude and re-learns the rate from the fixes it had
    rejected, so it re-acquires once and then tracks (an altitude reset alone left the rate error in
    place, re-acquired every 2 s and never settled).
    """
    fixes = [_fix(k * 0.25, _wave(k * 0.25), k) for k in range(0, 81)]
    est = Estimator(*FLIGHT)
    out = _drive(est, _wave, 8.0, [f for f in fixes if f.arrival <= 8.0])
    for tick in est.history:
        tick.x[1] += 0.5
    est.filter.restore(est.history[-1].x, est.history[-1].P)
    out = _drive(est, _wave, 20.0, [f for f in fixes if f.arrival > 8.0], t_start=8.01)
    rejections = [r for e in out for r in e.rejections]
    assert len(rejections) == est.logic.reacquire_after - 1
    settled = [e for e in out if e.t >= 12.0]
    assert max(abs(e.x[0] - _wave(e.t)) for e in settled) < 0.02
    assert _rate_error(settled, _wave) < 0.05


def test_a_fix_metres_off_horizontally_does_not_reach_the_radial_distance():
    """A fused fix whose altitude is right but whose x, y are 5 m off (a wild fix in a flight of the
    campaign moved the reel's reference 1.8 m) leaves the horizontal passthrough where it was; the
    next good fix passes as before.
    """
    fixes = [_fix(k * 0.25, _wave(k * 0.25), k) for k in range(0, 41)]
    wild = _fix(10.25, _wave(10.25), 41)
    wild = Fix(wild.arrival, wild.fix_time, np.array([5.5, -4.0, wild.position[2]]), wild.std, wild.status, 41)
    good = _fix(10.5, _wave(10.5), 42)
    out = _drive(Estimator(), _wave, 10.6, [*fixes, wild, good])
    after_wild = next(e for e in out if 41 in [f.sequence for f in e.fused])
    assert after_wild.radial == pytest.approx(2.5) and after_wild.horizontal_fix_time == pytest.approx(10.0)
    assert out[-1].horizontal_fix_time == pytest.approx(10.5)

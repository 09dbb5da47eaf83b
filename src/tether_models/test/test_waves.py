"""Wave and boat-motion profiles (Sec. 2.7.2, 5.6): JONSWAP statistics, boat planes, CSV."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from tether_models.waves import MotionProfile
from tether_models.waves import ProfileError
from tether_models.waves import boat_profile
from tether_models.waves import jonswap_heave
from tether_models.waves import jonswap_spectrum
from tether_models.waves import load_csv
from tether_models.waves import named_profile
from tether_models.waves import thesis_heave_profile


@pytest.mark.parametrize('gamma', [1.0, 3.3, 5.0])
def test_jonswap_spectrum_integrates_to_the_significant_height(gamma):
    m0, _ = quad(jonswap_spectrum, 0.0, 20.0, args=(2.0, 8.0, gamma), limit=200)
    assert abs(4.0 * np.sqrt(m0) - 2.0) / 2.0 < 0.02  # the (1 - 0.287 ln gamma) normalization is approximate


@pytest.mark.parametrize(('hs', 'tp', 'seed'), [(1.0, 10.0, 0), (2.0, 7.0, 1), (0.8, 12.0, 2)])
def test_jonswap_heave_has_the_requested_peak_and_significant_height(hs, tp, seed):
    profile = jonswap_heave(240.0, hs, tp, seed, rate=10.0)
    assert abs(4.0 * profile.heave.std() - hs) / hs < 0.05
    freq = np.fft.rfftfreq(profile.t.size, 0.1)
    power = np.abs(np.fft.rfft(profile.heave)) ** 2
    peak_period = 1.0 / freq[np.argmax(power)]
    assert abs(peak_period - tp) / tp < 0.05
    assert np.all(profile.roll == 0) and np.all(profile.pitch == 0)


def test_thesis_heave_profile_matches_sec_5_6():
    """4 min, 1.6 m crest-to-trough range, about sea state 3 (Hs 0.5-1.25 m)."""
    profile = thesis_heave_profile(seed=4)
    assert abs(profile.t[-1] - 240.0) < 0.1
    assert abs(np.ptp(profile.heave) - 1.6) < 1e-12
    assert 0.5 <= 4.0 * profile.heave.std() <= 1.25


def test_seeds_repeat_and_differ():
    a, b, c = (boat_profile(3, 4.0, seed, 30.0, rate=10.0) for seed in (7, 7, 8))
    np.testing.assert_array_equal(a.roll, b.roll)
    assert np.abs(a.roll - c.roll).max() > 1e-3


def test_longer_hull_pitches_less():
    profile = boat_profile(3, 5.0, 1, 30.0)
    profile_long = boat_profile(3, 7.0, 1, 30.0)
    # a longer hull averages more of the short waves: less pitch
    assert np.abs(profile_long.pitch).max() < np.abs(profile.pitch).max()
    assert np.degrees(np.abs(profile.roll).max()) < 45.0


def test_sea_state_4_moves_more_than_sea_state_3():
    ss3, ss4 = boat_profile(3, 5.0, 2, 120.0, rate=10.0), boat_profile(4, 5.0, 2, 120.0, rate=10.0)
    assert np.ptp(ss4.heave) > 1.3 * np.ptp(ss3.heave)
    # the hull's mean height has the significant height of its Douglas band
    assert 0.5 < 4.0 * ss3.heave.std() < 1.25 < 4.0 * ss4.heave.std() < 2.5


def test_csv_round_trip(tmp_path):
    profile = boat_profile(3, 5.0, 1, 5.0)
    profile.save_csv(tmp_path / 'p.csv')
    loaded = load_csv(tmp_path / 'p.csv')
    np.testing.assert_allclose(loaded.roll, profile.roll, rtol=1e-15)
    np.testing.assert_allclose(loaded.t, profile.t, rtol=1e-15)


@pytest.mark.parametrize(('text', 'match'), [
    ('t,h,r,p\n0,0,0,0\n', 'header'),
    ('time,heave,roll,pitch\n0,0,0,0\n1,x,0,0\n', 'not a number'),
    ('time,heave,roll,pitch\n0,0,0,0\n', 'at least two rows'),
    ('time,heave,roll,pitch\n1,0,0,0\n0,0,0,0\n', 'increase'),
    ('time,heave,roll,pitch\n0,0,0,0\n1,nan,0,0\n', 'finite'),
])
def test_bad_csv_gives_one_line_error(tmp_path, text, match):
    path = tmp_path / 'bad.csv'
    path.write_text(text)
    with pytest.raises(ProfileError, match=match) as info:
        load_csv(path)
    assert '\n' not in str(info.value)


def test_missing_csv_and_unknown_profile_name(tmp_path):
    with pytest.raises(ProfileError, match='missing.csv'):
        named_profile(str(tmp_path / 'missing.csv'))
    with pytest.raises(ProfileError, match='unknown profile'):
        named_profile('tsunami')


def test_ramp_starts_level():
    profile = MotionProfile(np.linspace(0, 10, 101), np.ones(101), np.ones(101), np.ones(101), 'x').ramped(4.0)
    assert profile.heave[0] == 0.0 and profile.heave[-1] == 1.0


def test_hpr_profiles_fit_the_heave_range_of_the_replicator():
    """Sec. 5.6: heave ranges up to the 2.2 m capability."""
    for name in ('hpr1', 'hpr2', 'hpr3'):
        profile = named_profile(name, duration=120.0, rate=10.0)
        assert np.ptp(profile.heave) <= 2.2 + 1e-12
        assert abs(profile.heave.max() + profile.heave.min()) < 1e-12

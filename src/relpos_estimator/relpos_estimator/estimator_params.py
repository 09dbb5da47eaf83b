"""Parameters of the estimator node (no rclpy import; the bringup validates scenes with them).

The covariances are the diagonal entries of Q and R (see :mod:`relpos_estimator.kalman`).
``covariances: parameters`` (default) takes them from the ``sigma_*`` parameters, whose
defaults are the thesis's tuned values (Sec. 6.2); ``covariances: tuned`` takes them from
the package's ``share/relpos_estimator/config/estimator_tuned.yaml``, written by
``tethersim estimator tune`` on the UAV-surrogate reference bags (HPR #1, #2, heave-only;
bags/README.md); ``covariances: flight`` from ``config/estimator_flight.yaml``, measured by
``tethersim estimator measure`` on flight recordings (:mod:`relpos_estimator.noise`). The
tuned values were tuned with the UAV surrogate held still: they let the second channel's bias
absorb the accelerations of a flying UAV; the thesis's weigh the accelerometers so little
that a flying estimate is a dGPS extrapolation between fixes. The flight scenes use the
measured ones.
"""

from __future__ import annotations

from pathlib import Path

import yaml
from ament_index_python.packages import get_package_share_directory

from relpos_estimator.estimator import LogicConfig
from relpos_estimator.kalman import Covariances
from tether_common.parameters import ParamSpec


def tuned_file(name: str = 'tuned') -> Path:
    """The installed parameter file ``config/estimator_<name>.yaml`` of the estimator (tuned or flight)."""
    return Path(get_package_share_directory('relpos_estimator')) / 'config' / f'estimator_{name}.yaml'


def tuned_covariances(name: str = 'tuned') -> Covariances:
    """The covariances of :func:`tuned_file`."""
    section = yaml.safe_load(tuned_file(name).read_text(encoding='utf-8'))['/**']['ros__parameters']
    return Covariances(**{field: float(section[field]) for field in Covariances.names()})


_C = Covariances()
_L = LogicConfig()

_UNITS = {'sigma_z': 'm^2', 'sigma_zdot': '(m/s)^2', 'sigma_zddot': '(m/s^2)^2', 'sigma_mu1': '(m/s^2)^2',
          'sigma_mu2': '(m/s^2)^2', 'sigma_acc1': '(m/s^2)^2', 'sigma_acc2': '(m/s^2)^2', 'sigma_dgps': 'm^2'}

PARAMETERS: tuple[ParamSpec, ...] = (
    ParamSpec('rate', 100.0, 'filter rate (Sec. 4.4: 100 Hz); the IMU samples must come at this rate', 'Hz',
              low=1.0, high=1000.0, read_only=True),
    ParamSpec('dgps_rate', 4.0, 'nominal dGPS rate (sets the fix period of the jump limit)', 'Hz',
              low=0.1, high=100.0, read_only=True),
    ParamSpec('input_delay', 0.01, 'delay of the IMU inputs: tick t filters the samples stamped t - input_delay '
              '(the sensors node publishes a tick\'s samples one tick later)', 's', low=0.0, high=5.0,
              read_only=True),
    ParamSpec('fix_hold', _L.fix_hold, 'a fix is considered this long after its arrival stamp (so that it has '
              'reached the node whatever the load; it is fused at its time of fix)', 's', low=0.0, high=1.0,
              read_only=True),
    ParamSpec('covariances', 'parameters', 'where Q and R come from: parameters (the sigma_* parameters), tuned '
              '(config/estimator_tuned.yaml, written by tethersim estimator tune on the surrogate bags) or flight '
              '(config/estimator_flight.yaml, written by tethersim estimator measure on flight recordings); with '
              'tuned or flight the sigma_* are ignored', choices=('parameters', 'tuned', 'flight'), read_only=True),
    *(ParamSpec(name, float(getattr(_C, name)), f'{name}: diagonal entry of Q or R (Eq. 4.7, 4.9), tuned value '
                'of Sec. 6.2 by default', _UNITS[name], low=1e-30, high=1e12, read_only=True)
      for name in Covariances.names()),
    ParamSpec('min_status', _L.min_status, 'lowest DgpsFix status fused (4: RTK fixed)', low=0, high=4,
              read_only=True),
    ParamSpec('clock_tolerance', _L.clock_tolerance, 'how far a time of fix may lie after its arrival', 's',
              low=0.0, high=10.0, read_only=True),
    ParamSpec('max_age', _L.max_age, 'oldest arrival minus time of fix accepted (beyond: stale)', 's',
              low=0.0, high=60.0, read_only=True),
    ParamSpec('max_jump', _L.max_jump, 'largest altitude change between consecutive accepted fixes (Sec. 6.4)',
              'm', low=0.0, high=1000.0, read_only=True),
    ParamSpec('max_speed', _L.max_speed, 'relative vertical speed allowed on top of max_jump across a gap',
              'm/s', low=0.0, high=1000.0, read_only=True),
    ParamSpec('gate_chi2', _L.gate_chi2, 'NIS gate, chi-square with 1 degree of freedom (15.137: p = 0.9999)',
              low=0.0, high=1e6, read_only=True),
    ParamSpec('gate_max_std', _L.gate_max_std, 'cap on the predicted altitude std in the gate, so that it stays '
              'strict after a dropout', 'm', low=0.0, high=1000.0, read_only=True),
    ParamSpec('reacquire_after', _L.reacquire_after, 'consecutive consistent rejected fixes that reset the '
              'altitude to the fixes', low=1, high=1000, read_only=True),
    ParamSpec('history', _L.history, 'state history kept to fuse late fixes at their time of fix', 's',
              low=0.05, high=60.0, read_only=True),
)


def configs(params: dict) -> tuple[Covariances, LogicConfig]:
    """Covariances and message-logic settings of a parameter set."""
    cov = (tuned_covariances(params['covariances']) if params['covariances'] in ('tuned', 'flight')
           else Covariances(**{name: params[name] for name in Covariances.names()}))
    logic = LogicConfig(min_status=params['min_status'], clock_tolerance=params['clock_tolerance'],
                        max_age=params['max_age'], max_jump=params['max_jump'], max_speed=params['max_speed'],
                        gate_chi2=params['gate_chi2'], gate_max_std=params['gate_max_std'],
                        reacquire_after=params['reacquire_after'], history=params['history'],
                        fix_hold=params['fix_hold'])
    if logic.history < logic.max_age:
        raise ValueError(f'history {logic.history} s is shorter than max_age {logic.max_age} s')
    return cov, logic

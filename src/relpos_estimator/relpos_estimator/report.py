"""After-run report of the estimator: errors against the recorded truth beside thesis Table 6.1.

Reads ``/truth/relative``, ``/estimate/relative``, ``/estimate/foh``, ``/sensors/faults``
and ``/estimate/rejections`` from a bag, pairs estimate and truth by stamp, and reports the
mean absolute error and RMSE of the filter and of the FOH baseline from the first
initialized estimate on, the faults injected per kind and the rejections per reason.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from tether_bringup.bag_reader import read_bag  # noqa: E402
from tether_bringup.errors import BagError  # noqa: E402
from tether_common.report_figures import ReportLines  # noqa: E402

from relpos_estimator.messages import stamp_ns  # noqa: E402

THESIS_TABLE_6_1 = {
    'heave only': (0.00256, 0.00418, 0.00488, 0.00783),
    'HPR #1': (0.00135, 0.00239, 0.00280, 0.00439),
    'HPR #2': (0.00144, 0.00228, 0.00291, 0.00443),
    'zero motion': (0.00111, 0.00298, 0.0007, 0.0018),
}
"""Filter mean error, filter RMSE, FOH mean error, FOH RMSE (m), 4 Hz de-rated MoCap, no faults."""


def read_run(bag_path: Path) -> dict:
    """Truth, estimate and FOH altitudes by stamp, the faults and the rejections of a bag."""
    topics = ['/truth/relative', '/estimate/relative', '/estimate/foh', '/sensors/faults', '/estimate/rejections']
    try:
        bag = read_bag(bag_path, topics)
        truth, estimate, foh, faults, rejections = (bag.decoded(topic, required=False) for topic in topics)
    except BagError as error:
        raise ValueError(f'cannot read the bag: {error}') from None
    return {'truth': {stamp_ns(m.header.stamp): m.position.z for _, m in truth},
            'estimate': {stamp_ns(m.header.stamp): m.dz for _, m in estimate if m.initialized},
            'foh': {stamp_ns(m.header.stamp): m.dz for _, m in foh if m.initialized},
            'faults': [(m.sensor, m.kind_name, stamp_ns(m.header.stamp)) for _, m in faults],
            'rejections': [(m.reason_name, stamp_ns(m.fix_time)) for _, m in rejections]}


def errors(data: dict) -> dict[str, np.ndarray]:
    """Stamps and errors (m) of the filter and the FOH where truth and both outputs exist."""
    stamps = sorted(set(data['truth']) & set(data['estimate']) & set(data['foh']))
    truth = np.array([data['truth'][t] for t in stamps])
    return {'t': np.array(stamps) * 1e-9, 'truth': truth,
            'filter': np.array([data['estimate'][t] for t in stamps]) - truth,
            'foh': np.array([data['foh'][t] for t in stamps]) - truth}


def estimator_report(bag_path: str, out_dir: str) -> ReportLines:
    """Filter and FOH errors vs. truth, faults and rejections; writes estimator.png; returns summary lines, and as
    figures (data) the filter's and the FOH's Δz RMSE and largest error (m), faults injected and fixes rejected.
    """
    data = read_run(Path(bag_path))
    e = errors(data)
    if e['t'].size == 0:
        return ReportLines(['estimator: no initialized estimate with truth in the bag'], {})
    lines = [f'estimator vs truth over {e["t"][-1] - e["t"][0]:.1f} s ({e["t"].size} ticks):']
    for name in ('filter', 'foh'):
        err = e[name]
        lines.append(f'  {name:6s} mean |error| {np.mean(np.abs(err)) * 1000:.2f} mm, '
                     f'RMSE {np.sqrt(np.mean(err**2)) * 1000:.2f} mm, max {np.max(np.abs(err)) * 1000:.1f} mm')
    thesis = ', '.join(f'{k} {v[1] * 1000:.2f}/{v[3] * 1000:.2f}' for k, v in THESIS_TABLE_6_1.items())
    lines.append(f'  thesis Table 6.1 filter/FOH RMSE mm (4 Hz MoCap, no faults): {thesis}')
    faults = Counter(f'{s}:{k}' for s, k, _ in data['faults'])
    lines.append('  faults injected: ' + (', '.join(f'{k} {n}' for k, n in sorted(faults.items())) or 'none'))
    reasons = Counter(r for r, _ in data['rejections'])
    lines.append('  fixes rejected: ' + (', '.join(f'{k} {n}' for k, n in sorted(reasons.items())) or 'none'))
    fig, ax = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    ax[0].plot(e['t'], e['truth'], 'k', lw=1, label='truth')
    ax[0].plot(e['t'], e['truth'] + e['filter'], lw=0.8, label='filter')
    ax[0].plot(e['t'], e['truth'] + e['foh'], lw=0.8, label='FOH')
    ax[0].set_ylabel('relative altitude (m)')
    ax[0].legend(loc='upper right')
    ax[1].plot(e['t'], e['filter'] * 1000, lw=0.8, label='filter')
    ax[1].plot(e['t'], e['foh'] * 1000, lw=0.8, label='FOH')
    ax[1].set_ylabel('error (mm)')
    ax[1].set_xlabel('sim time (s)')
    ax[1].legend(loc='upper right')
    fig.tight_layout()
    fig.savefig(Path(out_dir) / 'estimator.png', dpi=110)
    plt.close(fig)
    figures = {f'{name}_dz_{kind}': value for name in ('filter', 'foh') for kind, value in
               (('rmse', np.sqrt(np.mean(e[name] ** 2))), ('max_error', np.max(np.abs(e[name]))))}
    return ReportLines(lines, {'dz_rmse': figures['filter_dz_rmse'], **figures,
                               'faults_injected': sum(faults.values()), 'fixes_rejected': sum(reasons.values())})

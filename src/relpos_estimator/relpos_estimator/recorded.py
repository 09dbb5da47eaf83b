"""Run the estimator directly on a recording's decoded sensor messages, and score it.

:func:`read_recording` decodes ``/imu/reel``, ``/imu/uav``, ``/dgps/fix``,
``/truth/relative`` and ``/sensors/faults`` of a bag with the same conversions the
estimator node applies (:mod:`relpos_estimator.messages`); :func:`replay` steps
:class:`~relpos_estimator.estimator.Estimator` over every reel-IMU tick exactly as the node
does (IMU samples by stamp, fixes handed over at their arrival stamp, which the core holds
for ``fix_hold``), and :func:`read_outputs` reads what the node itself published when the
recording was replayed to it (``tethersim replay``). :func:`score` gives the Table 6.1
figures against the recorded truth and, per fault kind, how many were injected, rejected
and fused and the largest shift of the estimate they caused: the run is repeated with the
kind's faulty dGPS messages replaced by clean ones carrying the fault's ground truth (a
missed message is put back), and the shift is the largest difference between the two.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from dataclasses import field
from dataclasses import replace
from pathlib import Path

import numpy as np
from tether_bringup.bag_reader import read_bag
from tether_bringup.errors import BagError

from relpos_estimator.estimator import Estimator
from relpos_estimator.messages import fix_from_message
from relpos_estimator.messages import imu_vertical
from relpos_estimator.messages import stamp_ns
from tether_models.dgps import Fix
from tether_models.dgps import STATUS_RTK_FIXED

TOPICS = ('/imu/reel', '/imu/uav', '/dgps/fix', '/truth/relative', '/sensors/faults')
CLEAN_LATENCY = 0.05
"""s, arrival delay of the clean fixes that stand in for faulty ones in the counterfactual run."""


@dataclass
class RecordedFault:
    """A /sensors/faults message."""

    sensor: str
    kind: str
    time: float
    fix_time: float
    sequence: int
    truth: np.ndarray


@dataclass
class Recording:
    """Decoded sensor inputs and truth of one bag."""

    name: str
    reel: dict[int, float] = field(default_factory=dict)
    uav: dict[int, float] = field(default_factory=dict)
    fixes: list[Fix] = field(default_factory=list)
    truth: dict[int, float] = field(default_factory=dict)
    truth_motion: dict[int, tuple[float, float]] = field(default_factory=dict)
    """stamp (ns) -> true relative vertical velocity (m/s) and acceleration (m/s^2)."""
    faults: list[RecordedFault] = field(default_factory=list)


def read_recording(bag: Path) -> Recording:
    """Decode one bag (file, bag directory or run directory)."""
    rec = Recording(name=Path(bag).name)
    try:
        recorded = read_bag(bag, list(TOPICS))
        for _, m in recorded.decoded('/imu/reel', required=False):
            rec.reel[stamp_ns(m.header.stamp)] = imu_vertical(m)
        for _, m in recorded.decoded('/imu/uav', required=False):
            rec.uav[stamp_ns(m.header.stamp)] = imu_vertical(m)
        rec.fixes = [fix_from_message(m) for _, m in recorded.decoded('/dgps/fix', required=False)]
        for _, m in recorded.decoded('/truth/relative', required=False):
            rec.truth[stamp_ns(m.header.stamp)] = m.position.z
            rec.truth_motion[stamp_ns(m.header.stamp)] = (m.velocity.z, m.acceleration.z)
        rec.faults = [RecordedFault(m.sensor, m.kind_name, stamp_ns(m.header.stamp) * 1e-9,
                                    stamp_ns(m.fix_time) * 1e-9, m.sequence, np.array([m.truth.x, m.truth.y, m.truth.z]))
                      for _, m in recorded.decoded('/sensors/faults', required=False)]
    except BagError as error:
        raise ValueError(f'cannot read the bag: {error}') from None
    if not rec.reel:
        raise ValueError(f'{bag}: no /imu/reel messages: not a recording of the sensors node')
    if not rec.truth:
        raise ValueError(f'{bag}: no /truth/relative messages: nothing to score against')
    return rec


@dataclass
class Outputs:
    """What the estimator produced over a recording, by filter tick."""

    ticks: dict[int, tuple[float, float, bool]]
    """stamp (ns) -> (filter dz, FOH dz, initialized)."""
    rejected: Counter
    """(sequence, time of fix in ns) -> how many fixes with that key were rejected."""


def _key(sequence: int, fix_time: float) -> tuple[int, int]:
    return sequence, int(round(fix_time * 1e9))


def replay(rec: Recording, estimator: Estimator, fixes: list[Fix] | None = None,
           input_delay: float = 0.0) -> Outputs:
    """Step ``estimator`` over the reel-IMU ticks as the node does; fixes are handed over at their arrival.

    The node runs filter tick t once the clock has reached t + ``input_delay``; replayed, the
    clock ends at the last message, so the ticks of the last ``input_delay`` are not run here either.
    """
    pending = sorted(rec.fixes if fixes is None else fixes, key=lambda f: (f.arrival, f.sequence))
    period = int(round(estimator.dt * 1e9))
    first, last = min(rec.reel), max(rec.reel) - int(round(input_delay * 1e9))
    out = Outputs({}, Counter())
    i = 0
    for t_ns in range(first, last + 1, period):
        t = t_ns * 1e-9
        due = []
        while i < len(pending) and pending[i].arrival <= t + 1e-9:
            due.append(pending[i])
            i += 1
        est = estimator.step(t, rec.reel.get(t_ns), rec.uav.get(t_ns), due)
        out.ticks[t_ns] = (float(est.x[0]), est.foh, est.initialized)
        for r in est.rejections:
            out.rejected[_key(r.sequence, r.fix_time)] += 1
    return out


def read_outputs(bag: Path) -> Outputs:
    """The estimator node's outputs recorded in a bag (``/estimate/relative``, ``/estimate/foh``, rejections)."""
    out = Outputs({}, Counter())
    try:
        recorded = read_bag(bag, ['/estimate/relative', '/estimate/foh', '/estimate/rejections'])
        estimate = {stamp_ns(m.header.stamp): m for _, m in recorded.decoded('/estimate/relative', required=False)}
        foh = {stamp_ns(m.header.stamp): m for _, m in recorded.decoded('/estimate/foh', required=False)}
        for _, m in recorded.decoded('/estimate/rejections', required=False):
            out.rejected[(m.sequence, stamp_ns(m.fix_time))] += 1
    except BagError as error:
        raise ValueError(f'cannot read the bag: {error}') from None
    if not estimate:
        raise ValueError(f'{bag}: no /estimate/relative messages')
    for t_ns, m in estimate.items():
        out.ticks[t_ns] = (m.dz, foh[t_ns].dz if t_ns in foh else math.nan, m.initialized)
    return out


def errors(rec: Recording, run: Outputs) -> dict[str, np.ndarray]:
    """Filter and FOH errors (m) at the ticks with truth and an initialized estimate and FOH."""
    ticks = run.ticks
    stamps = [t for t in sorted(ticks) if t in rec.truth and ticks[t][2] and math.isfinite(ticks[t][1])]
    truth = np.array([rec.truth[t] for t in stamps])
    return {'t': np.array(stamps) * 1e-9, 'filter': np.array([ticks[t][0] for t in stamps]) - truth,
            'foh': np.array([ticks[t][1] for t in stamps]) - truth}


def counterfactual_fixes(rec: Recording, kind: str) -> list[Fix]:
    """The recording's fixes with every dGPS fault of ``kind`` replaced by a clean fix carrying its truth."""
    faults = [f for f in rec.faults if f.sensor == 'dgps' and f.kind == kind]
    bad = {f.sequence for f in faults}
    fixes = [f for f in rec.fixes if f.sequence not in bad]
    if kind == 'duplicate':
        seen = set()
        fixes = []
        for f in rec.fixes:
            if (f.sequence, f.fix_time) not in seen:
                fixes.append(f)
            seen.add((f.sequence, f.fix_time))
        return fixes
    for fault in faults:
        if kind == 'late':
            original = next(x for x in rec.fixes if x.sequence == fault.sequence)
            fixes.append(replace(original, arrival=fault.fix_time + CLEAN_LATENCY))
        else:
            fixes.append(Fix(fault.fix_time + CLEAN_LATENCY, fault.fix_time, fault.truth.copy(), np.full(3, 0.01),
                             STATUS_RTK_FIXED, fault.sequence))
    return fixes


@dataclass
class Score:
    """Table 6.1 figures of one recording and the per-fault counts."""

    name: str
    test_time: float
    filter_mean: float
    filter_rmse: float
    foh_mean: float
    foh_rmse: float
    faults: dict[str, tuple[int, int, int, float]]
    """kind -> (injected, rejected, fused, largest estimate shift in m)."""


def score(rec: Recording, run: Outputs, make_estimator, counterfactuals: bool = True) -> Score:
    """Score the estimator's outputs ``run`` on the recording (see the module docstring).

    A faulty message counts as rejected when the estimator rejected it and as fused when it
    was considered (arrival plus the hold before the last tick) and not rejected; the
    shifts come from runs of ``make_estimator()`` with the counterfactual fixes.
    """
    e = errors(rec, run)
    if e['t'].size == 0:
        raise ValueError(f'{rec.name}: the estimator never initialized')
    last = max(run.ticks) * 1e-9
    hold = make_estimator().logic.fix_hold
    table: dict[str, tuple[int, int, int, float]] = {}
    for kind in sorted({f.kind for f in rec.faults}):
        faults = [f for f in rec.faults if f.kind == kind]
        if faults[0].sensor != 'dgps':
            table[f'{faults[0].sensor}:{kind}'] = (len(faults), len(faults), 0, math.nan)
            continue
        sequences = {f.sequence for f in faults}
        messages = Counter(_key(x.sequence, x.fix_time) for x in rec.fixes
                           if x.sequence in sequences and x.arrival + hold <= last + 1e-9)
        n_rejected = sum(min(n, run.rejected[key]) for key, n in messages.items())
        n_fused = sum(messages.values()) - n_rejected
        shift = math.nan
        if counterfactuals:
            other = replay(rec, make_estimator(), counterfactual_fixes(rec, kind)).ticks
            shift = max(abs(dz - other[t][0]) for t, (dz, _, ok) in run.ticks.items()
                        if ok and t in other and other[t][2])
        table[kind] = (len(faults), n_rejected, n_fused, shift)
    return Score(rec.name, float(e['t'][-1] - e['t'][0]), float(np.mean(np.abs(e['filter']))),
                 float(np.sqrt(np.mean(e['filter'] ** 2))), float(np.mean(np.abs(e['foh']))),
                 float(np.sqrt(np.mean(e['foh'] ** 2))), table)


def rmse(recs: list[Recording], make_estimator) -> float:
    """RMSE (m) of the filter against the truth over all recordings (Algorithm 1's cost)."""
    squares = [errors(rec, replay(rec, make_estimator()))['filter'] ** 2 for rec in recs]
    return float(np.sqrt(np.mean(np.concatenate(squares))))

"""Run the estimator directly on a recording's decoded sensor messages, and score it.

:func:`read_recording` decodes ``/imu/reel``, ``/imu/uav``, ``/dgps/fix``,
``/truth/relative`` and ``/sensors/faults`` of a bag with the same conversions the
estimator node applies (:mod:`relpos_estimator.messages`); :func:`replay` steps
:class:`~relpos_estimator.estimator.Estimator` over every reel-IMU tick exactly as the node
does (IMU samples by stamp, fixes by arrival stamp). :func:`score` gives the Table 6.1
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
from rosbags.highlevel import AnyReader
from rosbags.highlevel import AnyReaderError

from relpos_estimator.dgps import STATUS_RTK_FIXED
from relpos_estimator.dgps import Fix
from relpos_estimator.estimator import Estimator
from relpos_estimator.messages import fix_from_message
from relpos_estimator.messages import imu_vertical
from relpos_estimator.messages import stamp_ns

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
    faults: list[RecordedFault] = field(default_factory=list)


def read_recording(bag: Path) -> Recording:
    """Decode one bag (file, bag directory or run directory)."""
    path = Path(bag)
    if (path / 'bag').is_dir():
        path = path / 'bag'
    rec = Recording(name=Path(bag).name)
    try:
        with AnyReader([path]) as reader:
            connections = [c for c in reader.connections if c.topic in TOPICS]
            for connection, _, raw in reader.messages(connections=connections):
                m = reader.deserialize(raw, connection.msgtype)
                topic = connection.topic
                if topic == '/imu/reel':
                    rec.reel[stamp_ns(m.header.stamp)] = imu_vertical(m)
                elif topic == '/imu/uav':
                    rec.uav[stamp_ns(m.header.stamp)] = imu_vertical(m)
                elif topic == '/dgps/fix':
                    rec.fixes.append(fix_from_message(m))
                elif topic == '/truth/relative':
                    rec.truth[stamp_ns(m.header.stamp)] = m.position.z
                else:
                    rec.faults.append(RecordedFault(m.sensor, m.kind_name, stamp_ns(m.header.stamp) * 1e-9,
                                                    stamp_ns(m.fix_time) * 1e-9, m.sequence,
                                                    np.array([m.truth.x, m.truth.y, m.truth.z])))
    except (AnyReaderError, FileNotFoundError) as error:
        raise ValueError(f'{bag}: cannot read the bag: {error}') from None
    if not rec.reel:
        raise ValueError(f'{bag}: no /imu/reel messages: not a recording of the sensors node')
    if not rec.truth:
        raise ValueError(f'{bag}: no /truth/relative messages: nothing to score against')
    return rec


def replay(rec: Recording, estimator: Estimator, fixes: list[Fix] | None = None) -> dict[int, tuple]:
    """Step ``estimator`` over every reel-IMU tick; return {stamp: (dz, foh, initialized)}."""
    pending = sorted(rec.fixes if fixes is None else fixes, key=lambda f: (f.arrival, f.sequence))
    period = int(round(estimator.dt * 1e9))
    first, last = min(rec.reel), max(rec.reel)
    out = {}
    i = 0
    for t_ns in range(first, last + 1, period):
        t = t_ns * 1e-9
        due = []
        while i < len(pending) and pending[i].arrival <= t + 1e-9:
            due.append(pending[i])
            i += 1
        est = estimator.step(t, rec.reel.get(t_ns), rec.uav.get(t_ns), due)
        out[t_ns] = (float(est.x[0]), est.foh, est.initialized, est)
    return out


def errors(rec: Recording, run: dict[int, tuple]) -> dict[str, np.ndarray]:
    """Filter and FOH errors (m) at the ticks with truth and an initialized estimate."""
    stamps = [t for t in sorted(run) if t in rec.truth and run[t][2] and math.isfinite(run[t][1])]
    truth = np.array([rec.truth[t] for t in stamps])
    return {'t': np.array(stamps) * 1e-9, 'filter': np.array([run[t][0] for t in stamps]) - truth,
            'foh': np.array([run[t][1] for t in stamps]) - truth}


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
    for f in faults:
        if kind == 'late':
            original = next(x for x in rec.fixes if x.sequence == f.sequence)
            fixes.append(replace(original, arrival=f.fix_time + CLEAN_LATENCY))
        else:
            fixes.append(Fix(f.fix_time + CLEAN_LATENCY, f.fix_time, f.truth.copy(), np.full(3, 0.01),
                             STATUS_RTK_FIXED, f.sequence))
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


def score(rec: Recording, make_estimator, counterfactuals: bool = True) -> Score:
    """Run ``make_estimator()`` over the recording and score it (see the module docstring)."""
    run = replay(rec, make_estimator())
    e = errors(rec, run)
    if e['t'].size == 0:
        raise ValueError(f'{rec.name}: the estimator never initialized')
    rejected = Counter()
    fused = set()
    for value in run.values():
        est = value[3]
        for r in est.rejections:
            rejected[(r.sequence, r.fix_time)] += 1
        for f in est.fused:
            fused.add((f.sequence, f.fix_time))
    table: dict[str, tuple[int, int, int, float]] = {}
    for kind in sorted({f.kind for f in rec.faults}):
        faults = [f for f in rec.faults if f.kind == kind]
        if faults[0].sensor != 'dgps':
            table[f'{faults[0].sensor}:{kind}'] = (len(faults), len(faults), 0, math.nan)
            continue
        messages = [x for x in rec.fixes if x.sequence in {f.sequence for f in faults}]
        n_rejected = sum(1 for x in messages if (x.sequence, x.fix_time) in rejected)
        n_fused = sum(1 for x in messages if (x.sequence, x.fix_time) in fused)
        shift = math.nan
        if counterfactuals:
            other = replay(rec, make_estimator(), counterfactual_fixes(rec, kind))
            shift = max(abs(run[t][0] - other[t][0]) for t in run if run[t][2] and other[t][2])
        table[kind] = (len(faults), n_rejected, n_fused, shift)
    return Score(rec.name, float(e['t'][-1] - e['t'][0]), float(np.mean(np.abs(e['filter']))),
                 float(np.sqrt(np.mean(e['filter'] ** 2))), float(np.mean(np.abs(e['foh']))),
                 float(np.sqrt(np.mean(e['foh'] ** 2))), table)


def rmse(recs: list[Recording], make_estimator) -> float:
    """RMSE (m) of the filter against the truth over all recordings (Algorithm 1's cost)."""
    squares = [errors(rec, replay(rec, make_estimator()))['filter'] ** 2 for rec in recs]
    return float(np.sqrt(np.mean(np.concatenate(squares))))

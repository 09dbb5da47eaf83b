"""Run the sensor suite and the estimator together without ROS, tick by tick, as the two nodes do.

The nodes are thin wrappers of the same calls: the sensors node steps
:class:`~tether_models.sensor_suite.SensorSuite` with the truth of each tick, the estimator
node turns each IMU sample into its world-vertical acceleration
(:func:`~tether_models.imu.vertical_acceleration`) and steps
:class:`~relpos_estimator.estimator.Estimator` with the fixes that arrived in the tick.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from dataclasses import field

import numpy as np

from relpos_estimator.estimator import Estimate
from relpos_estimator.estimator import Estimator
from relpos_estimator.estimator import Rejection
from tether_models.dgps import Fault
from tether_models.imu import vertical_acceleration
from tether_models.sensor_suite import ImuSample
from tether_models.sensor_suite import SensorSuite
from tether_models.sensor_suite import Truth


def imu_vertical(sample: ImuSample | None) -> float | None:
    """World-vertical acceleration (m/s^2) of an IMU sample; None when there is none (NaN passes through)."""
    if sample is None:
        return None
    return vertical_acceleration(sample.quaternion, sample.accel)


@dataclass
class Trace:
    """Per-tick truth and outputs of one run."""

    t: list[float] = field(default_factory=list)
    truth: list[float] = field(default_factory=list)
    estimate: list[Estimate] = field(default_factory=list)
    faults: list[tuple[str, Fault]] = field(default_factory=list)
    rejections: list[Rejection] = field(default_factory=list)

    def arrays(self) -> dict[str, np.ndarray]:
        """t, truth dz, estimated dz, FOH dz, initialized flags as arrays."""
        return {
            't': np.array(self.t),
            'truth': np.array(self.truth),
            'dz': np.array([e.x[0] for e in self.estimate]),
            'foh': np.array([e.foh for e in self.estimate]),
            'initialized': np.array([e.initialized for e in self.estimate]),
        }


def run(truths: Iterable[tuple[float, Truth]], suite: SensorSuite, estimator: Estimator) -> Trace:
    """Step the suite and the estimator through ``(t, truth)`` pairs; return the trace."""
    trace = Trace()
    for t, truth in truths:
        out = suite.step(t, truth)
        est = estimator.step(t, imu_vertical(out.reel), imu_vertical(out.uav), out.fixes)
        trace.t.append(t)
        trace.truth.append(float(truth.relative_position[2]))
        trace.estimate.append(est)
        trace.faults.extend(out.faults)
        trace.rejections.extend(est.rejections)
    return trace

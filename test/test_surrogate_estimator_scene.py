"""The surrogate_estimator scene: the smart reel runs on the estimator's output, in lockstep, end to end."""

from __future__ import annotations

import math

import pytest

from tethersim_testing import tethersim

pytest.importorskip('rclpy')

from tether_bringup.bag_reader import read_bag  # noqa: E402


def _ns(msg) -> int:
    return msg.header.stamp.sec * 1_000_000_000 + msg.header.stamp.nanosec


def test_the_reel_follows_the_estimate(tmp_path):
    run = tmp_path / 'run'
    result = tethersim('run', 'surrogate_estimator', '--duration', '11', '--rate', 'max', '--out', str(run),
                       timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    bag = read_bag(run / 'bag')
    estimate = {_ns(m): m for _, m in bag.decoded('/estimate/relative')}
    truth = {_ns(m): m.position.z for _, m in bag.decoded('/truth/relative')}
    diagnostics = [m for _, m in bag.decoded('/reel/diagnostics')]
    assert len(estimate) >= 1090 and len(diagnostics) >= 540
    # each controller tick used the estimate of one tick earlier (input_delay 0.01 s), never the truth
    used = [(m.relative_height, estimate[_ns(m) - 10_000_000]) for m in diagnostics
            if _ns(m) - 10_000_000 in estimate and estimate[_ns(m) - 10_000_000].initialized]
    assert len(used) >= 500
    assert all(height == e.dz for height, e in used)
    assert any(e.dz != truth.get(_ns(e)) for _, e in used)
    assert all(math.isfinite(e.dz) for _, e in used)
    summary = (run / 'summary.txt').read_text()
    assert 'Table 6.2' in summary and 'RMSE 0.027 m' in summary

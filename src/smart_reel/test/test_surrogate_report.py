"""The surrogate report's table: a column for each run given, nothing for runs not given."""

from __future__ import annotations

from smart_reel.surrogate_report import _row


def test_one_run_gives_one_column():
    row = _row('safety trips', '', {'taut': '0'})
    assert row.split() == ['safety', 'trips', '0'] and '-' not in row


def test_columns_follow_catenary_taut_locked_whatever_the_order_given():
    row = _row('', 'thesis', {'locked': 'L', 'catenary': 'C'})
    assert row.split() == ['thesis', 'C', 'L']

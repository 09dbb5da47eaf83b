"""Print a run's recorded topics as the README's topic table: type, publisher → subscribers, rate, QoS.

The publishers, subscribers and offered reliability and durability come from the run's
``graph.yaml`` (written by the bringup once every node had joined the lockstep; ``recorder
(stream)`` for a topic the recorder takes from the node group's recording stream), the rates
from the bag: (messages − 1) over the span of their log times, which are their stamps. The
history depth is not discoverable, so the QoS column names only reliability and durability.
The time master's node is ``tethersim``; ``/lockstep/ack`` and the excluded topics are not
recorded and not listed.

Run:  ./tethersim-env python tools/topic_table.py RUN_DIR
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import yaml

from tether_bringup.bag_reader import read_bag


def qos_text(qos: list[dict]) -> str:
    """The offered QoS as the README writes it: ``reliable`` (``reliable, transient local`` when latched)."""
    words = []
    for profile in qos:
        text = profile['reliability'].replace('_', ' ')
        if profile['durability'] == 'transient_local':
            text += ', transient local'
        words.append(text)
    return ' / '.join(words)


def rate_hz(count: int, first_ns: int | None, last_ns: int | None) -> float:
    """Messages per second of sim time over the span of the log times (0 with fewer than two)."""
    if count < 2 or first_ns is None or last_ns is None or last_ns <= first_ns:
        return 0.0
    return (count - 1) / ((last_ns - first_ns) * 1e-9)


def topic_rows(run_dir: Path) -> list[tuple[str, str, str, str, str]]:
    """(topic, type, publisher → subscribers, rate, QoS) of every recorded topic, sorted by topic."""
    graph = yaml.safe_load((run_dir / 'graph.yaml').read_text())
    bag = read_bag(run_dir / 'bag')
    rows = []
    for name, topic in sorted(bag.topics.items()):
        entry = graph.get(name, {})
        publishers = ', '.join(entry.get('publishers', [])) or '?'
        readers = entry.get('subscribers', []) + (['recorder (stream)'] if entry.get('recorded') == 'stream' else [])
        subscribers = ', '.join(readers) or '-'
        rate = rate_hz(topic.count, topic.first_ns, topic.last_ns)
        rows.append((name, topic.type_name.replace('/msg/', '/'), f'{publishers} → {subscribers}',
                     f'{rate:.3g} Hz', qos_text(entry.get('qos', []))))
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('run', type=Path, help='a run directory of tethersim run (holds graph.yaml and bag/)')
    args = parser.parse_args(argv)
    if not (args.run / 'graph.yaml').is_file():
        print(f'topic_table: error: {args.run}: no graph.yaml (not a tethersim run directory?)', file=sys.stderr)
        return 2
    print('| topic | type | publisher → subscribers | rate | QoS |')
    print('|---|---|---|---|---|')
    for row in topic_rows(args.run):
        print('| ' + ' | '.join(row) + ' |')
    return 0


if __name__ == '__main__':
    sys.exit(main())

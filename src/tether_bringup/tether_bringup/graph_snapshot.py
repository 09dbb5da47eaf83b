"""The graph a run records, written to ``graph.yaml`` once every node has joined the lockstep.

Per topic: its type, the nodes publishing and subscribing it over DDS, the reliability and
durability its publishers offer (history depth is not part of DDS discovery, so it is not
listed), and how the run records it: ``dds`` (the recorder subscribes), ``stream`` (from the
node group's recording stream, :mod:`tether_common.record_stream`) or ``false``.
``tools/topic_table.py`` turns it and the bag into the README's topic table.
"""

from __future__ import annotations

from pathlib import Path

import yaml
from rclpy.node import Node

from tether_bringup.recorder_node import qos_record
from tether_common.lockstep import ACK_TOPIC


def graph_snapshot(node: Node, exclude: set[str], streamed: set[str] = frozenset()) -> dict:
    """Per topic of the graph ``node`` sees, sorted by name: type, publishers, subscribers, offered QoS, recorded
    (``streamed``: the topics the recorder takes from the node group's stream).
    """
    graph = {}
    for topic, types in sorted(node.get_topic_names_and_types()):
        publishers = node.get_publishers_info_by_topic(topic)
        offered = sorted({(q.reliability, q.durability) for q in (qos_record(info.qos_profile) for info in publishers)})
        graph[topic] = {
            'type': types[0] if len(types) == 1 else list(types),
            'publishers': sorted({info.node_name for info in publishers}),
            'subscribers': sorted({info.node_name for info in node.get_subscriptions_info_by_topic(topic)}),
            'qos': [{'reliability': reliability, 'durability': durability} for reliability, durability in offered],
            'recorded': ('stream' if topic in streamed else 'dds') if topic not in exclude and topic != ACK_TOPIC
            else False,
        }
    return graph


def write_graph(path: Path, node: Node, exclude: set[str], streamed: set[str] = frozenset()) -> None:
    """Write :func:`graph_snapshot` as YAML to ``path``."""
    path.write_text(yaml.safe_dump(graph_snapshot(node, exclude, streamed), sort_keys=False))

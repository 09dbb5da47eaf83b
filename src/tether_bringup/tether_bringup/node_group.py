"""The node group: a scene's nodes in one process, spun on one executor.

A message one node of the group publishes is handed to the others' subscriptions of its
topic inside the process, as their own copies, besides going over DDS to other processes
(:func:`tether_common.lockstep.link_in_process`): no shared-memory transport, no other
process to wake, no take by the executor. Its CDR bytes go to the recorder through a pipe
(:mod:`tether_common.record_stream`), and the recorder does not subscribe to a topic only
the group publishes. On this 2-core machine one process took
``outdoor_flight``'s seven nodes from 1.05 CPU s per simulated s in seven processes to 0.44
(README, "Throughput"). Each node stays a node of its own: its name, parameters, topics,
lockstep ack and recording are the same as in a process of its own, and so is every
recorded payload. The recorder stays a process of its own, so
the bag is finalized whatever happens to the group.

A node can join the group if its package registers its class under the ``tethersim.nodes``
entry points, named as its executable (:func:`node_classes`); the class takes rclpy's node
options (``cli_args``). The bringup writes the group's spec file (YAML) and starts
``nodes SPEC``::

    cpu_file: RUN/logs/nodes.cpu.yaml   # written at exit: lockstep callback CPU s per node
    record_fd: 5                        # the recorder's stream (a pipe's write end), -1 for none
    nodes:
      - {name: plant, package: tether_dynamics, executable: plant, params_file: RUN/params/plant.yaml}
"""

from __future__ import annotations

import sys
from collections.abc import Mapping
from importlib.metadata import EntryPoint
from pathlib import Path

import yaml

from tether_common.node_entry_points import node_entry_points

GROUP_NAME = 'nodes'
"""Name of the group's process in the run summary and of its log file."""
ENTRY_POINTS = 'tethersim.nodes'


def node_classes() -> Mapping[tuple[str, str], EntryPoint]:
    """The node classes that can join a group, by (package, executable); read from metadata, nothing imported."""
    return node_entry_points(ENTRY_POINTS)


def write_spec(path: Path, cpu_file: Path, members: list[tuple[str, str, str, Path]], record_fd: int = -1) -> None:
    """Write the group's spec: ``members`` are (name, package, executable, parameter file); ``record_fd`` the
    write end of the recorder's stream in the group's process (-1: none).
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    nodes = [{'name': name, 'package': package, 'executable': executable, 'params_file': str(params)}
             for name, package, executable, params in members]
    path.write_text(yaml.safe_dump({'cpu_file': str(cpu_file), 'record_fd': record_fd, 'nodes': nodes},
                                   sort_keys=False))


def read_cpu(path: Path) -> dict[str, float]:
    """The lockstep callback CPU s per node the group wrote at exit (empty if it wrote none)."""
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError):
        return {}
    return {str(name): float(seconds) for name, seconds in data.items()} if isinstance(data, dict) else {}


def _factory(entry: EntryPoint, name: str, params_file: str):
    def build():
        return entry.load()(cli_args=['--ros-args', '-r', f'__node:={name}', '--params-file', params_file])
    return build


def main() -> None:
    """Run the nodes of the spec file given as the only argument.

    rclpy is imported here, not with the module: scene validation reads :data:`GROUP_NAME`
    without loading ROS.
    """
    from tether_common.lockstep import callback_cpu
    from tether_common.node_main import run_nodes
    from tether_common.record_stream import StreamWriter
    if len(sys.argv) != 2:
        print(f'{Path(sys.argv[0]).name}: error: expected one argument, the group\'s spec file', file=sys.stderr)
        sys.exit(2)
    spec = yaml.safe_load(Path(sys.argv[1]).read_text())
    classes = node_classes()
    factories = {}
    for member in spec['nodes']:
        entry = classes.get((member['package'], member['executable']))
        if entry is None:
            print(f'{member["name"]}: error: {member["package"]}/{member["executable"]} registers no class under '
                  f'{ENTRY_POINTS}', file=sys.stderr)
            sys.exit(2)
        factories[member['name']] = _factory(entry, member['name'], member['params_file'])
    record_fd = int(spec.get('record_fd', -1))
    status = run_nodes(factories, [sys.argv[0]], record=StreamWriter(record_fd) if record_fd >= 0 else None)
    cpu = {name.lstrip('/'): round(seconds, 6) for name, seconds in callback_cpu().items()}
    Path(spec['cpu_file']).write_text(yaml.safe_dump(cpu, sort_keys=False))
    sys.exit(status)

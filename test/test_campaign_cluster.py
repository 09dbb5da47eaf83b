"""``tethersim sweep --address``: a two-node Ray cluster on this machine, started as a user starts one on two.

The head (``ray start --head``) and a second node (``ray start --address``, with a resource of
its own) each offer one CPU, so the campaign's two runs, one CPU each, run at once on both. The
cluster is private to the test: its own temporary directory, ports, authentication token and
the loopback address; each node is started with ``--block`` and stopped with SIGTERM, which
stops that node's processes (``ray stop`` would stop every Ray instance on the machine, other
people's too). Every process the nodes started is watched, and none may be left.
"""

from __future__ import annotations

import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import psutil
import pyarrow.parquet as pq
from campaign_testing import ProcessWatch
from campaign_testing import write_spec
from tethersim_testing import tethersim

RAY = str(Path(sys.executable).parent / 'ray')
HOST = '127.0.0.1'


def _free_ports(count: int) -> list[int]:
    sockets = [socket.socket() for _ in range(count)]
    for sock in sockets:
        sock.bind((HOST, 0))
    ports = [sock.getsockname()[1] for sock in sockets]
    for sock in sockets:
        sock.close()
    return ports


def _start_node(arguments: list[str], env: dict, log: Path) -> subprocess.Popen:
    """``ray start --block ARGUMENTS`` with ports of its own; returns once the node is up."""
    ports = _free_ports(6)
    command = [RAY, 'start', '--block', '--node-ip-address', HOST, '--num-cpus', '1',
               '--object-store-memory', str(100 * 2**20), '--disable-usage-stats',
               '--node-manager-port', str(ports[0]), '--object-manager-port', str(ports[1]),
               '--dashboard-agent-listen-port', str(ports[2]), '--dashboard-agent-grpc-port', str(ports[3]),
               '--metrics-export-port', str(ports[4]), '--runtime-env-agent-port', str(ports[5]), *arguments]
    with open(log, 'wb') as file:
        node = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=file, stderr=subprocess.STDOUT, env=env)
    deadline = time.monotonic() + 300
    while 'Ray runtime started' not in log.read_text(errors='replace'):
        assert node.poll() is None, log.read_text(errors='replace')
        assert time.monotonic() < deadline, f'the Ray node did not start within 300 s: {log.read_text()}'
        time.sleep(0.5)
    return node


def _stop_node(node: subprocess.Popen) -> None:
    if node.poll() is None:
        node.send_signal(signal.SIGTERM)
        try:
            node.wait(120)
        except subprocess.TimeoutExpired:
            for child in psutil.Process(node.pid).children(recursive=True):
                child.kill()
            node.kill()
            node.wait()


def test_a_campaign_through_address_runs_on_both_nodes_of_a_cluster(tmp_path):
    temp_dir = Path(tempfile.mkdtemp(prefix='tethersim-raycluster-'))
    env = dict(os.environ, RAY_AUTH_MODE='token', RAY_AUTH_TOKEN=secrets.token_hex(32), RAY_USAGE_STATS_ENABLED='0')
    port, = _free_ports(1)
    nodes: list[subprocess.Popen] = []
    watches: list[ProcessWatch] = []
    try:
        nodes.append(_start_node(['--head', '--port', str(port), '--include-dashboard', 'false', '--node-name', 'head-node', '--temp-dir',
                                  str(temp_dir)], env, tmp_path / 'head.log'))
        watches.append(ProcessWatch(nodes[-1].pid))
        nodes.append(_start_node(['--address', f'{HOST}:{port}', '--node-name', 'second-node', '--resources',
                                  '{"second_node": 1}', '--temp-dir', str(temp_dir)], env, tmp_path / 'second.log'))
        watches.append(ProcessWatch(nodes[-1].pid))
        spec = write_spec(tmp_path / 'two.yaml', description='two short runs', scene='platform', count=2,
                          set={'duration': 2.0, 'rate': 'max'}, random={'platform.seed': {'range': [1, 1000]}})
        out = tmp_path / 'campaign'
        result = tethersim('sweep', str(spec), '--out', str(out), '--address', f'{HOST}:{port}', env=env, timeout=600)
        assert result.returncode == 0, result.stderr
        assert 'on 2 Ray node(s) with 2 CPUs' in result.stderr
        rows = pq.read_table(out / 'results.parquet').to_pylist()
        assert [row['status'] for row in rows] == ['ok', 'ok']
        assert sorted(row['node'] for row in rows) == ['head-node', 'second-node']
        assert len({row['node_id'] for row in rows}) == 2
        assert all((out / 'runs' / row['run'] / 'bag' / 'bag_0.mcap').is_file() for row in rows)
    finally:
        for node in reversed(nodes):
            _stop_node(node)
        shutil.rmtree(temp_dir, ignore_errors=True)
    left = [line for watch in watches for line in watch.left_behind()]
    assert left == []
    named = [p.pid for p in psutil.process_iter(['cmdline']) if str(temp_dir) in ' '.join(p.info['cmdline'] or [])]
    assert named == []

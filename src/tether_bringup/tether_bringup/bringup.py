"""Run a scene: its nodes in one process (the node group) or each in its own, sim time from the bringup, one bag.

Sequence: the recorder starts first and waits until every node of the scene is in the
graph and subscribed to; then /clock starts, once every node has subscribed to it and
joined the lockstep, so the bag holds all topics from the first message. /clock advances
in lockstep (:mod:`tether_bringup.barrier`): the next value is published once every node
and the recorder have acked the value ``lockstep_window`` before it, and no sooner than the
requested real-time factor allows (``rate: max``: as soon as they have). Within the window a
node runs the ticks whose inputs have arrived, so nodes on different cores overlap their
work instead of taking turns; what each tick selects is fixed by stamps, not by the window. The run ends at the scene's duration,
on Ctrl-C or SIGTERM, or when a node dies; in every case the nodes are stopped, the
recorder stops last and finalizes the bag, and no process is left behind.

Every node whose package registers its class (:mod:`tether_bringup.node_group`) runs in
the node group, unless the scene says ``compose: false``; the others (external simulators'
bridges, test doubles, scripts) and the recorder run in processes of their own. The bringup
opens a pipe from the group to the recorder, the group's recording stream
(:mod:`tether_common.record_stream`), and keeps neither end.
"""

from __future__ import annotations

import importlib
import json
import os
import resource
import signal
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import rclpy
import yaml
from ament_index_python.packages import get_package_prefix
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from tether_bringup.bag_info import describe_bag
from tether_bringup.bag_recover import recover_bag
from tether_bringup.bag_reader import read_bag
from tether_bringup.bag_reader import resolve_bag
from tether_bringup.barrier import Barrier
from tether_bringup.environment import run_environment
from tether_bringup.errors import BagError
from tether_bringup.errors import GraphConflictError
from tether_bringup.errors import RunDirectoryError
from tether_bringup.errors import RunError
from tether_bringup.graph_snapshot import write_graph
from tether_bringup.live_server import live_lines
from tether_bringup.machine_load import CoreTimes
from tether_bringup.machine_load import core_times
from tether_bringup.machine_load import shares
from tether_bringup.node_group import GROUP_NAME
from tether_bringup.node_group import node_classes
from tether_bringup.node_group import read_cpu
from tether_bringup.node_group import write_spec
from tether_bringup.processes import ChildProcess
from tether_bringup.recorder_node import streamed_topics
from tether_bringup.recorder_params import DEFAULT_EXCLUDE
from tether_bringup.scene import LOCKSTEP_WINDOW
from tether_bringup.scene import NodeConfig
from tether_bringup.sim_clock import rate_text
from tether_common.lockstep import END_VARIABLE
from tether_common.lockstep import NODES_VARIABLE
from tether_common.lockstep import RECORDER_READY_VARIABLE
from tether_common.node_main import make_executor
from tether_common.record_stream import open_pipe
from tether_common.report_figures import scalar

READY_TIMEOUT = 180.0
"""Start-up: nine Python node processes importing numpy, scipy and rclpy on a loaded 2-core machine take minutes."""
STALL_TIMEOUT = 120.0
"""No ack from anyone for this long ends the run: generous, for ticks on a loaded machine with every core busy."""
EXTERNAL_READY_TIMEOUT = 600.0
CLOCK_SUBSCRIBER_TIMEOUT = 30.0
PROGRESS_PERIOD = 0.5
LIVE_STATS = 'live.yaml'
"""The live server's URL and, after the run, its statistics, in the run directory."""
FIGURES_FILE = 'figures.json'
"""The run's figures as data in its directory: the run's own (:func:`_run_figures`) and its reports'."""


@dataclass
class RunOptions:
    """Where and how a run happens."""

    out_dir: Path
    domain_id: int
    discovery: str = 'localhost'
    exclude: tuple[str, ...] = DEFAULT_EXCLUDE
    reports: tuple[str, ...] = ()
    title: str = ''
    lockstep_window: float = LOCKSTEP_WINDOW
    compose: bool = True
    live: tuple[str, int] | None = None
    """(host, port) of the live Foxglove WebSocket server in the recorder (:mod:`tether_bringup.live_server`)."""
    live_wait: bool = False
    """Start the clock only once a client has subscribed to the live server."""


class _Stop(Exception):
    def __init__(self, signum: int) -> None:
        self.signum = signum


def _on_signal(signum, frame):
    raise _Stop(signum)


def execute(nodes: list[NodeConfig], source, options: RunOptions) -> int:
    """Run ``nodes`` with ``source`` driving /clock; return the process exit status."""
    out = options.out_dir
    if any((out / 'bag').glob('*.mcap')):
        raise RunDirectoryError(f'{out}: this run directory already holds a bag; give another --out')
    out.mkdir(parents=True, exist_ok=True)
    env = run_environment(options.domain_id, options.discovery, str(out / 'logs' / 'ros'))
    env[NODES_VARIABLE] = ','.join(['tethersim', 'recorder'] + [config.name for config in nodes])
    env[END_VARIABLE] = f'{source.end_time:.9f}'
    ready_file = out / 'recorder.ready'
    ready_file.unlink(missing_ok=True)
    env[RECORDER_READY_VARIABLE] = str(ready_file)
    os.environ.update({key: env[key] for key in ('ROS_DOMAIN_ID', 'ROS_AUTOMATIC_DISCOVERY_RANGE', 'ROS_LOG_DIR')})
    os.environ.pop('ROS_LOCALHOST_ONLY', None)

    previous = {sig: signal.signal(sig, _on_signal) for sig in (signal.SIGINT, signal.SIGTERM)}
    children: list[ChildProcess] = []
    recorder: ChildProcess | None = None
    status = 0
    failure: str | None = None
    wall_start = time.monotonic()
    cpu = RunCpu()
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = Node('tethersim')
    executor = make_executor()
    executor.add_node(node)
    barrier = Barrier(node, [f'/{config.name}' for config in nodes if config.lockstep] + ['/recorder'])
    stream: tuple[int, int] | None = None
    try:
        source.attach(node)
        grouped = _grouped(nodes) if options.compose else []
        stream = open_pipe() if grouped else None
        recorder = _start(out, env, NodeConfig(
            name='recorder', command=[_bringup_program('recorder')],
            parameters={'bag_directory': str(out / 'bag'), 'ready_file': str(ready_file),
                        'expected_nodes': [n.name for n in nodes] + ['tethersim'],
                        'exclude': list(options.exclude),
                        'stream_fd': stream[0] if stream else -1,
                        'stream_nodes': [f'/{config.name}' for config in grouped], **_live_parameters(options, out)}),
                          pass_fds=stream[:1] if stream else ())
        children.append(recorder)
        for config in nodes:
            if config.external:
                _write_params(out, config)
            elif config not in grouped:
                children.append(_start(out, env, config))
        if stream is not None:
            children.append(_start_group(out, env, grouped, stream[1]))
            _close_stream(stream)
            stream = None
        external = [config.name for config in nodes if config.external]
        waiting = f' and the external node(s) {", ".join(external)}' if external else ''
        _progress(f'{options.title}: {len(nodes) - len(external)} node(s) started in {len(children) - 1} process(es), '
                  f'waiting for the recorder{waiting} (ROS_DOMAIN_ID={env["ROS_DOMAIN_ID"]})')
        if options.live is not None:
            _wait_for(lambda: (out / LIVE_STATS).exists(), READY_TIMEOUT, children, executor,
                      lambda: 'the recorder did not start the live server within {:.0f} s')
            _progress(f'{options.title}: live view on {yaml.safe_load((out / LIVE_STATS).read_text())["url"]}'
                      + (': the clock starts once a client subscribes' if options.live_wait else ''))
        _wait_for(lambda: ready_file.exists(),
                  EXTERNAL_READY_TIMEOUT if external or options.live_wait else READY_TIMEOUT, children, executor,
                  lambda: 'the recorder did not subscribe to every node' + (' and no live client subscribed'
                                                                            if options.live_wait else '')
                  + ' within {:.0f} s')
        expected = len(nodes) + 1
        _wait_for(lambda: source.clock_publisher.get_subscription_count() >= expected and source.matched(node),
                  CLOCK_SUBSCRIBER_TIMEOUT, children, executor,
                  lambda: 'not every node subscribed to /clock and the replayed topics within {:.0f} s')
        _wait_for(lambda: barrier.reached(0), READY_TIMEOUT, children, executor,
                  lambda: f'{", ".join(barrier.behind(0))} did not join the lockstep within {{:.0f}} s '
                          '(a node joins once each of its inputs has a publisher)')
        contested = source.contested(node)
        if contested:
            raise GraphConflictError('replayed topic(s) published by the scene\'s own nodes too, refused (two sources '
                                     'of one topic): ' + '; '.join(f'{topic} by {", ".join(nodes)}'
                                                                    for topic, nodes in sorted(contested.items())))
        write_graph(out / 'graph.yaml', node, set(options.exclude), streamed_topics(ready_file))
        failure = _advance(source, barrier, children, executor, options, cpu)
        if failure:
            status = 1
    except _Stop as stop:
        status = 128 + stop.signum
        failure = f'interrupted by {signal.Signals(stop.signum).name} at sim time {source.sim_time:.2f} s'
    except RunError as error:
        status = error.exit_status
        failure = str(error)
    finally:
        if stream is not None:
            _close_stream(stream)
        source.clock.stop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, signal.SIG_IGN)
        time.sleep(0.2)
        for child in reversed(children):
            if child is not recorder:
                child.stop()
        if recorder is not None:
            recorder.stop(timeout=30.0)
        executor.remove_node(node)
        node.destroy_node()
        rclpy.try_shutdown()

    late = None if failure else _failed_when_stopped(children)
    if late:
        status, failure = 1, late
    wall = time.monotonic() - wall_start
    lines = _summary(options, source, children, wall, failure, cpu, read_cpu(out / 'logs' / f'{GROUP_NAME}.cpu.yaml'))
    lines += live_lines(out / LIVE_STATS) if options.live is not None else []
    figures: dict = {}
    if recorder is not None and recorder.returncode not in (0, None) and status == 0:
        status = 1
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, _on_signal)
    status = _finish(out, options.reports, lines, status, figures)
    text = '\n'.join(lines) + '\n'
    (out / 'summary.txt').write_text(text)
    _write_figures(out / FIGURES_FILE, _run_figures(source, children, wall, failure, cpu, status), figures)
    print(text, end='', flush=True)
    if failure:
        print(f'tethersim: error: {failure}', file=sys.stderr, flush=True)
    for sig, handler in previous.items():
        signal.signal(sig, handler)
    return status


def _live_parameters(options: RunOptions, out: Path) -> dict:
    """The recorder's parameters of the live server (none without one)."""
    if options.live is None:
        return {}
    return {'live_host': options.live[0], 'live_port': options.live[1], 'live_stats_file': str(out / LIVE_STATS),
            'live_wait': options.live_wait}


def _finish(out: Path, reports: tuple[str, ...], lines: list[str], status: int, figures: dict) -> int:
    """Verify the recorded bag, recover it if damaged, run the reports; add their lines and their figures (data) to
    ``figures``; return the exit status.

    The bag the recorder finalized is read whole (:func:`tether_bringup.bag_reader.read_bag`:
    every chunk's CRC, the data section's and the summary's): ``bag verified``, or the run
    fails and the damaged bag is rewritten with what is intact, saying what was dropped. A
    SIGINT or SIGTERM in this phase (the caller installs :func:`_on_signal`) stops it; the
    lines say what was not done. Signals are ignored once this returns.
    """
    step = ['verifying the bag']
    try:
        status = _verify_and_report(out, reports, lines, status, step, figures)
    except _Stop as stop:
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, signal.SIG_IGN)
        name = signal.Signals(stop.signum).name
        lines.append(f'interrupted by {name} while {step[0]}: ' + (
            'the bag is not verified and no report was run' if step[0] == 'verifying the bag' else
            'the lines above are all the reports did'))
        status = status or 128 + stop.signum
    finally:
        for sig in (signal.SIGINT, signal.SIGTERM):
            signal.signal(sig, signal.SIG_IGN)
    lines += [f'plot: {png}' for png in sorted(out.glob('*.png'))]
    return status


def _verify_and_report(out: Path, reports: tuple[str, ...], lines: list[str], status: int, step: list[str],
                       figures: dict) -> int:
    bag_dir = out / 'bag'
    if not any(bag_dir.glob('*.mcap')):
        return status
    try:
        bag = read_bag(bag_dir, allow_damaged=True)
        recovery = None if bag.complete else recover_bag(bag_dir)
    except BagError as error:
        lines.append(f'no recording: {error}')
        return status or 1
    if recovery is None:
        lines.append(f'bag verified: {bag.checked_line()}')
        lines += describe_bag(bag)
    else:
        lines.append(f'bag verification FAILED: damaged at {bag.damage_line()}')
        lines.append(recovery.line())
        lines += describe_bag(read_bag(bag_dir))
        status = status or 1
    step[0] = 'running the reports'
    report_failed = _reports(reports, bag_dir, out, lines, figures)
    return 1 if report_failed and status == 0 else status


def _bringup_program(name: str) -> str:
    """Path of one of tether_bringup's own executables (the recorder, the node group)."""
    return str(Path(get_package_prefix('tether_bringup')) / 'lib' / 'tether_bringup' / name)


def _write_params(out: Path, config: NodeConfig) -> Path:
    """Write the node's parameter file into the run directory; return its path."""
    path = out / 'params' / f'{config.name}.yaml'
    path.parent.mkdir(parents=True, exist_ok=True)
    params = {'/**': {'ros__parameters': {**config.parameters, 'use_sim_time': config.name != 'recorder'}}}
    path.write_text(yaml.safe_dump(params, sort_keys=False))
    return path


def _start(out: Path, env: dict[str, str], config: NodeConfig, pass_fds: tuple[int, ...] = ()) -> ChildProcess:
    params_file = _write_params(out, config)
    command = config.command + ['--ros-args', '-r', f'__node:={config.name}', '--params-file', str(params_file)]
    return ChildProcess(config.name, command, out / 'logs' / f'{config.name}.log', env, pass_fds=pass_fds)


def _close_stream(stream: tuple[int, int]) -> None:
    """Close the bringup's copies of the recorder's stream: the group holds the write end, the recorder the
    read end, and the recorder reads the stream's end once the group has exited.
    """
    for fd in stream:
        os.close(fd)


def _grouped(nodes: list[NodeConfig]) -> list[NodeConfig]:
    """The nodes that run in the node group: started by the bringup, their class registered."""
    classes = node_classes()
    return [config for config in nodes if not config.external and (config.package, config.executable) in classes]


def _start_group(out: Path, env: dict[str, str], grouped: list[NodeConfig], record_fd: int) -> ChildProcess:
    spec = out / 'params' / f'{GROUP_NAME}.yaml'
    write_spec(spec, out / 'logs' / f'{GROUP_NAME}.cpu.yaml', [
        (config.name, config.package, config.executable, _write_params(out, config)) for config in grouped],
        record_fd)
    return ChildProcess(GROUP_NAME, [_bringup_program(GROUP_NAME), str(spec)], out / 'logs' / f'{GROUP_NAME}.log', env,
                        members=tuple(config.name for config in grouped), pass_fds=(record_fd,))


def _check_children(children: list[ChildProcess]) -> None:
    for child in children:
        code = child.poll()
        if code is not None and not child.stop_requested:
            raise RunError(_death(child, 'died'))


def _death(child: ChildProcess, how: str) -> str:
    """A child's end in words: its exit status and its cause first (its last error line), then its last lines."""
    which = f'node {child.name}' if child.members == (child.name,) else \
        f'node group {child.name} ({", ".join(child.members)})'
    cause = next((line for line in reversed(child.tail(10)) if '[ERROR]' in line or ': error: ' in line), '')
    cause = cause.rpartition(']: ')[2] if '[ERROR]' in cause else cause
    return (f'{which} {how} with exit status {child.returncode}' + (f': {cause}' if cause else '')
            + f'; {_log_tail(child, 10)}')


def _log_tail(child: ChildProcess, count: int) -> str:
    """``last lines of LOG:`` and its last ``count`` lines indented, or that the log is empty."""
    tail = child.tail(count)
    if not any(line.strip() for line in tail):
        return f'its log {child.log_path} is empty (it wrote nothing before it ended)'
    return f'last lines of {child.log_path}:\n' + '\n'.join(f'    {line}' for line in tail)


def _failed_when_stopped(children: list[ChildProcess]) -> str | None:
    """A node that, asked to stop at the end, exited with a status of its own other than 0 (the sitl node
    finding its autopilot dead): the run failed, with the node's cause.
    """
    for child in children:
        if child.stop_requested and child.returncode is not None and child.returncode > 0:
            return _death(child, 'ended')
    return None


def _wait_for(condition, timeout: float, children, executor, message) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        _check_children(children)
        if time.monotonic() > deadline:
            raise RunError(message().format(timeout))
        executor.spin_once(timeout_sec=0.05)


def _wait_for_barrier(barrier: Barrier, time_ns: int, children, executor) -> None:
    """Spin until every member acked ``time_ns``; fail if none makes progress for STALL_TIMEOUT."""
    if barrier.reached(time_ns):
        return
    acks = barrier.acks
    last_progress = time.monotonic()
    while not barrier.reached(time_ns):
        executor.spin_once(timeout_sec=0.5)
        if barrier.acks != acks:
            acks = barrier.acks
            last_progress = time.monotonic()
            continue
        _check_children(children)
        if time.monotonic() - last_progress > STALL_TIMEOUT:
            behind = barrier.behind(time_ns)
            tails = '; '.join(_log_tail(child, 5) for child in children
                              if any(f'/{member}' in behind for member in child.members))
            raise RunError(f'lockstep stalled at sim time {time_ns / 1e9:.3f} s: no ack from '
                           f'{", ".join(behind)} within {STALL_TIMEOUT:.0f} s' + (f'; {tails}' if tails else ''))


class RunCpu:
    """CPU seconds of each process (``tethersim`` and the children) at the first tick and once the last is acked.

    Their difference over the simulated time is a process's CPU per simulated second,
    without its start-up and shutdown, and independent of what else loads the machine. The
    same for each process's main thread, the one that runs Python (rclpy's executor and the
    nodes' callbacks) and so uses at most one core whatever the DDS threads beside it do. And
    the machine's cores' times at the same marks (:mod:`tether_bringup.machine_load`).
    """

    def __init__(self) -> None:
        self.start: dict[str, tuple[float, float]] = {}
        self.end: dict[str, tuple[float, float]] = {}
        self.sim_time = 0.0
        self.machine_start: CoreTimes | None = None
        self.machine_end: CoreTimes | None = None

    def mark_start(self, children: list[ChildProcess]) -> None:
        """The first tick: each process's CPU and the machine's cores' times."""
        self.start, self.machine_start = self.sample(children), core_times()

    def mark_end(self, children: list[ChildProcess]) -> None:
        """The last ack: each process's CPU and the machine's cores' times."""
        self.end, self.machine_end = self.sample(children), core_times()

    @staticmethod
    def sample(children: list[ChildProcess]) -> dict[str, tuple[float, float]]:
        """(process, main thread) CPU s of ``tethersim`` and of each running child."""
        own = resource.getrusage(resource.RUSAGE_SELF)
        thread = resource.getrusage(resource.RUSAGE_THREAD)
        cpu = {'tethersim': (own.ru_utime + own.ru_stime, thread.ru_utime + thread.ru_stime)}
        for child in children:
            now, main = child.cpu_now(), child.cpu_now(main_thread=True)
            if now is not None and main is not None:
                cpu[child.name] = (now, main)
        return cpu

    def per_sim_second(self, name: str, main_thread: bool = False) -> float | None:
        """CPU s per simulated s of one process (or its main thread) between the marks, or None without both."""
        if name not in self.start or name not in self.end or self.sim_time <= 0:
            return None
        which = 1 if main_thread else 0
        return (self.end[name][which] - self.start[name][which]) / self.sim_time


def _advance(source, barrier: Barrier, children: list[ChildProcess], executor, options: RunOptions,
             cpu: RunCpu) -> str | None:
    """Publish /clock step by step, each once the barrier has reached the window behind it; then wait for the last."""
    cpu.mark_start(children)
    start_time = source.sim_time
    window_ns = round(options.lockstep_window * 1e9)
    next_check = time.monotonic()
    interactive = sys.stderr.isatty()
    last_line = 0.0
    while True:
        try:
            _wait_for_barrier(barrier, source.published_ns - window_ns, children, executor)
        except RunError as error:
            return str(error)
        if not source.step():
            break
        now = time.monotonic()
        if now >= next_check:
            next_check = now + PROGRESS_PERIOD
            try:
                _check_children(children)
            except RunError as error:
                return str(error)
            if interactive or now - last_line >= 5.0:
                last_line = now
                _progress(f'{options.title}: sim {source.sim_time:8.2f} / {source.duration:.2f} s'
                          f'   real-time factor {source.achieved_rate():6.2f}', interactive)
    if interactive:
        print(file=sys.stderr)
    try:
        _wait_for_barrier(barrier, source.published_ns, children, executor)
    except RunError as error:
        return str(error)
    cpu.mark_end(children)
    cpu.sim_time = source.sim_time - start_time
    return None


def _progress(text: str, interactive: bool = False) -> None:
    print(('\r' if interactive else '') + text, end='' if interactive else '\n', file=sys.stderr, flush=True)


def _summary(options: RunOptions, source, children, wall: float, failure: str | None, cpu: RunCpu,
             group_cpu: dict[str, float]) -> list[str]:
    """The run's lines: what was simulated, and the CPU of each process.

    Under the node group, each node's lockstep callbacks (``group_cpu``); the rest of the
    group's CPU is rclpy's executor taking and converting messages and Fast DDS's threads.
    """
    lines = [
        f'{options.title}',
        f'simulated {source.sim_time:.2f} s of {source.duration:.2f} s in {wall:.1f} s wall, start-up included; '
        f'achieved real-time factor {source.achieved_rate():.2f} from the first tick '
        f'(requested {rate_text(source.clock.rate)})',
    ]
    if failure:
        lines.append(f'ended early: {failure.splitlines()[0]}')
    lines.append(f'{"node":<20} {"exit":>5} {"cpu s":>8} {"cpu s/sim s":>12} {"peak RSS MB":>12}')
    own = resource.getrusage(resource.RUSAGE_SELF)
    rows = [('tethersim', '-', own.ru_utime + own.ru_stime, own.ru_maxrss / 1024)]
    rows += [(child.name, '-' if child.returncode is None else str(child.returncode), child.cpu_time,
              child.peak_rss / 2**20) for child in children]
    members = {child.name: child.members for child in children if child.members != (child.name,)}
    rates = {name: cpu.per_sim_second(name) for name, *_ in rows}
    for name, code, cpu_s, rss in rows:
        rate = rates[name]
        lines.append(f'{name:<20} {code:>5} {cpu_s:8.2f} {"-" if rate is None else f"{rate:.3f}":>12} {rss:12.1f}')
        if name in members and group_cpu and cpu.sim_time > 0:
            for member in members[name]:
                seconds = group_cpu.get(member, 0.0)
                lines.append(f'{"  " + member:<20} {"":>5} {seconds:8.2f} {seconds / cpu.sim_time:12.3f}')
            if rate is not None:
                rest = rate - sum(group_cpu.get(member, 0.0) for member in members[name]) / cpu.sim_time
                lines.append(f'{"  executor and DDS":<20} {"":>5} {"":>8} {rest:12.3f}')
    measured = {name: rate for name, rate in rates.items() if rate is not None}
    if len(measured) == len(rows) and sum(measured.values()) > 0:
        total = sum(measured.values())
        cores = os.cpu_count() or 1
        mains = {name: cpu.per_sim_second(name, main_thread=True) or 0.0 for name in measured}
        busiest = max(mains, key=mains.__getitem__)
        allows = 1.0 / max(mains[busiest], 1e-9)
        ceiling = min(cores / total, allows)
        lines.append(f'{"total":<20} {"":>5} {"":>8} {total:12.3f} {"":>12}')
        lines.append(f'cpu s/sim s: CPU from the first tick to the last ack per simulated second (start-up and '
                     f'shutdown excluded); {cores} cores allow at most {cores / total:.2f}x real time; a process\'s '
                     f'main thread (Python) runs on one core at most: the busiest, {busiest} at {mains[busiest]:.3f} '
                     f'CPU s per sim s, allows {allows:.2f}x; ceiling {ceiling:.2f}x')
        if members:
            lines.append('the node group\'s rows under it: each node\'s lockstep callbacks (its ticks and what they '
                         'publish); executor and DDS: the rest (rclpy taking and converting messages, Fast DDS\'s threads)')
        if cpu.machine_start is not None and cpu.machine_end is not None:
            split = shares(cpu.machine_start, cpu.machine_end, total * cpu.sim_time)
            if split is not None:
                lines.append(f'the machine\'s {cores} cores from the first tick to the last ack (/proc/stat): '
                             + ', '.join(f'{name} {share:.0%}' for name, share in split.items()))
    return lines


def _reports(reports: tuple[str, ...], bag_dir: Path, out: Path, lines: list[str], figures: dict) -> bool:
    """Run each report, adding its lines to ``lines`` as it ends and the figures of those that give them
    (:class:`tether_common.report_figures.ReportLines`) to ``figures``; True if one failed. A signal
    (:class:`_Stop`) ends the phase: the report it interrupted and those not run are named.
    """
    failed = False
    for number, report in enumerate(reports):
        module_name, _, function_name = report.partition(':')
        try:
            function = getattr(importlib.import_module(module_name), function_name)
            result = function(str(resolve_bag(bag_dir)), str(out))
            lines += list(result)
            for name, value in getattr(result, 'figures', {}).items():
                figures[f'{function_name}.{name}' if name in figures else name] = value
        except _Stop as stop:
            lines.append(f'report {report} interrupted by {signal.Signals(stop.signum).name}; not run: '
                         + (', '.join(reports[number + 1:]) or 'none'))
            raise
        except Exception as error:  # a report's failure must not hide the run's other results
            lines.append(f'report {report} failed: {type(error).__name__}: {error}')
            failed = True
    return failed


def _run_figures(source, children: list[ChildProcess], wall: float, failure: str | None, cpu: RunCpu,
                 status: int) -> dict:
    """The run's own figures: exit status, why it ended early, sim and wall time, achieved real-time factor, and
    CPU: per simulated second from the first tick to the last ack (None unless every process was measured),
    and in all, start-up and shutdown included.
    """
    rates = [cpu.per_sim_second(name) for name in ('tethersim', *(child.name for child in children))]
    own = resource.getrusage(resource.RUSAGE_SELF)
    return {'exit_status': status, 'ended_early': failure.splitlines()[0] if failure else None,
            'sim_time': source.sim_time, 'wall_time': wall, 'realtime_factor': source.achieved_rate(),
            'cpu_per_sim_s': None if None in rates else sum(r for r in rates if r is not None),
            'cpu_time': own.ru_utime + own.ru_stime + sum(child.cpu_time for child in children)}


def _write_figures(path: Path, run: dict, reports: dict) -> None:
    """Write the run's figures and its reports' (a report's figure named like one of the run's gets the
    ``report.`` prefix) as one flat JSON object; non-finite numbers as null.
    """
    figures = {name: scalar(value) for name, value in run.items()}
    figures.update({f'report.{name}' if name in figures else name: value for name, value in reports.items()})
    path.write_text(json.dumps(figures, indent=1) + '\n')

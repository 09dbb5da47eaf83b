"""Serve a run's recorded topics live over the Foxglove WebSocket protocol (``tethersim run --live``).

The recorder already holds every recorded topic's ``ros2msg`` schema and each message's CDR
bytes and sim-time stamp, in the order it writes them: :class:`LiveBag` wraps the recorder's
:class:`~tether_bringup.bag_writer.BagWriter` and hands each message it has written to a
:class:`LiveServer`, which serves it with the Foxglove SDK's WebSocket server (``foxglove-sdk``)
as a ``cdr`` channel with the bag's concatenated ``ros2msg`` schema, so Foxglove or Lichtblick
decode it as they decode the bag, and broadcasts the latest ``/clock`` value as the server's time.

Serving never holds up the recorder, so never the lockstep: the write path only appends
(channel, bytes, time) to a bounded deque, which drops its oldest entry when the serving
thread falls behind; that thread hands what is queued to the SDK every :data:`POLL_PERIOD`;
the SDK keeps a bounded backlog per client and drops a slow client's oldest messages. The bag
is written first, with the same bytes, and nothing flows back: a bag does not depend on
whether it was served.

The server's CPU (its thread and the SDK's ``tokio`` threads) from the first ``/clock`` value it
served to the last it sampled, and the sim time between them, are written with its counts to
``stats_file`` when it stops, for the run summary and ``bench/graph_throughput``: as the run
summary's ``cpu s/sim s``, without the start-up, when the server idles.
"""

from __future__ import annotations

import os
import threading
import time
from collections import deque
from functools import cache
from pathlib import Path

import foxglove
import yaml
from foxglove.websocket import Capability
from foxglove.websocket import ServerListener

from tether_bringup.msgdef import concatenated_definition

POLL_PERIOD = 0.02
"""Seconds between the serving thread's passes over the queue: the latency a viewer sees, at most."""
SAMPLE_PERIOD = 0.25
"""Wall seconds between samples of the server's CPU, each at the /clock value it has just served."""
QUEUE_LENGTH = 20000
"""Messages the queue holds before it drops the oldest (about 10 s of outdoor_flight at real time)."""
CLOCK_TOPIC = '/clock'
RESCAN_PERIOD = 2.0
"""Wall seconds between looks for new SDK threads (its runtime starts them as it needs them)."""
SDK_THREAD = 'tokio-rt-worker'
"""The name of the Foxglove SDK server's threads (its Rust runtime's workers) in /proc."""
_TICKS = os.sysconf('SC_CLK_TCK')


@cache
def _schema(type_name: str) -> foxglove.Schema:
    return foxglove.Schema(name=type_name, encoding='ros2msg', data=concatenated_definition(type_name).encode())


def sdk_threads() -> list[Path]:
    """The /proc directories of this process's Foxglove SDK threads."""
    found = []
    for task in Path('/proc/self/task').iterdir():
        try:
            if (task / 'comm').read_text().strip() == SDK_THREAD:
                found.append(task)
        except OSError:
            continue
    return found


def thread_cpu(task: Path) -> float:
    """CPU seconds of one thread: its ``schedstat`` run time (ns), else its ``stat`` user and system ticks."""
    try:
        return int((task / 'schedstat').read_text().split()[0]) / 1e9
    except (OSError, ValueError, IndexError):
        pass
    try:
        fields = (task / 'stat').read_text().rpartition(')')[2].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / _TICKS


class _Subscriptions(ServerListener):
    """The server's listener: sets ``subscribed`` once a client has subscribed to a channel (the SDK's
    defaults for every other event).
    """

    def __init__(self) -> None:
        self.subscribed = threading.Event()

    def on_subscribe(self, client, channel) -> None:
        self.subscribed.set()


class LiveServer:
    """A Foxglove WebSocket server on ``host:port`` (0: any free port) with one channel per topic.

    With ``wait_for_client``, :attr:`ready` is False until a client has subscribed to a channel:
    the recorder reports ready only then, so the clock starts with a viewer watching. The URL
    goes into ``stats_file`` only when :meth:`announce` is called: the recorder does so once it has
    advertised every topic of the settled graph, because a client that connects while channels are
    being added can be sent a channel the SDK's server then does not know ("attempted to subscribe
    to unknown channel"), and that subscription is lost.
    """

    def __init__(self, host: str, port: int, stats_file: str = '', wait_for_client: bool = False) -> None:
        self._context = foxglove.Context()
        self._listener = _Subscriptions()
        if not wait_for_client:
            self._listener.subscribed.set()
        self._server = foxglove.start_server(name='tethersim', host=host, port=port, capabilities=[Capability.Time],
                                             context=self._context, server_listener=self._listener)
        self.url = f'ws://{host}:{self._server.port}'
        self._stats_file = stats_file
        self._channels: dict[str, foxglove.Channel] = {}
        self._queue: deque[tuple[foxglove.Channel, bytes, int]] = deque(maxlen=QUEUE_LENGTH)
        self._clock: foxglove.Channel | None = None
        self.offered = 0
        self.served = 0
        self._samples: list[tuple[int, float]] = []
        """(sim time ns, CPU s) at the first /clock value served and then every SAMPLE_PERIOD."""
        self._total_cpu = 0.0
        self._sdk_threads: list[Path] = []
        self._rescan = 0.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._serve, name='live server', daemon=True)
        self._thread.start()
        self._announced = False

    def announce(self) -> None:
        """Write the server's URL into the statistics file (once), for the bringup and its clients to connect to."""
        if self._stats_file and not self._announced:
            Path(self._stats_file).write_text(yaml.safe_dump({'url': self.url}))
        self._announced = True

    @property
    def ready(self) -> bool:
        """False while the server waits for a client to subscribe."""
        return self._listener.subscribed.is_set()

    def advertise(self, topic: str, type_name: str) -> None:
        """Add a channel for ``topic`` with the ros2msg schema of ``type_name``."""
        if topic in self._channels:
            return
        channel = foxglove.Channel(topic, schema=_schema(type_name), message_encoding='cdr', context=self._context)
        self._channels[topic] = channel
        if topic == CLOCK_TOPIC:
            self._clock = channel

    def offer(self, topic: str, data: bytes, time_ns: int) -> None:
        """Queue one message of an advertised topic (never blocks; the oldest is dropped when the queue is full)."""
        self._queue.append((self._channels[topic], data, time_ns))
        self.offered += 1

    def _cpu(self) -> float:
        """CPU seconds of the serving thread (called in it) and the SDK's threads so far."""
        if time.monotonic() >= self._rescan:
            self._rescan = time.monotonic() + RESCAN_PERIOD
            self._sdk_threads = sdk_threads()
        return time.thread_time() + sum(thread_cpu(task) for task in self._sdk_threads)

    def _serve(self) -> None:
        queue, clock, sampled = self._queue, None, 0.0
        while True:
            stopping = self._stop.wait(POLL_PERIOD)
            while queue:
                channel, data, time_ns = queue.popleft()
                channel.log(data, log_time=time_ns)
                self.served += 1
                if channel is self._clock:
                    clock = time_ns
            if clock is not None:
                self._server.broadcast_time(clock)
                if time.monotonic() - sampled >= SAMPLE_PERIOD:
                    sampled = time.monotonic()
                    sample = (clock, self._cpu())
                    self._samples = [self._samples[0], sample] if self._samples else [sample]
                clock = None
            if stopping:
                break
        self._rescan = 0.0
        self._total_cpu = self._cpu()

    def stop(self) -> None:
        """Serve what is queued, close the connections and write the statistics file (once)."""
        if self._stop.is_set():
            return
        self._stop.set()
        self._thread.join()
        self._server.stop()
        (start_ns, start_cpu), (end_ns, end_cpu) = (self._samples[0], self._samples[-1]) if self._samples \
            else ((0, 0.0), (0, 0.0))
        if self._stats_file:
            Path(self._stats_file).write_text(yaml.safe_dump({
                'url': self.url, 'offered': self.offered, 'served': self.served,
                'dropped': self.offered - self.served, 'cpu_s': round(self._total_cpu, 4),
                'window_sim_s': (end_ns - start_ns) / 1e9, 'window_cpu_s': round(end_cpu - start_cpu, 4)},
                sort_keys=False))


class LiveBag:
    """A bag writer that also serves each message it writes; anything else is the wrapped writer's."""

    def __init__(self, bag, server: LiveServer) -> None:
        self._bag = bag
        self.server = server

    def add_topic(self, name: str, type_name: str, *args, **kwargs) -> None:
        """Register the topic in the bag, then advertise it."""
        self._bag.add_topic(name, type_name, *args, **kwargs)
        self.server.advertise(name, type_name)

    def write(self, topic: str, data: bytes, log_time_ns: int, *args, **kwargs) -> None:
        """Write the message to the bag, then offer it to the server."""
        self._bag.write(topic, data, log_time_ns, *args, **kwargs)
        self.server.offer(topic, data, log_time_ns)

    def close(self) -> None:
        """Finalize the bag, then stop the server."""
        self._bag.close()
        self.server.stop()

    def __getattr__(self, name: str):
        return getattr(self._bag, name)


def cpu_per_sim_second(stats: dict) -> float | None:
    """The server's CPU s per simulated s between its first and last samples (None without two)."""
    return stats['window_cpu_s'] / stats['window_sim_s'] if stats.get('window_sim_s', 0) > 0 else None


def live_lines(stats_file: Path) -> list[str]:
    """The run summary's line about the live server, from its statistics file (none without one)."""
    try:
        stats = yaml.safe_load(stats_file.read_text())
    except OSError:
        return []
    if not isinstance(stats, dict) or 'cpu_s' not in stats:
        return []
    rate = cpu_per_sim_second(stats)
    per_sim = '' if rate is None else (f', {rate:.4f} CPU s per sim s over {stats["window_sim_s"]:.2f} s of sim '
                                       'time (start-up excluded)')
    return [f'live view: served on {stats["url"]}: {stats["served"]} of {stats["offered"]} messages handed to the '
            f'Foxglove server ({stats["dropped"]} dropped while it fell behind); its CPU {stats["cpu_s"]:.2f} s in all'
            f'{per_sim}']

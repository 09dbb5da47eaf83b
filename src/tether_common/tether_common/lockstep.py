"""Deterministic lockstep: every node ticks on sim time, selects its inputs by stamp, and acks.

The rules (README, "Writing a node") that make a run's recording the same at any
real-time factor and under any CPU load:

1. A node's periodic work is a *task* with a period P: it runs at sim times k·P (k ≥ 1),
   in order, never skipping one, and everything it publishes for tick t carries stamp t.
2. A task declares its inputs once: topic, type, the *producer's* period and a delay d.
   At tick t it gets, from each input, the latest message with stamp ≤ t − d, or None when
   the producer has no tick at or before t − d (its first message has stamp P_producer).
3. Before running tick t a task waits until each input has delivered the message it will
   select (its stamp is known: the latest multiple of the producer's period ≤ t − d).
   Nothing depends on arrival order; a stamp that is not a multiple of the declared period
   is an error, since the selection would then depend on timing.
4. After the ticks up to the latest ``/clock`` value have run, the node publishes a
   :class:`tether_msgs.msg.LockstepAck` on ``/lockstep/ack``; the time master advances
   ``/clock`` only once every node has acked, so no node runs ahead of the slowest.
5. A feed-forward edge may have d = 0 (the consumer waits for the producer's message of
   the same tick). Every cycle of the graph needs d ≥ the producer's period on at least
   one edge, or it deadlocks: that is the loop's explicit one-step delay.
6. Randomness comes from a seeded ``numpy.random.Generator`` drawn inside the ticks, whose
   order is fixed: by sim time, then by the order the tasks were added.

A node's tasks share one :class:`Lockstep`, so their ticks interleave in that fixed order::

    from tether_common.lockstep import Input, Lockstep

    class Controller(Node):
        def __init__(self):
            super().__init__('controller')
            params = declare_parameters(self, PARAMETERS)
            self.command_pub = self.create_publisher(ReelCommand, '/reel/command', COMMAND)
            self.lockstep = Lockstep(self)
            self.lockstep.every(1.0 / params['rate'], self.step, inputs=[
                Input('/tether/state', TetherState, period=0.01, delay=0.0)])

        def step(self, tick):
            state = tick.inputs['/tether/state']      # stamp <= tick time, or None
            command = ReelCommand()
            command.header.stamp = tick.stamp
            ...
            self.command_pub.publish(command)

Inputs are subscribed reliable (a lost message would stall the barrier); their producers
publish reliable too (:mod:`tether_common.qos`). The time master lets ``/clock`` lead the
slowest ack by a window of a few ticks (the scene's ``lockstep_window``), so a producer may
be that far ahead of a consumer busy in a long tick: an input's reader keeps at least
``INPUT_DEPTH`` messages, whatever depth its producer's profile names.

**In-process hand-off.** When several nodes share a process (``tether_bringup``'s node
group), :func:`link_in_process` hands each message one of them publishes on another's
input straight to that input, as its own copy (:mod:`tether_common.message_copy`), after
writing it to DDS as the CDR bytes :mod:`tether_common.cdr` serializes (while a reader other
than the idle ones below has matched the topic: :class:`GroupPublisher`), and adding those bytes to the
recorder's stream (:mod:`tether_common.record_stream`). The input's DDS
reader stays in the graph, matched, so ``ros2 topic info``, the join rules and the graph a
run writes are those of separate processes; its samples are not taken, and it is best effort
(``ros2 topic info -v`` shows it so), which spares the publisher heartbeats and acks. A take and its
conversion cost the group's one Python thread 55–100 µs per message with the recorder
subscribed; the copy 1.3–3.0 µs (:mod:`tether_common.message_copy`). Ticks that a hand-off makes runnable run after the
current callback, one node at a time (:class:`_Scheduler`), never inside another node's
tick; the rules above make the result independent of that order. One ``/clock``
subscription advances all the process's lockstep nodes; the others' ``/clock`` readers
stay in the graph, idle, as the inputs' do.
"""

from __future__ import annotations

import copy
import os
import time
import weakref
from collections import deque
from collections.abc import Callable
from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field
from typing import Any

from builtin_interfaces.msg import Time as TimeMsg
from rclpy.clock import Clock
from rclpy.clock import ClockType
from rclpy.node import Node
from rclpy.publisher import Publisher
from rclpy.qos import QoSProfile
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock as ClockMsg
from tether_msgs.msg import LockstepAck

from tether_common import cdr
from tether_common.message_copy import copy_message
from tether_common.message_types import message_class
from tether_common.node_main import ConfigurationError
from tether_common.qos import CLOCK
from tether_common.qos import IDLE_READER
from tether_common.qos import LOCKSTEP_ACK
from tether_common.qos import STATE
from tether_common.rclpy_internals import as_subclass
from tether_common.rclpy_internals import idle_reader
from tether_common.record_stream import StreamWriter

ACK_TOPIC = '/lockstep/ack'
NODES_VARIABLE = 'TETHERSIM_NODES'
RECORDER_READY_VARIABLE = 'TETHERSIM_RECORDER_READY'
END_VARIABLE = 'TETHERSIM_END'
"""Set by the bringup for its nodes: the sim time (s) at which the run ends (:func:`run_end`)."""
JOIN_CHECK_PERIOD = 0.05
JOIN_SETTLE = 0.5
STALL_LOG_PERIOD = 5.0
INPUT_DEPTH = 100
NS = 1_000_000_000
_CALLBACK_CPU: dict[str, float] = {}
_LOCKSTEPS: weakref.WeakSet[Lockstep] = weakref.WeakSet()


def callback_cpu() -> dict[str, float]:
    """Thread CPU time (s) each lockstep node of this process has spent advancing its ticks: selecting
    their inputs, running them and publishing what they produce, including handing it over to the
    process's other nodes. It leaves out what the executor spends taking messages and converting
    them before the callbacks; the node group (``tether_bringup``) reports it per node.
    """
    return dict(_CALLBACK_CPU)


def run_end() -> float | None:
    """Sim time (s) at which the run ends (``TETHERSIM_END``, set by the bringup); None outside a run."""
    value = os.environ.get(END_VARIABLE, '')
    try:
        return float(value) if value else None
    except ValueError:
        raise ConfigurationError(f'{END_VARIABLE}={value!r}: expected the run\'s end in s of sim time') from None


class LockstepError(ConfigurationError):
    """An input breaks the lockstep's rules (a stamp off the declared period, out of order)."""


@dataclass(frozen=True)
class Input:
    """One input of a task.

    ``msg_type`` is the message class or its name (``pkg/msg/Type``); it must have a
    ``header``. ``period`` is the producer's period in s (its stamps are multiples of it),
    ``delay`` the input's delay d in s: the task at tick t uses the latest message with
    stamp ≤ t − d.
    """

    topic: str
    msg_type: type | str
    period: float
    delay: float = 0.0
    qos: QoSProfile = field(default_factory=lambda: STATE)


@dataclass(frozen=True)
class Tick:
    """One tick of a task: its sim time and the inputs selected for it by stamp."""

    time_ns: int
    inputs: dict

    @property
    def seconds(self) -> float:
        """Sim time of the tick, s."""
        return self.time_ns / NS

    @property
    def stamp(self) -> TimeMsg:
        """The tick's sim time as a ``builtin_interfaces/Time`` for ``header.stamp``."""
        sec, nanosec = divmod(self.time_ns, NS)
        return TimeMsg(sec=sec, nanosec=nanosec)


def publishers_matched(node: Node, publishers=None) -> bool:
    """Each of ``publishers`` (default: all of ``node``'s) has matched every subscription of its topic
    that ``node``'s graph shows. A subscription matching a publisher does not mean the publisher has
    matched it (each side discovers the other on its own), and a message published before that is
    lost to the subscription.
    """
    return all(publisher.get_subscription_count() >= node.count_subscribers(publisher.topic_name)
               for publisher in (node.publishers if publishers is None else publishers))


def period_ns(period: float) -> int:
    """A period in integer nanoseconds, as producers and consumers must both round it."""
    if not period > 0:
        raise ValueError(f'period must be positive, got {period}')
    return round(period * NS)


def stamp_ns(stamp) -> int:
    """Nanoseconds of a ``builtin_interfaces/Time``."""
    return stamp.sec * NS + stamp.nanosec


class _Stream:
    """Messages of one input topic, kept by stamp until no task can select them any more."""

    def __init__(self, topic: str, msg_type: type, period: int) -> None:
        self.topic = topic
        self.msg_type = msg_type
        self.period_ns = period
        self.messages: deque = deque()
        self.latest_ns = -1
        self.subscription: Any = None
        """The stream's rclpy subscription, or once linked in process its idle DDS reader."""
        self.tasks: list[tuple[_Task, int]] = []
        """The tasks selecting from this stream, each with its input's delay, ns."""

    def add(self, msg) -> None:
        stamp = stamp_ns(msg.header.stamp)
        if stamp % self.period_ns:
            raise LockstepError(
                f'input {self.topic}: stamp {stamp / NS:.9f} s is not a multiple of the declared producer period '
                f'{self.period_ns / NS:g} s (declare the producer\'s period, or stamp messages with their tick time)')
        if stamp <= self.latest_ns:
            raise LockstepError(f'input {self.topic}: stamp {stamp / NS:.9f} s arrived after '
                                f'{self.latest_ns / NS:.9f} s (one message per producer tick, in stamp order)')
        self.latest_ns = stamp
        self.messages.append((stamp, msg))

    def expected(self, bound_ns: int) -> int:
        """Stamp of the message selected at ``bound_ns`` = t − d (0: none is due, producers start at k = 1)."""
        return max(bound_ns, 0) // self.period_ns * self.period_ns

    def ready(self, bound_ns: int) -> bool:
        """The message selected at ``bound_ns`` has arrived, or none is due."""
        period = self.period_ns
        return bound_ns < period or self.latest_ns >= bound_ns - bound_ns % period

    def select(self, bound_ns: int):
        chosen = None
        for stamp, msg in self.messages:
            if stamp > bound_ns:
                break
            chosen = msg
        return chosen

    def prune(self, bound_ns: int) -> None:
        """Forget messages older than the latest one with stamp ≤ ``bound_ns``."""
        while len(self.messages) > 1 and self.messages[1][0] <= bound_ns:
            self.messages.popleft()


class _Task:
    def __init__(self, index: int, period: int, callback: Callable[[Tick], None],
                 inputs: list[tuple[str, _Stream, int]]) -> None:
        self.index = index
        self.period_ns = period
        self.callback = callback
        self.inputs = inputs
        self.next_ns = period

    def blocking_input(self) -> tuple[_Stream, int] | None:
        """The first input whose message for the next tick has not arrived, with that message's stamp; None if all have."""
        next_ns = self.next_ns
        for _, stream, delay in self.inputs:
            bound = next_ns - delay
            if not stream.ready(bound):
                return stream, stream.expected(bound)
        return None


def _task_order(task: _Task) -> tuple[int, int]:
    return task.next_ns, task.index


class Lockstep:
    """The lockstep scheduler of one node: its tasks, their inputs, and its acks.

    Create one per node after the node's publishers, add tasks with :meth:`every`. The node
    joins the run (acks sim time 0) once the run's nodes are in the graph, every input
    subscription has matched a publisher and each of its publishers has matched every
    subscription of its topic in the graph (:meth:`_try_join`).
    """

    def __init__(self, node: Node) -> None:
        self._node = node
        self._name = node.get_fully_qualified_name()
        self._tasks: list[_Task] = []
        self._streams: dict[str, _Stream] = {}
        self._clock_ns = 0
        self._acked_ns = -1
        self._joined = False
        self._stalled_at: tuple[int, str, int, int] | None = None
        self._waiting: tuple[_Stream, int] | None = None
        """The input and stamp the next tick waits for: until that stamp arrives no tick can run."""
        self._ready_since: float | None = None
        self._expected_nodes = {name for name in os.environ.get(NODES_VARIABLE, '').split(',') if name}
        self._recorder_ready = os.environ.get(RECORDER_READY_VARIABLE, '')
        _CALLBACK_CPU.setdefault(self._name, 0.0)
        _LOCKSTEPS.add(self)
        self._ack_pub = node.create_publisher(LockstepAck, ACK_TOPIC, LOCKSTEP_ACK)
        self._clock_sub = node.create_subscription(ClockMsg, '/clock', self._on_clock, CLOCK)
        self._clock_shared: list[Lockstep] = [self]
        """The locksteps this one's ``/clock`` subscription advances: itself, or its process's (:func:`link_in_process`)."""
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._join_timer = node.create_timer(JOIN_CHECK_PERIOD, self._try_join, clock=steady)
        self._stall_timer = node.create_timer(STALL_LOG_PERIOD, self._log_stall, clock=steady)

    @property
    def clock_ns(self) -> int:
        """The latest ``/clock`` value received, ns."""
        return self._clock_ns

    def every(self, period: float, callback: Callable[[Tick], None], inputs: Sequence[Input] = ()) -> None:
        """Run ``callback(tick)`` at every multiple k·``period`` (k ≥ 1) of sim time, inputs selected by stamp."""
        task_inputs = []
        for spec in inputs:
            stream = self._stream(spec)
            delay = round(spec.delay * NS)
            if delay < 0:
                raise ValueError(f'input {spec.topic}: delay must not be negative, got {spec.delay}')
            task_inputs.append((spec.topic, stream, delay))
        task = _Task(len(self._tasks), period_ns(period), callback, task_inputs)
        self._tasks.append(task)
        for _, stream, delay in task_inputs:
            stream.tasks.append((task, delay))

    def _stream(self, spec: Input) -> _Stream:
        msg_type = _message_class(spec.msg_type)
        if 'header' not in msg_type.get_fields_and_field_types():
            raise ValueError(f'input {spec.topic}: {msg_type.__name__} has no header; lockstep inputs are stamped')
        stream = self._streams.get(spec.topic)
        if stream is None:
            stream = _Stream(spec.topic, msg_type, period_ns(spec.period))
            qos = copy.copy(spec.qos)
            qos.depth = max(qos.depth, INPUT_DEPTH)
            stream.subscription = self._node.create_subscription(
                msg_type, spec.topic, lambda msg: self._on_input(stream, msg), qos)
            self._streams[spec.topic] = stream
        elif stream.period_ns != period_ns(spec.period) or stream.msg_type is not msg_type:
            raise ValueError(f'input {spec.topic}: declared twice with different types or periods')
        return stream

    def _on_clock(self, msg: ClockMsg) -> None:
        clock_ns = stamp_ns(msg.clock)
        for lockstep in self._clock_shared:
            lockstep._clock_ns = max(lockstep._clock_ns, clock_ns)
        _SCHEDULER.run(*self._clock_shared)

    def _on_input(self, stream: _Stream, msg) -> None:
        """A message taken over DDS (inside the executor) or handed over by its producer (inside the producer's tick).

        A node still waiting for another message than this one is not scheduled: its
        :meth:`_advance` would return at once (most hand-offs: a tick of five inputs waits for
        four of them in vain).
        """
        stream.add(msg)
        if not self._still_waiting():
            _SCHEDULER.run(self)

    def _still_waiting(self) -> bool:
        """The next tick still waits for the input message it waited for at the last :meth:`_advance`."""
        waiting = self._waiting
        return waiting is not None and waiting[0].latest_ns < waiting[1]

    def _advance(self) -> None:
        """Run the ticks that are due and whose inputs have arrived, in (time, task) order; ack when caught up.

        Called after every input message, so its common case is cheap: a node still waiting
        for the message it waited for last time returns at once.
        """
        if self._still_waiting():
            return
        self._waiting = None
        tasks = self._tasks
        clock_ns = self._clock_ns
        caught_up = True
        while tasks:
            task = tasks[0] if len(tasks) == 1 else min(tasks, key=_task_order)
            time_ns = task.next_ns
            if time_ns > clock_ns:
                break
            self._waiting = task.blocking_input()
            if self._waiting is not None:
                caught_up = False
                break
            task.callback(Tick(time_ns, {topic: stream.select(time_ns - delay) for topic, stream, delay in task.inputs}))
            task.next_ns = time_ns + task.period_ns
            self._prune(task)
        if caught_up and self._joined and clock_ns > self._acked_ns:
            self._ack(clock_ns)

    def _prune(self, advanced: _Task) -> None:
        """Forget what no task can select any more from the streams ``advanced`` reads (only their bounds moved)."""
        for _, stream, _ in advanced.inputs:
            readers = stream.tasks
            if len(readers) == 1:
                task, delay = readers[0]
                stream.prune(task.next_ns - delay)
            else:
                stream.prune(min(task.next_ns - delay for task, delay in readers))

    def _ack(self, done_ns: int) -> None:
        self._acked_ns = done_ns
        msg = LockstepAck()
        msg.node = self._name
        msg.done.sec, msg.done.nanosec = divmod(done_ns, NS)
        self._ack_pub.publish(msg)

    def _try_join(self) -> None:
        """Join once every node of the run is in the graph (``TETHERSIM_NODES``, set by the bringup),
        the recorder has subscribed to every topic or taken it from the group's stream (its ready file,
        ``TETHERSIM_RECORDER_READY``, exists), every input has a publisher and every publisher of the node has matched every
        subscription the graph shows, all unchanged for ``JOIN_SETTLE``: no message of the first
        ticks is published before its subscribers are matched. Matching is seen from each side
        on its own: the recorder's subscription matching a publisher does not mean the publisher
        has matched it, so the node checks its own publishers once the recorder's subscriptions
        are in the graph.
        """
        node = self._node
        if self._recorder_ready and not os.path.exists(self._recorder_ready):
            self._ready_since = None
            return
        present = {name for name, _ in node.get_node_names_and_namespaces()}
        ready = self._expected_nodes <= present and all(
            stream.subscription.get_publisher_count() > 0 for stream in self._streams.values()) and \
            publishers_matched(node)
        now = time.monotonic()
        if not ready:
            self._ready_since = None
            return
        if self._ready_since is None:
            self._ready_since = now
        if now - self._ready_since >= JOIN_SETTLE:
            self._join_timer.cancel()
            self._joined = True
            self._ack(0)
            _SCHEDULER.run(self)

    def _log_stall(self) -> None:
        waiting = None
        for task in self._tasks:
            if task.next_ns <= self._clock_ns:
                blocked = task.blocking_input()
                if blocked is not None:
                    stream, expected = blocked
                    waiting = (task.next_ns, stream.topic, expected, stream.latest_ns)
                    break
        if waiting is not None and waiting == self._stalled_at:
            tick_ns, topic, expected, latest = waiting
            latest_text = f'{latest / NS:.6f} s' if latest >= 0 else 'none'
            self._node.get_logger().warning(
                f'lockstep: tick {tick_ns / NS:.6f} s waits for {topic} stamp {expected / NS:.6f} s '
                f'(latest received: {latest_text}); is its producer running with the declared period?')
        self._stalled_at = waiting


class _Scheduler:
    """Runs the ticks of this process's lockstep nodes one node at a time.

    A callback (``/clock``, an input, the join) or a hand-off marks its node pending; the
    outermost call runs the pending nodes' ticks, in the order they were marked, until none
    is pending. A hand-off inside a tick only marks its consumer, so no node's tick runs
    inside another's. Each node's thread CPU time is counted here (:func:`callback_cpu`), one clock
    reading per node run: those readings are system calls, about 0.6 µs each on this machine.
    """

    def __init__(self) -> None:
        self._pending: list[Lockstep] = []
        self._running = False

    def run(self, *locksteps: Lockstep) -> None:
        for lockstep in locksteps:
            if lockstep not in self._pending:
                self._pending.append(lockstep)
        if self._running:
            return
        self._running = True
        try:
            start = time.thread_time()
            while self._pending:
                current = self._pending.pop(0)
                current._advance()
                end = time.thread_time()
                _CALLBACK_CPU[current._name] += end - start
                start = end
        finally:
            self._pending.clear()
            self._running = False


_SCHEDULER = _Scheduler()


class GroupPublisher(Publisher):
    """A publisher of the node group: it sends each message over DDS as CDR bytes serialized by
    :mod:`tether_common.cdr` (12-20 µs less of the group's Python thread per message than
    rclpy's conversion and Fast DDS's serialization), then hands it to the subscribers of its
    process that :func:`link_in_process` linked to it, each as its own copy.

    It writes to DDS only while a reader other than its process's idle ones is matched (another
    process's, ``ros2 topic echo``'s, a subscription made after linking): with none, a write
    reached nobody and cost the group's Python thread 10-20 µs. A reader that joins late gets
    the messages published after it matched, not the transient-local history of those before:
    writing that history at the match would hand the recorder, when it turns a streamed topic
    over to DDS, messages it already has from the stream.
    """

    handoffs: list[Callable[[object], None]]
    serialize: Callable[[object], bytes] | None
    record: StreamWriter | None
    record_id: int
    idle_readers: int

    def publish(self, msg) -> None:
        write = self.get_subscription_count() > self.idle_readers
        if write or self.record is not None:
            data = msg
            if isinstance(msg, self.msg_type):  # type: ignore[arg-type]  # rclpy's MsgType protocol: the class
                if self.serialize is not None:
                    data = self.serialize(msg)
                elif self.record is not None:  # a type cdr does not write: rclpy's bytes serve DDS and the stream
                    data = serialize_message(msg)
            if write:
                super().publish(data)
            if self.record is not None:
                self.record.add(self.record_id, data)
        for deliver in self.handoffs:
            deliver(copy_message(msg))


class InProcessLinks:
    """The hand-offs :func:`link_in_process` made; :meth:`close` destroys the idle DDS readers before their nodes."""

    def __init__(self) -> None:
        self.readers: list = []
        self.idle_topics: dict[str, int] = {}
        """Idle readers per topic."""

    def idle(self, node: Node, subscription):
        """Replace ``subscription`` with a DDS reader of its topic and type that keeps it in the graph,
        matched; the executor never sees the reader. Its QoS is :data:`~tether_common.qos.IDLE_READER`:
        a reliable one cost the publishing thread about 6 µs per message and reader in
        heartbeats, acks and history, a best-effort one about 3.5 µs (this machine).
        """
        msg_type, topic = subscription.msg_type, subscription.topic_name
        node.destroy_subscription(subscription)
        reader = idle_reader(node, msg_type, topic, IDLE_READER)
        self.readers.append(reader)
        self.idle_topics[topic] = self.idle_topics.get(topic, 0) + 1
        return reader

    def close(self) -> None:
        for reader in self.readers:
            reader.destroy_when_not_in_use()
        self.readers.clear()


def _input_delivery(lockstep: Lockstep, stream: _Stream) -> Callable[[object], None]:
    return lambda msg: lockstep._on_input(stream, msg)


def _plain_delivery(callback: Callable, raw: bool) -> Callable[[object], None]:
    if raw:
        return lambda msg: callback(cdr.serialize(msg))
    return callback


def link_in_process(nodes: Sequence[Node], record: StreamWriter | None = None) -> InProcessLinks:
    """Hand every message a node of ``nodes`` publishes to the subscribers among ``nodes`` of its topic.

    Call once, after the nodes are built and before they spin. Each publisher of ``nodes``
    becomes a :class:`GroupPublisher`; with ``record``, the recorder's stream
    (:mod:`tether_common.record_stream`), it announces itself there and adds the bytes of every
    message it publishes. A linked lockstep input gets the message appended
    and its node's ticks run after the current callback (:class:`_Scheduler`); any other
    linked subscription's callback runs at once, inside the publish, so it has the message
    before anything published after it, as the executor would have taken it. Each linked
    subscription's DDS reader stays in the graph, idle (module docstring). A topic published
    only by another process stays a DDS subscription.
    """
    links = InProcessLinks()
    publishers: dict[str, list[GroupPublisher]] = {}
    for node in nodes:
        for plain in node.publishers:
            publisher = _to_group_publisher(plain)
            publishers.setdefault(publisher.topic_name, []).append(publisher)
            if record is not None and publisher.topic_name != ACK_TOPIC:
                publisher.record = record
                publisher.record_id = record.announce(publisher.topic_name, node.get_fully_qualified_name())
    if record is not None:
        record.announced()

    def link(topic: str, deliver: Callable[[object], None]) -> None:
        for publisher in publishers[topic]:
            publisher.handoffs.append(deliver)

    order = {id(node): index for index, node in enumerate(nodes)}
    locksteps = sorted((lockstep for lockstep in _LOCKSTEPS if id(lockstep._node) in order),
                       key=lambda lockstep: order[id(lockstep._node)])
    _share_clock(locksteps, links)
    for lockstep in locksteps:
        node = lockstep._node
        for stream in lockstep._streams.values():
            topic = stream.subscription.topic_name
            if topic in publishers:
                stream.subscription = links.idle(node, stream.subscription)
                link(topic, _input_delivery(lockstep, stream))
    for node in nodes:
        for subscription in list(node.subscriptions):
            topic = subscription.topic_name
            if topic in publishers:
                deliver = _plain_delivery(subscription.callback, subscription.raw)
                links.idle(node, subscription)
                link(topic, deliver)
    for topic, topic_publishers in publishers.items():
        for publisher in topic_publishers:
            publisher.idle_readers = links.idle_topics.get(topic, 0)
    return links


def _to_group_publisher(plain: Publisher) -> GroupPublisher:
    if isinstance(plain, GroupPublisher):
        return plain
    publisher = as_subclass(plain, GroupPublisher)
    publisher.handoffs = []
    publisher.record = None
    publisher.idle_readers = 0
    try:
        publisher.serialize = cdr.serializer(publisher.msg_type)
    except NotImplementedError:
        publisher.serialize = None
    return publisher


def _share_clock(locksteps: list[Lockstep], links: InProcessLinks) -> None:
    """One ``/clock`` subscription, the first lockstep's, advances every lockstep of the process;
    the others' readers stay in the graph, idle.
    """
    if len(locksteps) < 2:
        return
    for lockstep in locksteps[1:]:
        lockstep._clock_sub = links.idle(lockstep._node, lockstep._clock_sub)
        lockstep._clock_shared = []
    locksteps[0]._clock_shared = list(locksteps)


def _message_class(msg_type: type | str) -> Any:
    return message_class(msg_type) if isinstance(msg_type, str) else msg_type

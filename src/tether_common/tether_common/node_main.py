"""The one ``main`` every tethersim node uses: init, spin, clean exit.

Nodes spin on rclpy's ``EventsExecutor`` (:func:`make_executor`): it runs callbacks in the
order their events arrive, and takes and dispatches a message for less CPU time than the
default ``SingleThreadedExecutor`` (``bench/graph_throughput`` measures both). It is spun
one event at a time: its ``spin()`` does not return on SIGINT/SIGTERM (rclpy 7.1.6);
``spin_once`` raises ``ExternalShutdownException`` once the signal has shut rclpy down.

Ctrl-C, SIGTERM and an external shutdown end the node normally (exit status 0), also
while the node is still being built, and also when the parent ignored SIGINT. A
:class:`ConfigurationError` raised while the node is built (a bad parameter, a missing
file), or rclpy's own refusal of a parameter value (a parameter declared without a
specification, such as ``use_sim_time``: a value of another type), is printed as one line
``<program>: error: parameter NAME: expected ..., got VALUE`` and ends the process with
status 2, without a traceback; so is a :class:`ConfigurationError` raised while the node
runs (an input breaking the lockstep's rules). So are ``--ros-args`` rcl cannot parse (a list mixing
types): rcl's own log line about them is replaced by the one line.

Destroying the nodes can hang: Fast DDS 2.14 may deadlock in ``DomainParticipant::set_listener``
when the last node's participant is destroyed while a discovery callback for a vanishing remote
participant runs (seen once in a test run: the platform node spun there, holding the GIL, for
over ten minutes after SIGINT). A watchdog outside the GIL (``faulthandler``) then prints
every thread's stack and ends the process with status 1 after :data:`SHUTDOWN_TIMEOUT`, so no
node is left behind. It is armed by the signal itself, from a thread of its own
(:func:`_watch_for_shutdown_signals`), wherever the main thread is, and again when the
destruction begins.
"""

from __future__ import annotations

import cProfile
import faulthandler
import os
import re
import signal
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from contextlib import contextmanager
from pathlib import Path

import rclpy
from rclpy.exceptions import ParameterException
from rclpy.executors import Executor
from rclpy.executors import ExternalShutdownException
from rclpy.executors import SingleThreadedExecutor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node

from tether_common.rclpy_internals import RCLError
from tether_common.record_stream import StreamWriter

SPIN_TIMEOUT = 0.5
SHUTDOWN_TIMEOUT = 10.0
"""Seconds the nodes' destruction and rclpy's shutdown may take before the watchdog ends the process."""
EXECUTOR_VARIABLE = 'TETHERSIM_EXECUTOR'
PROFILE_VARIABLE = 'TETHERSIM_PROFILE'


class ConfigurationError(Exception):
    """A node cannot start with the parameters or files it was given."""


def make_executor(context=None):
    """The executor tethersim processes spin their nodes on (``context``: rclpy's default).

    ``TETHERSIM_EXECUTOR=single`` selects rclpy's ``SingleThreadedExecutor`` instead: the
    baseline ``bench/graph_throughput`` measures in the same run.
    """
    if os.environ.get(EXECUTOR_VARIABLE, 'events') == 'single':
        return SingleThreadedExecutor(context=context)
    return EventsExecutor(context=context)


def run_node(factory: Callable[[], Node], args: list[str] | None = None,
             executor: Callable[[], Executor] | None = None, interrupt_callbacks: bool = True) -> int:
    """Build the node with ``factory`` and spin it until shutdown; return the exit status.

    ``executor`` makes the executor that spins it (default: :func:`make_executor`). With
    ``interrupt_callbacks`` false, SIGINT (Ctrl-C) ends the spin as SIGTERM does, once the
    running callback returns, instead of raising ``KeyboardInterrupt`` inside it: for a node
    whose callback must not stop halfway (the recorder, in the middle of writing a chunk).
    """
    return run_nodes({Path(sys.argv[0]).name: factory}, args, executor, interrupt_callbacks=interrupt_callbacks)


def run_nodes(factories: dict[str, Callable[[], Node]], args: list[str] | None = None,
              executor: Callable[[], Executor] | None = None, record: StreamWriter | None = None,
              interrupt_callbacks: bool = True) -> int:
    """Build each node (name: factory, in order) in this process and spin them all on one executor.

    A node that cannot be built is reported under its name (``<name>: error: ...``); an
    error while they spin, under the program's. One executor for several nodes: a message
    one of them publishes is handed to the others' subscriptions of its topic inside the
    process, and one ``/clock`` subscription advances them all
    (:func:`tether_common.lockstep.link_in_process`; ``tether_bringup``'s node group). With
    ``record``, what they publish also goes to the recorder's stream, written after each
    executor callback and closed on every exit (:mod:`tether_common.record_stream`).
    """
    from tether_common.lockstep import link_in_process  # lockstep imports this module's ConfigurationError
    program = Path(sys.argv[0]).name
    stop = _watch_for_shutdown_signals(interrupt_callbacks)
    refused = _init(args)
    if refused:
        print(f'{program}: error: invalid --ros-args: {refused}', file=sys.stderr, flush=True)
        return 2
    nodes: list[Node] = []
    links = None
    status = 0
    building = program
    try:
        for name, factory in factories.items():
            building = name
            nodes.append(factory())
        building = program
        links = link_in_process(nodes, record)
        spinner = executor() if executor is not None else make_executor()
        for node in nodes:
            spinner.add_node(node)
        with _profiled(nodes[0].get_name() if len(nodes) == 1 else program):
            while rclpy.ok() and not stop.is_set():
                spinner.spin_once(timeout_sec=SPIN_TIMEOUT)
                if record is not None:
                    record.flush()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    except ConfigurationError as error:
        print(f'{building}: error: {error}', file=sys.stderr, flush=True)
        status = 2
    except ParameterException as error:
        print(f'{building}: error: {_parameter_refusal(error)}', file=sys.stderr, flush=True)
        status = 2
    except Exception:
        if rclpy.ok():
            raise
        # SIGTERM shut the context down while a node was being built: the rcl call that
        # failed on the dead context is the normal end, not an error
    finally:
        faulthandler.dump_traceback_later(SHUTDOWN_TIMEOUT, exit=True)
        try:
            if links is not None:
                links.close()
            for node in nodes:
                node.destroy_node()
            rclpy.try_shutdown()
        finally:
            if record is not None:
                record.close()
            faulthandler.cancel_dump_traceback_later()
    return status


def _watch_for_shutdown_signals(interrupt_callbacks: bool) -> threading.Event:
    """Act on SIGINT and SIGTERM from the main thread as well as rclpy's, and arm the watchdog on their arrival.

    Call before ``rclpy.init``: rclpy's handler shuts the context down from a thread of its
    own and then calls the handler it found, so that one must be Python's. A parent that
    ignores SIGINT (a shell's background job) would otherwise leave the node deaf to it
    until ``rclpy.init``, and with rclpy's thread alone to end the spin after that (in a
    test run started that way, once it did not: the estimator spun on for 30 s).

    SIGINT raises ``KeyboardInterrupt``, inside the running callback; with
    ``interrupt_callbacks`` false it, like SIGTERM, sets the returned event, which ends the
    spin once the callback returns. Python's C handler also writes the signal's number to
    the wakeup pipe at once, and a thread blocked reading that pipe arms ``faulthandler``'s
    timer, so a main thread that never comes back from the executor is ended too.
    """
    stop = threading.Event()

    def request_stop(signum, frame) -> None:
        stop.set()

    reader, writer = os.pipe()
    os.set_blocking(writer, False)
    signal.set_wakeup_fd(writer, warn_on_full_buffer=False)
    signal.signal(signal.SIGINT, signal.default_int_handler if interrupt_callbacks else request_stop)
    signal.signal(signal.SIGTERM, request_stop)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, (signal.SIGINT, signal.SIGTERM))
    threading.Thread(target=_arm_watchdog_on_signal, args=(reader,), name='shutdown watchdog', daemon=True).start()
    return stop


def _arm_watchdog_on_signal(reader: int) -> None:
    """Wait for a signal's byte on the wakeup pipe, then start the watchdog (status 1 after SHUTDOWN_TIMEOUT)."""
    os.read(reader, 1)
    faulthandler.dump_traceback_later(SHUTDOWN_TIMEOUT, exit=True)


_TYPE_WORDS = {'BOOL': 'a boolean', 'INTEGER': 'an integer', 'DOUBLE': 'a number', 'STRING': 'a string',
               'BYTE_ARRAY': 'a list of bytes', 'BOOL_ARRAY': 'a list of booleans', 'INTEGER_ARRAY': 'a list of integers',
               'DOUBLE_ARRAY': 'a list of numbers', 'STRING_ARRAY': 'a list of strings', 'NOT_SET': 'no value'}


def _parameter_refusal(error: ParameterException) -> str:
    """rclpy's refusal of a parameter of the wrong type in the project's words: ``parameter NAME: expected ...``.

    rclpy's ``InvalidParameterTypeException`` keeps only its message and the parameter's name,
    so the value and the types are taken from the message; any other refusal keeps rclpy's text.
    """
    match = re.search(r"parameter '(.+)' to '(.*)' of type '(\w+)', expecting type '(?:Type\.)?(\w+)'", str(error))
    if match is None:
        return str(error)
    name, value, given, expected = match.groups()
    return (f'parameter {name}: expected {_TYPE_WORDS.get(expected, expected)}, got {value} '
            f'({_TYPE_WORDS.get(given, given)})')


@contextmanager
def _profiled(name: str):
    """Profile the spin (CPU time) with cProfile into ``$TETHERSIM_PROFILE/<name>.prof`` when that variable is set."""
    directory = os.environ.get(PROFILE_VARIABLE)
    if not directory:
        yield
        return
    profile = cProfile.Profile(time.process_time)
    profile.enable()
    try:
        yield
    finally:
        profile.disable()
        Path(directory).mkdir(parents=True, exist_ok=True)
        profile.dump_stats(str(Path(directory) / f'{name}.prof'))


def _init(args: list[str] | None) -> str | None:
    """Initialize rclpy; return why rcl refused the arguments, or None.

    rcl logs its own line to standard error before refusing; that output is held back and
    shown only when initialization succeeds.
    """
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as held:
        os.dup2(held.fileno(), 2)
        try:
            rclpy.init(args=args)
        except RCLError as error:
            return re.sub(r', at \S+:\d+', '', str(error)).removeprefix('failed to initialize rcl: ')
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        held.seek(0)
        sys.stderr.buffer.write(held.read())
        sys.stderr.flush()
    return None

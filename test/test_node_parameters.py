"""Node parameters through the shared node main, with the installed executables.

A wrong type, an out-of-range value, an unknown choice, a vector of the wrong length or a
missing file given with ``--ros-args -p`` ends the node with one line naming the parameter,
the value and what is expected, and exit status 2: the project's own contract, asserted
against the specification's reason, never against rcl's or rclpy's wording; an integer
for a floating-point parameter is taken as that number. A parameter the node reads once is
read-only: setting it while the node runs is refused (the refusal names it) instead of
silently ignored.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import rclpy
from ament_index_python.packages import get_package_prefix
from rcl_interfaces.msg import ParameterType
from rclpy.parameter import Parameter
from rclpy.parameter_client import AsyncParameterClient

from tether_bringup.recorder_params import PARAMETERS as RECORDER_PARAMETERS
from tether_common.parameters import parameter_module
from tether_common.parameters import specified_nodes

NODES = Path(__file__).resolve().parent / 'nodes'
SOURCES = Path(__file__).resolve().parent.parent / 'src'


def _program(package: str, executable: str) -> str:
    return str(Path(get_package_prefix(package)) / 'lib' / package / executable)


PLATFORM = _program('psr_platform_sim', 'platform')
RECORDER = _program('tether_bringup', 'recorder')
PLANT = _program('tether_dynamics', 'plant')
BUILTIN_UAV = _program('uav_bridge', 'builtin_uav')
FAST_PLATFORM = ['-p', 'table_steps:=60', '-p', 'profile_duration:=2.0', '-p', 'profile:=still']

def _spec(package: str, executable: str, name: str):
    specs = parameter_module(package, executable).PARAMETERS
    return next(spec for spec in specs if spec.name == name)


def _refusal(package: str, executable: str, name: str, value: object) -> str:
    """The one line the project promises for ``value`` of a specified parameter: its check's own reason."""
    reason = _spec(package, executable, name).check(value)
    assert reason
    return f'{executable}: error: parameter {name}: {reason}'


BAD = [
    ('platform out of range', PLATFORM, ['state_rate:=5000.0'],
     _refusal('psr_platform_sim', 'platform', 'state_rate', 5000.0)),
    ('platform wrong type', PLATFORM, ['state_rate:=fast'], _refusal('psr_platform_sim', 'platform', 'state_rate', 'fast')),
    ('platform float for int', PLATFORM, ['seed:=1.5'], _refusal('psr_platform_sim', 'platform', 'seed', 1.5)),
    ('platform unknown choice', PLATFORM, ['profile:=hpr9'], _refusal('psr_platform_sim', 'platform', 'profile', 'hpr9')),
    ('platform missing file', PLATFORM, ['profile:=/no/such/heave.csv'],
     _refusal('psr_platform_sim', 'platform', 'profile', '/no/such/heave.csv')),
    ('platform list item', PLATFORM, ['reel_offset:=[fore, port, up]'],
     _refusal('psr_platform_sim', 'platform', 'reel_offset', ['fore', 'port', 'up'])),
    ('platform vector of the wrong length', PLATFORM, ['reel_offset:=[0.0, 1.0]'],
     _refusal('psr_platform_sim', 'platform', 'reel_offset', [0.0, 1.0])),
    ('plant vector of the wrong length', PLANT, ['uav_position:=[1.0,2.0]'],
     _refusal('tether_dynamics', 'plant', 'uav_position', [1.0, 2.0])),
    ('recorder out of range', RECORDER, ['flush_period:=100.0'],
     _refusal('tether_bringup', 'recorder', 'flush_period', 100.0)),
    ('recorder wrong list', RECORDER, ['exclude:=[1, 2]'], _refusal('tether_bringup', 'recorder', 'exclude', [1, 2])),
    ('plant step its elements cannot take', PLANT, ['fidelity:=linear', 'integration_step:=0.01'],
     "plant: error: at the reel's full length (100 m): dt 0.01 s is above the stable step 0.00303 s of elements of "
     '5 m (EA 20000 N, mu 0.042 kg/m, damping ratio 0); reduce dt or lengthen the elements'),
    ('builtin UAV IMU rate off its ticks', BUILTIN_UAV, ['imu_rate:=30.0'],
     'builtin_uav: error: parameter imu_rate: 30 Hz is not rate 100 Hz divided by a whole number (its messages '
     'go out at ticks)'),
]
"""A value the project's own specification refuses: the exact line (the specification's reason)."""

UNSPECIFIED = [
    ('rclpy parameter', PLATFORM, 'use_sim_time', '1', 'a boolean'),
    ('node without specification', sys.executable, 'rate', 'fast', 'a number'),
]
"""A parameter declared without a specification (rclpy's own, a test double's): the same contract, type only."""


def _specified_nodes() -> list[tuple[str, str]]:
    """(package, executable) of every node whose package registers a parameters module."""
    return sorted(specified_nodes())


def test_every_parameters_module_is_registered():
    """A parameters module (``*params.py``) its package does not register would be a node the scene validator never checks."""
    registered = {entry.value for entry in specified_nodes().values()}
    files = {'.'.join(path.relative_to(SOURCES).with_suffix('').parts[1:]) for path in SOURCES.glob('*/*/**/*params.py')}
    assert files == registered


def _bad_values(specs) -> list[tuple[str, object]]:
    """One out-of-range number and one unknown choice (if the node has them)."""
    bad = []
    number = next((s for s in specs if s.kind in (int, float) and s.high is not None), None)
    if number is not None:
        bad.append((number.name, number.kind(number.high * 2 + 1)))
    choice = next((s for s in specs if s.kind is str and s.choices), None)
    if choice is not None:
        bad.append((choice.name, 'no_such_choice'))
    return bad


@pytest.mark.parametrize('package, executable', _specified_nodes())
def test_every_specified_node_refuses_bad_values_in_one_line(ros_domain, tmp_path, package, executable):
    """Every node built on the shared declaration, present and future, answers the same way."""
    specs = parameter_module(package, executable).PARAMETERS
    bad = _bad_values(specs)
    assert bad, f'{package}/{executable} has no ranged number or choice to try'
    for name, value in bad:
        reason = next(s for s in specs if s.name == name).check(value)
        result = subprocess.run(_command(_program(package, executable), '-p', f'{name}:={value}'),
                                capture_output=True, text=True, timeout=120, cwd=tmp_path)
        assert result.returncode == 2, result.stderr
        assert result.stderr.strip().splitlines() == [f'{executable}: error: parameter {name}: {reason}']


def _command(program: str, *arguments: str) -> list[str]:
    script = [str(NODES / 'talker_double.py')] if program == sys.executable else []
    return [program, *script, '--ros-args', *arguments]


def _refused(program: str, tmp_path: Path, *values: str) -> str:
    """Start ``program`` with ``-p`` ``values``; assert exit status 2 and one line on standard error; return it."""
    arguments = [item for value in values for item in ('-p', value)]
    result = subprocess.run(_command(program, *arguments, '-p', f'cache_dir:={tmp_path}')
                            if program == PLATFORM else _command(program, *arguments),
                            capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert result.returncode == 2, result.stderr
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1, result.stderr
    return lines[0]


@pytest.mark.parametrize('program, values, expected', [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_bad_parameter_gives_one_line_and_status_2(ros_domain, tmp_path, program, values, expected):
    assert _refused(program, tmp_path, *values) == expected


@pytest.mark.parametrize('program, name, value, expected', [u[1:] for u in UNSPECIFIED], ids=[u[0] for u in UNSPECIFIED])
def test_unspecified_parameter_of_the_wrong_type_names_it_and_its_type(ros_domain, tmp_path, program, name, value,
                                                                        expected):
    executable = 'talker_double.py' if program == sys.executable else Path(program).name
    line = _refused(program, tmp_path, f'{name}:={value}')
    assert line.startswith(f'{executable}: error: parameter {name}: expected {expected}, got {value}'), line


def test_arguments_rcl_cannot_parse_name_the_parameter(ros_domain, tmp_path):
    """A list mixing types: rcl refuses the arguments before any node exists; the line still names the parameter."""
    line = _refused(PLATFORM, tmp_path, 'reel_offset:=[0.0, fore, 1.0]')
    assert line.startswith('platform: error: invalid --ros-args: ') and 'reel_offset' in line, line


def _parameter_client(node_name: str, timeout: float = 120.0):
    rclpy.init()
    probe = rclpy.create_node('parameter_probe')
    client = AsyncParameterClient(probe, node_name)
    assert client.wait_for_services(timeout_sec=timeout), f'{node_name} offers no parameter services'
    return probe, client


def _call(probe, future):
    rclpy.spin_until_future_complete(probe, future, timeout_sec=30.0)
    assert future.done()
    return future.result()


def _stop(process: subprocess.Popen) -> str:
    process.send_signal(2)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 0, err
    return err


def test_integer_for_a_double_is_taken_as_that_number_and_read_only_is_refused(ros_domain, tmp_path):
    process = subprocess.Popen(_command(PLATFORM, '-p', 'state_rate:=50', '-p', f'cache_dir:={tmp_path}',
                                        *FAST_PLATFORM), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        probe, client = _parameter_client('/platform')
        try:
            value = _call(probe, client.get_parameters(['state_rate'])).values[0]
            assert (value.type, value.double_value) == (ParameterType.PARAMETER_DOUBLE, 50.0)
            result = _call(probe, client.set_parameters([Parameter('state_rate', value=20.0)])).results[0]
            assert not result.successful and 'state_rate' in result.reason
            described = _call(probe, client.describe_parameters(['state_rate'])).descriptors[0]
            assert described.read_only and described.floating_point_range[0].to_value == 1000.0
        finally:
            probe.destroy_node()
            rclpy.shutdown()
        assert process.poll() is None, process.communicate()[1]
    finally:
        if process.poll() is None:
            _stop(process)


def test_recorder_parameters_read_once_are_read_only(ros_domain, tmp_path):
    process = subprocess.Popen(_command(RECORDER, '-p', f'bag_directory:={tmp_path / "bag"}'),
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        probe, client = _parameter_client('/recorder')
        try:
            names = [spec.name for spec in RECORDER_PARAMETERS]
            results = _call(probe, client.set_parameters(
                [Parameter(spec.name, value=spec.default if spec.default != [] else ['x']) for spec in
                 RECORDER_PARAMETERS])).results
            refused = {name: result.reason for name, result in zip(names, results) if not result.successful}
            assert set(refused) == set(names), refused
            assert all(name in reason for name, reason in refused.items()), refused
        finally:
            probe.destroy_node()
            rclpy.shutdown()
    finally:
        if process.poll() is None:
            _stop(process)


def test_sigterm_while_the_node_is_being_built_ends_it_quietly(ros_domain, tmp_path):
    """rclpy shuts the context down on SIGTERM; the node's next rcl call must not become a traceback."""
    started = tmp_path / 'started'
    process = subprocess.Popen([sys.executable, str(NODES / 'slow_start_double.py'), '--ros-args',
                                '-p', f'started_file:={started}'], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    while not started.exists():
        assert process.poll() is None, process.communicate()[1]
        time.sleep(0.01)
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 0, err
    assert 'Traceback' not in err

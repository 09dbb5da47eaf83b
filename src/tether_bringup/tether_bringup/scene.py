"""Scene files: which nodes run, with which parameters, for how long, and what is reported.

A scene is YAML::

    description: One line shown by `tethersim scenes`.
    duration: 60.0            # s of sim time
    rate: 1.0                 # real-time factor (10 = ten times faster than real time), or max
    clock_step: 0.01          # s of sim time between /clock ticks
    lockstep_window: 0.05     # s of sim time /clock may lead the slowest node's ack
    compose: true             # nodes whose package registers their class run in one process
                              # (tether_bringup.node_group); false: each node in its own process
    nodes:
      platform:               # node name
        package: psr_platform_sim
        executable: platform  # or `script: path/to/node.py`, relative to the scene file
        parameters: {...}     # validated against the node's registered PARAMETERS
        external: false       # true: started elsewhere (another machine), waited for, not started
        lockstep: true        # false: a node outside the lockstep barrier (driven by wall time or an
                              # external simulator, e.g. ArduPilot SITL); the run is then not reproducible
    record:
      exclude: [/rosout, /parameter_events]
    reports:
      - psr_platform_sim.report:tracking_report

Physical effects and model fidelity are parameters of the node that simulates them (for
example ``effects: [drag, wind]``), so a scene simulates only what it names. Everything is
checked before anything starts; the first problem is reported as one line naming the file,
the key and what was expected.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from dataclasses import field
from pathlib import Path
from typing import Any

import yaml
from ament_index_python.packages import PackageNotFoundError
from ament_index_python.packages import get_package_prefix
from ament_index_python.packages import get_package_share_directory

from tether_bringup.errors import SceneError
from tether_bringup.node_group import GROUP_NAME
from tether_bringup.recorder_params import DEFAULT_EXCLUDE
from tether_bringup.sim_clock import MAX_RATE
from tether_common.parameters import ParamSpec
from tether_common.parameters import parameter_module
from tether_common.parameters import spec_table

LOCKSTEP_WINDOW = 0.05
"""Default lead of /clock over the slowest ack, s. A producer is then at most window + clock_step
ahead of a consumer: at 100 Hz, far fewer messages than a lockstep input's reader keeps
(``tether_common.lockstep.INPUT_DEPTH``) or the recorder's queue holds."""

TOP_LEVEL = {
    'description': ParamSpec('description', '', 'One-line description of the scene'),
    'duration': ParamSpec('duration', 60.0, 'Simulated time', 's', 1e-3, 1e7),
    'rate': ParamSpec('rate', 1.0, 'Real-time factor (or max: as fast as the slowest node)', '', 1e-3, 1000.0),
    'clock_step': ParamSpec('clock_step', 0.01, 'Sim time between /clock ticks', 's', 1e-4, 1.0),
    'lockstep_window': ParamSpec('lockstep_window', LOCKSTEP_WINDOW, 'Sim time /clock may lead the slowest node\'s ack '
                                 '(nodes on different cores overlap their ticks within it)', 's', 0.0, 0.1),
    'compose': ParamSpec('compose', True, 'Run the nodes whose packages register their class in one process '
                         '(the node group); false: each node in a process of its own'),
    'nodes': None,
    'record': None,
    'reports': ParamSpec('reports', [], 'Report functions module:function', item_type=str),
}
NODE_KEYS = ('package', 'executable', 'script', 'parameters', 'external', 'lockstep')
RESERVED_NAMES = ('tethersim', 'recorder', GROUP_NAME)
RECORD_KEYS = {'exclude': ParamSpec('exclude', [], 'Topics not recorded', item_type=str)}


@dataclass
class NodeConfig:
    """One node of a scene: how to start it and its validated parameters."""

    name: str
    command: list[str]
    parameters: dict
    package: str = ''
    executable: str = ''
    external: bool = False
    lockstep: bool = True


@dataclass
class Scene:
    """A validated scene."""

    path: Path
    name: str
    description: str
    duration: float
    rate: float
    clock_step: float
    nodes: list[NodeConfig]
    lockstep_window: float = LOCKSTEP_WINDOW
    compose: bool = True
    exclude: list[str] = field(default_factory=lambda: list(DEFAULT_EXCLUDE))
    reports: list[str] = field(default_factory=list)


def scenes_directory() -> Path:
    """Return the installed scenes directory of tether_bringup."""
    return Path(get_package_share_directory('tether_bringup')) / 'scenes'


def find_scene(name_or_path: str) -> Path:
    """Resolve a scene given by name (installed scenes) or by path to a YAML file."""
    candidate = Path(name_or_path)
    if candidate.suffix in ('.yaml', '.yml') or candidate.exists():
        if candidate.is_dir():
            raise SceneError(f'{name_or_path}: a directory, not a scene file (give a scene name or a YAML file)')
        if not candidate.is_file():
            raise SceneError(f'{name_or_path}: scene file not found')
        return candidate
    installed = scenes_directory() / f'{name_or_path}.yaml'
    if not installed.is_file():
        known = ', '.join(sorted(p.stem for p in scenes_directory().glob('*.yaml')))
        raise SceneError(f'{name_or_path}: no such scene (installed scenes: {known})')
    return installed


def list_scenes() -> list[tuple[str, str]]:
    """Return (name, description) of every installed scene."""
    result = []
    for path in sorted(scenes_directory().glob('*.yaml')):
        try:
            description = load_scene(path).description
        except SceneError as error:
            description = f'(invalid: {error})'
        result.append((path.stem, description))
    return result


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene file; raise :class:`SceneError` naming the first problem."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding='utf-8'))
    except FileNotFoundError:
        raise SceneError(f'{path}: scene file not found') from None
    except IsADirectoryError:
        raise SceneError(f'{path}: a directory, not a scene file') from None
    except UnicodeDecodeError as error:
        raise SceneError(f'{path}: not a UTF-8 text file (byte {error.start} is 0x{error.object[error.start]:02x}); '
                         'a scene is YAML in UTF-8') from None
    except OSError as error:
        raise SceneError(f'{path}: cannot read scene file ({error.strerror})') from None
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        where = f' at line {mark.line + 1}' if mark else ''
        raise SceneError(f'{path}: not valid YAML{where}') from None
    return scene_from_data(path, data)


def scene_from_data(path: Path, data: object) -> Scene:
    """Validate a scene's parsed YAML ``data`` as the file ``path`` (scripts are relative to it; errors name it)."""
    if not isinstance(data, dict):
        raise SceneError(f'{path}: expected a mapping of scene keys at the top level')

    def fail(key: str, reason: str) -> SceneError:
        return SceneError(f'{path}: {key}: {reason}')

    for key in data:
        if key not in TOP_LEVEL:
            raise fail(key, f'unknown key (expected one of {", ".join(TOP_LEVEL)})')
    values: dict[str, Any] = {}
    for key, spec in TOP_LEVEL.items():
        if spec is None:
            continue
        if key not in data:
            if key == 'description':
                raise fail(key, 'missing (expected a one-line string)')
            values[key] = spec.default
            continue
        if key == 'rate' and data[key] == 'max':
            values[key] = MAX_RATE
            continue
        reason = spec.check(data[key])
        if reason:
            raise fail(key, reason)
        values[key] = spec.coerce(data[key])

    for report in values['reports']:
        module, _, function = report.partition(':')
        if not module or not function:
            raise fail('reports', f'expected module:function, got {report!r}')

    exclude = list(DEFAULT_EXCLUDE)
    record = data.get('record') or {}
    if not isinstance(record, dict):
        raise fail('record', f'expected a mapping with keys {", ".join(RECORD_KEYS)}')
    for key, value in record.items():
        spec = RECORD_KEYS.get(key)
        if spec is None:
            raise fail(f'record.{key}', f'unknown key (expected one of {", ".join(RECORD_KEYS)})')
        reason = spec.check(value)
        if reason:
            raise fail(f'record.{key}', reason)
        exclude = sorted(set(exclude) | set(value))

    nodes_data = data.get('nodes')
    if not isinstance(nodes_data, dict) or not nodes_data:
        raise fail('nodes', 'expected a mapping of node names to node settings')
    nodes = [_node_config(path, name, settings, fail) for name, settings in nodes_data.items()]

    return Scene(path=path, name=path.stem, description=values['description'],
                 duration=values['duration'], rate=values['rate'], clock_step=values['clock_step'],
                 lockstep_window=values['lockstep_window'], compose=values['compose'],
                 nodes=nodes, exclude=exclude, reports=values['reports'])


def _node_config(path: Path, name: object, settings: object, fail) -> NodeConfig:
    key = f'nodes.{name}'
    if not isinstance(name, str) or not name.replace('_', 'a').isalnum() or name[0].isdigit():
        raise fail(key, 'node names must be letters, digits and underscores, not starting with a digit')
    if name in RESERVED_NAMES:
        raise fail(key, f'{name!r} names a process of the bringup itself (reserved: {", ".join(RESERVED_NAMES)})')
    if not isinstance(settings, dict):
        raise fail(key, 'expected a mapping with package/executable or script, and parameters')
    for setting in settings:
        if setting not in NODE_KEYS:
            raise fail(f'{key}.{setting}', f'unknown key (expected one of {", ".join(NODE_KEYS)})')
    parameters = settings.get('parameters') or {}
    if not isinstance(parameters, dict):
        raise fail(f'{key}.parameters', 'expected a mapping of parameter names to values')
    external = settings.get('external', False)
    lockstep = settings.get('lockstep', True)
    if not isinstance(lockstep, bool):
        raise fail(f'{key}.lockstep', f'expected true or false, got {lockstep!r}')
    if not isinstance(external, bool):
        raise fail(f'{key}.external', f'expected true or false, got {external!r}')

    if 'script' in settings:
        if 'package' in settings or 'executable' in settings:
            raise fail(key, 'give either script or package/executable, not both')
        script = settings['script']
        if not isinstance(script, str):
            raise fail(f'{key}.script', f'expected a path to a Python file, got {script!r}')
        script_path = (path.parent / script).resolve()
        if not script_path.is_file():
            raise fail(f'{key}.script', f'file not found: {script_path}')
        for parameter, value in parameters.items():
            if not _is_ros_value(value):
                raise fail(f'{key}.parameters.{parameter}', f'not a ROS parameter value: {value!r}')
        return NodeConfig(name=name, command=[sys.executable, str(script_path)], parameters=parameters,
                          external=external, lockstep=lockstep)

    for required in ('package', 'executable'):
        if not isinstance(settings.get(required), str):
            raise fail(f'{key}.{required}', 'missing (expected a string)')
    package, executable = settings['package'], settings['executable']
    try:
        prefix = Path(get_package_prefix(package))
    except (PackageNotFoundError, ValueError):
        if not external:
            raise fail(f'{key}.package', f'package {package!r} is not installed') from None
        return NodeConfig(name=name, command=[], parameters=parameters, package=package,
                          executable=executable, external=True, lockstep=lockstep)
    program = prefix / 'lib' / package / executable
    if not program.is_file():
        raise fail(f'{key}.executable', f'package {package} has no executable {executable!r}')
    specs = parameter_specs(package, executable)
    if specs is None:
        raise fail(f'{key}.executable', f'{package}/{executable} has no parameter specification '
                                        f'({package}.{executable}_params.PARAMETERS)')
    table = spec_table(specs)
    validated = {}
    for parameter, value in parameters.items():
        spec = table.get(parameter)
        if spec is None:
            raise fail(f'{key}.parameters.{parameter}',
                       f'unknown parameter of {package}/{executable} (expected one of {", ".join(table)})')
        reason = spec.check(value)
        if reason:
            raise fail(f'{key}.parameters.{parameter}', reason)
        validated[parameter] = spec.coerce(value)
    return NodeConfig(name=name, command=[str(program)], parameters=validated,
                      package=package, executable=executable, external=external, lockstep=lockstep)


def parameter_specs(package: str, executable: str) -> tuple[ParamSpec, ...] | None:
    """The declared parameters of a node (its registered parameters module's ``PARAMETERS``); None without them."""
    module = parameter_module(package, executable)
    return getattr(module, 'PARAMETERS', None) if module is not None else None


def _is_ros_value(value: object) -> bool:
    if isinstance(value, (bool, int, float, str)):
        return True
    if isinstance(value, list) and value:
        kinds = {bool if isinstance(v, bool) else type(v) for v in value}
        return len(kinds) == 1 and kinds <= {bool, int, float, str} or kinds == {int, float}
    return False

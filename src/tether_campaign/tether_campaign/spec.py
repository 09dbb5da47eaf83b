"""Campaign specs: a base scene, what varies over its runs, and how many; each run's scene from the spec and its index.

A spec is YAML::

    description: The default mission over three sea states and twenty seeds each.
    scene: outdoor_flight        # an installed scene's name, or a scene file relative to the spec
    count: 20                    # runs at each grid point (default 1)
    seed: 0                      # the campaign's root seed (default 0)
    set:                         # fixed overrides of every run
      duration: 120.0
    grid:                        # every combination of these values
      platform.profile: [hpr1, hpr2, hpr3]
    random:                      # a seeded draw for every run
      platform.seed: {range: [1, 1000000]}     # an integer in [a, b]
      uav.wind_speed: {uniform: [0.0, 8.0]}    # a float in [a, b)
    cpus: 1                      # CPUs a run reserves on the Ray cluster (default 1)
    retries: 2                   # a failed run is tried again this many times (default 2)

A key is ``node.parameter`` (any parameter of a node of the scene) or a top-level scene key
(``duration``, ``rate``, ``clock_step``, ``lockstep_window``, ``compose``). There are
``count`` x (product of the grid's sizes) runs; run ``i`` takes grid point ``i mod G``
(the grid points in row-major order of the keys as written, so the first runs cover every
point) and repeat ``i // G``. Its random draws come from
``numpy.random.SeedSequence(seed, spawn_key=(i, crc32(key)))``: every run is fixed by the
spec and its index alone, a key's draws do not change when another key is added, and the
drawn values are written into the run's scene file, which ``tethersim run`` runs alone to
the same messages.

Every run's scene is validated by the scene validation (:func:`tether_bringup.scene.scene_from_data`)
before anything starts; the first problem is one line naming the spec, the key and why.
"""

from __future__ import annotations

import copy
import itertools
import math
import zlib
from dataclasses import dataclass
from dataclasses import field
from pathlib import Path

import numpy as np
import yaml

from tether_bringup.errors import SceneError
from tether_bringup.errors import TethersimError
from tether_bringup.scene import Scene
from tether_bringup.scene import find_scene
from tether_bringup.scene import scene_from_data

SPEC_KEYS = ('description', 'scene', 'count', 'seed', 'set', 'grid', 'random', 'cpus', 'retries')
SCENE_KEYS = ('duration', 'rate', 'clock_step', 'lockstep_window', 'compose')
"""Top-level scene keys a campaign may vary (the nodes' parameters by ``node.parameter``)."""
DRAWS = ('uniform', 'range')
DEFAULT_RETRIES = 2


class SpecError(TethersimError):
    """A campaign spec is missing, malformed, or names an unknown node, parameter or a bad value."""


@dataclass(frozen=True)
class Draw:
    """A seeded random draw: ``uniform`` a float in [low, high), ``range`` an integer in [low, high]."""

    kind: str
    low: float
    high: float

    def sample(self, rng: np.random.Generator) -> float | int:
        """One value from ``rng``."""
        if self.kind == 'range':
            return int(rng.integers(int(self.low), int(self.high), endpoint=True))
        return float(rng.uniform(self.low, self.high))


@dataclass
class Campaign:
    """A validated campaign spec."""

    path: Path
    name: str
    description: str
    scene_path: Path
    base: dict
    count: int = 1
    seed: int = 0
    fixed: dict = field(default_factory=dict)
    grid: dict = field(default_factory=dict)
    random: dict = field(default_factory=dict)
    cpus: float = 1.0
    retries: int = DEFAULT_RETRIES

    @property
    def points(self) -> list[tuple]:
        """The grid's points (one empty point without a grid), keys in the spec's order."""
        return list(itertools.product(*self.grid.values()))

    @property
    def size(self) -> int:
        """The number of runs."""
        return self.count * len(self.points)

    @property
    def factors(self) -> list[str]:
        """The keys that vary between runs: the grid's, then the random draws'."""
        return [*self.grid, *self.random]

    def values(self, index: int) -> dict:
        """Run ``index``'s values of the fixed, grid and random keys."""
        if not 0 <= index < self.size:
            raise IndexError(f'run {index} of a campaign of {self.size}')
        points = self.points
        values = dict(self.fixed)
        values.update(zip(self.grid, points[index % len(points)]))
        for key, draw in self.random.items():
            sequence = np.random.SeedSequence(self.seed, spawn_key=(index, zlib.crc32(key.encode())))
            values[key] = draw.sample(np.random.default_rng(sequence))
        return values

    def scene_data(self, index: int) -> dict:
        """Run ``index``'s scene as YAML data: the base scene with its values, scripts by absolute path."""
        return apply(self.base, self.values(index), self.scene_path)

    def scene(self, index: int) -> Scene:
        """Run ``index``'s validated scene; raise :class:`SpecError` naming the spec key of a bad value."""
        values = self.values(index)
        try:
            return scene_from_data(self.scene_path, apply(self.base, values, self.scene_path))
        except SceneError as error:
            raise SpecError(self._explain(str(error), values, index)) from None

    def _explain(self, message: str, values: dict, index: int) -> str:
        """The scene validation's message about a run, as one naming the spec's key."""
        detail = message.removeprefix(f'{self.scene_path}: ')
        key, _, reason = detail.partition(': ')
        parts = key.split('.')
        spec_key = f'{parts[1]}.{parts[3]}' if len(parts) == 4 and parts[0] == 'nodes' else key
        section = next((name for name, keys in (('set', self.fixed), ('grid', self.grid), ('random', self.random))
                        if spec_key in keys), None)
        if section is None:
            return f'{self.path}: scene {self.scene_path}: {detail}'
        return f'{self.path}: {section}.{spec_key}: {reason} (run {index})'

    def run_name(self, index: int) -> str:
        """The name of run ``index``'s directory."""
        return f'run-{index:0{max(4, len(str(self.size - 1)))}d}'


def apply(base: dict, values: dict, scene_path: Path) -> dict:
    """A copy of the scene data ``base`` with ``values`` (``node.parameter`` or top-level key -> value) set and the
    nodes' scripts given by absolute path (the run's scene file lives elsewhere than ``scene_path``).
    """
    data = copy.deepcopy(base)
    for key, value in values.items():
        node, dot, parameter = key.partition('.')
        if dot:
            settings = data['nodes'][node]
            settings['parameters'] = dict(settings.get('parameters') or {})
            settings['parameters'][parameter] = value
        else:
            data[key] = value
    for settings in data['nodes'].values():
        if isinstance(settings, dict) and isinstance(settings.get('script'), str):
            settings['script'] = str((scene_path.parent / settings['script']).resolve())
    return data


def load_campaign(path: str | Path) -> Campaign:
    """Read and validate a campaign spec and every run's scene; raise :class:`SpecError` on the first problem."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except FileNotFoundError:
        raise SpecError(f'{path}: campaign spec not found') from None
    except OSError as error:
        raise SpecError(f'{path}: cannot read the campaign spec ({error.strerror})') from None
    except yaml.YAMLError as error:
        mark = getattr(error, 'problem_mark', None)
        raise SpecError(f'{path}: not valid YAML' + (f' at line {mark.line + 1}' if mark else '')) from None
    if not isinstance(data, dict):
        raise SpecError(f'{path}: expected a mapping of campaign keys ({", ".join(SPEC_KEYS)})')

    def fail(key: str, reason: str) -> SpecError:
        return SpecError(f'{path}: {key}: {reason}')

    for key in data:
        if key not in SPEC_KEYS:
            raise fail(str(key), f'unknown key (expected one of {", ".join(SPEC_KEYS)})')
    scene_name = data.get('scene')
    if not isinstance(scene_name, str) or not scene_name:
        raise fail('scene', 'missing (expected an installed scene\'s name or a scene file)')
    relative = path.parent / scene_name
    try:
        scene_path = find_scene(str(relative) if relative.suffix in ('.yaml', '.yml') else scene_name).resolve()
        base_scene_data = yaml.safe_load(scene_path.read_text())
        scene_from_data(scene_path, base_scene_data)
    except (SceneError, yaml.YAMLError) as error:
        raise fail('scene', str(error).splitlines()[0]) from None
    campaign = Campaign(path=path, name=path.stem, description=str(data.get('description', '')),
                        scene_path=scene_path, base=base_scene_data,
                        count=_integer(data, 'count', 1, 1, fail), seed=_integer(data, 'seed', 0, 0, fail),
                        retries=_integer(data, 'retries', DEFAULT_RETRIES, 0, fail))
    cpus = data.get('cpus', 1)
    if isinstance(cpus, bool) or not isinstance(cpus, (int, float)) or not 0 < cpus <= 1024:
        raise fail('cpus', f'expected a number of CPUs in (0, 1024], got {cpus!r}')
    campaign.cpus = float(cpus)
    seen: set[str] = set()
    for section in ('set', 'grid', 'random'):
        entries = data.get(section) or {}
        if not isinstance(entries, dict):
            raise fail(section, 'expected a mapping of node.parameter (or scene key) to values')
        for key, value in entries.items():
            where = f'{section}.{key}'
            _check_key(key, base_scene_data, scene_path, fail, where)
            if key in seen:
                raise fail(where, 'given in more than one of set, grid and random')
            seen.add(key)
            if section == 'set':
                campaign.fixed[key] = value
            elif section == 'grid':
                if not isinstance(value, list) or not value:
                    raise fail(where, f'expected a non-empty list of values, got {value!r}')
                campaign.grid[key] = value
            else:
                campaign.random[key] = _draw(value, fail, where)
    for index in range(campaign.size):
        campaign.scene(index)
    return campaign


def _integer(data: dict, key: str, default: int, low: int, fail) -> int:
    value = data.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or value < low:
        raise fail(key, f'expected an integer >= {low}, got {value!r}')
    return value


def _check_key(key: object, scene: dict, scene_path: Path, fail, where: str) -> None:
    """Raise if ``key`` names no node of the scene, or no top-level key a campaign may vary."""
    if not isinstance(key, str):
        raise fail(where, 'expected node.parameter or a scene key')
    node, dot, parameter = key.partition('.')
    if not dot:
        if key not in SCENE_KEYS:
            raise fail(where, f'expected node.parameter or one of the scene keys {", ".join(SCENE_KEYS)}')
        return
    nodes = scene.get('nodes') or {}
    if node not in nodes:
        raise fail(where, f'no node {node!r} in scene {scene_path.stem} (nodes: {", ".join(nodes)})')
    if not parameter or '.' in parameter:
        raise fail(where, 'expected node.parameter')


def _draw(value: object, fail, where: str) -> Draw:
    """A random draw ``{uniform: [a, b]}`` or ``{range: [a, b]}``."""
    if not isinstance(value, dict) or len(value) != 1 or next(iter(value)) not in DRAWS:
        raise fail(where, f'expected {{uniform: [a, b]}} or {{range: [a, b]}}, got {value!r}')
    kind, bounds = next(iter(value.items()))
    numbers = isinstance(bounds, list) and len(bounds) == 2 and all(
        isinstance(b, (int, float)) and not isinstance(b, bool) and math.isfinite(b) for b in bounds)
    if not numbers:
        raise fail(where, f'{kind}: expected [a, b] of two numbers, got {bounds!r}')
    low, high = bounds
    if kind == 'range' and not (isinstance(low, int) and isinstance(high, int) and low <= high):
        raise fail(where, f'range: expected two integers a <= b, got {bounds!r}')
    if kind == 'uniform' and not low < high:
        raise fail(where, f'uniform: expected a < b, got {bounds!r}')
    return Draw(kind, float(low), float(high))

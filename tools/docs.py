"""``make docs``: regenerate the documentation's result blocks from the commands that produce them.

Every measured figure the README and ``docs/*.md`` show sits in a block

    <!-- generated: NAME -->
    ... (written by this script, never by hand)
    <!-- end -->

and each NAME is one generator below, which runs the command the block names and writes its
output. The scene runs and analyses run in a scratch directory; the paths they print are
rewritten to ``runs/...``, the directory the block's command names, so a block is the same
wherever it was made. Blocks of deterministic results (lockstep runs, recorded bags, the scene
files) are the same on every run; ``--check`` regenerates them and fails, naming each block,
when the text in the docs differs (``test/test_docs.py`` does that in CI for the fast ones and
one full scene run). Timing blocks depend on the machine and carry the date, the commit and the
command instead; ``--check`` skips them.

``make docs`` also writes ``docs/img/outdoor_flight.png``, the README's picture: the mission
report's flight and tether plots of the default run, scaled down.

Run:  ./tethersim-env python tools/docs.py [--check] [--work DIR] [NAME ...]
      (no NAME: every block; ``--list`` names them)
"""

from __future__ import annotations

import argparse
import datetime
import difflib
import re
import subprocess
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / 'src' / 'tether_bringup' / 'scenes'
PICTURE = ROOT / 'docs' / 'img' / 'outdoor_flight.png'
BLOCK = re.compile(r'(<!-- generated: (?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- end -->)', re.S)
MISSION_SCENE = 'outdoor_flight'
SURROGATE_SCENES = {'jonswap': ('surrogate_catenary', 'surrogate_taut', 'surrogate_locked'),
                    'hpr2': ('surrogate_catenary_hpr', 'surrogate_taut_hpr', 'surrogate_locked_hpr')}
ESTIMATOR_BAGS = ('bags/estimator-hpr3-40s', 'bags/estimator-still-40s')
BAG_MARK = 'bag: '
"""The run summary's first line after its timing lines: the bag's (``tether_bringup.bag_info``)."""


def doc_files() -> list[Path]:
    """The documentation the blocks live in: the README and every ``docs/*.md``."""
    return [ROOT / 'README.md', *sorted((ROOT / 'docs').glob('*.md'))]


class Work:
    """The scratch directory of one regeneration; each scene is run at most once in it."""

    def __init__(self, directory: Path):
        self.directory = directory
        self._runs: dict[str, Path] = {}

    def shown(self, text: str) -> str:
        """``text`` with the scratch directory written as ``runs`` (the directory the docs' commands name) and
        the checkout's paths relative to it, so a block does not depend on where it was made.
        """
        return text.replace(str(self.directory), 'runs').replace(f'{ROOT}/', '')

    def tethersim(self, *args: str) -> str:
        """Run ``./tethersim ARGS``; its standard output, or SystemExit naming the command that failed."""
        result = subprocess.run([str(ROOT / 'tethersim'), *args], cwd=ROOT, capture_output=True, text=True)
        if result.returncode != 0:
            raise SystemExit(f'docs: ./tethersim {self.shown(" ".join(args))} failed ({result.returncode}):\n'
                             f'{result.stderr[-2000:]}')
        return result.stdout

    def run(self, scene: str) -> Path:
        """The run directory of a full run of ``scene`` at ``--rate max`` (made on first use)."""
        if scene not in self._runs:
            out = self.directory / scene
            print(f'docs: ./tethersim run {scene} --rate max --out runs/{scene}', file=sys.stderr, flush=True)
            self.tethersim('run', scene, '--rate', 'max', '--out', str(out))
            self._runs[scene] = out
        return self._runs[scene]

    def ran(self, scene: str) -> bool:
        """Whether ``scene`` was run in this regeneration."""
        return scene in self._runs


def _fenced(command: str, output: str) -> str:
    return f'```text\n$ {command}\n{output.rstrip()}\n```\n'


def _default_profile() -> str:
    from psr_platform_sim.platform_params import PARAMETERS

    return next(str(spec.default) for spec in PARAMETERS if spec.name == 'profile')


def scene_table(work: Work) -> str:
    """The installed scenes: what each shows (its description up to the first colon), platform motion, length, reports."""
    default_profile = _default_profile()
    rows = ['| scene | what it shows | platform motion | sim time | reports |', '|---|---|---|---|---|']
    for path in sorted(SCENES.glob('*.yaml')):
        scene = yaml.safe_load(path.read_text(encoding='utf-8'))
        what = ' '.join(str(scene.get('description', '')).split()).split(': ')[0].rstrip('.')
        platform = (scene.get('nodes') or {}).get('platform')
        profile = f'`{(platform.get("parameters") or {}).get("profile", default_profile)}`' if platform else '—'
        reports = ', '.join(f'`{r.split(":")[-1]}`' for r in scene.get('reports', [])) or '—'
        rows.append(f'| `{path.stem}` | {what} | {profile} | {scene.get("duration", 0):g} s | {reports} |')
    return '\n'.join(rows) + '\n'


def mission(work: Work) -> str:
    """``tethersim report mission`` of a full run of the default scene (the report the scene's summary prints)."""
    run = work.run(MISSION_SCENE)
    out = work.directory / 'report-mission'
    text = work.tethersim('report', 'mission', str(run), '--out', str(out))
    return (f'After `./tethersim run {MISSION_SCENE} --rate max --out runs/{MISSION_SCENE}` (what `make run` runs):\n\n'
            + _fenced(f'./tethersim report mission runs/{MISSION_SCENE} --out runs/report-mission', work.shown(text)))


def topics(work: Work) -> str:
    """The default run's recorded topics: type, publisher → subscribers, rate from the bag, QoS."""
    run = work.run(MISSION_SCENE)
    result = subprocess.run([str(ROOT / 'tethersim-env'), 'python', str(ROOT / 'tools' / 'topic_table.py'), str(run)],
                            cwd=ROOT, capture_output=True, text=True, check=True)
    command = f'./tethersim-env python tools/topic_table.py runs/{MISSION_SCENE}'
    return f'Made by `{command}` after `./tethersim run {MISSION_SCENE}`:\n\n{result.stdout.rstrip()}\n'


def surrogate(work: Work) -> str:
    """``tethersim report surrogate`` over full runs of the surrogate scenes, one report per platform profile."""
    blocks = []
    for profile, scenes in SURROGATE_SCENES.items():
        runs = [str(work.run(scene)) for scene in scenes]
        out = work.directory / f'report-surrogate-{profile}'
        text = work.tethersim('report', 'surrogate', *runs, '--out', str(out))
        command = ' '.join(('./tethersim report surrogate', *(f'runs/{s}' for s in scenes),
                            f'--out runs/report-surrogate-{profile}'))
        blocks.append(_fenced(command, work.shown(text)))
    return '\n'.join(blocks)


def _report_lines(summary: list[str]) -> list[str]:
    """The scene's report lines of a run summary: after the bag's topic table, without the plot list."""
    start = next(i for i, line in enumerate(summary) if line.startswith(BAG_MARK)) + 3
    while start < len(summary) and summary[start].startswith('/'):
        start += 1
    return [line for line in summary[start:] if not line.startswith('plot: ')]


def surrogate_estimator(work: Work) -> str:
    """The reports of a full run of ``surrogate_estimator``: the estimate-fed reel beside Table 6.2."""
    summary = (work.run('surrogate_estimator') / 'summary.txt').read_text(encoding='utf-8').splitlines()
    return _fenced('./tethersim run surrogate_estimator --rate max --out runs/surrogate_estimator   # summary.txt, '
                   'reports', work.shown('\n'.join(_report_lines(summary))))


def estimator(work: Work) -> str:
    """``tethersim estimator evaluate`` over the reference bags kept for evaluation."""
    out = work.directory / 'estimator-evaluate'
    text = work.tethersim('estimator', 'evaluate', *ESTIMATOR_BAGS, '--out', str(out))
    return _fenced(f'./tethersim estimator evaluate {" ".join(ESTIMATOR_BAGS)} --out runs/estimator-evaluate',
                   work.shown(text))


def _commit() -> str:
    head = subprocess.run(['git', 'rev-parse', '--short', 'HEAD'], cwd=ROOT, capture_output=True, text=True)
    dirty = subprocess.run(['git', 'status', '--porcelain', '--untracked-files=no'], cwd=ROOT, capture_output=True,
                           text=True)
    return head.stdout.strip() + ('+local changes' if dirty.stdout.strip() else '') if head.returncode == 0 else 'unknown'


def timing(work: Work) -> str:
    """The default run's speed and CPU from its summary, with the date, commit and command (machine-dependent)."""
    summary = (work.run(MISSION_SCENE) / 'summary.txt').read_text(encoding='utf-8').splitlines()
    kept = summary[:next((i for i, line in enumerate(summary) if line.startswith(BAG_MARK)), len(summary))]
    stamp = datetime.datetime.now(datetime.UTC).strftime('%Y-%m-%d %H:%M UTC')
    return (f'Measured {stamp}, commit {_commit()}, on the 2-core machine the project is built on:\n\n'
            + _fenced(f'./tethersim run {MISSION_SCENE} --rate max --out runs/{MISSION_SCENE}   # summary.txt, first lines',
                      work.shown('\n'.join(kept))))


def picture(work: Work) -> None:
    """docs/img/outdoor_flight.png: the default run's flight and tether plots stacked, scaled to 900 px wide."""
    from PIL import Image

    run = work.run(MISSION_SCENE)
    parts = [Image.open(next(run.glob(f'*{suffix}.png'))).convert('RGB') for suffix in ('_flight', '_tether')]
    width = 900
    parts = [p.resize((width, round(p.height * width / p.width)), Image.Resampling.LANCZOS) for p in parts]
    picture = Image.new('RGB', (width, sum(p.height for p in parts)), 'white')
    top = 0
    for part in parts:
        picture.paste(part, (0, top))
        top += part.height
    PICTURE.parent.mkdir(parents=True, exist_ok=True)
    picture.quantize(colors=64).save(PICTURE, optimize=True)


@dataclass(frozen=True)
class Generator:
    """One kind of block: how it is made and whether it is the same on every machine."""

    make: Callable[[Work], str]
    deterministic: bool


GENERATORS = {
    'scenes': Generator(scene_table, True),
    'mission': Generator(mission, True),
    'topics': Generator(topics, True),
    'timing': Generator(timing, False),
    'surrogate': Generator(surrogate, True),
    'estimator': Generator(estimator, True),
    'surrogate-estimator': Generator(surrogate_estimator, True),
}


def blocks(text: str) -> list[str]:
    """The names of the generated blocks in a document, in order."""
    return [m['name'] for m in BLOCK.finditer(text)]


def regenerate(names: list[str], work: Work, check: bool) -> list[str]:
    """Make the named blocks; write them into the docs, or with ``check`` return the stale ones (unified diffs).

    Every block is made before any file is read for writing, so a file edited while the runs
    go on keeps its edits.
    """
    present = {path: blocks(path.read_text(encoding='utf-8')) for path in doc_files()}
    for path, found in present.items():
        unknown = sorted(set(found) - set(GENERATORS))
        if unknown:
            raise SystemExit(f'docs: {path.relative_to(ROOT)}: unknown generated block(s) {", ".join(unknown)}')
    wanted = [name for name in names if any(name in found for found in present.values())]
    made = {name: GENERATORS[name].make(work) for name in wanted}
    stale = []
    for path in present:
        text = path.read_text(encoding='utf-8')

        def replace(match: re.Match, path: Path = path) -> str:
            name = match['name']
            if name not in made:
                return match[0]
            if check and made[name] != match['body']:
                diff = difflib.unified_diff(match['body'].splitlines(), made[name].splitlines(), 'in the docs',
                                            'from the command', lineterm='', n=1)
                stale.append(f'{path.relative_to(ROOT)}: block "{name}" is stale:\n' + '\n'.join(diff))
            return match[1] + made[name] + match[4]

        new = BLOCK.sub(replace, text)
        if not check and new != text:
            path.write_text(new, encoding='utf-8')
            print(f'docs: updated {path.relative_to(ROOT)}', file=sys.stderr)
    return stale


def main(argv: list[str] | None = None) -> int:
    """Regenerate (or check) the named blocks, every block without names."""
    parser = argparse.ArgumentParser(prog='tools/docs.py', description=__doc__.split('\n')[0])
    parser.add_argument('names', nargs='*', help=f'blocks to make (default: all): {", ".join(GENERATORS)}')
    parser.add_argument('--check', action='store_true', help='fail when a deterministic block differs; write nothing')
    parser.add_argument('--work', type=Path, help='scratch directory for the runs (default: a temporary one)')
    parser.add_argument('--list', action='store_true', help='print each block name with the files holding it')
    args = parser.parse_args(argv)
    if args.list:
        for path in doc_files():
            for name in blocks(path.read_text(encoding='utf-8')):
                print(f'{name}\t{path.relative_to(ROOT)}')
        return 0
    unknown = sorted(set(args.names) - set(GENERATORS))
    if unknown:
        parser.error(f'unknown block(s) {", ".join(unknown)}; known: {", ".join(GENERATORS)}')
    names = args.names or list(GENERATORS)
    if args.check:
        names = [n for n in names if GENERATORS[n].deterministic]
    with tempfile.TemporaryDirectory(prefix='tethersim-docs-') as scratch:
        work = Work((args.work or Path(scratch)).resolve())
        work.directory.mkdir(parents=True, exist_ok=True)
        stale = regenerate(names, work, args.check)
        if not args.check and work.ran(MISSION_SCENE):
            picture(work)
            print(f'docs: wrote {PICTURE.relative_to(ROOT)}', file=sys.stderr)
    if stale:
        print('\n\n'.join(stale) + '\n\ndocs: run `make docs` and commit the result', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())

"""The documentation a user follows: links resolve, commands exist, the quickstart works, no result is stale.

- every relative link of README.md and docs/*.md names a file of the checkout, and an anchor
  a heading of that file;
- every ``tethersim`` command in a fenced ``sh`` block of the README is one that
  ``tethersim --help`` lists (with its subcommand in ``tethersim COMMAND --help``, and each
  of its options in the command's help), every ``make`` target one the Makefile has;
- the quickstart's replay line runs as written (but for ``--out``);
- the generated blocks of deterministic results are what their commands print now
  (``tools/docs.py --check``): the scene table and the estimator evaluation from the
  reference bags, and the default mission and its topics from one full run of
  ``outdoor_flight``; the surrogate tables from full runs of the surrogate scenes in
  test_docs_surrogate.py.
"""

from __future__ import annotations

import importlib.util
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from uav_bridge.mission.report import analyse
from uav_bridge.mission.report import load_run

from default_mission_checks import check_default_mission
from tethersim_testing import tethersim

ROOT = Path(__file__).resolve().parent.parent
DOCS = [ROOT / 'README.md', *sorted((ROOT / 'docs').glob('*.md'))]
LINK = re.compile(r'(?<!!)\[[^\]]*\]\(([^)\s]+)\)|!\[[^\]]*\]\(([^)\s]+)\)')
FENCE = re.compile(r'^```(\w*)\n(.*?)^```', re.S | re.M)


def _prose(text: str) -> str:
    """The text without its fenced blocks, where brackets are code, not links."""
    return FENCE.sub('', text)


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces as hyphens."""
    text = re.sub(r'[`*_]', '', heading.strip().lower())
    return re.sub(r'[^\w\- ]', '', text).replace(' ', '-')


def anchors(path: Path) -> set[str]:
    """The anchors of a markdown file's headings."""
    return {slug(m[1]) for m in re.finditer(r'^#+ (.*)$', _prose(path.read_text(encoding='utf-8')), re.M)}


def relative_links(path: Path) -> list[str]:
    """The links of a markdown file that point into the checkout (not http, not mailto)."""
    targets = [a or b for a, b in LINK.findall(_prose(path.read_text(encoding='utf-8')))]
    return [t for t in targets if not re.match(r'[a-z]+:', t)]


def sh_commands(path: Path) -> list[list[str]]:
    """Each command line of the file's fenced ``sh`` blocks, continuation lines joined, comments dropped."""
    commands = []
    for language, body in FENCE.findall(path.read_text(encoding='utf-8')):
        if language != 'sh':
            continue
        for line in body.replace('\\\n', ' ').splitlines():
            lexer = shlex.shlex(line, posix=True, punctuation_chars=True)
            lexer.whitespace_split = True
            words = list(lexer)
            command: list[str] = []
            for word in [*words, ';']:
                if word in (';', '&&', '||', '|', 'do', 'then', 'done'):
                    if command:
                        commands.append(command)
                    command = []
                else:
                    command.append(word)
    return commands


def _listed(help_text: str) -> set[str]:
    """The (sub)command names an argparse help lists: the words indented by four spaces."""
    return set(re.findall(r'^ {4}(\w[\w-]*)', help_text, re.M))


@pytest.mark.parametrize('path', DOCS, ids=[p.relative_to(ROOT).as_posix() for p in DOCS])
def test_every_relative_link_resolves(path):
    broken = []
    for target in relative_links(path):
        file, _, anchor = target.partition('#')
        resolved = (path.parent / file).resolve() if file else path
        if not resolved.exists():
            broken.append(f'{target}: no such file')
        elif anchor and resolved.suffix == '.md' and anchor not in anchors(resolved):
            broken.append(f'{target}: no heading "{anchor}" in {resolved.relative_to(ROOT)}')
    assert not broken, f'{path.relative_to(ROOT)}: ' + '; '.join(broken)


def test_the_docs_have_links_and_the_readme_sh_blocks_have_commands():
    assert len(relative_links(ROOT / 'README.md')) >= 10
    assert sum(c[0] in ('./tethersim', 'tethersim') for c in sh_commands(ROOT / 'README.md')) >= 5


def test_every_command_and_option_of_the_readme_sh_blocks_is_in_tethersim_help():
    commands = [c for c in sh_commands(ROOT / 'README.md') if c[0] in ('./tethersim', 'tethersim', 'make')]
    top = tethersim('--help', check=True).stdout
    known: set[str] = _listed(top)
    sub_help: dict = {}
    phony = set(re.search(r'^\.PHONY:(.*)$', (ROOT / 'Makefile').read_text(), re.M)[1].split())
    missing = []
    for command in commands:
        if command[0] == 'make':
            missing += [f'make {t}' for t in command[1:] if '=' not in t and t not in phony]
            continue
        if len(command) < 2 or command[1] not in known:
            missing.append(' '.join(command[:2]))
            continue
        name = command[1]
        if name not in sub_help:
            sub_help[name] = tethersim(name, '--help', check=True).stdout
        subcommands = _listed(sub_help[name])
        if subcommands and (len(command) < 3 or command[2] not in subcommands):
            missing.append(' '.join(command[:3]))
            continue
        path = tuple(command[1:3] if subcommands else command[1:2])
        if path not in sub_help:
            sub_help[path] = tethersim(*path, '--help', check=True).stdout
        missing += [f'{" ".join(path)} {word}' for word in command if word.startswith('--') and word not in sub_help[path]]
    assert not missing, f'README sh blocks name commands tethersim --help does not list: {missing}'


def test_the_quickstart_replay_line_runs_as_written(tmp_path):
    line = next(c for c in sh_commands(ROOT / 'README.md') if c[:2] == ['./tethersim', 'replay'])
    out = line.index('--out')
    args = [*line[2:out], '--out', str(tmp_path / 'replay'), *line[out + 2:]]
    result = subprocess.run([str(ROOT / 'tethersim'), 'replay', *args], cwd=ROOT, capture_output=True, text=True,
                            timeout=300)
    assert result.returncode == 0, result.stderr[-2000:]
    info = tethersim('bag', 'info', str(tmp_path / 'replay'), check=True).stdout
    assert re.search(r'^/estimate/relative\s+\S+\s+[1-9]\d*', info, re.M), info


def _check(names: list[str], work: Path, timeout: float) -> subprocess.CompletedProcess:
    return subprocess.run([str(ROOT / 'tethersim-env'), 'python', str(ROOT / 'tools' / 'docs.py'), '--check',
                           '--work', str(work), *names], cwd=ROOT, capture_output=True, text=True, timeout=timeout)


def test_the_scene_table_and_the_estimator_table_are_what_their_commands_print(tmp_path):
    result = _check(['scenes', 'estimator'], tmp_path, 300)
    assert result.returncode == 0, result.stderr[-4000:]


@pytest.fixture(scope='module')
def default_run(tmp_path_factory):
    """The docs' check of the mission and topics blocks, from one full run of the default scene (kept in its work
    directory for the default mission's own checks, default_mission_checks.py).
    """
    work = tmp_path_factory.mktemp('docs-default')
    return _check(['mission', 'topics'], work, 1800), work / 'outdoor_flight'


def test_the_default_mission_and_its_topics_are_what_a_full_run_prints(default_run):
    result, _ = default_run
    assert result.returncode == 0, result.stderr[-4000:]


def test_the_default_mission_lands_on_the_pad_without_an_abort_a_trip_or_fouling(default_run):
    """The README's flagship outcome, asserted from the same run (test_default_mission.py's checks)."""
    _, run = default_run
    check_default_mission(analyse(load_run(run / 'bag')))


def test_a_changed_figure_in_a_block_is_reported_stale(tmp_path, monkeypatch):
    """The check can fail: a copy of the checkout's scene block with one figure changed is stale."""
    spec = importlib.util.spec_from_file_location('docs_tool', ROOT / 'tools' / 'docs.py')
    module = importlib.util.module_from_spec(spec)
    monkeypatch.setitem(sys.modules, spec.name, module)
    spec.loader.exec_module(module)
    made = module.scene_table(module.Work(tmp_path))
    changed = made.replace('| 255 s |', '| 254 s |', 1)
    assert changed != made
    doc = tmp_path / 'doc.md'
    doc.write_text(f'text\n<!-- generated: scenes -->\n{changed}<!-- end -->\n')
    module.doc_files = lambda: [doc]
    module.ROOT = tmp_path
    stale = module.regenerate(['scenes'], module.Work(tmp_path), check=True)
    assert len(stale) == 1 and 'block "scenes" is stale' in stale[0] and '254 s' in stale[0]

"""The README's package dependencies are the workspace's: one direction, declared, and the only imports.

Each line of the README's list names a package and the project packages it may import, all
on earlier lines. The test reads every ``package.xml`` and every import under ``src/`` (the
package's module and its tests), so a new import of a simulator from another simulator, or
of the estimator from a simulator, fails here until the README and the ``package.xml`` say so.
"""

from __future__ import annotations

import ast
import re
import xml.etree.ElementTree as ElementTree
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SOURCES = ROOT / 'src'
PACKAGES = sorted(path.parent.name for path in SOURCES.glob('*/package.xml'))


def _readme_dependencies() -> dict[str, list[str]]:
    """The README's list, in its order: package -> the packages it may import."""
    text = (ROOT / 'README.md').read_text()
    block = re.search(r'<!-- package dependencies -->\n```\n(.*?)```', text, re.S)
    assert block, 'README.md has no package dependencies block'
    listed = {}
    for line in block.group(1).strip().splitlines():
        name, _, deps = line.partition('<-')
        listed[name.strip()] = [dep.strip() for dep in deps.split(',') if dep.strip()]
    return listed


def _declared(package: str) -> set[str]:
    """The project packages a package.xml depends on."""
    root = ElementTree.parse(SOURCES / package / 'package.xml').getroot()
    tags = ('depend', 'exec_depend', 'build_depend')
    return {element.text for tag in tags for element in root.iter(tag) if element.text in PACKAGES}


def _imported(package: str) -> set[str]:
    """The other project packages a package's Python files import (tests included)."""
    found = set()
    for path in (SOURCES / package).rglob('*.py'):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                found.add(node.module.split('.')[0])
            elif isinstance(node, ast.Import):
                found.update(alias.name.split('.')[0] for alias in node.names)
    return found & set(PACKAGES) - {package}


def test_readme_lists_every_package_once_and_in_one_direction():
    listed = _readme_dependencies()
    assert sorted(listed) == PACKAGES
    order = list(listed)
    for package, deps in listed.items():
        later = [dep for dep in deps if order.index(dep) >= order.index(package)]
        assert not later, f'{package} depends on {later}, listed at or after it'


@pytest.mark.parametrize('package', PACKAGES)
def test_package_xml_declares_what_readme_lists(package):
    assert _declared(package) == set(_readme_dependencies()[package])


@pytest.mark.parametrize('package', PACKAGES)
def test_imports_stay_within_the_listed_dependencies(package):
    assert _imported(package) <= set(_readme_dependencies()[package])

"""Print the numba cache directory for the compiled code in this checkout's ``src``.

numba keys a cached function on its own file only: a kernel that calls a compiled function,
or reads a constant, of another file keeps running the old machine code from its cache after
that file changes (``fem_kernels.advance`` calls ``bodies.body_step``, which compiles
``winch.spool_rate_step``). ``tethersim-env`` therefore points ``NUMBA_CACHE_DIR`` at a
directory named by a digest of every module that imports numba and of every project module
they import, transitively: an edit to any of them, or a ``git pull`` that changes one, starts
a fresh cache; an edit elsewhere keeps it.

    python tools/numba_cache_dir.py SRC CACHE_ROOT     # prints CACHE_ROOT/<digest>
"""

from __future__ import annotations

import ast
import hashlib
import sys
from pathlib import Path

DIGEST_CHARS = 16


def module_file(src: Path, module: str) -> Path | None:
    """The file of a project module under the colcon layout ``src/<package>/<package>/...``."""
    parts = module.split('.')
    base = src / parts[0] / Path(*parts)
    for candidate in (base.with_suffix('.py'), base / '__init__.py'):
        if candidate.is_file():
            return candidate
    return None


def imported_modules(path: Path) -> list[tuple[str, tuple[str, ...]]]:
    """(module, names) of each absolute module-level import in a file (compiled code reads
    module globals only): ``import a.b`` gives ('a.b', ()), ``from a.b import c, d`` gives
    ('a.b', ('c', 'd')).
    """
    found: list[tuple[str, tuple[str, ...]]] = []
    for node in ast.parse(path.read_text(encoding='utf-8'), filename=str(path)).body:
        if isinstance(node, ast.Import):
            found.extend((alias.name, ()) for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.append((node.module, tuple(alias.name for alias in node.names)))
    return found


def imported_files(src: Path, path: Path) -> set[Path]:
    """The project files a file's compiled code can reach: for ``from a.b import c`` the module
    ``a.b.c`` when c is one, else ``a.b`` (whose package ``__init__`` compiles nothing of c).
    """
    files: set[Path] = set()
    for module, names in imported_modules(path):
        submodules = [module_file(src, f'{module}.{name}') for name in names]
        if not names or None in submodules:
            submodules.append(module_file(src, module))
        files.update(p for p in submodules if p is not None)
    return files


def uses_numba(path: Path) -> bool:
    """Whether a file imports numba (read as text first: most files do not mention it)."""
    if 'numba' not in path.read_text(encoding='utf-8'):
        return False
    return any(module == 'numba' or module.startswith('numba.') for module, _ in imported_modules(path))


def compiled_sources(src: Path) -> list[Path]:
    """Every package module that imports numba and the project modules they reach by import."""
    pending = [path for path in sorted(src.glob('*/*/**/*.py')) if '/test/' not in path.as_posix()
               and uses_numba(path)]
    seen: set[Path] = set()
    while pending:
        path = pending.pop()
        if path in seen:
            continue
        seen.add(path)
        pending.extend(found for found in imported_files(src, path) if found not in seen)
    return sorted(seen)


def cache_digest(src: Path) -> str:
    """A digest of the compiled sources' paths (relative to src) and contents."""
    digest = hashlib.sha256()
    for path in compiled_sources(src):
        digest.update(path.relative_to(src).as_posix().encode() + b'\0' + path.read_bytes() + b'\0')
    return digest.hexdigest()[:DIGEST_CHARS]


def main(argv: list[str]) -> int:
    """Print CACHE_ROOT/<digest of SRC's compiled sources>."""
    if len(argv) != 2:
        print('usage: numba_cache_dir.py SRC CACHE_ROOT', file=sys.stderr)
        return 2
    src, root = Path(argv[0]), Path(argv[1])
    print(root / cache_digest(src))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))

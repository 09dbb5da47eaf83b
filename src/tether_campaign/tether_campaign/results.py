"""A campaign's results: one row per run, kept as ``rows/<run>.json`` while it goes and written as a table.

``results.parquet`` (pyarrow) and ``results.csv`` beside it hold the finished runs in index
order: the run (``index``, ``run``, ``status`` ok/failed, ``attempts``, ``reason``, ``node``,
``node_id``, ``hostname``, ``task_time``, ``command`` that reruns it alone), its values of
the campaign's varied keys (``node.parameter`` columns) and its figures (``figures.json``:
the run's real-time factor and CPU, the scene reports' figures).
"""

from __future__ import annotations

import csv
import json
import os
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

ROWS = 'rows'
PARQUET = 'results.parquet'
CSV = 'results.csv'
RUN_COLUMNS = ('index', 'run', 'status', 'attempts', 'reason', 'node', 'node_id', 'hostname', 'task_time', 'command')


def _atomic_write(path: Path, text: str) -> None:
    temporary = path.with_name(path.name + '.tmp')
    temporary.write_text(text)
    os.replace(temporary, path)


def write_row(campaign_dir: Path, row: dict) -> None:
    """Record one finished run (atomically: a row file is whole or absent)."""
    directory = campaign_dir / ROWS
    directory.mkdir(exist_ok=True)
    _atomic_write(directory / f'{row["run"]}.json', json.dumps(row, indent=1) + '\n')


def read_rows(campaign_dir: Path) -> list[dict]:
    """The finished runs' rows, in index order."""
    rows = [json.loads(path.read_text()) for path in sorted((campaign_dir / ROWS).glob('*.json'))]
    return sorted(rows, key=lambda row: row['index'])


def columns(rows: list[dict]) -> list[str]:
    """The table's columns: the run's, then the others in order of first appearance."""
    names = list(RUN_COLUMNS)
    for row in rows:
        names += [name for name in row if name not in names]
    return names


def _column(values: list) -> pa.Array:
    """A column of one type: flags, integers, numbers (integers and floats together), or text (a mix as text)."""
    kinds = {type(v) for v in values if v is not None}
    if kinds == {bool}:
        return pa.array(values, type=pa.bool_())
    if kinds == {int}:
        return pa.array(values, type=pa.int64())
    if kinds == {int, float} or kinds == {float}:
        return pa.array([None if v is None else float(v) for v in values], type=pa.float64())
    return pa.array([None if v is None else str(v) for v in values], type=pa.string())


def write_tables(campaign_dir: Path) -> int:
    """Write ``results.parquet`` and ``results.csv`` from the rows; return the number of rows."""
    rows = read_rows(campaign_dir)
    names = columns(rows)
    table = pa.table({name: _column([row.get(name) for row in rows]) for name in names})
    temporary = campaign_dir / (PARQUET + '.tmp')
    pq.write_table(table, temporary)
    os.replace(temporary, campaign_dir / PARQUET)
    temporary = campaign_dir / (CSV + '.tmp')
    with open(temporary, 'w', newline='') as file:
        writer = csv.DictWriter(file, fieldnames=names)
        writer.writeheader()
        for row in rows:
            writer.writerow({name: '' if row.get(name) is None else row.get(name) for name in names})
    os.replace(temporary, campaign_dir / CSV)
    return len(rows)


def read_table(campaign_dir: Path) -> list[dict]:
    """``results.parquet`` as a list of rows."""
    return pq.read_table(campaign_dir / PARQUET).to_pylist()

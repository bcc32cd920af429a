"""Sweeps and Monte-Carlo runs: many simulations of one model with values varied, as one
table.

By default the runs go to the Rust library, which derives the equations once and runs on all
cores. Given an ``executor`` (any :class:`concurrent.futures.Executor`: a
``ProcessPoolExecutor``, ``dask.distributed.Client(...).get_executor()``, a Ray pool's), the
runs are cut into chunks and each chunk is submitted as one task: the model travels as its
text and its values, and each worker runs its chunk on all of its own cores. A chunk whose
task fails (a worker died, lost its connection) is submitted once more; if it fails again its
runs are in the table with their parameters, ``outcome`` ``"lost"`` and the error — never
dropped.
"""

from __future__ import annotations

import itertools
import math
from ._model import Model, _want_frame

TYPE_CHECKING = False  # typing is not imported at run time: `import lagrange` stays quick
if TYPE_CHECKING:
    from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

    Grid = Union[Mapping[str, Sequence[float]], Sequence[Mapping[str, float]]]

__all__ = ["sweep", "Table"]


class Table(dict):
    """A sweep's table when pandas is not installed: a ``dict`` of column name → NumPy
    array (one row per run), columns in order, with :attr:`array` (float columns) and
    :attr:`columns`."""

    def __init__(self, columns: Dict[str, Any]) -> None:
        super().__init__(columns)
        self.columns = list(columns)


def sweep(
    model: Model,
    grid: Grid,
    *,
    executor: Any = None,
    chunk_size: Optional[int] = None,
    retries: int = 1,
    as_frame: Optional[bool] = None,
    **options: Any,
):
    """Runs ``model`` once for each set of values in ``grid`` and returns one table.

    ``grid`` is either a mapping of names to values — every combination is run (a grid),
    ``{"k": [10, 20, 30], "theta": [0.1, 0.2]}`` is six runs — or a sequence of mappings, one
    per run (Monte-Carlo draws). Names are parameters, inputs or initial values.

    ``options`` are :meth:`Model.simulate`'s: ``t_end``, ``method``, ``rtol``, ``atol``,
    ``stop_when``, ``through_contact_loss``, ``max_steps``.

    Without ``executor`` the runs go to Rust on all cores. With one, chunks of
    ``chunk_size`` runs (default: the runs cut into 32 chunks) are submitted to it; a failed chunk is retried ``retries`` times, then its runs are reported
    with ``outcome == "lost"`` and the exception in ``error``.

    The table has one row per run, in the grid's order: the varied names, ``final_`` and each
    simulation column (the last row of the run), ``steps``, ``outcome`` (``"finished"``,
    ``"event"``, ``"failed …"``, ``"error"``, ``"lost"``) and ``error`` (``None`` when it ran).
    A pandas ``DataFrame`` when pandas is installed, else a :class:`Table`.
    """
    import numpy as np

    names, rows = _plan(grid)
    values = np.array(rows, dtype=float).reshape(len(rows), len(names))
    if executor is None:
        parts = model._native.sweep(names, values, **options)
        columns, finals, steps, outcomes, errors = parts
    else:
        columns, finals, steps, outcomes, errors = _spread(
            model, names, values, executor, chunk_size, retries, options
        )
    return _table(names, values, columns, finals, steps, outcomes, errors, as_frame)


def _plan(grid: Grid) -> Tuple[List[str], List[List[float]]]:
    """The names and one row of values per run."""
    if hasattr(grid, "keys"):  # a mapping of names to values
        names = list(grid)
        axes = [list(_as_values(grid[name])) for name in names]
        return names, [list(row) for row in itertools.product(*axes)]
    runs = list(grid)
    if not runs:
        raise ValueError("the grid has no runs")
    names = list(runs[0])
    for run in runs:
        if list(run) != names:
            raise ValueError(f"every run must set the same names; {list(run)} differs from {names}")
    return names, [[float(run[name]) for name in names] for run in runs]


def _as_values(axis: Any) -> Sequence[float]:
    if isinstance(axis, (int, float)):
        return [float(axis)]
    return [float(v) for v in axis]


def _run_chunk(model: Model, names: List[str], values: Any, options: Dict[str, Any]):
    """One task on a worker: a chunk of runs, on all of the worker's cores."""
    return model._native.sweep(names, values, **options)


def _spread(model, names, values, executor, chunk_size, retries, options):
    import numpy as np

    total = len(values)
    if total == 0:
        raise ValueError("the grid has no runs")
    size = chunk_size or max(1, math.ceil(total / 32))
    chunks = [values[i : i + size] for i in range(0, total, size)]
    futures = [executor.submit(_run_chunk, model, names, chunk, options) for chunk in chunks]
    results: List[Any] = []
    for chunk, future in zip(chunks, futures):
        results.append(_settle(executor, future, model, names, chunk, options, retries))
    columns = next((r[0] for r in results if not isinstance(r, BaseException)), None)
    if columns is None:
        # Every chunk was lost: the columns come from one local run's shape.
        columns = model._native.sweep(names, values[:1], **options)[0]
    finals, steps, outcomes, errors = [], [], [], []
    for chunk, result in zip(chunks, results):
        if isinstance(result, BaseException):
            finals.append(np.full((len(chunk), len(columns)), np.nan))
            steps += [0] * len(chunk)
            outcomes += ["lost"] * len(chunk)
            errors += [f"{type(result).__name__}: {result}"] * len(chunk)
        else:
            finals.append(result[1])
            steps += list(result[2])
            outcomes += list(result[3])
            errors += list(result[4])
    return columns, np.vstack(finals), steps, outcomes, errors


def _settle(executor, future, model, names, chunk, options, retries):
    """The chunk's result, retrying a failed task; the last exception when every try failed."""
    for attempt in range(retries + 1):
        try:
            return future.result()
        except Exception as error:  # a lost worker, a broken pool, an error in the task
            if attempt == retries:
                return error
            future = executor.submit(_run_chunk, model, names, chunk, options)
    raise AssertionError("unreachable")


def _table(names, values, columns, finals, steps, outcomes, errors, as_frame):
    import numpy as np

    table: Dict[str, Any] = {}
    for i, name in enumerate(names):
        table[name] = values[:, i]
    for j, column in enumerate(columns):
        table["final_" + column] = finals[:, j]
    table["steps"] = np.asarray(steps, dtype=np.int64)
    table["outcome"] = np.asarray(outcomes, dtype=object)
    table["error"] = np.asarray(errors, dtype=object)
    if _want_frame(as_frame):
        import pandas as pd

        return pd.DataFrame(table)
    return Table(table)

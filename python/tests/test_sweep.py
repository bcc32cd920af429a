"""Sweeps: on all cores in Rust, spread over a ProcessPoolExecutor and over a Dask
LocalCluster, with the same table; a failed chunk retried once, else reported by its
parameters."""

import concurrent.futures

import numpy as np
import pytest

import lagrange

GRID = {"k": [10.0, 20.0, 30.0, 40.0], "theta": [0.1, 0.2, 0.3]}


def finals_one_by_one(model, names, rows, t_end):
    out = []
    for row in rows:
        run = model.with_values(**dict(zip(names, row))).simulate(t_end, as_frame=False)
        out.append(run.array[-1])
    return np.array(out)


def test_a_grid_in_rust_is_every_combination_run_alone(seed_7_1):
    table = lagrange.sweep(seed_7_1, GRID, t_end=1.0, as_frame=False)
    assert isinstance(table, lagrange.Table)
    assert list(table["k"]) == [10.0] * 3 + [20.0] * 3 + [30.0] * 3 + [40.0] * 3
    assert list(table["theta"][:3]) == [0.1, 0.2, 0.3]
    assert list(table["outcome"]) == ["finished"] * 12
    assert all(e is None for e in table["error"])
    expected = finals_one_by_one(seed_7_1, ["k", "theta"], zip(table["k"], table["theta"]), 1.0)
    finals = np.column_stack([table["final_" + c] for c in
                              ("t", "x", "theta", "x_d", "theta_d", "energy_error", "constraint_drift")])
    assert np.array_equal(finals, expected)


def test_monte_carlo_runs_are_a_list_of_values(seed_7_1):
    rng = np.random.default_rng(1)
    runs = [{"m_B": m, "l": l} for m, l in rng.uniform(0.5, 1.5, size=(5, 2))]
    table = lagrange.sweep(seed_7_1, runs, t_end=0.5, as_frame=False)
    assert list(table["m_B"]) == [r["m_B"] for r in runs]
    with pytest.raises(ValueError, match="the same names"):
        lagrange.sweep(seed_7_1, [{"k": 1.0}, {"g": 2.0}], t_end=0.5)


def test_a_run_that_cannot_start_is_reported_by_its_parameters(seed_7_1):
    # A negative mass makes the mass matrix indefinite: that run fails, the others run.
    table = lagrange.sweep(seed_7_1, {"m_A": [2.0, -1.0]}, t_end=0.5, as_frame=False)
    assert table["outcome"][0] == "finished"
    assert table["m_A"][1] == -1.0
    assert table["outcome"][1] != "finished"


def test_a_process_pool_gives_the_same_table(seed_7_1):
    local = lagrange.sweep(seed_7_1, GRID, t_end=1.0, as_frame=False)
    with concurrent.futures.ProcessPoolExecutor(max_workers=2) as pool:
        spread = lagrange.sweep(seed_7_1, GRID, t_end=1.0, executor=pool, chunk_size=5,
                                as_frame=False)
    assert list(spread) == list(local)
    for column in local:
        assert list(spread[column]) == list(local[column]), column


def test_a_dask_local_cluster_gives_the_same_table(seed_7_1):
    distributed = pytest.importorskip("distributed", reason="dask[distributed] is installed by .ci/run")
    local = lagrange.sweep(seed_7_1, GRID, t_end=1.0)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            spread = lagrange.sweep(seed_7_1, GRID, t_end=1.0, executor=client.get_executor())
    assert spread.equals(local)


class FlakyExecutor(concurrent.futures.Executor):
    """Runs tasks in this process; the tasks whose number is in `fail` raise as a lost
    worker would."""

    def __init__(self, fail):
        self.fail = set(fail)
        self.submitted = 0

    def submit(self, fn, *args, **kwargs):
        future = concurrent.futures.Future()
        number = self.submitted
        self.submitted += 1
        if number in self.fail:
            future.set_exception(ConnectionError(f"worker of task {number} died"))
        else:
            future.set_result(fn(*args, **kwargs))
        return future


def test_a_failed_chunk_is_retried(seed_7_1):
    local = lagrange.sweep(seed_7_1, GRID, t_end=1.0, as_frame=False)
    flaky = FlakyExecutor(fail={1})
    spread = lagrange.sweep(seed_7_1, GRID, t_end=1.0, executor=flaky, chunk_size=4, as_frame=False)
    assert flaky.submitted == 4  # three chunks, the second once more
    for column in local:
        assert list(spread[column]) == list(local[column]), column


def test_a_chunk_that_fails_twice_is_reported_not_lost(seed_7_1):
    flaky = FlakyExecutor(fail={1, 3})
    table = lagrange.sweep(seed_7_1, GRID, t_end=1.0, executor=flaky, chunk_size=4, as_frame=False)
    assert len(table["k"]) == 12
    assert list(table["outcome"]) == ["finished"] * 4 + ["lost"] * 4 + ["finished"] * 4
    assert list(table["k"][4:8]) == [20.0, 20.0, 30.0, 30.0]
    assert list(table["theta"][4:8]) == [0.2, 0.3, 0.1, 0.2]  # the parameters, kept
    assert table["error"][4] == "ConnectionError: worker of task 3 died"
    assert np.isnan(table["final_x"][4:8]).all()

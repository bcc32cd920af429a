"""Simulation against SciPy's integration of `model.rhs`; equilibria and linearizations as
arrays against the command line's JSON."""

import json
import subprocess

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from conftest import SEED_7_1


def cli_json(cli, *args):
    out = subprocess.run([cli, *args, str(SEED_7_1), "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def test_simulate_agrees_with_scipy_on_the_rhs(seed_7_1):
    run = seed_7_1.simulate(3.0, rtol=1e-11, atol=1e-12, as_frame=False)
    assert run.ending == "finished" and run.t == 3.0
    assert run.columns == ["t", "x", "theta", "x_d", "theta_d", "energy_error", "constraint_drift"]
    y0 = seed_7_1.initial_state()
    assert np.array_equal(run.array[0, 1:5], y0)
    scipy_run = solve_ivp(seed_7_1.rhs, (0.0, 3.0), y0, method="DOP853", rtol=1e-12, atol=1e-12)
    assert scipy_run.success
    assert np.allclose(run.array[-1, 1:5], scipy_run.y[:, -1], rtol=0, atol=1e-7)
    assert abs(run["energy_error"]).max() < 1e-8


def test_simulate_gives_a_dataframe_with_pandas(seed_7_1):
    pandas = pytest.importorskip("pandas", reason="pandas is installed by .ci/run")
    frame = seed_7_1.simulate(1.0, output_step=0.1)
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame["t"].round(12)) == [round(0.1 * i, 12) for i in range(11)]
    assert frame.attrs["ending"] == "finished"


def test_simulate_options_are_checked(seed_7_1):
    with pytest.raises(ValueError, match="unknown method `euler`"):
        seed_7_1.simulate(1.0, method="euler")
    with pytest.raises(TypeError):
        seed_7_1.simulate(1.0, tolerance=1e-3)
    stopped = seed_7_1.simulate(10.0, stop_when="theta", as_frame=False)
    assert stopped.ending == "event" and stopped.t < 10.0


def test_equilibria_are_the_command_lines(seed_7_1, cli):
    expected = cli_json(cli, "equilibria")
    found = seed_7_1.equilibria()
    assert found.shape == (len(expected["equilibria"]), 2)
    for row, equilibrium in zip(found, expected["equilibria"]):
        assert list(row) == [equilibrium["values"][q] for q in expected["coordinates"]]
    assert np.allclose(found, [[0.0, 0.0], [0.0, np.pi]])


def test_linearizations_are_the_command_lines(seed_7_1, cli):
    expected = cli_json(cli, "linearize")["linearized"]
    found = seed_7_1.linearize()
    assert len(found) == len(expected) == 2
    for ours, theirs in zip(found, expected):
        for key in ("M0", "C0", "K0", "B0", "A", "B", "modes"):
            assert np.array_equal(getattr(ours, key), np.array(theirs[key], dtype=float)), key
        assert np.array_equal(ours.eigenvalues.real, [re for re, _ in theirs["eigenvalues"]])
        assert np.array_equal(ours.eigenvalues.imag, [im for _, im in theirs["eigenvalues"]])
        assert ours.stable == theirs["stable"]
    hanging = found[0]
    assert hanging.stable
    assert np.allclose(hanging.M0, [[3.0, 0.5], [0.5, 0.25]])
    assert np.allclose(hanging.K0, [[30.0, 0.0], [0.0, 4.905]])
    # K0 φ = ω² M0 φ for each mode.
    for omega, mode in zip(hanging.frequencies, hanging.modes):
        assert np.allclose(hanging.K0 @ mode, omega**2 * hanging.M0 @ mode, atol=1e-9)

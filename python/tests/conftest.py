"""Shared fixtures of the Python package's tests: the repository's paths, the seed's 7.1 and
the command-line binary the arrays are compared with."""

import os
import pathlib
import shutil

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SEED_7_1 = ROOT / "examples" / "seed" / "7.1-cart-pendulum.lag"


@pytest.fixture(scope="session")
def seed_7_1():
    import lagrange

    return lagrange.Model.from_file(SEED_7_1)


@pytest.fixture(scope="session")
def cli():
    """The `lagrange` binary: $LAGRANGE_BIN, else the workspace's debug or release build, else
    one on PATH. Missing, the test fails (CI builds it before this suite runs)."""
    candidates = [os.environ.get("LAGRANGE_BIN")]
    candidates += [str(ROOT / "target" / p / "lagrange") for p in ("debug", "release")]
    candidates.append(shutil.which("lagrange"))
    for candidate in candidates:
        if candidate and os.access(candidate, os.X_OK):
            return candidate
    pytest.fail("no lagrange binary: build it (cargo build) or set LAGRANGE_BIN")

#!/usr/bin/env bash
# The Whipple bicycle (issue 18) side by side: lagrange from examples/whipple-bicycle.lag to
# the eigenvalues at v = 5 m/s (and a 100-point speed sweep), against SymPy's own bicycle
# test, sympy/physics/mechanics/tests/test_kane3.py::test_bicycle (KanesMethod, then
# KanesMethod.linearize, then the A matrix checked against its stored values), run from the
# installed SymPy package as it ships. Makes its own virtual environment (bench/.venv,
# git-ignored) with a pinned SymPy; builds lagrange in release.
#   bench/bicycle/run.sh              both, SymPy bounded by CAP seconds (default 1800)
#   CAP=600 bench/bicycle/run.sh
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$root/bench/.venv"
cap="${CAP:-1800}"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet sympy==1.14.0
(cd "$root" && cargo build --release --quiet -p lagrange-cli)
lagrange="$root/target/release/lagrange"
model="$root/examples/whipple-bicycle.lag"

echo "== lagrange: model file to the eigenvalues at v = 5 (farm-bench, 10 runs)"
farm-bench -n 10 -- "$lagrange" linearize "$model" --set v=5 --format json
echo "== lagrange: 100-point sweep of v over 0..10 with the stability changes (farm-bench, 5 runs)"
farm-bench -n 5 -- "$lagrange" linearize "$model" --sweep v=0..10 --steps 100 --format json
echo "== SymPy $("$venv/bin/python" -c 'import sympy; print(sympy.__version__)'): test_bicycle, one run, bounded at ${cap} s"
farm-bench -n 1 --warmup 0 --timeout "$cap" -- "$venv/bin/python" -c \
    'from sympy.physics.mechanics.tests.test_kane3 import test_bicycle; test_bicycle(); print("test_bicycle passed")'

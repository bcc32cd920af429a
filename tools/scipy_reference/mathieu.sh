#!/usr/bin/env bash
# Regenerate crates/lagrange/tests/data/mathieu_scipy.csv: the monodromy matrix of Mathieu's
# equation x'' + (δ + ε cos t) x = 0 over one period 2π on a (δ, ε) grid, integrated by
# SciPy's DOP853 at rtol = atol = 1e-12 (independent of lagrange), with its trace: since
# det Φ = 1, x = 0 is stable when |tr Φ| < 2. Makes its own virtual environment in
# tools/.venv (git-ignored).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet numpy scipy
exec "$venv/bin/python" "$root/tools/scipy_reference/mathieu_chart.py" \
    "$root/crates/lagrange/tests/data/mathieu_scipy.csv"

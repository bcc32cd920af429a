#!/usr/bin/env bash
# Regenerate tests/data/simulation/*.csv: SymPy derives the equations of motion of independent
# models of our examples (Lagrange II written out here, not read from lagrange), SciPy's DOP853
# integrates them at rtol = atol = 1e-12. Makes its own virtual environment in tools/.venv
# (git-ignored).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet sympy==1.14.0 numpy scipy
exec "$venv/bin/python" "$root/tools/scipy_reference/simulate_reference.py" "$@"

#!/usr/bin/env bash
# Regenerate crates/lagrange/tests/data/kkt_*.json: the equilibria, multipliers and reduced
# frequencies of the constrained examples (four-bar, slider-crank, Cartesian pendulum, Atwood
# machine), each system stated by hand in kkt_reference.py and solved with NumPy/SciPy, not
# read from lagrange. Makes its own virtual environment in tools/.venv (git-ignored).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet numpy scipy
exec "$venv/bin/python" "$root/tools/kkt_reference/kkt_reference.py" "$root/crates/lagrange/tests/data"

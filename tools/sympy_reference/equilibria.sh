#!/usr/bin/env bash
# Regenerate tests/data/equilibria/*.json: equilibria and linearizations computed by SymPy's
# LagrangesMethod (independent models written here, not read from our files).
# Uses the same virtual environment as run.sh (tools/.venv, git-ignored, pinned SymPy).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet sympy==1.14.0 numpy
exec "$venv/bin/python" "$root/tools/sympy_reference/equilibria_reference.py" "$@"

#!/usr/bin/env bash
# Regenerate tests/data/eom/*.json: SymPy's LagrangesMethod on independent models of our examples.
# Makes its own virtual environment in tools/.venv (git-ignored) with pinned SymPy.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet sympy==1.14.0 numpy
exec "$venv/bin/python" "$root/tools/sympy_reference/eom_reference.py" "$@"

#!/usr/bin/env bash
# Regenerate tests/data/reactions/*.json: reactions by Newton's law in SymPy, independently of
# lagrange. Makes its own virtual environment in tools/.venv (git-ignored) with pinned SymPy.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet sympy==1.14.0 numpy
exec "$venv/bin/python" "$root/tools/sympy_reference/reactions.py" "$@"

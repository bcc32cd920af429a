#!/usr/bin/env bash
# Regenerate crates/lagrange/tests/data/rolling_disk.json: the rolling disk's equations by
# Newton–Euler, integrated by SciPy's DOP853 (tools/scipy_reference/rolling_disk.py). Makes its
# own virtual environment in tools/.venv (git-ignored), as run.sh does.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet numpy scipy
exec "$venv/bin/python" "$root/tools/scipy_reference/rolling_disk.py" "$@"

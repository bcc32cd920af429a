#!/usr/bin/env bash
# Every expression string of `lagrange eom --format json`, on every example model, read by
# SymPy's sympify and evaluated: the same numbers as lagrange's (tools/json_sympy/check.py).
# Makes its own virtual environment in tools/.venv-json (git-ignored); it reuses a SymPy
# already installed on the system when there is one, else installs the pinned version (which
# needs the network).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv-json"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv --system-site-packages "$venv"
fi
if ! "$venv/bin/python" -c "import sympy" 2>/dev/null; then
    "$venv/bin/pip" install --quiet sympy==1.14.0
fi
numbers="$(mktemp -d)"
trap 'rm -rf "$numbers"' EXIT
LAGRANGE_JSON_NUMBERS="$numbers" cargo test --quiet --manifest-path "$root/Cargo.toml" \
    -p lagrange-report --test eom_json every_string_reads_back >/dev/null
exec "$venv/bin/python" "$root/tools/json_sympy/check.py" "$numbers"

#!/usr/bin/env bash
# Every expression string of `lagrange eom --format json`, on every example model and on
# generated models (crates/lagrange/tests/generated_models.rs), read by SymPy's sympify and
# evaluated: the same numbers as lagrange's (tools/json_sympy/check.py). Run by CI (.ci/run).
#
# Makes its own virtual environment in tools/.venv-json (git-ignored): `python3 -m venv`
# (on Debian, without python3-venv, it installs that package with apt-get when it can, as
# .ci/run does for other tools), then reuses a SymPy already installed on the system when
# there is one, else installs the pinned version from PyPI (which needs the network).
# GENERATED (default 12) models are generated.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/tools/.venv-json"
generated="${GENERATED:-12}"
if [ ! -x "$venv/bin/python" ]; then
    if ! python3 -m venv --system-site-packages "$venv" 2>/dev/null; then
        rm -rf "$venv"
        if command -v apt-get >/dev/null 2>&1; then
            sudo=""
            [ "$(id -u)" -ne 0 ] && sudo="sudo"
            $sudo apt-get install -y -qq python3-venv >/dev/null || {
                $sudo apt-get update -qq && $sudo apt-get install -y -qq python3-venv >/dev/null; }
        fi
        python3 -m venv --system-site-packages "$venv"
    fi
fi
if ! "$venv/bin/python" -c "import sympy" 2>/dev/null; then
    "$venv/bin/python" -m pip install --quiet sympy==1.14.0
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/models" "$work/numbers"
LAGRANGE_GENERATED_MODELS="$work/models" LAGRANGE_GENERATED_COUNT="$generated" \
    LAGRANGE_GENERATED_SKIP_SLOW=1 cargo test --quiet --manifest-path "$root/Cargo.toml" \
    -p lagrange --test generated_models write_models -- --ignored --exact >/dev/null
echo "$(ls "$work/models" | wc -l) generated models, and the examples"
LAGRANGE_JSON_NUMBERS="$work/numbers" LAGRANGE_JSON_MODELS="$work/models" \
    cargo test --quiet --manifest-path "$root/Cargo.toml" \
    -p lagrange-report --test eom_json every_string_reads_back >/dev/null
"$venv/bin/python" "$root/tools/json_sympy/check.py" "$work/numbers"

#!/usr/bin/env bash
# Simulation speed, lagrange vs SymPy lambdify (cse=True) + SciPy solve_ivp, side by side in
# one run: one right-hand side evaluation, and a whole 10 s simulation at rtol 1e-9,
# atol 1e-11 (or RTOL, ATOL from the environment) with the same method on both sides —
# lagrange dopri5 against SciPy RK45 (Dormand–Prince 5(4)) and lagrange dop853 against SciPy
# DOP853 — best of 5 interleaved repetitions, with the evaluations each side took. Models:
# the planar n-link pendulum of bench/models/nlink.sh. Makes its own venv in bench/.venv
# (git-ignored).
# Usage: bench/simulate/run.sh [N …]   (default: 2 10)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
venv="$root/bench/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet sympy==1.14.0 numpy scipy
target="${CARGO_TARGET_DIR:-$root/target}"
cargo build --quiet --release -p lagrange-cli --manifest-path "$root/Cargo.toml"
cargo build --quiet --release -p lagrange --example rhs_timing \
    --manifest-path "$root/Cargo.toml"
rtol="${RTOL:-1e-9}"
atol="${ATOL:-1e-11}"
sizes=("$@")
if [ ${#sizes[@]} -eq 0 ]; then sizes=(2 10); fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "10 s runs at rtol $rtol, atol $atol; best of 5 interleaved repetitions"
printf '%-3s %-16s %11s %7s %11s %7s %7s   %s\n' n "method (SciPy)" "lagrange" evals "SciPy" nfev ratio "RHS lagrange / SciPy"
for n in "${sizes[@]}"; do
    model="$work/nlink-$n.lag"
    "$root/bench/models/nlink.sh" "$n" > "$model"
    rhs=$("$target/release/examples/rhs_timing" "$model" 200000 | sed -n 's/rhs_ns=\([0-9.]*\).*/\1/p')
    "$venv/bin/python" "$root/bench/simulate/scipy_side.py" "$n" "$target/release/lagrange" \
        "$model" "$rtol" "$atol" > "$work/side-$n.txt"
    py_rhs=$(sed -n 's/^rhs //p' "$work/side-$n.txt")
    grep -v '^rhs ' "$work/side-$n.txt" | while read -r method ms evals py_ms nfev; do
        peer=RK45
        [ "$method" = dop853 ] && peer=DOP853
        awk -v n="$n" -v m="$method ($peer)" -v a="$ms" -v e="$evals" -v b="$py_ms" -v f="$nfev" \
            -v r="$rhs" -v pr="$py_rhs" 'BEGIN{
            printf "%-3s %-16s %8.2f ms %7d %8.1f ms %7d %6.0f×   %.3f / %.1f µs (%.0f×)\n",
                n, m, a, e, b, f, b/a, r/1000, pr, pr*1000/r }'
    done
done

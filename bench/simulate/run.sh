#!/usr/bin/env bash
# Simulation speed, lagrange vs SymPy lambdify + SciPy solve_ivp, side by side in one run:
# one right-hand side evaluation, and a whole 10 s simulation at rtol 1e-8, atol 1e-10 with the
# same Dormand–Prince 5(4) method (lagrange dopri5, SciPy RK45). Models: the planar n-link
# pendulum of bench/models/nlink.sh. Makes its own venv in bench/.venv (git-ignored).
# Usage: bench/simulate/run.sh [N …]   (default: 2 5 10)
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
sizes=("$@")
if [ ${#sizes[@]} -eq 0 ]; then sizes=(2 5 10); fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
printf '%-4s %12s %12s %8s %12s %12s %8s\n' n "rhs lagrange" "rhs scipy" ratio "10 s lagr." "10 s scipy" ratio
for n in "${sizes[@]}"; do
    model="$work/nlink-$n.lag"
    "$root/bench/models/nlink.sh" "$n" > "$model"
    rhs=$("$target/release/examples/rhs_timing" "$model" 200000 | sed -n 's/rhs_ns=\([0-9.]*\).*/\1/p')
    # Best of 5 runs of the whole simulation; the summary's wall time excludes loading and
    # deriving (SciPy's excludes its derivation too), and with --output-step 10 only the two
    # end rows are formatted, as solve_ivp formats none.
    sim=$(for _ in 1 2 3 4 5; do
        "$target/release/lagrange" simulate "$model" --t-end 10 --rtol 1e-8 --atol 1e-10 \
            --output-step 10 --out /dev/null 2>&1 | sed -n 's/.*evaluations, \([0-9.]*\) \(µs\|ms\|s\),.*/\1 \2/p'
    done | awk '{v=$1; if($2=="µs")v/=1000; if($2=="s")v*=1000; if(min==""||v<min)min=v} END{print min}')
    read -r py_rhs py_sim < <("$venv/bin/python" "$root/bench/simulate/scipy_side.py" "$n")
    awk -v n="$n" -v a="$rhs" -v b="$py_rhs" -v c="$sim" -v d="$py_sim" 'BEGIN{
        printf "%-4s %9.3f µs %9.1f µs %7.0f× %9.2f ms %9.1f ms %7.0f×\n", n, a/1000, b, b*1000/a, c, d, d/c }'
done

#!/usr/bin/env bash
# Deriving the planar n-link pendulum: lagrange (`derive_timing --same-work`: parse, check,
# lower, K, V, Lagrange's equations, M and f in normal form) against SymEngine doing the same
# derivation directly (symengine_side.py), side by side in one run, interleaved, best of
# several cold runs each (issue 20). Makes its own venv (bench/.venv, git-ignored).
#   bench/compare/symengine.sh [N ...]        (default: 5 10 20 40)
# With BEFORE=path/to/an/older/derive_timing, that binary is interleaved too (a before/after
# column in the same run). On a loaded machine run it as `nice -n -20 …` (both sides alike).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$root/bench/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet symengine==0.14.1
(cd "$root" && cargo build --release --quiet -p lagrange-model --example derive_timing)
timer="${CARGO_TARGET_DIR:-$root/target}/release/examples/derive_timing"
sizes=("$@")
if [ ${#sizes[@]} -eq 0 ]; then sizes=(5 10 20 40); fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
before="${BEFORE:-}"
if [ -n "$before" ]; then
    printf '%-4s %14s %14s %14s %8s %8s\n' n before lagrange symengine before× ratio
else
    printf '%-4s %14s %14s %8s\n' n lagrange symengine ratio
fi
min() { awk -v a="$1" -v b="$2" 'BEGIN{print (b < a) ? b : a}'; }
for n in "${sizes[@]}"; do
    "$root/bench/models/nlink.sh" "$n" > "$work/nlink.lag"
    ours=1e9; peer=1e9; old=1e9
    # Interleaved rounds, so that both sides see the same load; the peer's rounds are fewer
    # where one derivation takes seconds.
    rounds=5; if [ "$n" -ge 40 ]; then rounds=2; fi
    for ((r = 0; r < rounds; r++)); do
        if [ -n "$before" ]; then
            old=$(min "$old" "$("$before" "$work/nlink.lag" --same-work)")
        fi
        ours=$(min "$ours" "$("$timer" "$work/nlink.lag" --same-work)")
        peer=$(min "$peer" "$("$venv/bin/python" "$here/symengine_side.py" "$n" 1)")
    done
    if [ -n "$before" ]; then
        awk -v n="$n" -v o="$old" -v a="$ours" -v b="$peer" 'BEGIN{
            printf "%-4s %11.2f ms %11.2f ms %11.2f ms %7.1f× %7.1f×\n",
                n, o * 1000, a * 1000, b * 1000, b / o, b / a }'
    else
        awk -v n="$n" -v a="$ours" -v b="$peer" 'BEGIN{
            printf "%-4s %11.2f ms %11.2f ms %7.1f×\n", n, a * 1000, b * 1000, b / a }'
    fi
done

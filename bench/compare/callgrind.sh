#!/usr/bin/env bash
# Instructions of one right-hand-side evaluation, counted by callgrind where the machine's
# timing noise hides the difference (issue 20): two runs with different call counts, so that
# the model's derivation and compilation cancel out.
#   bench/compare/callgrind.sh lagrange MODEL.lag [tree|dense]   lagrange's rhs (rhs_timing)
#   bench/compare/callgrind.sh kernel N                         the hand-written n-link kernel
# Needs the release examples (rhs_timing, nlink_kernel). Pinocchio's timer is built with
# -march=native, which valgrind does not run on this machine (it stops at the first AVX-512
# instruction), so Pinocchio is compared by time only.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
examples="${CARGO_TARGET_DIR:-$root/target}/release/examples"
count() {  # instructions of a whole run
    local out
    out="$(mktemp)"
    valgrind --tool=callgrind --callgrind-out-file="$out" "$@" >/dev/null 2>&1
    callgrind_annotate "$out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}'
    rm -f "$out"
}
per_call() {  # per_call CALLS1 CALLS2 EVALUATIONS_PER_CALL command… (CALLS goes where @ is)
    local a="$1" b="$2" k="$3"
    shift 3
    local one two
    one="$(count "${@/@/$a}")"
    two="$(count "${@/@/$b}")"
    echo $(((two - one) / ((b - a) * k)))
}
case "${1:-}" in
    lagrange) per_call 200 1200 5 "$examples/rhs_timing" "$2" @ ${3:-} ;;
    kernel) per_call 200 1200 7 "$examples/nlink_kernel" "$2" @ kernel ;;
    *) echo "usage: callgrind.sh lagrange MODEL [tree|dense] | kernel N" >&2; exit 2 ;;
esac

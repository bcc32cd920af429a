#!/usr/bin/env bash
# A 200-run simulation sweep, derived once (this tree) against a binary that derived the
# equations again for every run (main before the `lagrange` library crate, a7ae01c), side by
# side in one run: the best of 3 wall times of
#   lagrange simulate MODEL --sweep th1=0..1 --steps 199 --t-end 1
# on the planar n-link pendulum (bench/models/nlink.sh) for n = 2, 5, 10.
# Usage: bench/sweep/run.sh OLD_LAGRANGE_BINARY [N …]
#   OLD_LAGRANGE_BINARY: e.g. built by
#     git worktree add /tmp/old a7ae01c && (cd /tmp/old && cargo build --release -p lagrange-cli)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
old="${1:?usage: bench/sweep/run.sh OLD_LAGRANGE_BINARY [N …]}"
shift
target="${CARGO_TARGET_DIR:-$root/target}"
cargo build --quiet --release -p lagrange-cli --manifest-path "$root/Cargo.toml"
new="$target/release/lagrange"
sizes=("$@")
if [ ${#sizes[@]} -eq 0 ]; then sizes=(2 5 10); fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

best() { # best of 3 CPU seconds (user + system of the process and its threads) of "$@"
    for _ in 1 2 3; do
        python3 -c 'import resource, subprocess, sys
subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(r.ru_utime + r.ru_stime)' "$@"
    done | sort -g | head -1
}

printf '%-4s %16s %16s %8s\n' n "per-run derive" "derive once" ratio
for n in "${sizes[@]}"; do
    model="$work/nlink-$n.lag"
    "$root/bench/models/nlink.sh" "$n" > "$model"
    args=(simulate "$model" --sweep th1=0..1 --steps 199 --t-end 1)
    a=$(best "$old" "${args[@]}")
    b=$(best "$new" "${args[@]}")
    awk -v n="$n" -v a="$a" -v b="$b" 'BEGIN{ printf "%-4s %12.3f s cpu %12.3f s cpu %7.1f×\n", n, a, b, a/b }'
done

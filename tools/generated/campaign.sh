#!/usr/bin/env bash
# A longer campaign of the property test on generated models (crates/lagrange/tests/
# generated_models.rs, docs/reliability.md): COUNT models from SEED, each in its own process
# under a time limit, so that a model lagrange derives slowly is reported as slow and the
# campaign goes on. A disagreement with the numeric route prints the model's text.
#
#   tools/generated/campaign.sh [--seed S] [--count N] [--first I] [--links L] [--timeout SECONDS]
#
# Exit 0 when every model agrees and none is slow; 1 otherwise. The models that failed or were
# slow are left in $OUT (default: a fresh temporary directory) as generated-I.lag.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
seed=1 count=200 first=0 links=5 limit=60 out=""
while [ $# -gt 0 ]; do
    case "$1" in
        --seed) seed="$2"; shift 2 ;;
        --count) count="$2"; shift 2 ;;
        --first) first="$2"; shift 2 ;;
        --links) links="$2"; shift 2 ;;
        --timeout) limit="$2"; shift 2 ;;
        --out) out="$2"; shift 2 ;;
        *) echo "unknown argument $1" >&2; exit 2 ;;
    esac
done
out="${out:-$(mktemp -d)}"
mkdir -p "$out"
# Build once; find the test binary cargo made.
binary="$(cargo test --manifest-path "$root/Cargo.toml" -p lagrange --test generated_models \
    --no-run --message-format=json 2>/dev/null \
    | python3 -c 'import json,sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get("reason") == "compiler-artifact" and m["target"]["name"] == "generated_models" and m.get("executable"):
        print(m["executable"])' | tail -1)"
[ -x "$binary" ] || { echo "no test binary" >&2; exit 2; }
agreed=0 slow=0 failed=0
for ((i = first; i < first + count; i++)); do
    log="$out/model-$i.log"
    set +e
    LAGRANGE_GENERATED_SEED="$seed" LAGRANGE_GENERATED_FIRST="$i" LAGRANGE_GENERATED_COUNT=1 \
        LAGRANGE_GENERATED_LINKS="$links" LAGRANGE_GENERATED_VERBOSE=1 \
        timeout "$limit" "$binary" --ignored --exact campaign_of_generated_models --nocapture \
        >"$log" 2>&1
    status=$?
    set -e
    if [ $status -eq 0 ]; then
        agreed=$((agreed + 1)); rm -f "$log"
    elif [ $status -eq 124 ]; then
        slow=$((slow + 1)); echo "model $i: slow (over ${limit} s)"
    else
        failed=$((failed + 1)); echo "model $i: DISAGREES (see $log)"
    fi
done
# The slow and failed models' text, for reproducing them with `lagrange eom`.
if [ $((slow + failed)) -gt 0 ]; then
    dir="$(mktemp -d)"
    LAGRANGE_GENERATED_MODELS="$dir" LAGRANGE_GENERATED_SEED="$seed" \
        LAGRANGE_GENERATED_COUNT=$((first + count)) LAGRANGE_GENERATED_LINKS="$links" \
        "$binary" --ignored --exact write_models >/dev/null 2>&1 || true
    for log in "$out"/model-*.log; do
        i="${log##*/model-}"; i="${i%.log}"
        cp "$dir/generated-$(printf %03d "$i").lag" "$out/generated-$i.lag" 2>/dev/null || true
    done
    rm -rf "$dir"
fi
echo "seed $seed, models $first..$((first + count - 1)), up to $links links: $agreed agree, $slow slow, $failed disagree (logs in $out)"
[ $((slow + failed)) -eq 0 ]

#!/usr/bin/env bash
# A longer coverage-guided campaign on the model front end (crates/model/fuzz, target
# parse_check: parse, check, summarize and render any bytes), with libFuzzer through cargo fuzz.
# Not part of CI (it needs a nightly toolchain and minutes to hours); see docs/reliability.md.
#
#     tools/fuzz/cargo-fuzz.sh [SECONDS]      # default 300
#
# Installs cargo-fuzz if it is missing (`cargo install cargo-fuzz`), seeds the corpus with the
# example models, and runs the target for SECONDS. A crash leaves its input under
# crates/model/fuzz/artifacts/parse_check/ and makes this script exit non-zero; reproduce it
# with `cargo +nightly fuzz run parse_check ARTIFACT` in crates/model/fuzz.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
seconds=${1:-300}

if ! rustup toolchain list | grep -q '^nightly'; then
    echo "cargo-fuzz.sh: cargo fuzz needs a nightly toolchain (libFuzzer's sanitizer flags);" >&2
    echo "install one with 'rustup toolchain install nightly' and run this again." >&2
    exit 2
fi
if ! cargo fuzz --version > /dev/null 2>&1; then
    echo "== installing cargo-fuzz (cargo install cargo-fuzz)"
    cargo install cargo-fuzz --locked
fi

corpus=crates/model/fuzz/corpus/parse_check
mkdir -p "$corpus"
find examples -name '*.lag' -exec cp {} "$corpus/" \;

echo "== cargo +nightly fuzz run parse_check for ${seconds} s"
cd crates/model/fuzz
# Its own target directory: the fuzz build is instrumented and would only evict the main one's.
export CARGO_TARGET_DIR=${FUZZ_TARGET_DIR:-$root/target/fuzz}
cargo +nightly fuzz run parse_check -- -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096

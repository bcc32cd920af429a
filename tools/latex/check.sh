#!/usr/bin/env bash
# Compiles every example's solution (`lagrange solve --format tex --out DIR`) with pdflatex and
# fails on a LaTeX error, a missing character or an overfull line (text past the margin).
# Usage: tools/latex/check.sh BINARY
set -euo pipefail
binary=${1:?usage: tools/latex/check.sh path/to/lagrange}
cd "$(dirname "$0")/../.."
command -v pdflatex >/dev/null || { echo "pdflatex not found (Debian: texlive-latex-recommended lmodern)"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
overfull_total=0
for model in examples/*.lag examples/seed/*.lag; do
    name=$(basename "$model" .lag)
    # The four-bar's reactions take minutes to be refused (docs/performance.md).
    [ "$name" = four-bar ] && continue
    dir="$work/$name"
    if ! "$binary" solve --format tex --out "$dir" "$model" >/dev/null 2>"$dir.err"; then
        code=$?
        # A solve that reports a failed run (3) still writes its document.
        [ -f "$dir/$name.tex" ] || { echo "FAIL $model: solve exited $code"; cat "$dir.err"; failed=1; continue; }
    fi
    if ! (cd "$dir" && pdflatex -interaction=nonstopmode -halt-on-error "$name.tex" >/dev/null 2>&1); then
        echo "FAIL $model: pdflatex"; grep -A3 '^!' "$dir/$name.log" | head -20; failed=1; continue
    fi
    missing=$(grep -c "Missing character" "$dir/$name.log" || true)
    overfull=$(grep -c "^Overfull \\\\hbox" "$dir/$name.log" || true)
    overfull_total=$((overfull_total + overfull))
    if [ "$overfull" != 0 ]; then
        echo "FAIL $model: $overfull overfull lines"; grep -A2 "^Overfull" "$dir/$name.log" | head -12; failed=1
    fi
    if [ "$missing" != 0 ]; then
        echo "FAIL $model: $missing missing characters"; grep "Missing character" "$dir/$name.log" | sort | uniq -c | head; failed=1
    fi
    echo "ok   $model ($(grep -o '[0-9]* pages' "$dir/$name.log" | head -1), $overfull overfull lines)"
done
echo "overfull lines in all: $overfull_total"
exit $failed

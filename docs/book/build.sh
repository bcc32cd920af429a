#!/usr/bin/env bash
# Builds the seed's solutions (examples/seed/*.md and their figures) into a small Jupyter Book,
# offline: jupyter-book 1.x is installed into a venv this script creates, and MathJax comes
# from a local copy (the PyPI package django-static-mathjax ships MathJax 3) put into the book's
# _static, so a page loads nothing from the network.
#
# Usage: docs/book/build.sh [OUT]   (OUT: where the HTML goes; default target/book)
# NOTEBOOKS: a directory of executed notebooks to show (default docs/notebooks, unexecuted).
# Environment: BOOK_VENV (default target/book-venv) to reuse a venv; PYTHON (default python3).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
out=$(realpath -m "${1:-$root/target/book}")
venv=$(realpath -m "${BOOK_VENV:-$root/target/book-venv}")
python=${PYTHON:-python3}

# A venv that does not run (moved or copied elsewhere: its scripts name the old path) is made anew.
if ! "$venv/bin/jupyter-book" --version >/dev/null 2>&1 || [ ! -d "$("$venv/bin/python" -c 'import mathjax, os; print(os.path.dirname(mathjax.__file__))' 2>/dev/null)/static/mathjax/es5" ]; then
    rm -rf "$venv"
    "$python" -m venv "$venv"
    "$venv/bin/pip" install -q --upgrade pip
    "$venv/bin/pip" install -q "jupyter-book<2" "django-static-mathjax==3.2.2.1"
fi
mathjax=$("$venv/bin/python" -c 'import mathjax, os; print(os.path.dirname(mathjax.__file__))')/static/mathjax/es5
[ -f "$mathjax/tex-mml-chtml.js" ] || { echo "no MathJax in $mathjax" >&2; exit 1; }

book=$(mktemp -d)
trap 'rm -rf "$book"' EXIT
cp "$root/docs/book/_config.yml" "$root/docs/book/_toc.yml" "$root/docs/book/intro.md" "$book/"
for page in "$root"/examples/seed/*.md; do
    cp "$page" "$book/"
    stem=$(basename "$page" .md)
    # The figures the page shows and the animation it links.
    cp "$root"/examples/seed/"$stem".svg "$root"/examples/seed/"$stem"-motion.svg "$book/" 2>/dev/null || true
    cp "$root"/examples/seed/"$stem".html "$book/" 2>/dev/null || true
done
# The notebooks of the exercises, as CI ran them when it did (NOTEBOOKS, written by
# python/tests/test_notebook.py), else as committed (code without outputs).
mkdir -p "$book/notebooks"
notebooks=${NOTEBOOKS:-$root/docs/notebooks}
[ -d "$notebooks" ] && [ -n "$(ls "$notebooks"/*.ipynb 2>/dev/null)" ] || notebooks=$root/docs/notebooks
cp "$notebooks"/*.ipynb "$book/notebooks/"
cp "$root/docs/book/python.md" "$book/"
mkdir -p "$book/_mathjax"
cp -r "$mathjax" "$book/_mathjax/mathjax"

rm -rf "$out"
"$venv/bin/jupyter-book" build --quiet --builder html --path-output "$book/build" "$book" >&2
cp -r "$book/build/_build/html" "$out"
echo "$out"

#!/usr/bin/env bash
# lagrange side by side with SymPy mechanics, PyDy and Pinocchio, in one run (issue 9).
# Makes its own virtual environment (bench/.venv, git-ignored) from PyPI with pinned versions,
# builds lagrange in release, compiles Pinocchio's ABA timer against the `pin` wheel's headers,
# then runs compare.py. Results go to bench/compare/results/.
#   bench/compare/run.sh                       everything (about 20 min with the default cap)
#   bench/compare/run.sh --only derive --cap 30 --sizes 1,2,5,10,20,40
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$root/bench/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet sympy==1.14.0 pydy==0.9.4 pin==4.1.0 cmeel-eigen \
    numpy scipy matplotlib cython setuptools

(cd "$root" && cargo build --release --quiet -p lagrange-cli && \
    cargo build --release --quiet -p lagrange-model --example derive_timing)
if [ -f "$root/crates/lagrange/examples/rhs_timing.rs" ]; then
    (cd "$root" && cargo build --release --quiet -p lagrange --example rhs_timing)
fi

prefix="$("$venv/bin/python" -c 'import cmeel, os; print(os.path.join(os.path.dirname(cmeel.__path__[0]), "cmeel.prefix"))')"
mkdir -p "$here/.build"
if [ ! -x "$here/.build/pinocchio_aba" ] || [ "$here/pinocchio_aba.cpp" -nt "$here/.build/pinocchio_aba" ]; then
    echo "compiling the Pinocchio timer (about a minute)…"
    # The definitions are the ones Pinocchio's CMake config exports to its users.
    g++ -O3 -DNDEBUG -march=native -std=c++17 \
        -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS -DBOOST_MPL_LIMIT_LIST_SIZE=30 \
        -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 -DBOOST_FUSION_INVOKE_MAX_ARITY=12 \
        -I"$prefix/include" -I"$prefix/include/eigen3" "$here/pinocchio_aba.cpp" \
        -L"$prefix/lib" -lpinocchio_default -Wl,-rpath,"$prefix/lib" -o "$here/.build/pinocchio_aba"
fi
exec "$venv/bin/python" "$here/compare.py" "$@"

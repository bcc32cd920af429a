"""The SymPy + SciPy side of bench/simulate/run.sh for the planar n-link pendulum.

Derives M q̈ = f with SymPy (Lagrange II; not timed) and lambdifies M and f together, with
common subexpressions eliminated (`cse=True`, one NumPy function returning both), the fastest
right-hand side found for solve_ivp (see docs/performance.md); the right-hand side is
`np.linalg.solve(M, f)`.

`scipy_side.py N LAGRANGE MODEL RTOL ATOL` prints

    rhs MICROSECONDS
    METHOD LAGRANGE_MS LAGRANGE_EVALUATIONS SCIPY_MS SCIPY_EVALUATIONS   (dopri5, dop853)

the RHS time (best of 3 × 2000 calls) and, for each pair of the same method (lagrange dopri5
against SciPy RK45, dop853 against DOP853), a 10 s run from θ₁ = 0.5 at rest at the given
tolerances: the best of 5 repetitions, the two sides interleaved (lagrange, then SciPy, in
each repetition) so that both see the same load. lagrange's time is the integration's own
(its summary line; loading and deriving excluded, as SciPy's derivation is).
"""

import re
import subprocess
import sys
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

PAIRS = [("dopri5", "RK45"), ("dop853", "DOP853")]
REPETITIONS = 5


def nlink(n):
    t = sp.Symbol("t")
    th = [sp.Function(f"th{i + 1}")(t) for i in range(n)]
    g = sp.Rational(981, 100)
    x = y = 0
    K = V = 0
    for i in range(n):
        x = x + sp.sin(th[i])
        y = y - sp.cos(th[i])
        K += sp.Rational(1, 2) * (sp.diff(x, t) ** 2 + sp.diff(y, t) ** 2)
        V += g * y
    L = K - V
    qd = [sp.diff(q, t) for q in th]
    qdd = [sp.diff(q, t, 2) for q in th]
    eqs = [sp.expand(sp.diff(sp.diff(L, qd[j]), t) - sp.diff(L, th[j])) for j in range(n)]
    M = sp.Matrix(n, n, lambda i, k: eqs[i].coeff(qdd[k]))
    f = -sp.Matrix([eqs[i].subs({a: 0 for a in qdd}) for i in range(n)])
    qs, vs = sp.symbols(f"q0:{n}"), sp.symbols(f"v0:{n}")
    sub = {**{qd[i]: vs[i] for i in range(n)}, **{th[i]: qs[i] for i in range(n)}}
    # One function for both, so that the subexpressions M and f share (sin θᵢ, cos(θᵢ − θⱼ))
    # are computed once per call.
    mass_and_force = sp.lambdify((qs, vs), [M.subs(sub), f.subs(sub)], "numpy", cse=True)

    def rhs(_t, y):
        mass, force = mass_and_force(y[:n], y[n:])
        a = np.linalg.solve(mass, force.ravel())
        return np.concatenate([y[n:], a])

    return rhs


def lagrange_run(binary, model, method, rtol, atol):
    """One run of the lagrange CLI: (milliseconds, evaluations) from its summary line."""
    out = subprocess.run(
        [binary, "simulate", model, "--t-end", "10", "--rtol", rtol, "--atol", atol,
         "--method", method, "--output-step", "10", "--out", "/dev/null"],
        check=True, capture_output=True, text=True).stderr
    found = re.search(r"(\d+) evaluations, ([\d.]+) (µs|ms|s),", out)
    assert found, out
    scale = {"µs": 1e-3, "ms": 1.0, "s": 1e3}[found.group(3)]
    return float(found.group(2)) * scale, int(found.group(1))


def main():
    n = int(sys.argv[1])
    binary, model, rtol, atol = sys.argv[2:6]
    rhs = nlink(n)
    y0 = np.zeros(2 * n)
    y0[0] = 0.5
    calls = 2000
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        for _ in range(calls):
            rhs(0.0, y0)
        best = min(best, (time.perf_counter() - start) / calls)
    print(f"rhs {best * 1e6:.3f}")
    results = {ours: [float("inf"), 0, float("inf"), 0] for ours, _ in PAIRS}
    for _ in range(REPETITIONS):
        for ours, theirs in PAIRS:
            ms, evaluations = lagrange_run(binary, model, ours, rtol, atol)
            start = time.perf_counter()
            sol = solve_ivp(rhs, (0.0, 10.0), y0, method=theirs, rtol=float(rtol), atol=float(atol))
            scipy_ms = (time.perf_counter() - start) * 1e3
            assert sol.success, sol.message
            r = results[ours]
            r[0], r[1] = min(r[0], ms), evaluations
            r[2], r[3] = min(r[2], scipy_ms), sol.nfev
    for ours, _ in PAIRS:
        r = results[ours]
        print(f"{ours} {r[0]:.3f} {r[1]} {r[2]:.3f} {r[3]}")


if __name__ == "__main__":
    main()

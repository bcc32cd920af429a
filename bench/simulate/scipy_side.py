"""The SymPy + SciPy side of bench/simulate/run.sh for the planar n-link pendulum.

Derives M q̈ = f with SymPy (Lagrange II; not timed), lambdifies M and f to NumPy, and times
one right-hand side (both lambdified functions and np.linalg.solve) and a 10 s solve_ivp run
with RK45 at rtol 1e-8, atol 1e-10. Prints "rhs_microseconds simulation_milliseconds".
"""

import sys
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp


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
    Mf = sp.lambdify((qs, vs), M.subs(sub), "numpy")
    ff = sp.lambdify((qs, vs), f.subs(sub), "numpy")

    def rhs(_t, y):
        a = np.linalg.solve(np.asarray(Mf(y[:n], y[n:]), dtype=float),
                            np.asarray(ff(y[:n], y[n:]), dtype=float).ravel())
        return np.concatenate([y[n:], a])

    return rhs


def main():
    n = int(sys.argv[1])
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
    sim = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        sol = solve_ivp(rhs, (0.0, 10.0), y0, method="RK45", rtol=1e-8, atol=1e-10)
        sim = min(sim, time.perf_counter() - start)
        assert sol.success, sol.message
    print(f"{best * 1e6:.3f} {sim * 1e3:.3f}")


if __name__ == "__main__":
    main()

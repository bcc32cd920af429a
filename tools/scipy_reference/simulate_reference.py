"""Reference trajectories for lagrange's simulation tests.

Each case writes tests/data/simulation/<name>.csv with the columns lagrange writes
(t, coordinates, rates q_d). The equations of motion are derived here with SymPy from the
Lagrangian, independently of lagrange, and integrated by SciPy's DOP853 at rtol = atol = 1e-12;
rows are at the listed output times (DOP853's dense output). The model files the tests run are
named in each case; parameters and initial values are the same.

Usage: tools/scipy_reference/run.sh [--check]   (--check also integrates at 1e-13 and prints
the largest difference, a bound on the reference's own error).
"""

import csv
import pathlib
import sys

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "tests" / "data" / "simulation"


def lagrange_rhs(q, L, params):
    """q: list of SymPy functions of t; returns f(t, y) for y = (q, q_d) from Lagrange II."""
    t = sp.Symbol("t")
    n = len(q)
    qd = [sp.diff(x, t) for x in q]
    qdd = [sp.diff(x, t, 2) for x in q]
    eqs = [sp.diff(sp.diff(L, qd[j]), t) - sp.diff(L, q[j]) for j in range(n)]
    M = sp.Matrix(n, n, lambda i, k: sp.diff(eqs[i], qdd[k]))
    f = -sp.Matrix([eqs[i].subs({a: 0 for a in qdd}) for i in range(n)])
    qs = sp.symbols(f"q0:{n}")
    vs = sp.symbols(f"v0:{n}")
    sub = {**{qd[i]: vs[i] for i in range(n)}, **{q[i]: qs[i] for i in range(n)}}
    M = M.subs(params).subs(sub)
    f = f.subs(params).subs(sub)
    Mf = sp.lambdify((qs, vs), M, "numpy")
    ff = sp.lambdify((qs, vs), f, "numpy")

    def rhs(_t, y):
        a = np.linalg.solve(np.array(Mf(y[:n], y[n:]), dtype=float),
                            np.array(ff(y[:n], y[n:]), dtype=float).ravel())
        return np.concatenate([y[n:], a])

    return rhs


def double_pendulum():
    t = sp.Symbol("t")
    m1, m2, l1, l2, g = 1, 1, 1, 1, sp.Rational(981, 100)
    th1, th2 = sp.Function("theta1")(t), sp.Function("theta2")(t)
    x1, y1 = l1 * sp.sin(th1), -l1 * sp.cos(th1)
    x2, y2 = x1 + l2 * sp.sin(th2), y1 - l2 * sp.cos(th2)
    K = sp.Rational(1, 2) * (m1 * (sp.diff(x1, t) ** 2 + sp.diff(y1, t) ** 2)
                            + m2 * (sp.diff(x2, t) ** 2 + sp.diff(y2, t) ** 2))
    V = m1 * g * y1 + m2 * g * y2
    return [th1, th2], K - V, {}


def simple_pendulum():
    t = sp.Symbol("t")
    m, l, g = 1, 1, sp.Rational(981, 100)
    th = sp.Function("theta")(t)
    K = sp.Rational(1, 2) * m * l**2 * sp.diff(th, t) ** 2
    V = -m * g * l * sp.cos(th)
    return [th], K - V, {}


# name, model, coordinate names, initial (q, q_d), output times
CASES = [
    # Both arms raised to 2 rad: a chaotic start (a 1e-9 change of theta1 grows 3e4-fold by
    # t = 10), still resolved to ~3e-8 at t = 10 by a 1e-12 integration (--check).
    ("double_pendulum_chaotic", double_pendulum, ["theta1", "theta2"],
     [2.0, 2.0, 0.0, 0.0], np.linspace(0.0, 10.0, 21)),
    # A regular start (errors grow ~10-fold by t = 10): a tighter check.
    ("double_pendulum_regular", double_pendulum, ["theta1", "theta2"],
     [1.5, 1.0, 0.0, 0.5], np.linspace(0.0, 10.0, 21)),
    ("simple_pendulum_large", simple_pendulum, ["theta"],
     [3.0, 0.0], np.linspace(0.0, 10.0, 21)),
]


def integrate(model, y0, times, tol):
    q, L, params = model()
    rhs = lagrange_rhs(q, L, params)
    sol = solve_ivp(rhs, (times[0], times[-1]), y0, method="DOP853", rtol=tol, atol=tol,
                    t_eval=times, dense_output=False)
    if not sol.success:
        raise RuntimeError(sol.message)
    return sol.y.T


def main():
    check = "--check" in sys.argv
    OUT.mkdir(parents=True, exist_ok=True)
    for name, model, names, y0, times in CASES:
        rows = integrate(model, y0, times, 1e-12)
        if check:
            finer = integrate(model, y0, times, 1e-13)
            print(f"{name}: max |1e-12 − 1e-13| = {np.max(np.abs(rows - finer)):.2e}")
        path = OUT / f"{name}.csv"
        with path.open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(["t", *names, *(f"{n}_d" for n in names)])
            for t, row in zip(times, rows):
                writer.writerow([repr(float(t)), *(repr(float(x)) for x in row)])
        print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()

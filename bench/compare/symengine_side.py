"""The planar n-link pendulum's Lagrange equations derived with SymEngine directly (issue 20):
the peer side of `bench/compare/symengine.sh`.

The same work as `derive_timing --same-work` (and SymPy's `LagrangesMethod`): positions,
velocities by the chain rule, K and V, L = K - V, for each coordinate
d/dt(dL/dq') - dL/dq, then the mass matrix M (the coefficients of the accelerations) and the
forcing f = -(the equation with the accelerations set to zero), each expanded (SymEngine's
normal form is the expanded polynomial in sin and cos of the angles; it applies no
sin^2 + cos^2 = 1, so its M_ii keeps l^2 (sin^2 + cos^2) terms lagrange's normal form sums to
l^2). Prints the best of `repeats` cold derivations in seconds; each derivation uses fresh
symbol names, so no cache is reused.

Usage: python symengine_side.py N [REPEATS]
"""

import sys
import time

import symengine as se


def derive(n: int, tag: str) -> tuple[list[list[se.Basic]], list[se.Basic]]:
    th = [se.Symbol(f"th{i}_{tag}") for i in range(n)]
    thd = [se.Symbol(f"thd{i}_{tag}") for i in range(n)]
    thdd = [se.Symbol(f"thdd{i}_{tag}") for i in range(n)]
    m = [se.Symbol(f"m{i}_{tag}") for i in range(n)]
    l = [se.Symbol(f"l{i}_{tag}") for i in range(n)]
    g = se.Symbol(f"g_{tag}")

    def dt(e):
        return sum((e.diff(th[i]) * thd[i] + e.diff(thd[i]) * thdd[i] for i in range(n)), se.Integer(0))

    x, y = se.Integer(0), se.Integer(0)
    kinetic, potential = se.Integer(0), se.Integer(0)
    for i in range(n):
        x = x + l[i] * se.sin(th[i])
        y = y - l[i] * se.cos(th[i])
        vx, vy = dt(x), dt(y)
        kinetic = kinetic + m[i] * (vx**2 + vy**2) / 2
        potential = potential + m[i] * g * y
    # Expanding only the results is SymEngine's fastest route here (expanding L and each
    # equation as well took 1.2-2.5x longer at n = 5-20).
    lagrangian = kinetic - potential
    equations = [dt(lagrangian.diff(thd[i])) - lagrangian.diff(th[i]) for i in range(n)]
    mass = [[se.expand(eq.diff(thdd[j])) for j in range(n)] for eq in equations]
    at_rest = {a: se.Integer(0) for a in thdd}
    forcing = [se.expand(-eq.subs(at_rest)) for eq in equations]
    return mass, forcing


def main() -> None:
    n = int(sys.argv[1])
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    best = float("inf")
    for r in range(repeats):
        start = time.perf_counter()
        derive(n, f"r{r}")
        best = min(best, time.perf_counter() - start)
    print(f"{best:.6f}")


if __name__ == "__main__":
    main()

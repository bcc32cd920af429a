"""The Ince-Strutt chart of Mathieu's equation x'' + (delta + eps cos t) x = 0 by SciPy.

For each (delta, eps) on the grid, the two solutions with x(0), x'(0) = (1, 0) and (0, 1)
are integrated over one period 2*pi (DOP853, rtol = atol = 1e-12); they are the columns of
the monodromy matrix. Its determinant is 1 (Liouville: no damping), so the multipliers are
the roots of mu^2 - tr mu + 1 and x = 0 is stable when |tr| < 2, unstable when |tr| > 2.
Writes delta, eps, the trace, the largest |mu| and the verdict, one row per point.
"""

import csv
import math
import sys

import numpy as np
from scipy.integrate import solve_ivp


def monodromy(delta, eps):
    def rhs(t, y):
        k = delta + eps * math.cos(t)
        return [y[1], -k * y[0], y[3], -k * y[2]]

    sol = solve_ivp(rhs, (0.0, 2.0 * math.pi), [1.0, 0.0, 0.0, 1.0],
                    method="DOP853", rtol=1e-12, atol=1e-12)
    y = sol.y[:, -1]
    return np.array([[y[0], y[2]], [y[1], y[3]]])


def main(path):
    deltas = np.linspace(-0.5, 1.5, 41)
    epss = np.linspace(0.0, 1.0, 21)
    with open(path, "w", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(["delta", "eps", "trace", "max_abs_multiplier", "verdict"])
        for delta in deltas:
            for eps in epss:
                phi = monodromy(delta, eps)
                mu = np.linalg.eigvals(phi)
                trace = float(np.trace(phi))
                verdict = "stable" if abs(trace) < 2.0 else "unstable"
                out.writerow([f"{delta:.6f}", f"{eps:.6f}", f"{trace:.12g}",
                              f"{max(abs(mu)):.12g}", verdict])


if __name__ == "__main__":
    main(sys.argv[1])

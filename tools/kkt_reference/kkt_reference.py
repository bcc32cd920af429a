"""Independent reference for the equilibria of constrained systems (issue 17).

Each system of examples/ with constraints kept by multipliers is stated here by hand: the
potential V(q) and its gradient, the constraints Phi(q) and their Jacobian A(q), the mass
matrix M(q). The equilibria solve the KKT system

    grad V(q) + A(q)^T lam = 0,    Phi(q) = 0

(lagrange's sign: M qdd + A^T lam = f with f = -grad V at rest), found by scipy.optimize.root
from many starts and polished by Newton; the Hessians come from complex-step derivatives of
the hand-written gradients (exact to rounding). The linearization on the constraints uses
N = scipy.linalg.null_space(A): K_r = N^T (H_V + sum lam_k H_Phi_k) N, M_r = N^T M N, and
omega^2 from scipy.linalg.eigh(K_r, M_r). Written as JSON, one file per model.
"""

import json
import math
import sys
from pathlib import Path

import numpy as np
from scipy import linalg, optimize


def complex_step_jacobian(fun, q):
    """d fun / dq by complex steps (fun analytic in q): exact to rounding."""
    h = 1e-30
    cols = []
    for j in range(len(q)):
        z = np.array(q, dtype=complex)
        z[j] += 1j * h
        cols.append(np.imag(np.asarray(fun(z))) / h)
    return np.array(cols).T


class System:
    def __init__(self, name, coordinates, angles, grad_v, phi, jac_phi, mass, box):
        self.name = name
        self.coordinates = coordinates
        self.angles = angles
        self.grad_v = grad_v
        self.phi = phi
        self.jac_phi = jac_phi
        self.mass = mass
        self.box = box
        self.n = len(coordinates)
        self.m = len(phi(np.zeros(self.n)))

    def kkt(self, z):
        q, lam = z[: self.n], z[self.n :]
        a = self.jac_phi(q)
        return np.concatenate([self.grad_v(q) + a.T @ lam, self.phi(q)])

    def kkt_jacobian(self, z):
        q, lam = z[: self.n], z[self.n :]
        a = self.jac_phi(q)
        top = np.hstack([self.stiffness(q, lam), a.T])
        bottom = np.hstack([a, np.zeros((self.m, self.m))])
        return np.vstack([top, bottom]).real

    def stiffness(self, q, lam):
        """Hessian of V + lam . Phi."""
        k = complex_step_jacobian(self.grad_v, q)
        for i in range(self.m):
            k = k + lam[i] * complex_step_jacobian(lambda x, i=i: self.jac_phi(x)[i], q)
        return k

    def wrap(self, q):
        q = np.array(q, dtype=float)
        for i, angle in enumerate(self.angles):
            if angle:
                q[i] = math.remainder(q[i], 2 * math.pi)
                if q[i] <= -math.pi:
                    q[i] += 2 * math.pi
        return q


def polish(system, z):
    for _ in range(20):
        r = system.kkt(z)
        if np.linalg.norm(r) < 1e-15:
            break
        z = z - np.linalg.solve(system.kkt_jacobian(z), r)
    return z


def equilibria(system, starts=3000, seed=17):
    rng = np.random.default_rng(seed)
    found = []
    for _ in range(starts):
        q0 = np.array(
            [rng.uniform(-math.pi, math.pi) if ang else rng.uniform(*system.box) for ang in system.angles]
        )
        a = system.jac_phi(q0)
        lam0 = np.linalg.lstsq(a.T, -system.grad_v(q0), rcond=None)[0]
        sol = optimize.root(system.kkt, np.concatenate([q0, lam0]), jac=system.kkt_jacobian, method="hybr")
        if not sol.success or np.linalg.norm(system.kkt(sol.x)) > 1e-8:
            continue
        z = polish(system, sol.x)
        q = system.wrap(z[: system.n])
        inside = all(ang or system.box[0] <= v <= system.box[1] for v, ang in zip(q, system.angles))
        if not inside:
            continue
        diff = lambda p: [math.remainder(x - y, 2 * math.pi) if ang else x - y for x, y, ang in zip(p, q, system.angles)]
        if any(np.max(np.abs(diff(e["q"]))) < 1e-7 for e in found):
            continue
        found.append({"q": q.tolist(), "lambda": z[system.n :].tolist()})
    for e in found:
        q, lam = np.array(e["q"]), np.array(e["lambda"])
        n = linalg.null_space(system.jac_phi(q))
        k = n.T @ system.stiffness(q, lam) @ n
        m = n.T @ system.mass(q) @ n
        w2 = linalg.eigh((k + k.T) / 2, (m + m.T) / 2, eigvals_only=True)
        e["omega_squared"] = sorted(w2.tolist())
        e["stable"] = bool(all(w > 0 for w in w2))
    found.sort(key=lambda e: e["q"])
    return found


def planar_jacobian(entries, n):
    """The 2 x n Jacobian of a planar point from {coordinate index: (dx/dq, dy/dq)}."""
    j = np.zeros((2, n), dtype=complex)
    for i, (dx, dy) in entries.items():
        j[0, i], j[1, i] = dx, dy
    return j


def mass_from(points, rotations, q):
    """sum m J^T J over (mass, jacobian(q)) and the rotary inertias on the diagonal."""
    n = len(q)
    mass = np.zeros((n, n))
    for m, jac in points:
        j = jac(q).real
        mass += m * j.T @ j
    for i, inertia in rotations:
        mass[i, i] += inertia
    return mass


def four_bar():
    a, b, c, d, m1, m2, m3, g = 0.3, 1.0, 0.8, 1.0, 1.0, 2.0, 1.5, 9.81
    s, co = np.sin, np.cos
    grad_v = lambda q: np.array([g * (m1 * a / 2 + m2 * a) * co(q[0]), g * m2 * b / 2 * co(q[1]), g * m3 * c / 2 * co(q[2])])
    phi = lambda q: np.array([a * co(q[0]) + b * co(q[1]) - c * co(q[2]) - d, a * s(q[0]) + b * s(q[1]) - c * s(q[2])])
    jac_phi = lambda q: np.array([[-a * s(q[0]), -b * s(q[1]), c * s(q[2])], [a * co(q[0]), b * co(q[1]), -c * co(q[2])]])
    points = [
        (m1, lambda q: planar_jacobian({0: (-a / 2 * s(q[0]), a / 2 * co(q[0]))}, 3)),
        (m2, lambda q: planar_jacobian({0: (-a * s(q[0]), a * co(q[0])), 1: (-b / 2 * s(q[1]), b / 2 * co(q[1]))}, 3)),
        (m3, lambda q: planar_jacobian({2: (-c / 2 * s(q[2]), c / 2 * co(q[2]))}, 3)),
    ]
    rotations = [(0, m1 * a**2 / 12), (1, m2 * b**2 / 12), (2, m3 * c**2 / 12)]
    mass = lambda q: mass_from(points, rotations, q)
    return System("four-bar", ["th1", "th2", "th3"], [True] * 3, grad_v, phi, jac_phi, mass, (-10, 10))


def slider_crank():
    r, l, m1, m2, m3, k, l0, g = 0.2, 0.6, 1.0, 2.0, 1.5, 200.0, 0.5, 9.81
    s, co = np.sin, np.cos
    grad_v = lambda q: np.array([g * (m1 * r / 2 + m2 * r) * co(q[0]), g * m2 * l / 2 * co(q[1]), k * (q[2] - l0)])
    phi = lambda q: np.array([r * co(q[0]) + l * co(q[1]) - q[2], r * s(q[0]) + l * s(q[1])])
    jac_phi = lambda q: np.array([[-r * s(q[0]), -l * s(q[1]), -1.0 + 0 * q[2]], [r * co(q[0]), l * co(q[1]), 0 * q[2]]])
    points = [
        (m1, lambda q: planar_jacobian({0: (-r / 2 * s(q[0]), r / 2 * co(q[0]))}, 3)),
        (m2, lambda q: planar_jacobian({0: (-r * s(q[0]), r * co(q[0])), 1: (-l / 2 * s(q[1]), l / 2 * co(q[1]))}, 3)),
        (m3, lambda q: planar_jacobian({2: (1.0, 0.0)}, 3)),
    ]
    rotations = [(0, m1 * r**2 / 12), (1, m2 * l**2 / 12)]
    mass = lambda q: mass_from(points, rotations, q)
    return System("slider-crank", ["th", "phi", "s"], [True, True, False], grad_v, phi, jac_phi, mass, (-10, 10))


def cartesian_pendulum():
    m, l, g = 1.0, 1.0, 9.81
    grad_v = lambda q: np.array([0 * q[0], m * g + 0 * q[1]])
    phi = lambda q: np.array([q[0] ** 2 + q[1] ** 2 - l**2])
    jac_phi = lambda q: np.array([[2 * q[0], 2 * q[1]]])
    mass = lambda q: m * np.eye(2)
    return System("cartesian-pendulum", ["x", "y"], [False, False], grad_v, phi, jac_phi, mass, (-10, 10))


def atwood():
    """Linear: the KKT system is a linear system in (y1, y2, phi, lam1, lam2), inconsistent
    unless m1 = m2. Its least-squares residual certifies that there is no equilibrium."""
    m1, m2, r, length, g = 2.0, 1.0, 0.1, 2.0, 9.81
    # Unknowns (y1, y2, phi, lam1, lam2); rows: grad V + A^T lam = 0, Phi = 0.
    a = np.array(
        [
            [0, 0, 0, 1, 1],
            [0, 0, 0, 1, 0],
            [0, 0, 0, 0, -r],
            [1, 1, 0, 0, 0],
            [1, 0, -r, 0, 0],
        ],
        dtype=float,
    )
    rhs = np.array([m1 * g, m2 * g, 0, length, 0])
    solution, _, rank, _ = np.linalg.lstsq(a, rhs, rcond=None)
    residual = float(np.linalg.norm(a @ solution - rhs))
    return {
        "model": "atwood-machine",
        "coordinates": ["y1", "y2", "phi"],
        "equilibria": [],
        "rank": int(rank),
        "least_squares_residual": residual,
    }


def main():
    out = Path(sys.argv[1])
    out.mkdir(parents=True, exist_ok=True)
    for system in [four_bar(), slider_crank(), cartesian_pendulum()]:
        data = {
            "model": system.name,
            "coordinates": system.coordinates,
            "equilibria": equilibria(system),
        }
        (out / f"kkt_{system.name}.json").write_text(json.dumps(data, indent=1) + "\n")
        print(system.name, len(data["equilibria"]), "equilibria")
    data = atwood()
    (out / "kkt_atwood-machine.json").write_text(json.dumps(data, indent=1) + "\n")
    print("atwood-machine: least-squares residual", data["least_squares_residual"])


if __name__ == "__main__":
    main()

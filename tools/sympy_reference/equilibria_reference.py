"""Reference equilibria and linearizations from SymPy, for crates/cli/tests/equilibria.rs.

Each model is written here independently of lagrange's model files (same physics, same
parameter values). For every equilibrium we record the coordinates' values, the linearized
M0, C0, K0 (SymPy's LagrangesMethod + jacobians), the eigenvalues of the state matrix and the
generalized eigenvalues omega^2 of K0 x = omega^2 M0 x.
"""
import json
import pathlib

import numpy as np
import sympy as sp
from sympy.physics.mechanics import (LagrangesMethod, Particle, Point, ReferenceFrame,
                                     dynamicsymbols, Lagrangian)

OUT = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "equilibria"


def linearize(lag, coords, rates, equilibria, values, name):
    lm = LagrangesMethod(lag, coords)
    lm.form_lagranges_equations()
    mass = lm.mass_matrix
    forcing = lm.forcing
    accs = [sp.diff(r, dynamicsymbols._t) for r in rates]
    at_rest = {r: 0 for r in rates}
    at_rest.update({a: 0 for a in accs})
    k0 = -forcing.jacobian(coords)
    c0 = -forcing.jacobian(rates)
    entries = []
    for eq in equilibria:
        point = dict(zip(coords, eq))
        sub = {**at_rest, **point, **values}
        m = np.array(mass.subs(sub).evalf(), dtype=float)
        c = np.array(c0.subs(sub).evalf(), dtype=float)
        k = np.array(k0.subs(sub).evalf(), dtype=float)
        n = len(coords)
        a = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(m, k), -np.linalg.solve(m, c)]])
        lam = np.linalg.eigvals(a)
        w2 = np.sort(np.real(np.linalg.eigvals(np.linalg.solve(m, k))))
        entries.append({
            "values": [float(v) for v in eq],
            "M0": m.tolist(), "C0": c.tolist(), "K0": k.tolist(),
            "eigenvalues": sorted([[float(z.real), float(z.imag)] for z in lam]),
            "omega_squared": [float(v) for v in w2],
        })
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / f"{name}.json").write_text(json.dumps({"model": name, "equilibria": entries}, indent=1))


def cart_pendulum():
    # Seed 7.1: cart x on a spring k, pendulum theta (gravity along +y, theta = 0 hanging).
    x, th = dynamicsymbols("x theta")
    xd, thd = dynamicsymbols("x theta", 1)
    ma, mb, l, k, g = sp.symbols("m_A m_B l k g")
    N = ReferenceFrame("N")
    O = Point("O"); O.set_vel(N, 0)
    A = O.locatenew("A", x * N.x); A.set_vel(N, xd * N.x)
    B = A.locatenew("B", l * sp.sin(th) * N.x + l * sp.cos(th) * N.y)
    B.set_vel(N, B.pos_from(O).dt(N))
    pa, pb = Particle("pa", A, ma), Particle("pb", B, mb)
    pb.potential_energy = -mb * g * l * sp.cos(th)
    pa.potential_energy = k * x**2 / 2
    lag = Lagrangian(N, pa, pb)
    values = {ma: 2, mb: 1, l: 0.5, k: 30, g: 9.81}
    linearize(lag, [x, th], [xd, thd], [(0, 0), (0, sp.pi)], values, "7.1-cart-pendulum")


def inverted_pendulum():
    # Seed 7.4: cart M, uniform rod m, L hinged at the cart, theta from the upward vertical.
    x, th = dynamicsymbols("x theta")
    xd, thd = dynamicsymbols("x theta", 1)
    M, m, L, g = sp.symbols("M m L g")
    xg = x - L / 2 * sp.sin(th)
    yg = L / 2 * sp.cos(th)
    t = dynamicsymbols._t
    kin = M * xd**2 / 2 + m * (sp.diff(xg, t)**2 + sp.diff(yg, t)**2) / 2 \
        + (m * L**2 / 12) * thd**2 / 2
    lag = kin - m * g * yg
    values = {M: 1, m: 0.2, L: 0.6, g: 9.81}
    linearize(lag, [x, th], [xd, thd], [(0, 0), (0, sp.pi)], values, "7.4-inverted-pendulum")


def bead_on_hoop():
    th = dynamicsymbols("theta")
    thd = dynamicsymbols("theta", 1)
    m, R, W, g = sp.symbols("m R Omega g")
    kin = m * R**2 * (thd**2 + W**2 * sp.sin(th)**2) / 2
    lag = kin + m * g * R * sp.cos(th)
    values = {m: 0.1, R: 0.5, W: 6, g: 9.81}
    off = float(sp.acos(sp.Rational(981, 100) / (36 * sp.Rational(1, 2))))
    linearize(lag, [th], [thd], [(-off,), (0,), (off,), (sp.pi,)], values, "bead-on-rotating-hoop")


if __name__ == "__main__":
    cart_pendulum()
    inverted_pendulum()
    bead_on_hoop()

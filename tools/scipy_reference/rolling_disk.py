"""Reference motion of the 3-D rolling disk (examples/rolling-disk.lag), independent of lagrange.

A uniform thin disk (mass m, radius R) rolls without slipping on the horizontal plane z = 0.
Coordinates as in the example: the contact point (x, y), yaw ψ about N.z, lean θ about the
heading A.x, spin φ about the disk's axis L.y; the centre is at P + R L.z. The reduced
equations in ψ, θ, φ are derived here by hand with Newton–Euler about the centre -- a
different method from lagrange's Lagrange equations with multipliers -- and integrated by
SciPy's DOP853 at rtol = atol = 1e-13; the contact point follows from x' = R φ' cos ψ,
y' = R φ' sin ψ.

In the lean frame L (which turns at ω_L = (θ', ψ' sin θ, ψ' cos θ) in L's components) the
disk turns at ω = (w1, w2, w3) = (θ', ψ' sin θ + φ', ψ' cos θ). Rolling makes the centre's
velocity v = ω × R L.z = R (w2, −w1, 0), its acceleration a = v' + ω_L × v; the contact force
is F = m a + m g N.z with N.z = (0, sin θ, cos θ); the angular momentum about the centre is
H = m R² (w1/4, w2/2, w3/4), and H' + ω_L × H = −R L.z × F = (R F2, −R F1, 0). The three
components are linear in (θ'', ψ'', φ''), solved numerically at each state.

Writes crates/lagrange/tests/data/rolling_disk.json:
  - "general": a general motion from the example's initial state, states at fixed times;
  - "steady": a steady turn at constant lean θ₀ with yaw rate Ω: the spin rate φ' that keeps it
    steady, solved from the lean equation (θ'' = 0 at θ' = 0), and the closed form derived by
    hand (closed_form_spin), which must agree.

Usage: tools/scipy_reference/rolling_disk.sh
"""

import json
import pathlib

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "crates" / "lagrange" / "tests" / "data" / "rolling_disk.json"

M, R, G = 1.0, 0.5, 9.81
NAMES = ["x", "y", "psi", "theta", "phi"]


def residual(theta, rates, accelerations):
    """Newton–Euler's three moment equations (H' + ω_L × H − (R F2, −R F1, 0)), per unit mass,
    at lean θ, rates (ψ', θ', φ') and accelerations (ψ'', θ'', φ'')."""
    psi_d, theta_d, phi_d = rates
    psi_dd, theta_dd, phi_dd = accelerations
    s, c = np.sin(theta), np.cos(theta)
    o = np.array([theta_d, psi_d * s, psi_d * c])
    w = np.array([theta_d, psi_d * s + phi_d, psi_d * c])
    w_d = np.array([theta_dd, psi_dd * s + psi_d * theta_d * c + phi_dd,
                    psi_dd * c - psi_d * theta_d * s])
    v = R * np.array([w[1], -w[0], 0.0])
    v_d = R * np.array([w_d[1], -w_d[0], 0.0])
    force = v_d + np.cross(o, v) + G * np.array([0.0, s, c])
    inertia = R**2 * np.array([0.25, 0.5, 0.25])
    moment = np.array([R * force[1], -R * force[0], 0.0])
    return inertia * w_d + np.cross(o, inertia * w) - moment


def accelerations(theta, rates):
    """(ψ'', θ'', φ''): the residual is affine in them."""
    base = residual(theta, rates, np.zeros(3))
    matrix = np.column_stack([residual(theta, rates, e) - base for e in np.eye(3)])
    return np.linalg.solve(matrix, -base)


def rhs(_t, state):
    """state = (x, y, ψ, θ, φ, ψ', θ', φ')."""
    psi, theta = state[2], state[3]
    rates = state[5:]
    x_d, y_d = rolling_rates(psi, rates[2])
    return np.concatenate([[x_d, y_d], rates, accelerations(theta, rates)])


def rolling_rates(psi, phi_d):
    """x', y' of a rolling contact: the contact point moves at R φ' along the heading A.x."""
    return R * phi_d * np.cos(psi), R * phi_d * np.sin(psi)


def integrate(start, times):
    """Rows (q, q') at `times` from start = (x, y, ψ, θ, φ, ψ', θ', φ')."""
    solution = solve_ivp(rhs, (times[0], times[-1]), start, method="DOP853", rtol=1e-13,
                         atol=1e-13, t_eval=times)
    assert solution.success, solution.message
    states = []
    for state in solution.y.T:
        x_d, y_d = rolling_rates(state[2], state[7])
        states.append(list(state[:5]) + [x_d, y_d] + list(state[5:]))
    return states


def rows(times, states):
    columns = NAMES + [f"{n}_d" for n in NAMES]
    return [{"t": float(t), **{c: float(v) for c, v in zip(columns, s)}}
            for t, s in zip(times, states)]


def steady_spin(theta0, omega):
    """φ' of a steady turn at lean θ₀ and yaw rate Ω: the root of the lean acceleration θ''
    at θ' = 0."""
    return brentq(lambda phi_d: accelerations(theta0, [omega, 0.0, phi_d])[1], -200.0, 200.0,
                  xtol=1e-15, rtol=1e-15)


def closed_form_spin(theta0, omega):
    """φ' of the steady turn by hand, Newton–Euler about the centre: with V = R(Ω sin θ₀ + φ')
    the centre's speed along A.x, the contact force is F = m V Ω A.y + m g A.z, and the
    lean component of dH/dt = ω_L × H (H = I ω, I = m R² diag(1/4, 1/2, 1/4) in L) equals that
    of −R L.z × F:  R Ω cos θ₀ (−5/4 Ω sin θ₀ − 3/2 φ') = g sin θ₀."""
    s, c = np.sin(theta0), np.cos(theta0)
    return -(G * s + 1.25 * R * omega**2 * s * c) / (1.5 * R * omega * c)


def main():
    times = np.linspace(0.0, 4.0, 9)
    # The example's initial state: lean 0.2, yaw rate 1, lean rate 0.1, spin 6.
    general = [0.0, 0.0, 0.0, 0.2, 0.0, 1.0, 0.1, 6.0]
    theta0, omega = 0.3, 2.0
    spin = steady_spin(theta0, omega)
    assert abs(spin - closed_form_spin(theta0, omega)) < 1e-10, "the two steady spins differ"
    steady = [0.0, 0.0, 0.0, theta0, 0.0, omega, 0.0, spin]
    data = {
        "source": "tools/scipy_reference/rolling_disk.py: Newton-Euler by hand, DOP853 at 1e-13",
        "parameters": {"m": M, "R": R, "g": G},
        "general": rows(times, integrate(general, times)),
        "steady": {"theta": theta0, "psi_d": omega, "phi_d": spin,
                   "rows": rows(times, integrate(steady, times))},
    }
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {OUT}; steady spin {spin!r}")


if __name__ == "__main__":
    main()

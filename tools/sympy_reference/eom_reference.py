"""Independent reference data for lagrange's equations of motion.

Each system below re-models one of our `.lag` files from scratch in SymPy's
`sympy.physics.mechanics` (frames, points, particles, rigid bodies, and
`LagrangesMethod` with a force list for applied forces and dissipation), then
evaluates the mass matrix `M` and the forcing `f` of `M q_dd = f` at seeded
random values of every parameter, input, coordinate, rate and the time `t`.
The results are written to `tests/data/eom/<example-file-stem>.json`.

Nothing here reads the `.lag` files or calls lagrange: the geometry, the sign
conventions, the coordinate order and the parameter names were copied by hand
from each file (and its comments), so that a mistake in lagrange's pipeline
cannot also be a mistake in the reference.

Run it through `bash tools/sympy_reference/run.sh`, which pins SymPy 1.14.0.
"""

import json
import os
import sys

import numpy as np
import sympy as sp
import sympy.physics.mechanics as me

SEED = 20261122
SAMPLES = 5
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
OUT_DIR = os.path.join(ROOT, "tests", "data", "eom")
GENERATOR = f"tools/sympy_reference/eom_reference.py (SymPy {sp.__version__}, LagrangesMethod)"

t = me.dynamicsymbols._t

# Default sampling ranges. Parameters are positive (uniform 0.5..2), inputs and
# rates may have either sign, coordinates stay in a moderate range; systems
# override a range where the model needs it (see `ranges` below).
PARAM_RANGE = (0.5, 2.0)
INPUT_RANGE = (-2.0, 2.0)
COORD_RANGE = (-1.5, 1.5)
RATE_RANGE = (-2.0, 2.0)
TIME_RANGE = (0.0, 2.0)


class System:
    """One modelled system: Lagrangian, forces, and the names needed to sample it."""

    def __init__(self, stem, model, q, lagrangian, forces, frame, params, inputs=(),
                 ranges=None, derived_inputs=None, notes="", extra=None):
        self.stem = stem
        self.model = model
        self.q = list(q)
        self.lagrangian = lagrangian
        self.forces = list(forces)
        self.frame = frame
        self.params = list(params)
        self.inputs = list(inputs)
        self.ranges = ranges or {}
        # Inputs whose value the .lag file defines in terms of parameters and t:
        # they are sampled consistently with that definition, not drawn freely.
        self.derived_inputs = derived_inputs or {}
        self.notes = notes
        self.extra = extra


def qname(q):
    return q.func.__name__


def lagrange(system):
    lm = me.LagrangesMethod(system.lagrangian, system.q, forcelist=system.forces or None,
                            frame=system.frame)
    lm.form_lagranges_equations()
    return lm.mass_matrix, lm.forcing


def to_plain(expr, q):
    """Replace q(t), q'(t) by plain symbols `name`, `name_d`, so the expression can be evaluated."""
    qd = [qi.diff(t) for qi in q]
    sub = {}
    for qi, qdi in zip(q, qd):
        sub[qdi] = sp.Symbol(qname(qi) + "_d")
    for qi in q:
        sub[qi] = sp.Symbol(qname(qi))
    return me.msubs(expr, sub)


def draw(rng, lo_hi):
    lo, hi = lo_hi
    return float(rng.uniform(lo, hi))


def sample_values(system, rng):
    values = {}
    for p in system.params:
        values[p.name] = draw(rng, system.ranges.get(p.name, PARAM_RANGE))
    for u in system.inputs:
        if u.name not in system.derived_inputs:
            values[u.name] = draw(rng, system.ranges.get(u.name, INPUT_RANGE))
    for qi in system.q:
        name = qname(qi)
        values[name] = draw(rng, system.ranges.get(name, COORD_RANGE))
    for qi in system.q:
        name = qname(qi) + "_d"
        values[name] = draw(rng, system.ranges.get(name, RATE_RANGE))
    values["t"] = draw(rng, system.ranges.get("t", TIME_RANGE))
    for name, definition in system.derived_inputs.items():
        values[name] = float(definition.subs({sp.Symbol(k): v for k, v in values.items()}).evalf(30))
    return values


def evaluate(expr, values):
    # Match symbols by name: the models declare parameters with assumptions (positive=True).
    sub = {s: sp.Float(values[s.name], 30) for s in expr.free_symbols if s.name in values}
    out = sp.N(expr.xreplace(sub), 25)
    if out.free_symbols:
        raise RuntimeError(f"unevaluated symbols left: {out.free_symbols}")
    return float(out)


def generate(system, rng):
    mass_matrix, forcing = lagrange(system)
    mass_matrix = to_plain(mass_matrix, system.q)
    forcing = to_plain(forcing, system.q)
    samples = []
    for _ in range(SAMPLES):
        values = sample_values(system, rng)
        sample = {
            "values": values,
            "mass_matrix": [[evaluate(mass_matrix[i, j], values) for j in range(mass_matrix.shape[1])]
                            for i in range(mass_matrix.shape[0])],
            "forcing": [evaluate(forcing[i], values) for i in range(forcing.shape[0])],
        }
        if system.extra is not None:
            sample.update(system.extra(values))
        samples.append(sample)
    doc = {
        "schema": 1,
        "generator": GENERATOR,
        "model": system.model,
        "coordinates": [qname(qi) for qi in system.q],
        "notes": system.notes,
        "samples": samples,
    }
    return doc, mass_matrix, forcing


# --- The systems ---------------------------------------------------------------------------
# Each builder follows its .lag file line by line; the .lag lines are quoted in comments.

def simple_pendulum():
    theta = me.dynamicsymbols("theta")
    m, l, g = sp.symbols("m l g", positive=True)
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    P = O.locatenew("P", l * sp.sin(theta) * N.x - l * sp.cos(theta) * N.y)
    P.set_vel(N, P.pos_from(O).dt(N))
    bob = me.Particle("bob", P, m)
    forces = [(P, -m * g * N.y)]                        # gravity -g*N.y
    return System("simple-pendulum", "examples/simple-pendulum.lag", [theta],
                  me.Lagrangian(N, bob), forces, N, [m, l, g],
                  notes="Point mass on a massless rod; theta from the downward vertical; y up.")


def double_pendulum():
    theta1, theta2 = me.dynamicsymbols("theta1 theta2")
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g", positive=True)
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    P1 = O.locatenew("P1", l1 * sp.sin(theta1) * N.x - l1 * sp.cos(theta1) * N.y)
    P2 = P1.locatenew("P2", l2 * sp.sin(theta2) * N.x - l2 * sp.cos(theta2) * N.y)
    for P in (P1, P2):
        P.set_vel(N, P.pos_from(O).dt(N))
    bodies = [me.Particle("b1", P1, m1), me.Particle("b2", P2, m2)]
    forces = [(P1, -m1 * g * N.y), (P2, -m2 * g * N.y)]
    return System("double-pendulum", "examples/double-pendulum.lag", [theta1, theta2],
                  me.Lagrangian(N, *bodies), forces, N, [m1, m2, l1, l2, g],
                  notes="Two point masses on massless rods; both angles absolute, from the downward vertical.")


def spherical_pendulum():
    phi, theta = me.dynamicsymbols("phi theta")
    m, l, g = sp.symbols("m l g", positive=True)
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [phi, N.z])            # frame B = N rotated phi about z
    B = A.orientnew("B", "Axis", [theta, A.x])          #           then theta about x
    O = me.Point("O"); O.set_vel(N, 0)
    P = O.locatenew("P", -l * B.z)
    P.set_vel(N, P.pos_from(O).dt(N))
    forces = [(P, -m * g * N.z)]
    return System("spherical-pendulum", "examples/spherical-pendulum.lag", [phi, theta],
                  me.Lagrangian(N, me.Particle("bob", P, m)), forces, N, [m, l, g],
                  ranges={"theta": (0.3, 1.3)},
                  notes="Azimuth phi about N.z, then tilt theta about the intermediate x axis; bob at -l*B.z; z up. "
                        "theta is sampled in 0.3..1.3 (the mass matrix is singular at theta = 0).")


def bead_on_rotating_hoop():
    theta = me.dynamicsymbols("theta")
    m, R, Omega, g = sp.symbols("m R Omega g", positive=True)
    psi = Omega * t                                      # driven psi = Omega*t
    N = me.ReferenceFrame("N")
    H = N.orientnew("H", "Axis", [psi, N.z])
    O = me.Point("O"); O.set_vel(N, 0)
    P = O.locatenew("P", R * sp.sin(theta) * H.x - R * sp.cos(theta) * N.z)
    P.set_vel(N, P.pos_from(O).dt(N))
    forces = [(P, -m * g * N.z)]
    return System("bead-on-rotating-hoop", "examples/bead-on-rotating-hoop.lag", [theta],
                  me.Lagrangian(N, me.Particle("bead", P, m)), forces, N, [m, R, Omega, g],
                  notes="Rheonomic: psi = Omega*t is substituted before differentiation (psi is not in 'values'; "
                        "it is Omega*t). The hoop is massless.")


def atwood_machine():
    # The .lag file keeps y1, y2, phi with two holonomic constraints (multipliers). The M and f
    # written here are those of the unconstrained Lagrangian in all three coordinates, i.e. of the
    # DAE form M q_dd + A^T lambda = f; the constraint rows A (A q_dd = b) and the reduced one-degree-
    # of-freedom system in y1 (y2 = L - y1, phi = y1/R) are written alongside.
    y1, y2, phi = me.dynamicsymbols("y1 y2 phi")
    m1, m2, M, R, I, L, g = sp.symbols("m1 m2 M R I L g", positive=True)
    N = me.ReferenceFrame("N")
    P = N.orientnew("P", "Axis", [phi, N.z])
    O = me.Point("O"); O.set_vel(N, 0)
    A = O.locatenew("A", -R * N.x - y1 * N.y)
    B = O.locatenew("B", R * N.x - y2 * N.y)
    for pt in (A, B):
        pt.set_vel(N, pt.pos_from(O).dt(N))
    pulley = me.RigidBody("pulley", O, P, M, (me.inertia(P, I / 2, I / 2, I), O))
    bodies = [me.Particle("a", A, m1), me.Particle("b", B, m2), pulley]
    forces = [(A, -m1 * g * N.y), (B, -m2 * g * N.y), (O, -M * g * N.y)]
    lagr = me.Lagrangian(N, *bodies)

    # Reduced system, modelled again from the kinematics with y2 and phi eliminated.
    q = [y1, y2, phi]
    reduce = {y2: L - y1, phi: y1 / R}
    reduce_d = {y2.diff(t): -y1.diff(t), phi.diff(t): y1.diff(t) / R}
    lagr_red = me.msubs(lagr, reduce_d, reduce)
    Bred = O.locatenew("Bred", R * N.x - (L - y1) * N.y)
    Bred.set_vel(N, Bred.pos_from(O).dt(N))
    forces_red = [(A, -m1 * g * N.y), (Bred, -m2 * g * N.y)]
    lm_red = me.LagrangesMethod(lagr_red, [y1], forcelist=forces_red, frame=N)
    lm_red.form_lagranges_equations()
    m_red = to_plain(lm_red.mass_matrix, [y1])
    f_red = to_plain(lm_red.forcing, [y1])
    constraints = sp.Matrix([y1 + y2 - L, y1 - R * phi])  # rope, no_slip as lhs - rhs
    jac = to_plain(constraints.jacobian(q), q)

    def extra(values):
        # The constraints are linear in q with constant coefficients, so b = 0.
        return {
            "constraint_names": ["rope", "no_slip"],
            "constraint_jacobian": [[evaluate(jac[i, j], values) for j in range(3)] for i in range(2)],
            "constraint_rhs": [0.0, 0.0],
            "reduced": {
                "coordinates": ["y1"],
                "eliminated": {"y2": "L - y1", "phi": "y1/R"},
                "mass_matrix": [[evaluate(m_red[0, 0], values)]],
                "forcing": [evaluate(f_red[0], values)],
            },
        }

    return System("atwood-machine", "examples/atwood-machine.lag", q, lagr, forces, N,
                  [m1, m2, M, R, I, L, g], extra=extra,
                  notes="Constrained model (two holonomic constraints). mass_matrix/forcing are the unconstrained "
                        "Lagrangian's in (y1, y2, phi): the M and f of the DAE form M q_dd + A^T lambda = f. "
                        "constraint_jacobian is A = d(lhs - rhs)/dq of rope (y1 + y2 - L) and no_slip (y1 - R*phi), "
                        "A q_dd = constraint_rhs; 'reduced' is the 1-DOF system in y1 after eliminating "
                        "y2 = L - y1 and phi = y1/R (M = m1 + m2 + I/R^2, f = (m1 - m2) g). The sampled values of "
                        "y2 and phi are independent draws, so the samples of the full form are not on the "
                        "constraint manifold (M and f do not depend on them here).")


def two_masses_three_springs():
    x1, x2 = me.dynamicsymbols("x1 x2")
    m1, m2, k1, k2, k3, a = sp.symbols("m1 m2 k1 k2 k3 a", positive=True)
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    P1 = O.locatenew("P1", (a + x1) * N.x)
    P2 = O.locatenew("P2", (2 * a + x2) * N.x)
    W = O.locatenew("W", 3 * a * N.x)
    for P in (P1, P2):
        P.set_vel(N, P.pos_from(O).dt(N))
    # Springs with rest length a between points: V = 1/2 k (|P2 - P1| - a)^2, with the true
    # distance (a square root), exactly as the language defines it.
    V = (k1 / 2 * (P1.pos_from(O).magnitude() - a) ** 2
         + k2 / 2 * (P2.pos_from(P1).magnitude() - a) ** 2
         + k3 / 2 * (W.pos_from(P2).magnitude() - a) ** 2)
    T = me.kinetic_energy(N, me.Particle("p1", P1, m1), me.Particle("p2", P2, m2))
    return System("two-masses-three-springs", "examples/two-masses-three-springs.lag", [x1, x2],
                  T - V, [], N, [m1, m2, k1, k2, k3, a],
                  ranges={"x1": (-0.4, 0.4), "x2": (-0.4, 0.4)},
                  notes="Springs use the distance between their ends (|.|), rest length a. x1, x2 are sampled in "
                        "-0.4..0.4 so that every spring's length a + x1, a + x2 - x1, a - x2 stays positive "
                        "(a >= 0.5); there the model is the linear one.")


def damped_oscillator():
    x = me.dynamicsymbols("x")
    m, k, c, F0, omega = sp.symbols("m k c F0 omega", positive=True)
    F = sp.Symbol("F")
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    P = O.locatenew("P", x * N.x)
    P.set_vel(N, P.pos_from(O).dt(N))
    V = k / 2 * P.pos_from(O).magnitude() ** 2          # spring k from origin to P
    # damper c on x: Rayleigh 1/2 c x'^2, i.e. the generalized force -c x'; applied as a force
    # along N.x at P, whose partial velocity with respect to x' is N.x.
    forces = [(P, -c * x.diff(t) * N.x + F * N.x)]
    return System("damped-oscillator", "examples/damped-oscillator.lag", [x],
                  me.kinetic_energy(N, me.Particle("p", P, m)) - V, forces, N, [m, k, c, F0, omega],
                  inputs=[F], derived_inputs={"F": sp.Symbol("F0") * sp.cos(sp.Symbol("omega") * sp.Symbol("t"))},
                  notes="The input F is defined in the file as F0*cos(omega*t); the forcing is written with F "
                        "as a symbol and the sampled F equals F0*cos(omega*t) at the sampled t, so the data "
                        "holds whether or not the input is substituted.")


def driven_pivot_pendulum():
    theta = me.dynamicsymbols("theta")
    m, l, a, omega, g = sp.symbols("m l a omega g", positive=True)
    s = a * sp.cos(omega * t)                           # driven s = a*cos(omega*t)
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    pivot = O.locatenew("pivot", s * N.y)
    P = pivot.locatenew("P", l * sp.sin(theta) * N.x - l * sp.cos(theta) * N.y)
    P.set_vel(N, P.pos_from(O).dt(N))
    # damper 0.001 on theta: generalized force -0.001 theta', applied as a torque on a frame that
    # turns by theta about N.z (its angular velocity's partial with respect to theta' is N.z).
    Rod = N.orientnew("Rod", "Axis", [theta, N.z])
    c_hinge = sp.Rational(1, 1000)
    forces = [(P, -m * g * N.y), (Rod, -c_hinge * theta.diff(t) * N.z)]
    return System("driven-pivot-pendulum", "examples/driven-pivot-pendulum.lag", [theta],
                  me.Lagrangian(N, me.Particle("bob", P, m)), forces, N, [m, l, a, omega, g],
                  notes="Rheonomic: s = a*cos(omega*t) substituted (s is not in 'values'). The hinge damper "
                        "coefficient is the literal 0.001 of the file.")


def heavy_symmetric_top():
    psi, theta, phi = me.dynamicsymbols("psi theta phi")
    m, l, A, C, g = sp.symbols("m l A C g", positive=True)
    N = me.ReferenceFrame("N")
    F1 = N.orientnew("F1", "Axis", [psi, N.z])          # precession about N.z
    F2 = F1.orientnew("F2", "Axis", [theta, F1.x])      # nutation about the line of nodes
    B = F2.orientnew("B", "Axis", [phi, F2.z])          # spin about the top's axis
    O = me.Point("O"); O.set_vel(N, 0)
    G = O.locatenew("G", l * B.z)
    G.set_vel(N, G.pos_from(O).dt(N))
    # inertia A, A, C about origin: SymPy moves it to the centre of mass itself (parallel axes).
    top = me.RigidBody("top", G, B, m, (me.inertia(B, A, A, C), O))
    forces = [(G, -m * g * N.z)]
    return System("heavy-symmetric-top", "examples/heavy-symmetric-top.lag", [psi, theta, phi],
                  me.Lagrangian(N, top), forces, N, [m, l, A, C, g],
                  ranges={"theta": (0.3, 1.3)},
                  notes="z-x-z Euler angles as a chain of simple rotations (R = Rz(psi) Rx(theta) Rz(phi)); "
                        "inertia A, A, C about the fixed tip. theta is sampled in 0.3..1.3 (M is singular at "
                        "theta = 0). A and C are drawn independently (a physical top needs C <= 2A + 2 m l^2 "
                        "etc.; the equations do not care).")


def cart_pendulum_7_1():
    x, theta = me.dynamicsymbols("x theta")
    m_A, m_B, l, k, g = sp.symbols("m_A m_B l k g", positive=True)
    F, Cc = sp.symbols("F C")
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    A = O.locatenew("A", x * N.x)
    B = A.locatenew("B", l * sp.sin(theta) * N.x + l * sp.cos(theta) * N.y)
    for P in (A, B):
        P.set_vel(N, P.pos_from(O).dt(N))
    V = k / 2 * A.pos_from(O).magnitude() ** 2          # spring k from origin to A
    T = me.kinetic_energy(N, me.Particle("a", A, m_A), me.Particle("b", B, m_B))
    # generalized force C on theta: a torque C*N.z on a frame turning by theta about N.z has
    # exactly Q_theta = C and no other component.
    Aux = N.orientnew("Aux", "Axis", [theta, N.z])
    forces = [(A, m_A * g * N.y), (B, m_B * g * N.y),   # gravity g*N.y (y down)
              (A, F * N.x), (Aux, Cc * N.z)]
    return System("7.1-cart-pendulum", "examples/seed/7.1-cart-pendulum.lag", [x, theta],
                  T - V, forces, N, [m_A, m_B, l, k, g], inputs=[F, Cc],
                  notes="Gravity along +y (y down). The inputs F and C (default 0 in the file) are kept as "
                        "symbols and drawn at random. C enters only as Q_theta = C.")


def inverted_pendulum_7_4():
    x, theta = me.dynamicsymbols("x theta")
    M, m, L, g = sp.symbols("M m L g", positive=True)
    F = sp.Symbol("F")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [theta, N.z])
    O = me.Point("O"); O.set_vel(N, 0)
    A = O.locatenew("A", x * N.x)
    G = A.locatenew("G", L / 2 * B.y)
    for P in (A, G):
        P.set_vel(N, P.pos_from(O).dt(N))
    rod = me.RigidBody("rod", G, B, m, (me.inertia(B, m * L ** 2 / 12, 0, m * L ** 2 / 12), G))
    forces = [(A, -M * g * N.y), (G, -m * g * N.y), (A, F * N.x)]
    return System("7.4-inverted-pendulum", "examples/seed/7.4-inverted-pendulum.lag", [x, theta],
                  me.Lagrangian(N, me.Particle("cart", A, M), rod), forces, N, [M, m, L, g], inputs=[F],
                  notes="theta from the upward vertical, counter-clockwise (B.y along the rod); the rod is a "
                        "rigid body with central inertia m L^2/12 across it. The input F is drawn at random.")


SYSTEMS = [
    simple_pendulum,
    double_pendulum,
    spherical_pendulum,
    bead_on_rotating_hoop,
    atwood_machine,
    two_masses_three_springs,
    damped_oscillator,
    driven_pivot_pendulum,
    heavy_symmetric_top,
    cart_pendulum_7_1,
    inverted_pendulum_7_4,
]


# --- Sanity checks against closed forms ------------------------------------------------------

def check_closed_forms(results):
    S = sp.Symbol

    def plain(expr):
        return expr.xreplace({s: S(s.name) for s in expr.free_symbols})

    results = {k: (plain(v[0]), plain(v[1])) for k, v in results.items()}
    checks = 0
    # Simple pendulum: m l^2 theta_dd = -m g l sin(theta).
    Mm, f = results["simple-pendulum"]
    m, l, g, th = S("m"), S("l"), S("g"), S("theta")
    assert sp.simplify(Mm[0, 0] - m * l ** 2) == 0
    assert sp.simplify(f[0] + m * g * l * sp.sin(th)) == 0
    checks += 1
    # Double pendulum, the textbook closed form.
    Mm, f = results["double-pendulum"]
    m1, m2, l1, l2 = S("m1"), S("m2"), S("l1"), S("l2")
    t1, t2, t1d, t2d = S("theta1"), S("theta2"), S("theta1_d"), S("theta2_d")
    M_ref = sp.Matrix([[(m1 + m2) * l1 ** 2, m2 * l1 * l2 * sp.cos(t1 - t2)],
                       [m2 * l1 * l2 * sp.cos(t1 - t2), m2 * l2 ** 2]])
    f_ref = sp.Matrix([-m2 * l1 * l2 * t2d ** 2 * sp.sin(t1 - t2) - (m1 + m2) * g * l1 * sp.sin(t1),
                       m2 * l1 * l2 * t1d ** 2 * sp.sin(t1 - t2) - m2 * g * l2 * sp.sin(t2)])
    assert sp.simplify(sp.expand_trig(Mm - M_ref)) == sp.zeros(2, 2)
    assert sp.simplify(sp.expand_trig(f - f_ref)) == sp.zeros(2, 1)
    checks += 1
    # Bead on a hoop: m R^2 theta_dd = m R^2 Omega^2 sin cos - m g R sin.
    Mm, f = results["bead-on-rotating-hoop"]
    m, R, Om = S("m"), S("R"), S("Omega")
    assert sp.simplify(Mm[0, 0] - m * R ** 2) == 0
    assert sp.simplify(f[0] - (m * R ** 2 * Om ** 2 * sp.sin(th) * sp.cos(th) - m * g * R * sp.sin(th))) == 0
    checks += 1
    # Heavy top: the (psi, psi) entry is A sin^2 + C cos^2 (+ m l^2 sin^2 is not there: A is about the tip).
    Mm, f = results["heavy-symmetric-top"]
    A, C = S("A"), S("C")
    assert sp.simplify(Mm[0, 0] - (A * sp.sin(th) ** 2 + C * sp.cos(th) ** 2)) == 0
    assert sp.simplify(Mm[1, 1] - A) == 0 and sp.simplify(Mm[2, 2] - C) == 0
    assert sp.simplify(Mm[0, 2] - C * sp.cos(th)) == 0
    checks += 1
    # 7.4: M = [[M + m, -m L/2 cos], [., m L^2/3]], f_theta = m g L/2 sin(theta).
    Mm, f = results["7.4-inverted-pendulum"]
    Mc, L, x_d, th_d, F = S("M"), S("L"), S("x_d"), S("theta_d"), S("F")
    M_ref = sp.Matrix([[Mc + m, -m * L / 2 * sp.cos(th)], [-m * L / 2 * sp.cos(th), m * L ** 2 / 3]])
    f_ref = sp.Matrix([F - m * L / 2 * th_d ** 2 * sp.sin(th), m * g * L / 2 * sp.sin(th)])
    assert sp.simplify(Mm - M_ref) == sp.zeros(2, 2)
    assert sp.simplify(f - f_ref) == sp.zeros(2, 1)
    checks += 1
    return checks


def main():
    os.makedirs(OUT_DIR, exist_ok=True)
    rng = np.random.default_rng(SEED)
    results = {}
    for build in SYSTEMS:
        system = build()
        doc, mass_matrix, forcing = generate(system, rng)
        results[system.stem] = (mass_matrix, forcing)
        path = os.path.join(OUT_DIR, system.stem + ".json")
        with open(path, "w") as out:
            json.dump(doc, out, indent=1)
            out.write("\n")
        print(f"{system.stem}: {len(system.q)} coordinates, {SAMPLES} samples -> "
              f"{os.path.relpath(path, ROOT)}")
        for i in range(mass_matrix.shape[0]):
            print(f"  f[{i}] = {sp.simplify(forcing[i])}")
    print(f"closed-form checks passed: {check_closed_forms(results)}")


if __name__ == "__main__":
    sys.exit(main())

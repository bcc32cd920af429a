"""Independent reference data for lagrange's constraint reactions.

Each system below re-models one of our `.lag` files from scratch in SymPy: the
accelerations come from Lagrange's equations of the 2nd kind in minimal
coordinates (`sympy.physics.mechanics.LagrangesMethod`), and the reaction from
Newton's law written directly for the body it acts on,

    R = m a_G - m g - (applied forces on that body),

so neither the release with redundant coordinates nor lagrange's Newton-Euler
code is reused. Values at seeded random states are written to
`tests/data/reactions/<example-file-stem>.json`; `crates/cli/tests/reactions.rs`
compares lagrange's reactions with them.

Run it through `bash tools/sympy_reference/run_reactions.sh` (pins SymPy 1.14.0).
"""

import json
import os
import random

import sympy as sp
import sympy.physics.mechanics as me

SEED = 20261123
SAMPLES = 6
ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
OUT_DIR = os.path.join(ROOT, "tests", "data", "reactions")
GENERATOR = f"tools/sympy_reference/reactions.py (SymPy {sp.__version__}, LagrangesMethod + Newton)"
t = me.dynamicsymbols._t


def accelerations(L, q, forces, frame):
    """q_dd as expressions of q, q_d (minimal coordinates)."""
    lm = me.LagrangesMethod(L, q, forcelist=forces, frame=frame)
    lm.form_lagranges_equations()
    return list(lm.rhs()[len(q):])


def newton(m, r, q, qdd, gravity, applied=(0, 0, 0)):
    """R = m r'' - m g - F, with q'' replaced."""
    a = [sp.diff(c, t, 2) for c in r]
    sub = {sp.diff(qi, t, 2): v for qi, v in zip(q, qdd)}
    return [sp.simplify((m * a[k] - m * gravity[k] - applied[k]).subs(sub)) for k in range(3)]


def sample(rng, params, q, inputs=(), coord_range=(-1.5, 1.5)):
    values = {str(p): rng.uniform(0.5, 2.0) for p in params}
    for u in inputs:
        values[str(u)] = rng.uniform(-2.0, 2.0)
    for qi in q:
        name = qi.name
        values[name] = rng.uniform(*coord_range)
        values[name + "_d"] = rng.uniform(-2.0, 2.0)
    return values


def evaluate(expr, q, values):
    sub = {}
    for qi in q:
        sub[sp.diff(qi, t)] = sp.Symbol(qi.name + "_d")
    e = expr.subs(sub)
    sub2 = {qi: sp.Symbol(qi.name) for qi in q}
    e = e.subs(sub2)
    return float(e.subs({sp.Symbol(k): v for k, v in values.items()}))


def write(stem, model, q, params, reactions, notes, inputs=(), coord_range=(-1.5, 1.5), extra_values=None):
    rng = random.Random(f"{SEED}-{stem}")
    samples = []
    for _ in range(SAMPLES):
        values = sample(rng, params, q, inputs, coord_range)
        if extra_values:
            values.update(extra_values(values))
        out = {}
        for name, (kind, value) in reactions.items():
            if kind in ("components", "couple", "friction"):
                out[name] = [evaluate(c, q, values) for c in value]
            else:
                out[name] = evaluate(value, q, values)
        samples.append({"values": values, "reactions": out})
    data = {
        "schema": 1,
        "generator": GENERATOR,
        "model": model,
        "notes": notes,
        "kinds": {name: kind for name, (kind, _) in reactions.items()},
        "samples": samples,
    }
    os.makedirs(OUT_DIR, exist_ok=True)
    with open(os.path.join(OUT_DIR, stem + ".json"), "w") as f:
        json.dump(data, f, indent=1)
        f.write("\n")
    print("wrote", stem)


def simple_pendulum():
    th = me.dynamicsymbols("theta")
    m, l, g = sp.symbols("m l g")
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    P = O.locatenew("P", l * sp.sin(th) * N.x - l * sp.cos(th) * N.y)
    P.set_vel(N, P.pos_from(O).dt(N))
    bob = me.Particle("bob", P, m)
    bob.potential_energy = m * g * P.pos_from(O).dot(N.y)
    L = me.Lagrangian(N, bob)
    qdd = accelerations(L, [th], [], N)
    r = [P.pos_from(O).dot(v) for v in (N.x, N.y, N.z)]
    R = newton(m, r, [th], qdd, (0, -g, 0))
    write("simple-pendulum", "examples/simple-pendulum.lag", [th], [m, l, g],
          {"pivot": ("components", R)}, "hinge at the origin on the bob: R = m a - m g")


def cart_pendulum():
    x, th = me.dynamicsymbols("x theta")
    mA, mB, l, k, g, F, C = sp.symbols("m_A m_B l k g F C")
    N = me.ReferenceFrame("N")
    O = me.Point("O"); O.set_vel(N, 0)
    A = O.locatenew("A", x * N.x); A.set_vel(N, A.pos_from(O).dt(N))
    B = A.locatenew("B", l * sp.sin(th) * N.x + l * sp.cos(th) * N.y); B.set_vel(N, B.pos_from(O).dt(N))
    pa, pb = me.Particle("pa", A, mA), me.Particle("pb", B, mB)
    pb.potential_energy = -mB * g * B.pos_from(O).dot(N.y)
    pa.potential_energy = k * x**2 / 2
    L = me.Lagrangian(N, pa, pb)
    # F on the cart along x; the seed's C is the generalized force Q_theta = C, made here by
    # a couple C z on a frame whose angular velocity is +theta' z.
    Fr = me.ReferenceFrame("Fr"); Fr.orient(N, "Axis", [th, N.z])
    qdd = accelerations(L, [x, th], [(A, F * N.x), (Fr, C * N.z)], N)
    r = [B.pos_from(O).dot(v) for v in (N.x, N.y, N.z)]
    R = newton(mB, r, [x, th], qdd, (0, g, 0))
    # The track carries the cart and the pendulum: its push along -y balances both masses'
    # y-momentum (the spring and F act along x).
    track = -(newton(mB, r, [x, th], qdd, (0, g, 0))[1] - mA * g)
    write("7.1-cart-pendulum", "examples/seed/7.1-cart-pendulum.lag", [x, th],
          [mA, mB, l, k, g], {"hinge_A": ("components", R), "track": ("along", sp.simplify(track))},
          "hinge at A on the bob B (massless rod): R = m_B a_B - m_B g y; track normal force "
          "on cart + pendulum along -y: N = -(m_B a_B.y - (m_A + m_B) g); Q_theta = C", inputs=[F, C])


def inverted_pendulum():
    x, th = me.dynamicsymbols("x theta")
    M, m, Lr, g, F = sp.symbols("M m L g F")
    N = me.ReferenceFrame("N")
    B = N.orientnew("B", "Axis", [th, N.z])
    O = me.Point("O"); O.set_vel(N, 0)
    A = O.locatenew("A", x * N.x); A.set_vel(N, A.pos_from(O).dt(N))
    G = A.locatenew("G", Lr / 2 * B.y); G.set_vel(N, G.pos_from(O).dt(N))
    B.set_ang_vel(N, th.diff(t) * N.z)
    cart = me.Particle("cart", A, M)
    I = me.inertia(B, m * Lr**2 / 12, 0, m * Lr**2 / 12)
    rod = me.RigidBody("rod", G, B, m, (I, G))
    rod.potential_energy = m * g * G.pos_from(O).dot(N.y)
    L = me.Lagrangian(N, cart, rod)
    qdd = accelerations(L, [x, th], [(A, F * N.x)], N)
    r = [G.pos_from(O).dot(v) for v in (N.x, N.y, N.z)]
    R = newton(m, r, [x, th], qdd, (0, -g, 0))
    write("7.4-inverted-pendulum", "examples/seed/7.4-inverted-pendulum.lag", [x, th],
          [M, m, Lr, g], {"hinge_A": ("components", R)},
          "hinge at A on the rod: R = m a_G - m g", inputs=[F])


def atwood():
    y1 = me.dynamicsymbols("y1")
    m1, m2, M, R, I, Lr, g = sp.symbols("m1 m2 M R I L g")
    # Minimal coordinate y1: y2 = L - y1, phi = y1 / R.
    K = (m1 + m2) * y1.diff(t)**2 / 2 + I * (y1.diff(t) / R)**2 / 2
    V = m1 * g * (-y1) + m2 * g * (-(Lr - y1))
    N = me.ReferenceFrame("N")
    qdd = accelerations(K - V, [y1], [], N)
    r = [-R, -y1, 0]
    T = newton(m1, r, [y1], qdd, (0, -g, 0))[1]
    write("atwood-machine", "examples/atwood-machine.lag", [y1], [m1, m2, M, R, I, Lr, g],
          {"tension": ("along", T)},
          "rope tension on mass 1 along +y: T = m1 (a_1.y + g), minimal coordinate y1; the "
          "sampled y2 and phi are independent draws (the tension does not depend on them)",
          extra_values=lambda v: {"y2": 0.7, "y2_d": -v["y1_d"], "phi": 3.0, "phi_d": v["y1_d"] / v["R"]})


def particle_on_sphere():
    th = me.dynamicsymbols("theta")
    m, r, g = sp.symbols("m r g")
    pos = [r * sp.sin(th), r * sp.cos(th), 0]
    K = m * sum(sp.diff(c, t)**2 for c in pos) / 2
    V = m * g * pos[1]
    N = me.ReferenceFrame("N")
    qdd = accelerations(K - V, [th], [], N)
    Rv = newton(m, pos, [th], qdd, (0, -g, 0))
    n = [sp.sin(th), sp.cos(th), 0]
    Nn = sp.simplify(sum(a * b for a, b in zip(Rv, n)))
    write("particle-on-sphere", "examples/particle-on-sphere.lag", [th], [m, r, g],
          {"normal": ("along", Nn)}, "normal force of the sphere on the particle, outward: N = R.n")


def rolling_disk():
    x = me.dynamicsymbols("x")
    m, R, al, g = sp.symbols("m R alpha g")
    # Minimal coordinate x (phi = x / R): K = 1/2 m x'^2 + 1/2 (m R^2/2)(x'/R)^2.
    K = m * x.diff(t)**2 / 2 + m * R**2 / 2 * (x.diff(t) / R)**2 / 2
    Sx = [sp.cos(al), -sp.sin(al), 0]
    Sy = [sp.sin(al), sp.cos(al), 0]
    C = [x * Sx[k] + R * Sy[k] for k in range(3)]
    V = m * g * C[1]
    N = me.ReferenceFrame("N")
    qdd = accelerations(K - V, [x], [], N)
    Rv = newton(m, C, [x], qdd, (0, -g, 0))
    Nn = sp.simplify(sum(Rv[k] * Sy[k] for k in range(3)))
    friction = [sp.simplify(Rv[k] - Nn * Sy[k]) for k in range(3)]
    write("rolling-disk-incline", "examples/rolling-disk-incline.lag", [x], [m, R, al, g],
          {"roll": ("components", Rv), "contact": ("along", Nn), "contact@friction": ("friction", friction)},
          "contact force (normal + friction) on the disk: R = m a_C - m g; normal force N = R.S_y, "
          "friction R - N S_y; phi sampled as x/R",
          extra_values=lambda v: {"phi": v["x"] / v["R"], "phi_d": v["x_d"] / v["R"]})


def ladder():
    th = me.dynamicsymbols("theta")
    m, Lr, g = sp.symbols("m L g")
    G = [Lr / 2 * sp.sin(th), Lr / 2 * sp.cos(th), 0]
    K = m * sum(sp.diff(c, t)**2 for c in G) / 2 + (m * Lr**2 / 12) * th.diff(t)**2 / 2
    V = m * g * G[1]
    N = me.ReferenceFrame("N")
    qdd = accelerations(K - V, [th], [], N)
    Rv = newton(m, G, [th], qdd, (0, -g, 0))
    # Frictionless wall (normal +x) and floor (normal +y): each carries one component.
    write("ladder", "examples/ladder.lag", [th], [m, Lr, g],
          {"wall": ("along", Rv[0]), "floor": ("along", Rv[1])},
          "frictionless wall and floor: N_wall = m a_G.x, N_floor = m a_G.y + m g",
          coord_range=(0.1, 1.4))


def cart_with_mast():
    x = me.dynamicsymbols("x")
    M, m, Lr, be, k, g, F, W = sp.symbols("M m L beta k g F W")
    # One coordinate; the mast only translates. Newton for the whole: (M + m) x'' = F + W - k x.
    xdd = (F + W - k * x) / (M + m)
    By = [-sp.sin(be), sp.cos(be), 0]
    G = [x + Lr / 2 * By[0], Lr / 2 * By[1], 0]
    T = [x + Lr * By[0], Lr * By[1], 0]
    A = [x, 0, 0]
    aG = [xdd, 0, 0]
    wind = [W, 0, 0]
    weight = [0, -m * g, 0]
    # Newton for the mast: m a_G = m g + W + R; Euler about A (no rotation): 0 = (G - A) x (m g)
    # + (T - A) x W + (G - A) x (-m a_G) ... written as C = (G-A) x (m a_G - m g) - (T-A) x W.
    R = [m * aG[i] - weight[i] - wind[i] for i in range(3)]

    def cross(a, b):
        return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]

    GA = [G[i] - A[i] for i in range(3)]
    TA = [T[i] - A[i] for i in range(3)]
    C = [sp.simplify(u - v) for u, v in zip(cross(GA, [m * aG[i] - weight[i] for i in range(3)]), cross(TA, wind))]
    write("cart-with-mast", "examples/cart-with-mast.lag", [x], [M, m, Lr, be, k, g],
          {"weld": ("components", [sp.simplify(c) for c in R]), "weld@couple": ("couple", C)},
          "clamp at A on the mast: R = m a_G - m g - W (wind at the tip); couple about A: "
          "C = (G - A) x (m a_G - m g) - (T - A) x W", inputs=[F, W])


def double_pendulum():
    t1, t2 = me.dynamicsymbols("theta1 theta2")
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")
    P1 = [l1 * sp.sin(t1), -l1 * sp.cos(t1), 0]
    P2 = [P1[0] + l2 * sp.sin(t2), P1[1] - l2 * sp.cos(t2), 0]
    K = sum(m * sum(sp.diff(c, t)**2 for c in P) / 2 for m, P in ((m1, P1), (m2, P2)))
    V = g * (m1 * P1[1] + m2 * P2[1])
    N = me.ReferenceFrame("N")
    qdd = accelerations(K - V, [t1, t2], [], N)
    lower = newton(m2, P2, [t1, t2], qdd, (0, -g, 0))
    upper = newton(m1, P1, [t1, t2], qdd, (0, -g, 0))
    # The top pivot holds both bobs: the sum of their Newton's laws.
    top = [sp.simplify(a + b) for a, b in zip(upper, lower)]
    write("double-pendulum", "examples/double-pendulum.lag", [t1, t2], [m1, m2, l1, l2, g],
          {"top": ("components", top), "middle": ("components", lower)},
          "top pivot on both bobs: R = m1 a1 + m2 a2 - (m1 + m2) g; middle hinge on the lower bob")


if __name__ == "__main__":
    simple_pendulum()
    cart_pendulum()
    inverted_pendulum()
    atwood()
    particle_on_sphere()
    rolling_disk()
    ladder()
    cart_with_mast()
    double_pendulum()

"""The equations of motion of the seed's 7.1 against SymPy's own LagrangesMethod on the same
system, exactly (the difference simplifies to zero) and at random numbers; and the compiled
right-hand side against M⁻¹ f evaluated by SymPy."""

import random

import numpy as np
import sympy as sp
from sympy.physics import mechanics as me


def sympy_7_1():
    """7.1 built with sympy.physics.mechanics, as the model file states it: a cart A on a
    spring along x, a pendulum bob B on a massless rod of length l, gravity along +y, F on
    the cart, the couple C entering as the generalized force of theta."""
    x, theta = me.dynamicsymbols("x theta")
    m_A, m_B, l, k, g, F, C = sp.symbols("m_A m_B l k g F C")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    A = O.locatenew("A", x * N.x)
    B = A.locatenew("B", l * sp.sin(theta) * N.x + l * sp.cos(theta) * N.y)
    A.set_vel(N, A.pos_from(O).dt(N))
    B.set_vel(N, B.pos_from(O).dt(N))
    cart = me.Particle("cart", A, m_A)
    bob = me.Particle("bob", B, m_B)
    # Gravity along +y: V = -m_B g y_B; the spring from the origin: V = k x²/2.
    cart.potential_energy = k * x**2 / 2
    bob.potential_energy = -m_B * g * B.pos_from(O).dot(N.y)
    L = me.Lagrangian(N, cart, bob)
    # The rod turns by -theta about N.z (theta grows from +y towards +x): a couple C
    # about -N.z does virtual work C δθ.
    rod = N.orientnew("rod", "Axis", (-theta, N.z))
    forces = [(A, F * N.x), (rod, -C * N.z)]
    method = me.LagrangesMethod(L, [x, theta], forcelist=forces, frame=N)
    method.form_lagranges_equations()
    plain = {
        x.diff(): sp.Symbol("x_d"), theta.diff(): sp.Symbol("theta_d"),
        x: sp.Symbol("x"), theta: sp.Symbol("theta"),
    }
    # Rates before coordinates: x' contains x.
    M = method.mass_matrix.subs(plain)
    f = method.forcing.subs(plain)
    return M, f


def test_mass_matrix_and_forcing_equal_sympys_exactly(seed_7_1):
    M, f = seed_7_1.equations_of_motion()
    M_sympy, f_sympy = sympy_7_1()
    assert M.shape == M_sympy.shape == (2, 2)
    assert f.shape == f_sympy.shape == (2, 1)
    assert sp.simplify(M - M_sympy) == sp.zeros(2, 2)
    assert sp.simplify(f - f_sympy) == sp.zeros(2, 1)


def test_mass_matrix_and_forcing_equal_sympys_at_random_numbers(seed_7_1):
    eom = seed_7_1.equations_of_motion()
    M_sympy, f_sympy = sympy_7_1()
    names = sorted((M_sympy.free_symbols | f_sympy.free_symbols), key=str)
    assert {str(s) for s in names} == {str(s) for s in (eom.M.free_symbols | eom.f.free_symbols)}
    rng = random.Random(71)
    for _ in range(20):
        point = {s: rng.uniform(-2.0, 2.0) for s in names}
        ours = {eom.symbols[str(s)]: v for s, v in point.items()}
        assert np.allclose(np.array(eom.M.subs(ours), dtype=float),
                           np.array(M_sympy.subs(point), dtype=float), rtol=1e-12, atol=1e-12)
        assert np.allclose(np.array(eom.f.subs(ours), dtype=float),
                           np.array(f_sympy.subs(point), dtype=float), rtol=1e-12, atol=1e-12)


def test_the_symbols_unpack(seed_7_1):
    eom = seed_7_1.equations_of_motion()
    M, f = eom
    assert M is eom.M and f is eom.f
    assert [str(q) for q in eom.coordinates] == ["x", "theta"]
    assert [str(q) for q in eom.rates] == ["x_d", "theta_d"]


def test_rhs_is_the_inverse_mass_matrix_times_the_forcing(seed_7_1):
    eom = seed_7_1.equations_of_motion()
    values = {eom.symbols[name]: v for name, v in seed_7_1.values.items() if name in eom.symbols}
    q, qd = eom.coordinates, eom.rates
    accelerations = sp.lambdify(q + qd, (eom.M.subs(values).inv() * eom.f.subs(values)), "numpy")
    rng = np.random.default_rng(7)
    states = rng.uniform(-1.0, 1.0, size=(16, 4))
    batch = seed_7_1.rhs_batch(states, 0.0)
    for y, row in zip(states, batch):
        dy = seed_7_1.rhs(0.0, y)
        expected = np.concatenate([y[2:], np.ravel(accelerations(*y))])
        assert np.allclose(dy, expected, rtol=1e-12, atol=1e-12)
        assert np.array_equal(dy, row)


def test_rhs_refuses_a_state_of_the_wrong_length(seed_7_1):
    import pytest

    with pytest.raises(ValueError, match="the state has 3 entries"):
        seed_7_1.rhs(0.0, np.zeros(3))

"""lagrange: analytical mechanics from a model file, in Python and Jupyter.

Read a model (docs/language.md) and ask for what lagrange derives for it::

    import lagrange
    model = lagrange.Model.from_file("examples/seed/7.1-cart-pendulum.lag")
    model.solve()                       # the step-by-step solution (displays in Jupyter)
    M, f = model.equations_of_motion()  # SymPy matrices of M(q, t) q̈ = f(q, q̇, t)
    model.equilibria()                  # NumPy array, one row per equilibrium
    model.linearize()[0].eigenvalues    # linearized dynamics about each
    model.simulate(10)                  # time history (a DataFrame with pandas)
    model.with_values(k=40).rhs(0.0, y) # the compiled right-hand side, for solve_ivp
    lagrange.sweep(model, {"k": [10, 20, 30]}, t_end=5)

The mechanics is the Rust library's; this package is glue (docs/python.md).
"""

from ._errors import LagrangeError, MechanicsError, ModelError
from ._model import EquationsOfMotion, Linearization, Model, Run, Section, Solution
from ._native import __version__
from ._sweep import Table, sweep

__all__ = [
    "Model",
    "Solution",
    "Section",
    "EquationsOfMotion",
    "Linearization",
    "Run",
    "Table",
    "sweep",
    "LagrangeError",
    "ModelError",
    "MechanicsError",
    "__version__",
]

"""Speed of the Python package (docs/performance.md, "Python"): the time of `import lagrange`,
of `Model.from_file(7.1).solve()`, and the per-call cost of `model.rhs` beside a SymPy
`lambdify` function of the same equations and, when `pip install pin` works, Pinocchio's
`aba` on a planar double pendulum (two revolute joints) from Python.

Run with the package installed (`pip install ./python sympy numpy`, plus `pin` optionally):

    python bench/python/bench.py

A benchmark, not a test: it prints numbers (medians of repeated runs) and checks nothing.
"""

import pathlib
import statistics
import subprocess
import sys
import time
import timeit

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
SEED_7_1 = ROOT / "examples" / "seed" / "7.1-cart-pendulum.lag"


def median_seconds(statement, number, repeat=7, setup=None, globals=None):
    timer = timeit.Timer(statement, setup=setup or "pass", globals=globals)
    return statistics.median(t / number for t in timer.repeat(repeat=repeat, number=number))


def import_time(runs=15):
    code = "import time; t = time.perf_counter(); import lagrange; print(time.perf_counter() - t)"
    times = [float(subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                                  text=True).stdout) for _ in range(runs)]
    return statistics.median(times)


def solve_time():
    import lagrange

    return median_seconds(lambda: lagrange.Model.from_file(SEED_7_1).solve(), number=1, repeat=15)


def rhs_times():
    import sympy as sp

    import lagrange

    model = lagrange.Model.from_file(SEED_7_1)
    y = model.initial_state()
    rhs = model.rhs
    rhs(0.0, y)
    ours = median_seconds(lambda: rhs(0.0, y), number=20000)
    batch = np.tile(y, (1000, 1))
    ours_batch = median_seconds(lambda: model.rhs_batch(batch), number=50) / 1000

    eom = model.equations_of_motion()
    values = {eom.symbols[n]: v for n, v in model.values.items() if n in eom.symbols}
    accelerations = eom.M.subs(values).LUsolve(eom.f.subs(values))
    state = eom.coordinates + eom.rates
    qdd = sp.lambdify([sp.Symbol("t"), state], list(eom.rates) + list(accelerations), "math")

    def lambdified(t, y):
        return np.array(qdd(t, y))

    lambdified(0.0, y)
    theirs = median_seconds(lambda: lambdified(0.0, y), number=20000)
    return ours, ours_batch, theirs


def pinocchio_time():
    try:
        import pinocchio as pin
    except ImportError:
        return None
    model = pin.Model()
    joint = 0
    for i in range(2):
        placement = pin.SE3(np.eye(3), np.array([0.0, 0.0, -1.0 if i else 0.0]))
        joint = model.addJoint(joint, pin.JointModelRY(), placement, f"j{i}")
        inertia = pin.Inertia.FromSphere(1.0, 0.01)
        inertia.lever = np.array([0.0, 0.0, -1.0])
        model.appendBodyToJoint(joint, inertia, pin.SE3.Identity())
    data = model.createData()
    q, v, tau = np.array([0.1, 0.3]), np.zeros(2), np.zeros(2)
    pin.aba(model, data, q, v, tau)
    return median_seconds(lambda: pin.aba(model, data, q, v, tau), number=20000)


def main():
    print(f"python {sys.version.split()[0]}, numpy {np.__version__}")
    print(f"import lagrange: {import_time() * 1e3:.1f} ms (median of 15 fresh interpreters)")
    print(f"Model.from_file(7.1).solve(): {solve_time() * 1e3:.1f} ms (median of 15)")
    ours, ours_batch, theirs = rhs_times()
    print(f"model.rhs(t, y), 7.1 (n = 2): {ours * 1e6:.2f} µs per call")
    print(f"model.rhs_batch(ys), 7.1: {ours_batch * 1e6:.3f} µs per state (1000 states a call)")
    print(f"SymPy lambdify of M⁻¹f, 7.1: {theirs * 1e6:.2f} µs per call")
    aba = pinocchio_time()
    if aba is None:
        print("Pinocchio: not installed (pip install pin)")
    else:
        print(f"Pinocchio aba, planar double pendulum (n = 2): {aba * 1e6:.2f} µs per call")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""lagrange side by side with SymPy mechanics, PyDy and Pinocchio, in one run.

Run through bench/compare/run.sh, which makes the virtual environment, builds lagrange and the
Pinocchio C++ timer, then calls this script. Measures, for the planar n-link pendulum
(bench/models/nlink.sh) and a 3-D chain of rigid rods on universal joints
(bench/models/chain3d.sh):

  derive   model → mass matrix and forcing: lagrange in-process (crates/model/examples/
           derive_timing.rs), twice: the same work as the peer (parse, lower, K, V, Lagrange's
           equations, M and f in normal form; `--same-work`) and everything `lagrange eom`
           derives (also the first integrals with their checks, q̈ for n ≤ 2), and the whole
           `lagrange eom --format json` command (process start and JSON printing included),
           against SymPy LagrangesMethod and KanesMethod (M and f formed, not simplified,
           SymPy's import not counted), for growing n until a peer passes the cap;
  rhs      one right-hand-side evaluation q̈ = M⁻¹ f at a state: lagrange's compiled tape
           against SymPy lambdify + numpy.linalg.solve, PyDy's generated ODE function, and
           Pinocchio's ABA timed in C++;
  simulate a 10 s run at rtol = atol = 1e-8: `lagrange simulate` against lambdify + SciPy
           solve_ivp (RK45).

Writes results/compare.json, results/compare.md (tables with ratios) and results/derive.svg
(time against n, log scale).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
# run.sh builds with cargo, which honours CARGO_TARGET_DIR (relative to the workspace root).
TARGET = ROOT / os.environ.get("CARGO_TARGET_DIR", "target")
LAGRANGE = TARGET / "release" / "lagrange"
RHS_TIMER = TARGET / "release" / "examples" / "rhs_timing"  # crates/lagrange/examples
DERIVE_TIMER = TARGET / "release" / "examples" / "derive_timing"
PINOCCHIO = HERE / ".build" / "pinocchio_aba"

# ----------------------------------------------------------------------------- models


def model_text(kind: str, n: int) -> str:
    script = ROOT / "bench" / "models" / f"{kind}.sh"
    return subprocess.run(["bash", str(script), str(n)], check=True, capture_output=True, text=True).stdout


def sympy_system(kind: str, n: int, kane: bool):
    """The same system built with sympy.physics.mechanics, independently of lagrange."""
    import sympy as sp
    from sympy.physics import mechanics as me

    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    g = sp.Symbol("g")
    if kind == "nlink":
        q = me.dynamicsymbols(f"th1:{n + 1}")
        masses = sp.symbols(f"m1:{n + 1}")
        lengths = sp.symbols(f"l1:{n + 1}")
        params = [g, *masses, *lengths]
        values = [9.81] + [1.0] * n + [1.0] * n
    else:
        a = me.dynamicsymbols(f"a1:{n + 1}")
        b = me.dynamicsymbols(f"b1:{n + 1}")
        q = [x for pair in zip(a, b) for x in pair]
        m, l, J = sp.symbols("m l J")
        params = [g, m, l, J]
        values = [9.81, 1.0, 1.0, 0.001]
    u = me.dynamicsymbols(f"u1:{len(q) + 1}") if kane else [qi.diff() for qi in q]
    kd = [qi.diff() - ui for qi, ui in zip(q, u)] if kane else []

    items, loads = [], []
    top = O
    for i in range(n):
        if kind == "nlink":
            A = N.orientnew(f"A{i}", "Axis", [q[i], N.z])
            A.set_ang_vel(N, u[i] * N.z)
            P = top.locatenew(f"P{i}", -lengths[i] * A.y)
            P.v2pt_theory(top, N, A)
            part = me.Particle(f"Pa{i}", P, masses[i])
            part.potential_energy = masses[i] * g * P.pos_from(O).dot(N.y)
            items.append(part)
            loads.append((P, -masses[i] * g * N.y))
            top = P
        else:
            B = N.orientnew(f"B{i}", "Body", [a[i], b[i], 0], "XYZ")
            if kane:
                B.set_ang_vel(N, B.ang_vel_in(N).subs({a[i].diff(): u[2 * i], b[i].diff(): u[2 * i + 1]}))
            G = top.locatenew(f"G{i}", -l / 2 * B.z)
            P = top.locatenew(f"P{i}", -l * B.z)
            G.v2pt_theory(top, N, B)
            P.v2pt_theory(top, N, B)
            inertia = me.inertia(B, m * l**2 / 12, m * l**2 / 12, J)
            body = me.RigidBody(f"rod{i}", G, B, m, (inertia, G))
            body.potential_energy = m * g * G.pos_from(O).dot(N.z)
            items.append(body)
            loads.append((G, -m * g * N.z))
            top = P
    return dict(N=N, q=q, u=u, kd=kd, items=items, loads=loads, params=params, values=values)


def sympy_derive(kind: str, n: int, method: str):
    from sympy.physics import mechanics as me

    s = sympy_system(kind, n, kane=(method == "kane"))
    if method == "kane":
        km = me.KanesMethod(s["N"], q_ind=s["q"], u_ind=s["u"], kd_eqs=s["kd"])
        km.kanes_equations(s["items"], s["loads"])
        return s, km.mass_matrix, km.forcing, km
    L = me.Lagrangian(s["N"], *s["items"])
    lm = me.LagrangesMethod(L, s["q"])
    lm.form_lagranges_equations()
    return s, lm.mass_matrix, lm.forcing, lm


# ----------------------------------------------------------------------------- timing helpers


def run_capped(args: list[str], cap: float) -> float | None:
    """Runs this script as a worker with a wall-clock cap; the worker prints its own time."""
    try:
        out = subprocess.run(
            [sys.executable, __file__, *args], capture_output=True, text=True, timeout=cap, check=True
        )
    except subprocess.TimeoutExpired:
        return None
    except subprocess.CalledProcessError as e:
        print(f"  worker {' '.join(args)} failed: {e.stderr.strip()[-400:]}", file=sys.stderr)
        return None
    return float(out.stdout.strip().splitlines()[-1])


def time_lagrange_derive(path: Path, same_work: bool = False, repeats: int = 5) -> float:
    """In-process time of parse + lower + derive (no process start, no printing): the best of
    a few cold runs, each in a fresh process so that no memoised result is reused. With
    same_work, only what LagrangesMethod does (no first integrals)."""
    args = [str(DERIVE_TIMER), str(path)] + (["--same-work"] if same_work else [])
    return min(
        float(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
        for _ in range(repeats)
    )


def time_lagrange_eom(path: Path, repeats: int = 3) -> float:
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run([str(LAGRANGE), "eom", str(path), "--format", "json"], check=True, capture_output=True)
        best = min(best, time.perf_counter() - t0)
    return best


def per_call(f, min_time: float = 0.3) -> float:
    """Median seconds per call of f() over 5 batches, each at least min_time / 5 long."""
    reps = 1
    while True:
        t0 = time.perf_counter()
        for _ in range(reps):
            f()
        if time.perf_counter() - t0 > min_time / 5:
            break
        reps *= 2
    samples = []
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(reps):
            f()
        samples.append((time.perf_counter() - t0) / reps)
    return statistics.median(samples)


# ----------------------------------------------------------------------------- workers


def worker_derive(kind: str, n: int, method: str) -> None:
    # Import first: SymPy's import (about 0.3 s) is not part of the derivation.
    import sympy  # noqa: F401
    from sympy.physics import mechanics  # noqa: F401

    t0 = time.perf_counter()
    sympy_derive(kind, n, method)
    print(time.perf_counter() - t0)


def state(nq: int):
    import numpy as np

    q = 0.3 + 0.05 * np.arange(nq)
    qd = 0.1 + 0.01 * np.arange(nq)
    return q, qd


def worker_rhs_lambdify(kind: str, n: int) -> None:
    import numpy as np
    import sympy as sp

    s, M, f, _ = sympy_derive(kind, n, "lagrange")
    q = s["q"]
    qs = sp.symbols(f"q0:{len(q)}")
    us = sp.symbols(f"v0:{len(q)}")
    subs = {qi.diff(): ui for qi, ui in zip(q, us)}
    subs.update({qi: qsi for qi, qsi in zip(q, qs)})
    Mf = sp.lambdify([qs, us, s["params"]], M.subs(subs), "numpy")
    ff = sp.lambdify([qs, us, s["params"]], f.subs(subs), "numpy")
    x, v = state(len(q))
    p = s["values"]
    rhs = lambda: np.linalg.solve(np.asarray(Mf(x, v, p), dtype=float), np.asarray(ff(x, v, p), dtype=float).ravel())
    print(per_call(rhs))


def worker_rhs_pydy(kind: str, n: int) -> None:
    import numpy as np
    from pydy.codegen.ode_function_generators import generate_ode_function

    s, M, f, km = sympy_derive(kind, n, "kane")
    generator = "cython"
    try:
        import Cython  # noqa: F401
    except ImportError:
        generator = "lambdify"
    rhs_f = generate_ode_function(
        km.forcing, s["q"], s["u"], s["params"], mass_matrix=km.mass_matrix,
        coordinate_derivatives=sp_matrix([u for u in s["u"]]), generator=generator,
    )
    x, v = state(len(s["q"]))
    y = np.concatenate([x, v])
    p = np.array(s["values"])
    print(per_call(lambda: rhs_f(y, 0.0, p)))
    print(generator, file=sys.stderr)


def sp_matrix(items):
    import sympy as sp

    return sp.Matrix(items)


# ----------------------------------------------------------------------------- main


def lagrange_rhs_ns(path: Path, calls: int = 200000) -> float | None:
    if not RHS_TIMER.exists():
        return None
    out = subprocess.run([str(RHS_TIMER), str(path), str(calls)], check=True, capture_output=True, text=True).stdout
    # `rhs_ns=… instructions=…`
    fields = dict(item.split("=", 1) for item in out.split())
    return float(fields["rhs_ns"])


def pinocchio_ns(kind: str, n: int) -> float | None:
    if not PINOCCHIO.exists():
        return None
    out = subprocess.run([str(PINOCCHIO), kind, str(n)], check=True, capture_output=True, text=True).stdout
    return float(out.strip())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cap", type=float, default=60.0, help="seconds before a peer's derivation is abandoned")
    ap.add_argument("--sizes", default="1,2,3,4,5,6,8,10,12,15,20,30,40")
    ap.add_argument("--rhs-sizes", default="1,2,3,5,10")
    ap.add_argument("--only", choices=["derive", "rhs", "simulate"], action="append")
    ap.add_argument("--rhs-peers", default="lambdify,pydy,pinocchio",
                    help="the right-hand side's peers (lambdify and PyDy take minutes past n = 20)")
    ap.add_argument("--repeat", type=int, default=1,
                    help="right-hand side: interleaved rounds (lagrange, then each peer, per n); the best of each is kept")
    ap.add_argument("--worker", nargs="+", help=argparse.SUPPRESS)
    args = ap.parse_args()

    if args.worker:
        what, kind, n = args.worker[0], args.worker[1], int(args.worker[2])
        if what == "derive":
            worker_derive(kind, n, args.worker[3])
        elif what == "lambdify":
            worker_rhs_lambdify(kind, n)
        elif what == "pydy":
            worker_rhs_pydy(kind, n)
        return

    parts = args.only or ["derive", "rhs", "simulate"]
    sizes = [int(x) for x in args.sizes.split(",")]
    rhs_sizes = [int(x) for x in args.rhs_sizes.split(",")]
    # A partial run (--only) replaces its own parts and keeps the others from the last run.
    out = HERE / "results"
    previous = out / "compare.json"
    results: dict = json.loads(previous.read_text()) if previous.exists() else {}
    for part in ["derive", "rhs", "simulate"]:
        results.setdefault(part, [])
    for part in parts:
        results[part] = []
    results["cap_s"] = args.cap
    tmp = Path(tempfile.mkdtemp(prefix="lagrange-compare-"))

    if "derive" in parts:
        print("== derivation (seconds; '—' = over the cap)")
        for kind in ["nlink", "chain3d"]:
            alive = {"lagrange": True, "kane": True}
            for n in sizes:
                path = tmp / f"{kind}-{n}.lag"
                path.write_text(model_text(kind, n))
                row = {"system": kind, "n": n,
                       "lagrange_same_work": time_lagrange_derive(path, same_work=True),
                       "lagrange": time_lagrange_derive(path),
                       "lagrange_command": time_lagrange_eom(path)}
                for method in ["lagrange", "kane"]:
                    key = f"sympy_{method}"
                    row[key] = run_capped(["--worker", "derive", kind, str(n), method], args.cap) if alive[method] else None
                    if row[key] is None:
                        alive[method] = False
                results["derive"].append(row)
                print(f"  {kind:8} n={n:3}  lagrange {row['lagrange_same_work']:.4f} same work, {row['lagrange']:.4f} all "
                      f"(command {row['lagrange_command']:.4f})  "
                      f"LagrangesMethod {fmt(row['sympy_lagrange'])}  KanesMethod {fmt(row['sympy_kane'])}", flush=True)
                if kind == "chain3d" and n >= 10:
                    break

    if "rhs" in parts:
        print("== right-hand side, one evaluation (microseconds)")
        for kind in ["nlink", "chain3d"]:
            for n in rhs_sizes:
                path = tmp / f"{kind}-{n}.lag"
                path.write_text(model_text(kind, n))
                peers = args.rhs_peers.split(",")
                lam = run_capped(["--worker", "lambdify", kind, str(n)], args.cap * 3) if "lambdify" in peers else None
                pyd = run_capped(["--worker", "pydy", kind, str(n)], args.cap * 3) if "pydy" in peers else None
                lagrange_best, pinocchio_best = None, None
                for _ in range(max(1, args.repeat)):
                    # Fewer calls at large n, where one evaluation takes microseconds.
                    ours = lagrange_rhs_ns(path, max(2000, 200000 // max(1, n)))
                    theirs = pinocchio_ns(kind, n) if "pinocchio" in peers else None
                    lagrange_best = ours if lagrange_best is None or (ours is not None and ours < lagrange_best) else lagrange_best
                    pinocchio_best = theirs if pinocchio_best is None or (theirs is not None and theirs < pinocchio_best) else pinocchio_best
                row = {
                    "system": kind, "n": n,
                    "lagrange_us": ns_to_us(lagrange_best),
                    "lambdify_us": s_to_us(lam),
                    "pydy_us": s_to_us(pyd),
                    "pinocchio_aba_us": ns_to_us(pinocchio_best),
                }
                results["rhs"].append(row)
                print(f"  {kind:8} n={n:3}  " + "  ".join(f"{k} {fmt(v)}" for k, v in row.items() if k.endswith("_us")), flush=True)

    out.mkdir(exist_ok=True)
    (out / "compare.json").write_text(json.dumps(results, indent=2))
    (out / "compare.md").write_text(markdown(results))
    plot(results, out / "derive.svg")
    shutil.rmtree(tmp, ignore_errors=True)
    print(f"wrote {out / 'compare.md'}, {out / 'compare.json'}, {out / 'derive.svg'}")


def ns_to_us(x):
    return None if x is None else x / 1000.0


def s_to_us(x):
    return None if x is None else x * 1e6


def fmt(x) -> str:
    if x is None:
        return "—"
    return f"{x:.4g}"


def ratio(peer, ours) -> str:
    if peer is None or ours is None or ours == 0:
        return "—"
    r = peer / ours
    return f"{r:.0f}×" if r >= 100 else f"{r:.3g}×"


def markdown(r: dict) -> str:
    lines = [f"Derivation cap: {r['cap_s']} s per peer run. Ratios are peer time / lagrange time.", ""]
    if r["derive"]:
        lines += ["lagrange, same work: parse, lower, K, V, Lagrange's equations, M and f in normal form (what "
                  "LagrangesMethod does); all: also the first integrals and their checks (everything `lagrange eom` "
                  "derives). Ratios: peer / same work, and peer / all in brackets.", "",
                  "| system | n | lagrange, same work (s) | lagrange, all (s) | `lagrange eom` command (s) | "
                  "SymPy LagrangesMethod (s) | ratio | SymPy KanesMethod (s) | ratio |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for x in r["derive"]:
            same = x.get("lagrange_same_work")
            lines.append(f"| {x['system']} | {x['n']} | {fmt(same)} | {x['lagrange']:.4f} | {x['lagrange_command']:.4f} | "
                         f"{fmt(x['sympy_lagrange'])} | {ratio(x['sympy_lagrange'], same)} ({ratio(x['sympy_lagrange'], x['lagrange'])}) | "
                         f"{fmt(x['sympy_kane'])} | {ratio(x['sympy_kane'], same)} ({ratio(x['sympy_kane'], x['lagrange'])}) |")
        lines.append("")
    if r["rhs"]:
        lines += ["| system | n | lagrange (µs) | lambdify + solve (µs) | ratio | PyDy (µs) | ratio | Pinocchio ABA, C++ (µs) | lagrange / Pinocchio |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for x in r["rhs"]:
            ours = x["lagrange_us"]
            pin = x["pinocchio_aba_us"]
            vs_pin = "—" if ours is None or pin is None else f"{ours / pin:.2f}"
            lines.append(f"| {x['system']} | {x['n']} | {fmt(ours)} | {fmt(x['lambdify_us'])} | {ratio(x['lambdify_us'], ours)} | "
                         f"{fmt(x['pydy_us'])} | {ratio(x['pydy_us'], ours)} | {fmt(pin)} | {vs_pin} |")
        lines.append("")
    return "\n".join(lines)


def plot(r: dict, path: Path) -> None:
    if not r["derive"]:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, kind in zip(axes, ["nlink", "chain3d"]):
        rows = [x for x in r["derive"] if x["system"] == kind]
        for key, label in [("lagrange_same_work", "lagrange (same work)"), ("lagrange", "lagrange (all)"), ("lagrange_command", "lagrange eom (command)"), ("sympy_lagrange", "SymPy LagrangesMethod"), ("sympy_kane", "SymPy KanesMethod")]:
            pts = [(x["n"], x[key]) for x in rows if x.get(key) is not None]
            if pts:
                ax.plot(*zip(*pts), marker="o", label=label)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("n (links)" if kind == "nlink" else "n (rods, 2n coordinates)")
        ax.set_title("planar n-link pendulum" if kind == "nlink" else "3-D chain of rods")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("derivation time (s)")
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(path)


if __name__ == "__main__":
    main()

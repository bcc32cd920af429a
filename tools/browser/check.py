#!/usr/bin/env python3
"""Checks lagrange's figures and animations in a real browser (headless Chromium; docs/draw.md).

Usage: tools/browser/check.py path/to/lagrange

- Every example's figure (`lagrange draw`) and a few animations (`lagrange animate`, a mode
  among them) load with no error: no uncaught exception, no console error, no failed resource,
  no XML parse error, no request beyond the local file.
- A drawn point's rendered position (the centre of `#point-NAME`'s box) is the model's
  position at the drawn state, mapped by the figure's projection (`data-scale`,
  `data-origin`, `data-u`, `data-v`), within a pixel: the pendulum's bob, the cart of
  exercise 7.1 and its bob, a rim point of gear 1 of exercise 7.3. The model's positions are
  computed here from the models' own definitions (written out below for each).
- Two frames of an animation, chosen with its time slider, differ, and each shows the cart and
  bob of exercise 7.1 where `lagrange simulate` puts them at that frame's time, within a pixel.
- The animation plays: its time advances by itself.
- No two labels' rendered boxes overlap, and each lies in the picture.

Every check prints one line; the exit status is 1 when any check failed (or Chromium is
missing), 0 otherwise. Nothing is skipped.
"""

import csv
import glob
import io
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))

# The page script that measures an SVG: the rendered centre of each named point and the
# rendered box of each label, both in the SVG's page coordinates (its viewBox), and the
# projection the root carries.
MEASURE = """
(() => {
  const svg = document.querySelector('svg');
  if (!svg) return {problem: 'no svg element'};
  if (document.getElementsByTagName('parsererror').length)
    return {problem: 'XML parse error: ' + document.getElementsByTagName('parsererror')[0].textContent};
  const r = svg.getBoundingClientRect(), vb = svg.viewBox.baseVal;
  const sx = vb.width / r.width, sy = vb.height / r.height;
  const page = (x, y) => [vb.x + (x - r.left) * sx, vb.y + (y - r.top) * sy];
  const points = {};
  for (const c of svg.querySelectorAll('[id^="point-"]')) {
    const b = c.getBoundingClientRect();
    points[c.id.slice(6)] = page(b.left + b.width / 2, b.top + b.height / 2);
  }
  const labels = [];
  for (const t of svg.querySelectorAll('text')) {
    if (!t.textContent.trim()) continue;
    const b = t.getBoundingClientRect();
    const [x, y] = page(b.left, b.top);
    const given = (t.getAttribute('data-box') || '').trim().split(/\\s+/).map(Number);
    labels.push({id: t.id, text: t.textContent, box: [x, y, b.width * sx, b.height * sy],
                 given: given.length === 4 ? given : null});
  }
  const nums = (name) => (svg.getAttribute(name) || '').trim().split(/\\s+/).map(Number);
  return {points, labels, view: [vb.x, vb.y, vb.width, vb.height],
          scale: Number(svg.getAttribute('data-scale')), origin: nums('data-origin'),
          u: nums('data-u'), v: nums('data-v')};
})()
"""


class Checks:
    """The checks run so far and whether any failed."""

    def __init__(self):
        self.failed = 0
        self.passed = 0

    def report(self, ok, what, detail=""):
        if ok:
            self.passed += 1
            print(f"ok   {what}" + (f" ({detail})" if detail else ""))
        else:
            self.failed += 1
            print(f"FAIL {what}" + (f": {detail}" if detail else ""))
        sys.stdout.flush()


def run(binary, *args):
    """Runs lagrange; its standard output, or an exception with its error."""
    done = subprocess.run([binary, *args], capture_output=True, text=True, timeout=600)
    if done.returncode != 0:
        raise RuntimeError(f"lagrange {' '.join(args)} exited {done.returncode}: {done.stderr.strip()}")
    return done.stdout


def project(measured, p):
    """The page position of the world point `p` in the figure's projection."""
    dot = lambda a, b: sum(x * y for x, y in zip(a, b))  # noqa: E731
    p = list(p) + [0.0] * (3 - len(p))
    return (measured["origin"][0] + measured["scale"] * dot(p, measured["u"]),
            measured["origin"][1] - measured["scale"] * dot(p, measured["v"]))


def check_position(checks, measured, name, world, what):
    expected = project(measured, world)
    drawn = measured["points"].get(name)
    if drawn is None:
        checks.report(False, what, f"no #point-{name} in the figure")
        return
    error = math.hypot(drawn[0] - expected[0], drawn[1] - expected[1])
    checks.report(error <= 1.0, what,
                  f"drawn at ({drawn[0]:.2f}, {drawn[1]:.2f}), model at ({expected[0]:.2f}, "
                  f"{expected[1]:.2f}): {error:.3f} px apart")


def overlap(a, b, slack=0.5):
    """Whether two boxes `[x, y, w, h]` overlap by more than `slack` pixels both ways."""
    dx = min(a[0] + a[2], b[0] + b[2]) - max(a[0], b[0])
    dy = min(a[1] + a[3], b[1] + b[3]) - max(a[1], b[1])
    return dx > slack and dy > slack


def inside(a, b, margin):
    """Whether box `a` lies in box `b` grown by `margin` pixels on each side."""
    return (a[0] >= b[0] - margin and a[1] >= b[1] - margin
            and a[0] + a[2] <= b[0] + b[2] + margin and a[1] + a[3] <= b[1] + b[3] + margin)


def check_labels(checks, measured, what):
    labels = measured["labels"]
    clashes = [f"{a['text']!r} and {b['text']!r}"
               for i, a in enumerate(labels) for b in labels[i + 1:] if overlap(a["box"], b["box"])]
    checks.report(not clashes, f"{what}: {len(labels)} labels, none overlapping another",
                  "; ".join(clashes))
    x, y, w, h = measured["view"]
    outside = [repr(l["text"]) for l in labels
               if l["box"][0] < x - 0.5 or l["box"][1] < y - 0.5
               or l["box"][0] + l["box"][2] > x + w + 0.5 or l["box"][1] + l["box"][3] > y + h + 0.5]
    checks.report(not outside, f"{what}: every label inside the picture", ", ".join(outside))
    # The layout keeps each label's estimated box (`data-box`) clear of the drawing (tested in
    # crates/draw); the text as the browser sets it must stay inside that box.
    spilled = [f"{l['text']!r} rendered {[round(x, 1) for x in l['box']]} outside {l['given']}"
               for l in labels
               if not l["given"] or not inside(l["box"], l["given"], margin=1.0)]
    checks.report(not spilled, f"{what}: every label's text inside its placed box", "; ".join(spilled))


def load(checks, browser, path, what):
    """Opens `path`, reports its errors, and measures its SVG (None when it does not load)."""
    browser.open(path)
    measured = browser.evaluate(MEASURE)
    problem = measured.get("problem") if isinstance(measured, dict) else "nothing measured"
    errors = browser.errors + ([problem] if problem else [])
    checks.report(not errors, f"{what} loads without errors", "; ".join(errors))
    return None if errors else measured


def figures(checks, browser, binary, work):
    models = sorted(glob.glob(os.path.join(ROOT, "examples", "*.lag"))
                    + glob.glob(os.path.join(ROOT, "examples", "*", "*.lag")))
    if not models:
        checks.report(False, "example models found", "no examples/*.lag")
    for model in models:
        name = os.path.relpath(os.path.splitext(model)[0], os.path.join(ROOT, "examples"))
        out = os.path.join(work, name.replace(os.sep, "-") + ".svg")
        try:
            run(binary, "draw", model, "--out", out)
        except RuntimeError as e:
            checks.report(False, f"draw {name}", str(e))
            continue
        measured = load(checks, browser, out, f"figure {name}")
        if measured:
            check_labels(checks, measured, f"figure {name}")


def positions(checks, browser, binary, work):
    """Drawn points against the models' definitions, at states given with `--at`."""
    cases = [
        # examples/simple-pendulum.lag: P = l sin θ x̂ − l cos θ ŷ, l = 1.
        ("simple-pendulum", "theta=0.7", {"P": (math.sin(0.7), -math.cos(0.7))}),
        # examples/seed/7.1: A = x x̂, B = A + l sin θ x̂ + l cos θ ŷ, l = 0.5.
        ("seed/7.1-cart-pendulum", "x=0.25,theta=-0.4",
         {"A": (0.25, 0.0), "B": (0.25 + 0.5 * math.sin(-0.4), 0.5 * math.cos(-0.4))}),
        # examples/seed/7.3: P = O1 + R1 G1.x, G1 = N rotated φ₁ about z, R1 = 0.1.
        ("seed/7.3-gears-pendulum", "phi1=0.9",
         {"P": (0.1 * math.cos(0.9), 0.1 * math.sin(0.9))}),
    ]
    for model, at, points in cases:
        name = os.path.basename(model)
        out = os.path.join(work, f"{name}-at.svg")
        try:
            run(binary, "draw", os.path.join(ROOT, "examples", model + ".lag"), "--at", at, "--out", out)
        except RuntimeError as e:
            checks.report(False, f"draw {name} --at {at}", str(e))
            continue
        measured = load(checks, browser, out, f"figure {name} at {at}")
        if measured:
            for point, world in points.items():
                check_position(checks, measured, point, world, f"{name} at {at}: point {point}")


SHOW_FRAME = """
(() => {
  const s = document.getElementById('time');
  s.value = %d; s.dispatchEvent(new Event('input'));
  return document.getElementById('values').textContent;
})()
"""


def animation(checks, browser, binary, work):
    """Exercise 7.1's animation: frames chosen with the slider against `lagrange simulate`."""
    model = os.path.join(ROOT, "examples", "seed", "7.1-cart-pendulum.lag")
    out = os.path.join(work, "7.1.html")
    fps, t_end = 30, 2.0
    try:
        run(binary, "animate", model, "--t-end", str(t_end), "--fps", str(fps), "--trace", "B",
            "--out", out)
        table = run(binary, "simulate", model, "--t-end", str(t_end), "--output-step", repr(1 / fps))
    except RuntimeError as e:
        checks.report(False, "animate and simulate exercise 7.1", str(e))
        return
    rows = list(csv.DictReader(io.StringIO(table)))
    measured = load(checks, browser, out, "animation 7.1-cart-pendulum")
    if not measured:
        return
    first = browser.evaluate("document.getElementById('values').textContent")
    browser.open(out, settle=1.0)
    later = browser.evaluate("document.getElementById('values').textContent")
    checks.report(first != later, "animation 7.1 plays by itself", f"{first!r} then {later!r}")
    drawn = {}
    for k in (12, 45):
        if k >= len(rows):
            checks.report(False, f"frame {k} of 7.1", f"the simulation has {len(rows)} rows")
            continue
        shown = browser.evaluate(SHOW_FRAME % k)
        measured = browser.evaluate(MEASURE)
        row = rows[k]
        x, theta, t = float(row["x"]), float(row["theta"]), float(row["t"])
        checks.report(f"t = {t:.3f} s" in shown, f"frame {k} shows its time", repr(shown))
        check_position(checks, measured, "A", (x, 0.0), f"animation 7.1 frame {k} (t = {t:.3f}): cart A")
        bob = (x + 0.5 * math.sin(theta), 0.5 * math.cos(theta))
        check_position(checks, measured, "B", bob, f"animation 7.1 frame {k} (t = {t:.3f}): bob B")
        check_labels(checks, measured, f"animation 7.1 frame {k}")
        drawn[k] = measured["points"].get("B")
    if len(drawn) == 2 and None not in drawn.values():
        (a, b) = drawn.values()
        apart = math.hypot(a[0] - b[0], a[1] - b[1])
        checks.report(apart > 5.0, "frames 12 and 45 differ", f"the bob moved {apart:.1f} px")
    checks.report(not browser.errors, "animation 7.1 driven by its slider without errors",
                  "; ".join(browser.errors))


def other_animations(checks, browser, binary, work):
    cases = [
        ("seed/7.3-gears-pendulum", ["--t-end", "2"]),
        ("double-pendulum", ["--t-end", "2", "--trace", "P2"]),
        ("spherical-pendulum", ["--t-end", "2"]),
        ("double-pendulum", ["--mode", "2"]),
        ("seed/7.3-gears-pendulum", ["--mode", "2", "--trace", "Q"]),
        # Modes about a pole of the coordinates (the mass matrix singular there).
        ("spherical-pendulum", ["--mode", "1", "--trace", "P"]),
        ("heavy-symmetric-top", ["--mode", "2"]),
    ]
    for model, flags in cases:
        name = os.path.basename(model)
        out = os.path.join(work, f"{name}{'-'.join(flags)}.html")
        try:
            run(binary, "animate", os.path.join(ROOT, "examples", model + ".lag"), *flags, "--out", out)
        except RuntimeError as e:
            checks.report(False, f"animate {name}", str(e))
            continue
        load(checks, browser, out, f"animation {name} {' '.join(flags)}")
        last = browser.evaluate("Number(document.getElementById('time').max)")
        shown = browser.evaluate(SHOW_FRAME % last)
        checks.report(not browser.errors and shown.startswith("t = "),
                      f"animation {name}: last frame ({last}) shown", "; ".join(browser.errors) or shown)


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[2])
        return 2
    binary = os.path.abspath(sys.argv[1])
    checks = Checks()
    executable = cdp.find_chromium()
    if not executable:
        checks.report(False, "Chromium found", "install Debian's chromium (apt-get install chromium)")
        return 1
    browser = cdp.Browser(executable)
    try:
        with tempfile.TemporaryDirectory() as work:
            for part in (figures, positions, animation, other_animations):
                try:
                    part(checks, browser, binary, work)
                except (cdp.BrowserError, RuntimeError, KeyError, ValueError, TypeError) as e:
                    checks.report(False, part.__name__, f"{type(e).__name__}: {e}")
    finally:
        browser.close()
    print(f"{checks.passed} checks passed, {checks.failed} failed")
    return 1 if checks.failed else 0


if __name__ == "__main__":
    sys.exit(main())

"""Every expression string `lagrange eom --format json` writes, on every example model, read
with `sympy.sympify` and evaluated at the states lagrange evaluated it at: the same number.

Input: the directory `crates/report/tests/eom_json.rs` fills when `LAGRANGE_JSON_NUMBERS` is
set (one file per model: the strings, the symbols' values at three states, lagrange's values).
Run through check.sh, which makes the environment and the numbers.
"""

import json
import math
import re
import sys
from pathlib import Path

import sympy

FUNCTIONS = {"sin", "cos", "tan", "asin", "acos", "atan", "atan2", "exp", "log", "sqrt",
             "Abs", "sign"}
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def read(text):
    """sympify with every name that is not a function a plain symbol (so `E`, `I`, `N`, `S`,
    `beta`, `gamma` stay the model's names, not SymPy's constants or functions)."""
    names = {}
    for m in IDENTIFIER.finditer(text):
        name = m.group(0)
        follows = text[m.end():m.end() + 1]
        if name in FUNCTIONS and follows == "(":
            continue
        if name == "pi":
            continue
        names[name] = sympy.Symbol(name)
    return sympy.sympify(text, locals=names)


def main(directory):
    files = sorted(Path(directory).glob("*.json"))
    if not files:
        sys.exit(f"no numbers in {directory}")
    checked = failed = 0
    for path in files:
        data = json.loads(path.read_text())
        symbols = data["symbols"]
        for item in data["expressions"]:
            text = item["text"]
            try:
                expr = read(text)
            except Exception as error:  # noqa: BLE001 - any failure to read is a finding
                print(f"{data['model']}{item['pointer']}: SymPy cannot read it: {error}")
                failed += 1
                continue
            for round_, want in enumerate(item["values"]):
                if want is None:
                    continue
                env = {s: symbols[f"{s.name}#{round_}"] for s in expr.free_symbols}
                got = complex(expr.evalf(30, subs=env))
                ok = abs(got.imag) <= 1e-9 * (1 + abs(want)) and math.isclose(
                    got.real, want, rel_tol=1e-9, abs_tol=1e-9)
                checked += 1
                if not ok:
                    failed += 1
                    print(f"{data['model']}{item['pointer']}: SymPy {got}, lagrange {want}")
    print(f"{checked} values checked over {len(files)} models, {failed} failures")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main(sys.argv[1])

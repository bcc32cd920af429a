"""Checks the seed's solutions as a Jupyter Book shows them, in headless Chromium.

Usage: python3 tools/browser/book.py BOOK_HTML_DIR   (the output of docs/book/build.sh)

Every exercise page must load with no error and no request to the network (MathJax comes from
the book's own copy), MathJax must typeset every formula with no error (`mjx-merror`), no
display may be wider than the text column (it would be clipped or scroll), and no figure wider
than the column either. The window is 1000 px wide, a laptop's browser beside nothing else.

The notebook pages (the same exercises worked in Python, `notebooks/7.*.html`) must load with
no error, typeset with no MathJax error, and show the outputs of a run (the book is built from
the notebooks as CI executed them); their SymPy outputs may scroll sideways, as in Jupyter.
"""

import glob
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cdp  # noqa: E402

# Waits for MathJax to finish, then measures: the text column, each display and figure.
MEASURE = r"""
(async () => {
  if (!window.MathJax || !MathJax.startup) return {problem: 'MathJax did not load'};
  await MathJax.startup.promise;
  const article = document.querySelector('article') || document.querySelector('main') || document.body;
  const column = article.getBoundingClientRect().width;
  const displays = [];
  document.querySelectorAll('mjx-container[display="true"]').forEach((c, i) => {
    const math = c.querySelector('mjx-math');
    const width = math ? math.getBoundingClientRect().width : c.scrollWidth;
    const tex = (c.parentElement && c.parentElement.textContent || '').slice(0, 80);
    displays.push({i, width, tex});
  });
  const errors = [...document.querySelectorAll('mjx-merror')].map(e => e.getAttribute('data-mjx-error') || e.textContent);
  const figures = [...document.querySelectorAll('article img, main img')].map(img => ({
    src: img.getAttribute('src'), width: img.getBoundingClientRect().width,
    natural: img.naturalWidth, loaded: img.complete && img.naturalWidth > 0}));
  const outputs = document.querySelectorAll('.cell_output').length;
  return {column, displays, errors, figures, count: displays.length, outputs};
})()
"""


# Errors of the book's own theme, not of the pages lagrange writes: jupyter-book 1.0.4 with
# sphinx-thebe 0.3.1 writes the Thebe settings script twice (its `const` declared again).
# pydata-sphinx-theme 0.17 logs an empty colour mode on the first page a fresh profile opens.
KNOWN = ("Identifier 'THEBE_JS_URL' has already been declared", "Got invalid theme mode: .")


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[2])
        return 2
    book = os.path.abspath(sys.argv[1])
    pages = sorted(glob.glob(os.path.join(book, "7.*.html")))
    failed = passed = 0

    def report(ok, what, detail=""):
        nonlocal failed, passed
        if ok:
            passed += 1
            print(f"ok   {what}" + (f" ({detail})" if detail else ""))
        else:
            failed += 1
            print(f"FAIL {what}" + (f": {detail}" if detail else ""))
        sys.stdout.flush()

    report(len(pages) == 4, "the book has the four exercise pages", ", ".join(map(os.path.basename, pages)))
    executable = cdp.find_chromium()
    if not executable:
        report(False, "Chromium found", "install Debian's chromium (apt-get install chromium)")
        return 1
    browser = cdp.Browser(executable, width=1000, height=800)
    try:
        def typeset(page, name):
            """Opens a page; the measures when it loads and MathJax typesets it, else None."""
            browser.open(page, settle=0.5)
            measured = browser.evaluate(MEASURE)
            problem = measured.get("problem") if isinstance(measured, dict) else "nothing measured"
            errors = [e for e in browser.errors if not any(k in e for k in KNOWN)]
            errors += [problem] if problem else []
            report(not errors, f"{name} loads offline without errors", "; ".join(errors))
            if problem:
                return None
            report(not measured["errors"], f"{name}: MathJax typesets every formula ({measured['count']} displays)",
                   "; ".join(measured["errors"][:5]))
            return measured

        for page in pages:
            name = os.path.basename(page)
            measured = typeset(page, name)
            if measured is None:
                continue
            column = measured["column"]
            wide = [f"display {d['i']} is {d['width']:.0f} px: {d['tex']!r}"
                    for d in measured["displays"] if d["width"] > column + 0.5]
            report(not wide, f"{name}: no display wider than the {column:.0f} px column",
                   f"{len(wide)} too wide; " + "; ".join(wide[:4]))
            bad = [f"{f['src']} ({f['width']:.0f} px{'' if f['loaded'] else ', not loaded'})"
                   for f in measured["figures"] if not f["loaded"] or f["width"] > column + 0.5]
            report(not bad, f"{name}: every figure loads and fits the column", "; ".join(bad))
        notebooks = sorted(glob.glob(os.path.join(book, "notebooks", "7.*.html")))
        report(len(notebooks) == 4, "the book has the four notebooks", ", ".join(map(os.path.basename, notebooks)))
        for page in notebooks:
            name = "notebooks/" + os.path.basename(page)
            measured = typeset(page, name)
            if measured is None:
                continue
            report(measured["outputs"] >= 5, f"{name}: shows the outputs of a run ({measured['outputs']} outputs)")
            # The displayed solution is Markdown with `$$` math: rendered as MyST it gives a
            # dozen displays or more; as plain Markdown none of them (its TeX is mangled).
            report(measured["count"] >= 10, f"{name}: the solution's mathematics is typeset ({measured['count']} displays)")
    except (cdp.BrowserError, KeyError, TypeError) as e:
        report(False, "the book's pages", f"{type(e).__name__}: {e}")
    finally:
        browser.close()
    print(f"{passed} checks passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

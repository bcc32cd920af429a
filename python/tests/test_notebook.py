"""The notebooks of the seed's exercises (docs/notebooks/) run from top to bottom with
nbclient, and each solution displays as Markdown with the math; the book of the four
(docs/book/) is built from these notebooks."""

import os
from pathlib import Path

import nbclient
import nbformat
import pytest

from conftest import ROOT

NOTEBOOKS = ROOT / "docs" / "notebooks"


def execute(path):
    """The notebook at `path`, executed; its code cells' outputs."""
    notebook = nbformat.read(path, as_version=4)
    client = nbclient.NotebookClient(
        notebook, timeout=300, kernel_name="python3",
        resources={"metadata": {"path": str(path.parent)}},
    )
    client.execute()  # raises CellExecutionError on the first cell that fails
    # The book of the exercises (docs/book/build.sh) shows the notebooks as they ran here.
    executed = os.environ.get("LAGRANGE_EXECUTED_NOTEBOOKS")
    if executed:
        Path(executed).mkdir(parents=True, exist_ok=True)
        nbformat.write(notebook, str(Path(executed) / path.name))
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    return outputs


def markdown_of(outputs):
    return [o["data"]["text/markdown"] for o in outputs
            if o.output_type == "execute_result" and "text/markdown" in o.get("data", {})]


def test_the_7_1_notebook_runs():
    outputs = execute(NOTEBOOKS / "7.1-cart-pendulum.ipynb")
    assert any(m.startswith("# Exercise 7.1") and "\\begin{aligned}" in m
               for m in markdown_of(outputs))
    printed = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "largest difference at t = 10" in printed


@pytest.mark.parametrize("stem", ["7.2-rolling-cone", "7.3-gears-pendulum", "7.4-inverted-pendulum"])
def test_each_seed_notebook_runs_and_shows_its_solution(stem):
    outputs = execute(NOTEBOOKS / f"{stem}.ipynb")
    number = stem.split("-")[0]
    assert any(m.startswith(f"# Exercise {number}") and "\\begin{aligned}" in m
               for m in markdown_of(outputs)), stem
    printed = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    # At least one equilibrium is stable (7.2 lying on its side, 7.3 and 7.4 hanging).
    assert "True -" in printed, printed
    # The simulation's last rows, as a table (a DataFrame with pandas).
    assert any("text/html" in o.get("data", {}) or "text/plain" in o.get("data", {})
               for o in outputs if o.output_type == "execute_result")


def test_every_notebook_is_in_the_book():
    toc = (ROOT / "docs" / "book" / "_toc.yml").read_text()
    for path in NOTEBOOKS.glob("*.ipynb"):
        assert f"notebooks/{path.stem}" in toc, path.name

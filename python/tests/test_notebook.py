"""The notebook of the seed's 7.1 (docs/notebooks/) runs from top to bottom with nbclient, and
its solution displays as Markdown with the math."""

import nbclient
import nbformat

from conftest import ROOT

NOTEBOOK = ROOT / "docs" / "notebooks" / "7.1-cart-pendulum.ipynb"


def test_the_7_1_notebook_runs():
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        notebook, timeout=300, kernel_name="python3",
        resources={"metadata": {"path": str(NOTEBOOK.parent)}},
    )
    client.execute()  # raises CellExecutionError on the first cell that fails
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    markdown = [o["data"]["text/markdown"] for o in outputs
                if o.output_type == "execute_result" and "text/markdown" in o.get("data", {})]
    assert any(m.startswith("# Exercise 7.1") and "\\begin{aligned}" in m for m in markdown)
    printed = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "largest difference at t = 10" in printed

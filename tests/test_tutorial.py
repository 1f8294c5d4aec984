"""The tutorial notebook (docs/tutorial/first-hour.ipynb) runs top to bottom and shows what it says.

It is stored without outputs (the documentation build executes it); here it is executed
in a fresh kernel, in a temporary folder, and its outputs checked: the results' HTML
tables, the batch as a DataFrame, the picture.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

import dentopo

nbformat = pytest.importorskip("nbformat", reason="the test extra's nbformat runs the notebook")
nbclient = pytest.importorskip("nbclient", reason="the test extra's nbclient runs the notebook")
pytest.importorskip("ipykernel", reason="the test extra's ipykernel runs the notebook")
pytest.importorskip("pandas", reason="the tutorial's batch table needs pandas")
pytest.importorskip("pyvista", reason="the tutorial's picture needs pyvista")

NOTEBOOK = Path(__file__).resolve().parents[1] / "docs" / "tutorial" / "first-hour.ipynb"


def test_the_notebook_is_stored_without_outputs():
    notebook = json.loads(NOTEBOOK.read_text())
    nbformat.validate(nbformat.reads(NOTEBOOK.read_text(), as_version=4))
    code = [cell for cell in notebook["cells"] if cell["cell_type"] == "code"]
    assert code and all(c["outputs"] == [] and c["execution_count"] is None for c in code)


@pytest.mark.slow
def test_the_notebook_runs_top_to_bottom(tmp_path, monkeypatch):
    # the kernel imports the dentopo under test, whatever the folder it starts in
    here = str(Path(dentopo.__file__).resolve().parents[1])
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([here, os.environ.get("PYTHONPATH", "")]))
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        notebook,
        timeout=300,
        kernel_name="python3",
        resources={"metadata": {"path": str(tmp_path)}},
    )
    client.execute()  # raises CellExecutionError naming the cell on any error
    outputs = [o for cell in notebook.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    html = "".join(o.get("data", {}).get("text/html", "") for o in outputs)
    for shown in ("AriaDNEResult", "SlopeResult", "OPCRResult", "RFIResult", "BatchResult"):
        assert f"<caption>{shown}</caption>" in html, shown
    assert "<svg" in html  # the local curvature's histogram
    # the batch's DataFrame: the jittered scan has its RFI; the generated samples are partial
    frames = [o for o in outputs if 'class="dataframe"' in o.get("data", {}).get("text/html", "")]
    table = frames[0]["data"]["text/plain"]
    assert "jittered_tooth.ply       ok" in table and "partial" in table
    assert any("image/png" in o.get("data", {}) for o in outputs)  # the picture

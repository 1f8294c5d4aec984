"""A plain command imports only what it uses (issue 32, "Start in a second").

The command's warm start is mostly imports: trimesh (with networkx, shapely, lxml,
scipy's spatial and optimize) and scipy's sparse graphs cost about 0.7 s of CPU, and
a plain ariaDNE run of a PLY file needs none of them.  These tests hold that as a
property (which modules a fresh process has loaded), not as a timing.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

from dentopo.samples import sample_paths

#: Never imported by a plain ``dentopo crown.ply`` (ariaDNE, the default metrics).
NOT_IN_A_PLAIN_RUN = (
    "trimesh",
    "networkx",
    "scipy.sparse",
    "scipy.spatial",
    "scipy.optimize",
    "shapely",
    "lxml",
    "PIL",
    "pandas",
    "dask",
    "pyvista",
    "matplotlib",
    "dentopo.topography.relief",
    "dentopo.topography.dne",
    "dentopo.figures._render",
    "dentopo.report",
    "dentopo.app",
    "dentopo.study",
)


def _loaded(code: str, names) -> dict[str, bool]:
    """Run `code` in a fresh interpreter; which of `names` it has imported."""
    script = textwrap.dedent(code) + textwrap.dedent(
        f"""
        import json, sys
        print(json.dumps({{name: name in sys.modules for name in {list(names)!r}}}))
        """
    )
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=600, check=True
    )
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_import_dentopo_loads_no_heavy_dependency():
    loaded = _loaded("import dentopo", (*NOT_IN_A_PLAIN_RUN, "numba", "scipy"))
    assert not any(loaded.values()), loaded


def test_a_plain_run_imports_neither_trimesh_nor_scipy_sparse(tmp_path):
    tooth = str(sample_paths()["tooth"])
    out = str(tmp_path / "out.csv")
    loaded = _loaded(
        f"""
        from dentopo.cli import main
        assert main([{tooth!r}, "-o", {out!r}, "-q"]) == 0
        """,
        NOT_IN_A_PLAIN_RUN,
    )
    assert not any(loaded.values()), {name for name, was in loaded.items() if was}
    assert (tmp_path / "out.csv").read_text().count("\n") == 2


def test_ariadne_result_builds_the_same_mesh_on_first_read():
    tooth = str(sample_paths()["tooth"])
    loaded = _loaded(
        f"""
        import sys
        import numpy as np
        from dentopo import ariaDNE
        from dentopo.mesh import clean, load_mesh
        result = ariaDNE({tooth!r})
        assert "trimesh" not in sys.modules
        mesh = result.mesh  # built now, trimesh imported now
        read = load_mesh({tooth!r})
        cleaned = clean(read.vertices, read.faces)
        assert np.array_equal(mesh.vertices, cleaned.vertices)
        assert np.array_equal(mesh.faces, cleaned.faces)
        assert mesh.metadata["cleaning"] == cleaned.metadata["cleaning"]
        assert result.mesh is mesh
        """,
        ("trimesh",),
    )
    assert loaded["trimesh"]


def test_help_loads_no_trimesh():
    loaded = _loaded(
        """
        import contextlib, io
        from dentopo.cli import main
        with contextlib.redirect_stdout(io.StringIO()):
            main(["--help"])
        """,
        ("trimesh", "scipy.sparse", "networkx", "pandas"),
    )
    assert not any(loaded.values()), loaded

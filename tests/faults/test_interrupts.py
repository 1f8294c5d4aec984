"""Ctrl-C and SIGTERM at any moment: exit 130, one line, the rows done on disk, no traceback.

Each test starts ``dentopo`` in the background, waits for a moment of a mesh
(reported by the test hook ``DENTOPO_TEST_PHASES``, see ``live.py``), sends
the signal there and checks how the run ended.  Before the fix a Ctrl-C while
the ariaDNE kernel ran crashed the process (SIGSEGV: numba boxes the kernel's
results after a pending KeyboardInterrupt and unpacks a NULL), and SIGTERM
killed it without writing a row.
"""

from __future__ import annotations

import csv
import os
import re
import signal
import time

import pytest

from faults.harness import python
from faults.live import alive, environment, start, start_python, write_tooth

EXACT = ("--method", "exact")  # the compiled kernel, whatever the number of vertices


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    """Small meshes (a, c), a medium one (b: 0.9 s of exact kernel on two cores), and one whose
    kernel runs for seconds (big: about 5 s)."""
    folder = tmp_path_factory.mktemp("meshes")
    write_tooth(folder / "a.ply", 20)
    write_tooth(folder / "b.ply", 100)
    write_tooth(folder / "c.ply", 20)
    write_tooth(folder / "big.ply", 150)
    return folder


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return {os.path.basename(r["file"]): r for r in csv.DictReader(stream)}


def assert_clean_stop(ran, message="interrupted: "):
    assert ran.returncode == 130, ran.describe()
    assert message in ran.stderr, ran.describe()
    assert "Traceback" not in ran.stderr, ran.describe()
    assert "Fatal Python error" not in ran.stderr, ran.describe()


def assert_no_leftovers(out):
    folder = out.parent
    assert not (folder / f"{out.name}.partial.jsonl").exists()  # its rows are in the table
    assert not (folder / f".{out.name}.lock").exists()


def test_ctrl_c_during_the_kernel_stops_cleanly_and_keeps_the_rows_done(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "big.ply", "c.ply")]
    run = start(*files, *EXACT, "-o", str(out), env=environment(DENTOPO_TEST_PHASES="1"))
    run.wait_for(r"big\.ply: kernel")
    time.sleep(
        0.5
    )  # well inside the compiled loop (about 5 s on two cores; b.ply's 0.9 s was close)
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted: 1 of 3 files done")
    assert "big.ply: bending" not in ran.stderr  # stopped as the kernel returned
    table = rows(out)
    assert list(table) == ["a.ply"] and table["a.ply"]["status"] == "ok"
    assert_no_leftovers(out)


def test_ctrl_c_while_reading_stops_at_once(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "big.ply")]
    run = start(*files, *EXACT, "-o", str(out), env=environment(DENTOPO_TEST_PHASES="1"))
    run.wait_for(r"big\.ply: prepare")
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted: 1 of 2 files done")
    assert "big.ply: kernel" not in ran.stderr  # did not wait for the next phase
    assert list(rows(out)) == ["a.ply"]


def test_ctrl_c_during_the_sign_step_stops_cleanly(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "b.ply")]
    run = start(*files, *EXACT, "-o", str(out), env=environment(DENTOPO_TEST_PHASES="1"))
    run.wait_for(r"b\.ply: sign")
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted: 1 of 2 files done")
    assert "SystemError" not in ran.stderr  # never a wrong error row instead of stopping
    assert list(rows(out)) == ["a.ply"]


def test_ctrl_c_while_the_table_is_written_still_writes_it_whole(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "c.ply")]
    run = start(*files, "-o", str(out), env=environment(DENTOPO_TEST_SLOW_WRITE="2"))
    run.wait_for("dentopo-test: writing")
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted after the table was written")
    table = rows(out)
    assert list(table) == ["a.ply", "c.ply"]
    assert {r["status"] for r in table.values()} == {"ok"}
    assert_no_leftovers(out)


def test_sigterm_ends_like_ctrl_c(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "b.ply", "c.ply")]
    run = start(*files, *EXACT, "-o", str(out))
    run.wait_for(r"\[1/3\] .*a\.ply: ok")
    run.send(signal.SIGTERM)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted (SIGTERM): 1 of 3 files done")
    assert list(rows(out)) == ["a.ply"]
    assert_no_leftovers(out)


def test_ctrl_c_with_workers_stops_them_at_once(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "big.ply", "c.ply")]
    run = start(*files, *EXACT, "-j", "2", "-o", str(out))
    run.wait_for(r"\[2/3\] .*: ok")  # a and c done; big's kernel runs for seconds
    workers = run.workers()
    sent = time.monotonic()
    run.send(signal.SIGINT)
    ran = run.finish()
    assert time.monotonic() - sent < 5.0  # did not wait for big.ply
    assert_clean_stop(ran, "interrupted: 2 of 3 files done")
    assert sorted(rows(out)) == ["a.ply", "c.ply"]
    assert workers and not [pid for pid in workers if alive(pid)]


LIBRARY = """
import os, signal, threading
from dentopo import compute_batch
threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT)).start()  # during the kernel
try:
    compute_batch([{path!r}], method="exact")
except KeyboardInterrupt:
    print("KeyboardInterrupt")
"""


def test_compute_batch_raises_keyboard_interrupt_not_a_crash(meshes):
    ran = python(LIBRARY.format(path=str(meshes / "big.ply")))  # seconds of kernel
    assert ran.returncode == 0, ran.describe()
    assert ran.stdout.strip() == "KeyboardInterrupt", ran.describe()


# --- the library, and the subcommands, outside the batch runner's guard ---------------------
#
# Before the fix numba's compiled kernels returned new arrays, which numba boxes with a
# little Python code after the loop: a Ctrl-C during the loop was raised there, and
# ariaDNE called from a script ended with "SystemError: ... returned a result with an
# exception set" (or a segmentation fault), after the whole kernel had run.

#: Seconds from the signal to the KeyboardInterrupt: the kernel runs in slices of
#: a few tenths of a second, and Python reacts between them.
PROMPT = 1.0

ARIADNE_SCRIPT = """
import sys, time
from dentopo import ariaDNE
from dentopo.samples import tooth

mesh = tooth(rings=150)  # about 68k vertices: the exact kernel runs for seconds
{warm_up}

def phase(name):
    print(f"phase {{name}}", file=sys.stderr, flush=True)

try:
    ariaDNE(mesh, method="exact", progress=phase)
except KeyboardInterrupt:
    print("KeyboardInterrupt", file=sys.stderr, flush=True)
    sys.exit(0)
print("finished without an interrupt", file=sys.stderr, flush=True)
"""

WINDING_SCRIPT = """
import sys
import numpy as np
from dentopo.mesh import close_holes, prepare
from dentopo.samples import tooth
from dentopo.sign import inside

prepared = prepare(tooth(rings=150))
vertices, faces = close_holes(prepared.points, np.asarray(prepared.mesh.faces))
rng = np.random.default_rng(0)
points = np.repeat(prepared.points, 24, axis=0)
points += rng.normal(scale=1e-3, size=points.shape)  # near the surface: slow queries
inside(vertices, faces, points[:10])  # loads the compiled code (the long triangles' too)
print("start", file=sys.stderr, flush=True)
try:
    inside(vertices, faces, points)
except KeyboardInterrupt:
    print("KeyboardInterrupt", file=sys.stderr, flush=True)
    sys.exit(0)
print("finished without an interrupt", file=sys.stderr, flush=True)
"""


def interrupt_when(run, pattern: str, delay: float) -> float:
    """Send SIGINT `delay` seconds after a stderr line matching `pattern`; when it was sent."""
    run.wait_for(pattern, timeout=120.0)
    time.sleep(delay)
    sent = time.monotonic()
    run.send(signal.SIGINT)
    return sent


#: Loads (or compiles) every kernel the large mesh runs: small meshes take the paired
#: kernel (up to ``PAIRED_VERTICES`` vertices), larger ones the row kernel.
WARM_UP = """
from dentopo.ariadne import _kernel
ariaDNE(tooth(rings=4), method="exact")
_kernel.PAIRED_VERTICES, paired = 0, _kernel.PAIRED_VERTICES
ariaDNE(tooth(rings=4), method="exact")
_kernel.PAIRED_VERTICES = paired
"""

#: ... all but the row kernel, which the large mesh's kernel phase then compiles.
WARM_UP_BUT_THE_ROW_KERNEL = 'ariaDNE(tooth(rings=4), method="exact")'


def test_ctrl_c_in_ariadne_called_from_a_script_is_a_prompt_keyboard_interrupt():
    run = start_python(ARIADNE_SCRIPT.format(warm_up=WARM_UP))
    sent = interrupt_when(run, r"^phase kernel", 1.0)  # well inside the compiled loop
    run.wait_for(r"KeyboardInterrupt|finished|Error", timeout=60.0)
    seconds = time.monotonic() - sent
    ran = run.finish()
    assert ran.returncode == 0, ran.describe()
    assert ran.stderr.splitlines()[-1] == "KeyboardInterrupt", ran.describe()
    assert "phase bending" not in ran.stderr  # stopped inside the kernel
    assert seconds < PROMPT, (seconds, ran.describe())


@pytest.fixture(scope="module")
def numba_cache(tmp_path_factory):
    """A numba cache of its own, which the tests below empty of the row kernel."""
    return tmp_path_factory.mktemp("numba-cache")


# A fresh install compiles each kernel on its first call.  Before the fix, a Ctrl-C while
# LLVM compiled was lost: Python raised it in llvmlite's object-cache callback, a ctypes
# callback, which printed "Exception ignored ... KeyboardInterrupt" and went on, and the
# script ran to its end (1 s into the row kernel's compilation, in CI).  Where the signal
# lands in the compilation depends on the machine; tests/test_jit.py makes it certain.
@pytest.mark.parametrize("delay", [0.5, 1.0])
def test_ctrl_c_while_numba_compiles_a_kernel_is_raised_not_lost(numba_cache, delay):
    for cached in numba_cache.rglob("*_run_sums*"):
        cached.unlink()  # compiled afresh in the kernel phase
    run = start_python(
        ARIADNE_SCRIPT.format(warm_up=WARM_UP_BUT_THE_ROW_KERNEL),
        env=environment(NUMBA_CACHE_DIR=str(numba_cache)),
    )
    interrupt_when(run, r"^phase kernel", delay)
    run.wait_for(r"KeyboardInterrupt|finished|Error", timeout=120.0)
    ran = run.finish()
    assert ran.returncode == 0, ran.describe()
    assert ran.stderr.splitlines()[-1] == "KeyboardInterrupt", ran.describe()
    assert "phase bending" not in ran.stderr, ran.describe()  # stopped at the kernel
    assert "Exception ignored" not in ran.stderr, ran.describe()


def test_ctrl_c_in_the_winding_number_is_a_prompt_keyboard_interrupt():
    run = start_python(WINDING_SCRIPT)
    sent = interrupt_when(run, r"^start", 1.5)  # in the queries (about 3 s)
    run.wait_for(r"KeyboardInterrupt|finished|Error", timeout=60.0)
    seconds = time.monotonic() - sent
    ran = run.finish()
    assert ran.returncode == 0, ran.describe()
    assert ran.stderr.splitlines()[-1] == "KeyboardInterrupt", ran.describe()
    assert seconds < PROMPT, (seconds, ran.describe())


@pytest.fixture(scope="module")
def study_mesh(tmp_path_factory):
    """A crown just below the fast method's threshold: ``auto`` runs the exact kernel."""
    return write_tooth(tmp_path_factory.mktemp("study") / "crown.ply", 80)


@pytest.mark.parametrize("command", ["sweep", "robustness"])
def test_ctrl_c_in_the_study_commands_exits_130_with_one_line(study_mesh, tmp_path, command):
    options = ["--no-figures", "--sign-method", "centroid", "-o", str(tmp_path)]
    if command == "robustness":
        options += ["--perturbation", f"same={study_mesh}", "--no-classic"]
    run = start(command, str(study_mesh), *options, env=environment(DENTOPO_TEST_KERNEL="1"))
    sent = interrupt_when(run, r"dentopo-test: kernel", 0.2)  # the kernel runs for 0.5 s
    ran = run.finish()
    seconds = time.monotonic() - sent
    lines = [line for line in ran.stderr.splitlines() if not line.startswith("dentopo-test:")]
    assert ran.returncode == 130, ran.describe()
    assert lines == ["dentopo: interrupted"], ran.describe()
    assert seconds < PROMPT + 1.0, (seconds, ran.describe())  # the process's exit included


MIXED_PLY_HEADER = b"""ply
format binary_little_endian 1.0
element vertex 5
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
"""


def _returns_an_array(numba_type) -> bool:
    from numba.core import types

    if isinstance(numba_type, types.Array):
        return True
    if isinstance(numba_type, types.BaseTuple):
        return any(_returns_an_array(t) for t in numba_type.types)
    return False


def test_no_compiled_kernel_returns_an_array(tmp_path, monkeypatch):
    # the root of the crashes above: whatever numba compiles for dentopo returns
    # nothing or a number, never an array (a new kernel that does fails here)
    import importlib
    import inspect
    import pkgutil
    import struct

    import numpy as np
    from numba.core.registry import CPUDispatcher

    import dentopo
    from dentopo import ariaDNE
    from dentopo.mesh import load_mesh, orient_consistently
    from dentopo.samples import tooth
    from dentopo.sign import exact_winding_number, winding_number

    crown = tooth(rings=8)
    for sign_method in ("centroid", "winding", "mean_curvature", "gaussian_curvature"):
        ariaDNE(crown, method="exact", sign_method=sign_method)
    ariaDNE(crown, distance_type="geodesic")
    # the paths of large meshes: each vertex's row in full, the 3 x 3 solves in parallel
    from dentopo.ariadne import _eigen, _kernel

    monkeypatch.setattr(_kernel, "PAIRED_VERTICES", 0)
    monkeypatch.setattr(_eigen, "PARALLEL_VERTICES", 0)
    ariaDNE(crown, method="exact")
    monkeypatch.undo()
    from dentopo.ariadne import _fastgauss, _kernel
    from dentopo.mesh import prepare
    from dentopo.mesh._topology import edge_uses

    prepared = prepare(crown)  # the fast path's compiled bending, without FINUFFT
    _fastgauss.bending(_kernel.euclidean_moments(prepared.points, 0.08, 0.0), prepared.normals)
    edge_uses(crown.faces, len(crown.vertices))
    from dentopo.mesh import first_faces

    fan = np.column_stack([np.zeros(40, np.int64), np.arange(1, 41), np.arange(2, 42)])
    edge_uses(fan, 42)  # a vertex of many corners: the sorted paths
    first_faces(fan, np.ones(40, dtype=bool), 42)
    vertices, faces = np.array(crown.vertices), np.array(crown.faces)
    vertices[5] = 1e3  # long triangles, cut into strips
    winding_number(vertices, faces, vertices[:10])
    exact_winding_number(vertices, faces, vertices[:10])
    from dentopo.sign._strips import _split_long

    _split_long(vertices[faces])  # the strips written out (the hierarchy makes them itself)
    flipped = faces.copy()
    flipped[0] = flipped[0, ::-1]
    orient_consistently(flipped, len(vertices))
    mixed = tmp_path / "mixed.ply"  # rows of different lengths: a triangle and a quad
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], "<f4")
    rows = struct.pack("<B3i", 3, 0, 1, 4) + struct.pack("<B4i", 4, 0, 1, 2, 3)
    mixed.write_bytes(MIXED_PLY_HEADER + points.tobytes() + rows)
    load_mesh(mixed)
    from dentopo.topography import classic_dne, opcr, rfi, slope

    for metric in (slope, opcr, classic_dne):
        metric(crown)
    rfi(crown, find_alpha=True)
    from dentopo.topography.footprint._delaunay import delaunay

    delaunay(np.random.default_rng(0).random((200, 2)))  # general points: every certificate
    from dentopo import topography

    for name in (
        "arc",
        "doolkit_arc",
        "doolkit_dne",
        "angularity",
        "doolkit_slope",
        "inclination",
        "doolkit_opc",
        "doolkit_opcr",
        "relief_index",
        "relief_rate_below_median",
        "shape_index",
        "hypsodonty",
        "elevation",
        "projected_rfi",
    ):
        getattr(topography, name)(crown)
    topography.footprint_area(crown, hull="convex")
    topography.pcv(crown, rays=8)
    from dentopo.topography.occlusion._depth import lit_counts_depth_buffer

    lit_counts_depth_buffer(crown.vertices, crown.faces, np.eye(3), 64, path="image")

    kernels = {}
    inlined = {}  # compiled into their callers: their calls are compiled code too
    for info in pkgutil.walk_packages(dentopo.__path__, "dentopo."):
        if info.name.endswith("__main__"):  # runs the command
            continue
        try:
            module = importlib.import_module(info.name)
        except ImportError:  # an extra that is not installed: no kernel there
            continue
        for name, value in vars(module).items():
            if isinstance(value, CPUDispatcher) and value.__module__ == module.__name__:
                if value.targetoptions.get("inline", "never") == "never":
                    kernels[f"{module.__name__}.{name}"] = value
                else:
                    inlined[f"{module.__name__}.{name}"] = value
    assert len(kernels) >= 10, sorted(kernels)
    sources = {
        name: inspect.getsource(kernel.py_func) for name, kernel in {**kernels, **inlined}.items()
    }
    for name, kernel in kernels.items():
        short = name.rsplit(".", 1)[1]
        call = re.compile(rf"(?<![\w.]){re.escape(short)}\(")
        inner = any(call.search(source) for other, source in sources.items() if other != name)
        # a kernel called only by other kernels is compiled into them: its arrays are never
        # boxed, so it may return one; a kernel called from Python may not
        assert kernel.nopython_signatures or inner, f"{name} was not run by this test"
        if inner:
            continue
        for signature in kernel.nopython_signatures:
            assert not _returns_an_array(signature.return_type), (name, signature)


def write_shuffled_grid(path, side: int, seed: int = 0):
    """A dome over a jittered ``side`` x ``side`` grid, its vertices in random order.

    The order makes RFI's Delaunay sweep slow (no locality): with 1200 a side
    (1.4M vertices) it runs for about 4.5 s on two cores, after about 8 s of
    reading and cleaning.
    """
    import numpy as np

    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.arange(side, dtype=float), np.arange(side, dtype=float), indexing="ij")
    xy = np.stack([x.ravel(), y.ravel()], 1) + rng.uniform(-0.3, 0.3, (side * side, 2))
    r2 = ((xy - side / 2) ** 2).sum(1) / (side / 2) ** 2
    z = np.sqrt(np.clip(1.2 - r2, 0, None)) * side / 3 + rng.normal(scale=0.1, size=len(xy))
    vertices = np.column_stack([xy, z]).astype("<f4")
    idx = np.arange(side * side).reshape(side, side)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    perm = rng.permutation(len(vertices))
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    rows = np.empty(len(faces), dtype=[("n", "u1"), ("v", "<i4", 3)])
    rows["n"] = 3
    rows["v"] = inverse[faces]
    header = (
        f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    path.write_bytes(header.encode() + vertices[perm].tobytes() + rows.tobytes())
    return path


@pytest.fixture(scope="module")
def big_footprint(tmp_path_factory):
    return write_shuffled_grid(tmp_path_factory.mktemp("footprint") / "grid.ply", 1200)


# Before the fix RFI's Delaunay sweep was one compiled call: a Ctrl-C or SIGTERM 1 s into
# it with -j 1 waited for the whole sweep (3.5 s more here; 24-34 s on a 1M-vertex noisy
# crown under load).  The sweep now runs in bounded calls, and Python reacts between them.
@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_a_signal_in_rfis_delaunay_sweep_stops_the_run_promptly(big_footprint, tmp_path, signum):
    out = tmp_path / "out.csv"
    run = start(
        str(big_footprint),
        "--metrics",
        "rfi",
        "-j",
        "1",
        "-o",
        str(out),
        env=environment(DENTOPO_TEST_DELAUNAY="1"),
    )
    run.wait_for(r"dentopo-test: delaunay \d+ points", timeout=120.0)
    time.sleep(1.0)  # well inside the sweep (about 4.5 s on two cores)
    sent = time.monotonic()
    run.send(signum)
    ran = run.finish()
    seconds = time.monotonic() - sent
    lines = [line for line in ran.stderr.splitlines() if not line.startswith("dentopo-test:")]
    expected = "interrupted: " if signum == signal.SIGINT else "interrupted (SIGTERM): "
    assert_clean_stop(ran, expected + "0 of 1 files done")
    assert "dentopo-test: delaunay done" not in ran.stderr, ran.describe()
    assert len(lines) == 1, ran.describe()
    assert seconds < PROMPT + 1.0, (seconds, ran.describe())  # the process's exit included
    assert not out.exists()


EXACT_WINDING_SCRIPT = """
import sys
import numpy as np
from dentopo.samples import tooth
from dentopo.sign import exact_winding_number

mesh = tooth(rings=150)  # 135k faces: 2000 exact queries take about 7 s on two cores
vertices, faces = np.asarray(mesh.vertices), np.asarray(mesh.faces)
points = vertices[:2000] + 1e-3
exact_winding_number(vertices, faces, points[:4])  # loads the compiled code
print("start", file=sys.stderr, flush=True)
try:
    exact_winding_number(vertices, faces, points)
except KeyboardInterrupt:
    print("KeyboardInterrupt", file=sys.stderr, flush=True)
    sys.exit(0)
print("finished without an interrupt", file=sys.stderr, flush=True)
"""


# Before the fix the exact sums were one compiled call over every query: a Ctrl-C 1 s in
# waited for all of them (about 6 s more).  They now run in blocks of queries.
def test_ctrl_c_in_the_exact_winding_sums_is_a_prompt_keyboard_interrupt():
    run = start_python(EXACT_WINDING_SCRIPT)
    sent = interrupt_when(run, r"^start", 1.0)
    run.wait_for(r"KeyboardInterrupt|finished|Error", timeout=60.0)
    seconds = time.monotonic() - sent
    ran = run.finish()
    assert ran.returncode == 0, ran.describe()
    assert ran.stderr.splitlines()[-1] == "KeyboardInterrupt", ran.describe()
    assert seconds < PROMPT, (seconds, ran.describe())


# Before the fix the winding number's hierarchy was built by two compiled calls over every
# level (0.66 s and 0.60 s on 2.6M faces on two idle cores, seconds under load); a signal
# waited for them.  They now run a level a call, and Python reacts between calls.
def test_the_hierarchy_built_a_level_a_call_is_that_of_one_call():
    import numpy as np

    from dentopo.samples import tooth
    from dentopo.sign import _hierarchy as w
    from dentopo.sign._strips import no_strips

    mesh = tooth(rings=200)  # above PARALLEL_BUILD triangles: the levels' nodes in parallel
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    assert len(faces) >= w.PARALLEL_BUILD
    keep, strips = np.arange(len(faces)), no_strips()
    centres = np.empty((len(faces), 3))
    w._item_centres(vertices, faces, keep, *strips, centres)
    lo, hi, link, level = w._shape(len(faces), w.LEAF_SIZE)
    assert len(level) > 10
    built = {}
    for per_call in (1, 3, 10_000):
        moved, perm = centres.copy(), np.arange(len(faces))
        w._kd_order(moved, link, lo, hi, level, perm, per_call)
        tri = np.empty((len(faces), 3, 3))
        w._gather(vertices, faces, keep, *strips, perm, tri)
        nodes = np.zeros((len(link), 8))
        weight = np.empty(len(link), np.float32)
        w._summarise(tri, lo, hi, link, level, nodes, nodes.view(np.float32), weight, per_call)
        built[per_call] = (perm, moved, nodes, weight)
    for per_call in (1, 3):
        for sliced, whole in zip(built[per_call], built[10_000], strict=True):
            assert sliced.tobytes() == whole.tobytes()
    assert not np.array_equal(built[1][0], np.arange(len(faces)))  # the order was built

"""Test hooks for the fault suite, imported by every Python process a fault test starts.

Each is off unless its environment variable is set (see ``faults/live.py``).
They only watch or slow down dentopo from outside (wrapping a function,
changing a module constant); nothing in dentopo itself knows about them.
"""

import os
import signal
import sys
import time

_KILL_ON = os.environ.get("DENTOPO_TEST_KILL_WORKER_ON")
_PHASES = os.environ.get("DENTOPO_TEST_PHASES")
_SLOW_WRITE = os.environ.get("DENTOPO_TEST_SLOW_WRITE")
_KERNEL = os.environ.get("DENTOPO_TEST_KERNEL")
_DELAUNAY = os.environ.get("DENTOPO_TEST_DELAUNAY")

if _KILL_ON:
    import multiprocessing

    import dentopo.batch._runner as _runner

    _real_compute_task = _runner.compute_task

    def compute_task(task, settings, on_phase=None):
        """In a worker process, die of SIGKILL on the file named ``_KILL_ON``."""
        if multiprocessing.parent_process() is not None:
            if os.path.basename(task.file) == _KILL_ON:
                os.kill(os.getpid(), signal.SIGKILL)
        return _real_compute_task(task, settings, on_phase)

    _runner.compute_task = compute_task

if _PHASES:
    import dentopo.cli._progress as _progress

    _progress.SLOW_MESH_SECONDS = 0.0  # report every phase of every mesh

if _SLOW_WRITE:
    import importlib

    def _slowed(real):
        def write_table(path, records, **options):
            if not hasattr(path, "write"):  # a file, not stdout
                print(f"dentopo-test: writing {path}", file=sys.stderr, flush=True)
                time.sleep(float(_SLOW_WRITE))
            return real(path, records, **options)

        return write_table

    for _name in ("dentopo.cli._output", "dentopo.cli._compute"):
        try:
            _module = importlib.import_module(_name)
        except ImportError:
            continue
        if hasattr(_module, "write_table"):
            _module.write_table = _slowed(_module.write_table)

if _KERNEL:
    import dentopo.ariadne._kernel as _kernel

    _real_euclidean_moments = _kernel.euclidean_moments

    def euclidean_moments(points, bandwidth, cutoff):
        """Say that the exact kernel starts, then run it."""
        print(f"dentopo-test: kernel {len(points)} points", file=sys.stderr, flush=True)
        return _real_euclidean_moments(points, bandwidth, cutoff)

    _kernel.euclidean_moments = euclidean_moments

if _DELAUNAY:
    import dentopo.topography.footprint._alphahull as _alphahull

    _real_delaunay = _alphahull.delaunay

    def delaunay(points):
        """Say that RFI's Delaunay triangulation starts and ends, then run it."""
        print(f"dentopo-test: delaunay {len(points)} points", file=sys.stderr, flush=True)
        out = _real_delaunay(points)
        print("dentopo-test: delaunay done", file=sys.stderr, flush=True)
        return out

    _alphahull.delaunay = delaunay

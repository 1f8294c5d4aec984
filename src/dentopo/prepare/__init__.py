"""Preparation as a recorded protocol: from a raw scan to the crown that is measured.

Every tool of the field measures a crown somebody prepared by hand in other
software (cropped above the cervix, oriented occlusal side up, decimated to
about 10,000 faces, smoothed); here those steps are code with parameters, run
in a fixed order, each recorded with what it did:

1. **clean** (``_clean``): merge coincident vertices, drop degenerate and
   duplicate faces and unreferenced vertices (the published cleaning), and keep
   the largest piece by area (or all of them);
2. **orient** (``_orient``): a rigid motion that puts the crown occlusal side
   up (+z), its open base's plane parallel to x-y;
3. **crop** (``_crop``): keep what lies above a plane, cutting the faces that
   straddle it exactly;
4. **decimate** (``_decimate``): quadric edge collapse to a face count;
5. **smooth** (``_smooth``): Laplacian, Taubin, HC or implicit fairing.

A :class:`Protocol` (``_protocol``) holds the parameters of every step; it is
read from and written to TOML, and a few named protocols ship with the package
(``protocols/*.toml``).  :func:`prepare` (``_pipeline.run``) runs it and returns a
frozen :class:`PreparedCrown` (``_result``): the mesh, each :class:`Step` with
its parameters and effects, the rigid transform applied, and warnings.

May import: numpy, scipy, numba, trimesh, fast-simplification (and pymeshlab,
an optional GPL extra, only for ``decimate="meshlab"``), and of dentopo
``mesh`` (reading and cleaning) and ``topography`` (the orientation rules).
"""

from ._protocol import (
    DECIMATORS,
    SMOOTHERS,
    Protocol,
    ProtocolError,
    load_protocol,
    named_protocols,
    read_protocol,
)

#: Names imported on first use (PEP 562): ``import dentopo`` stays light (no numpy, trimesh).
_LAZY = {"PreparedCrown": "._result", "Step": "._result", "PrepareWarning": "._pipeline"}


def prepare(mesh, protocol=None, *, geometry=None, **changes):
    """Prepare a raw scan for measuring: clean, orient, crop, decimate, smooth, as a protocol says.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The raw mesh (never modified).
    protocol : Protocol, str, path-like or None
        The protocol: a :class:`Protocol`, the name of a shipped one
        (:func:`named_protocols`), a TOML file, or None for the defaults (clean
        keeping the largest piece, orient occlusal side up).
    geometry : str, optional
        Which mesh of a file holding several (see :func:`dentopo.load_mesh`).
    **changes
        Protocol parameters that replace the protocol's (``faces=10000``,
        ``smooth="implicit"``, ``crop_fraction=0.6``...; see :class:`Protocol`).

    Returns
    -------
    PreparedCrown
        The prepared mesh, each step with its parameters and effects, the
        rigid transform applied, and warnings (also issued as ``PrepareWarning``).

    Raises
    ------
    ProtocolError
        If a parameter is wrong (named).
    ValueError
        If the mesh is invalid, or a step leaves nothing (the step and its plane named).

    Examples
    --------
    >>> from dentopo import prepare
    >>> crown = prepare("scan.ply", faces=10000)              # doctest: +SKIP
    >>> crown.mesh, crown.step("decimate").faces_after        # doctest: +SKIP
    """
    from ._pipeline import run

    return run(mesh, protocol, geometry=geometry, **changes)


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'dentopo.prepare' has no attribute {name!r}")
    import importlib

    value = getattr(importlib.import_module(module, __name__), name)
    globals()[name] = value
    return value


__all__ = [
    "DECIMATORS",
    "SMOOTHERS",
    "PrepareWarning",
    "PreparedCrown",
    "Protocol",
    "ProtocolError",
    "Step",
    "load_protocol",
    "named_protocols",
    "prepare",
    "read_protocol",
]

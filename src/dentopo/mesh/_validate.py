"""Checks every mesh passes before it is measured: finite coordinates, face indices in range.

Nothing is repaired silently: a vertex with a NaN or infinite coordinate, or a
face that points outside the vertex array (a negative index would wrap around
to the end of it), is an error that says how many and which one comes first.
"""

from __future__ import annotations

import numpy as np


def plural(count: int, singular: str, plural_form: str | None = None) -> str:
    """``"1 vertex"``, ``"2 vertices"``: a count and its noun."""
    if count == 1:
        return f"1 {singular}"
    return f"{count} {plural_form or singular + 's'}"


def _numbers(values) -> str:
    return ", ".join(f"{v:g}" if isinstance(v, float) else str(v) for v in values.tolist())


#: The largest coordinate measured: the metrics form fourth powers of lengths (squared
#: areas), and above about 1e77 these overflow double precision (1.8e308) to infinity.
#: Every metric gives the same result from 1e-70 to 1e70 times a mesh's size as at 1.
MAX_COORDINATE = 1e70

#: The smallest mesh measured (the largest side of its bounding box): below about 1e-77
#: the fourth powers of its lengths underflow double precision (2.2e-308) to zero.
MIN_EXTENT = 1e-70


def check_finite(vertices: np.ndarray, *, where: str = "") -> None:
    """Raise if any vertex has a NaN or infinite coordinate, or the mesh is out of range.

    Out of range: a coordinate beyond :data:`MAX_COORDINATE` (its powers
    overflow), or a mesh smaller than :data:`MIN_EXTENT` but not a point
    (its powers underflow).  Such meshes were measured as "degenerate", or
    gave NaN; the message now names the overflow and the fix (rescale).

    Parameters
    ----------
    vertices : (n, 3) float
    where : str
        Put before the message (for example ``"'scan.ply': "``).

    Raises
    ------
    ValueError
        Naming how many vertices are non-finite (or too large) and the first
        (counting from 0), or the mesh's size.
    """
    if len(vertices) == 0:
        return
    low, high = np.min(vertices), np.max(vertices)
    if np.isfinite(low) and np.isfinite(high):  # (NaN if any value is, infinite if any is)
        _check_range(vertices, low, high, where)
        return
    finite = np.isfinite(vertices).all(axis=1)
    bad = np.flatnonzero(~finite)
    verb = "has" if len(bad) == 1 else "have"
    raise ValueError(
        f"{where}{plural(len(bad), 'vertex', 'vertices')} {verb} non-finite (NaN or infinite) "
        f"coordinates, the first is vertex {bad[0]} (counting from 0): "
        f"({_numbers(vertices[bad[0]])})"
    )


def _check_range(vertices: np.ndarray, low: float, high: float, where: str) -> None:
    """Raise if a (finite) coordinate is too large, or the mesh too small, for double precision."""
    if max(-low, high) > MAX_COORDINATE:
        large = (np.abs(vertices) > MAX_COORDINATE).any(axis=1)
        bad = np.flatnonzero(large)
        verb = "has" if len(bad) == 1 else "have"
        raise ValueError(
            f"{where}coordinates too large: {plural(len(bad), 'vertex', 'vertices')} {verb} a "
            f"coordinate beyond {MAX_COORDINATE:g}, the first is vertex {bad[0]} (counting from "
            f"0): ({_numbers(vertices[bad[0]])}); squaring its lengths overflows double "
            "precision: rescale the mesh (its units)"
        )
    extent = float(np.max(np.max(vertices, axis=0) - np.min(vertices, axis=0)))
    if 0 < extent < MIN_EXTENT:
        raise ValueError(
            f"{where}coordinates too small: the mesh spans {extent:g} units (below "
            f"{MIN_EXTENT:g}); squaring its lengths underflows double precision: rescale "
            "the mesh (its units)"
        )


def check_indices(faces: np.ndarray, n_vertices: int, *, where: str = "") -> None:
    """Raise if any face index is negative or not below `n_vertices`.

    Parameters
    ----------
    faces : (m, k) int
    n_vertices : int
    where : str
        Put before the message.

    Raises
    ------
    ValueError
        Naming how many faces have an index outside ``[0, n_vertices - 1]`` and
        the first such face with its indices.
    """
    if len(faces) == 0 or (np.min(faces) >= 0 and np.max(faces) < n_vertices):
        return
    outside = (faces < 0) | (faces >= n_vertices)
    bad = np.flatnonzero(outside.any(axis=1))
    raise ValueError(index_message(len(bad), int(bad[0]), faces[bad[0]], n_vertices, where=where))


def index_message(count: int, first: int, indices, n_vertices: int, *, where: str = "") -> str:
    """The message for `count` faces with indices outside the vertices, `first` the first."""
    verb = "has" if count == 1 else "have"
    return (
        f"{where}{plural(count, 'face')} {verb} vertex indices outside [0, {n_vertices - 1}], "
        f"the first is face {first} ({_numbers(np.asarray(indices))})"
    )

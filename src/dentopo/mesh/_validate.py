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


def check_finite(vertices: np.ndarray, *, where: str = "") -> None:
    """Raise if any vertex has a NaN or infinite coordinate.

    Parameters
    ----------
    vertices : (n, 3) float
    where : str
        Put before the message (for example ``"'scan.ply': "``).

    Raises
    ------
    ValueError
        Naming how many vertices are non-finite and the first (counting from 0).
    """
    if len(vertices) == 0 or (np.isfinite(np.min(vertices)) and np.isfinite(np.max(vertices))):
        return  # (min and max are NaN if any value is, infinite if any value is)
    finite = np.isfinite(vertices).all(axis=1)
    bad = np.flatnonzero(~finite)
    verb = "has" if len(bad) == 1 else "have"
    raise ValueError(
        f"{where}{plural(len(bad), 'vertex', 'vertices')} {verb} non-finite (NaN or infinite) "
        f"coordinates, the first is vertex {bad[0]} (counting from 0): "
        f"({_numbers(vertices[bad[0]])})"
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

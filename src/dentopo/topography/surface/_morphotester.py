"""How MorphoTester 1.1.1 reads a crown: its normals, boundary faces, areas and fairing.

MorphoTester (Winchester 2016; GPL-2) is reproduced here from a description of its
method (``docs/MORPHOTESTER.md`` of the shared data), never from its code.  Its DNE, RFI
and OPCR (:mod:`..dne._morphotester`, :mod:`..relief._morphotester`,
:mod:`..opc._morphotester`) share what is here:

- the mesh exactly as given: no vertex merged, no face dropped (MorphoTester does no
  cleaning of any kind);
- face normals: ``(p1 - p0) x (p2 - p0)`` scaled to unit length, a vector shorter than
  machine epsilon left as it is (a degenerate face keeps ``(0, 0, 0)``);
- vertex normals: the *unweighted* sum of the unit normals of the faces using the vertex,
  normalised by the same epsilon rule (an unreferenced vertex: ``(0, 0, 0)``);
- the orientation vote: with ``m_i`` the mean of vertex i's own three coordinates and
  ``s_k = sum_i (x_ik - m_i) n_ik``, if fewer of ``s_x, s_y, s_z`` are positive than
  negative, every vertex and face normal is negated;
- boundary faces by molaR's "leg" rule: a face owning an edge that exactly one face contains;
- face areas: half the length of ``(p1 - p0) x (p2 - p0)``;
- implicit fairing (``(I - step L) X_new = X`` with the unnormalised cotangent operator),
  which :mod:`dentopo.prepare` reuses, and its positive-definiteness rule: MorphoTester
  factorises ``I - step L`` by Cholesky and stops with a "Cholesky error" when it is not
  positive definite; so does this module (a ``ValueError`` naming the cause).
"""

from __future__ import annotations

import math
from decimal import ROUND_HALF_UP, Decimal

import numpy as np
from scipy import sparse
from scipy.sparse.linalg import splu

#: Machine epsilon: vectors shorter than this are not normalised (MorphoTester's rule).
EPSILON = float(np.finfo(np.float64).eps)


def py2_round(value: float, digits: int) -> float:
    """``round(value, digits)`` as Python 2 rounds: to the nearest, ties away from zero.

    The tie is decided on the exact binary value (``Decimal(value)``), as Python 2.7's
    correctly rounded ``round`` does; Python 3's ``round`` takes ties to even.
    Non-finite values are returned as they are.
    """
    value = float(value)
    if not math.isfinite(value):
        return value
    exact = Decimal(value).quantize(Decimal(1).scaleb(-digits), rounding=ROUND_HALF_UP)
    return float(exact)


def check_mesh(vertices: np.ndarray, faces: np.ndarray, what: str) -> None:
    """Raise ``ValueError`` naming `what` if the mesh has no face (the rest is ``as_arrays``')."""
    if len(faces) == 0:
        raise ValueError(f"{what}: the mesh has no faces")


def _normalise(vectors: np.ndarray) -> np.ndarray:
    """Unit vectors; a vector shorter than machine epsilon is left as it is (in place)."""
    length = np.sqrt(np.einsum("ij,ij->i", vectors, vectors))
    long = length >= EPSILON
    vectors[long] /= length[long, None]
    return vectors


def face_cross(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """``(p1 - p0) x (p2 - p0)`` of each face, in the file's vertex order."""
    p0 = vertices[faces[:, 0]]
    return np.cross(vertices[faces[:, 1]] - p0, vertices[faces[:, 2]] - p0)


def face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Half the length of each face's cross product (MorphoTester's surface area, per face)."""
    cross = face_cross(vertices, faces)
    return 0.5 * np.sqrt(np.einsum("ij,ij->i", cross, cross))


def normals(
    vertices: np.ndarray, faces: np.ndarray, *, vote: bool = True
) -> tuple[np.ndarray, np.ndarray, bool]:
    """MorphoTester's unit face normals, vertex normals and whether the vote negated them.

    Returns ``(face_normals (m, 3), vertex_normals (n, 3), negated)``; see the module
    docstring for the rules.  ``vote=False`` skips the orientation vote (DNE does not
    depend on it: negating every normal leaves each face's energy exactly as it is).
    """
    face_n = _normalise(face_cross(vertices, faces))
    vertex_n = np.zeros_like(vertices)
    for corner in range(3):
        np.add.at(vertex_n, faces[:, corner], face_n)
    _normalise(vertex_n)
    negated = False
    if vote:
        centred = vertices - vertices.mean(axis=1, keepdims=True)
        s = np.einsum("ik,ik->k", centred, vertex_n)
        if np.count_nonzero(s > 0) < np.count_nonzero(s < 0):
            negated = True
            face_n = -face_n
            vertex_n = -vertex_n
    return face_n, vertex_n, negated


def _edge_keys(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each face's distinct edges as ``(face, key)`` pairs, ``key = lo * n + hi`` (lo < hi).

    A face listing a vertex twice has fewer distinct edges; no pair is listed twice.
    """
    m = len(faces)
    n = int(faces.max()) + 1
    lo = np.concatenate([np.minimum(faces[:, k], faces[:, (k + 1) % 3]) for k in range(3)])
    hi = np.concatenate([np.maximum(faces[:, k], faces[:, (k + 1) % 3]) for k in range(3)])
    owner = np.tile(np.arange(m), 3)
    keep = lo != hi
    pairs = np.unique(np.stack([owner[keep], lo[keep] * n + hi[keep]], axis=1), axis=0)
    return pairs[:, 0], pairs[:, 1]


def boundary_faces(faces: np.ndarray) -> np.ndarray:
    """(m,) bool: faces owning a boundary edge (one that exactly one face contains).

    molaR's "leg" rule: a face touching the boundary only at a vertex is not a
    boundary face.  Edges are vertex-index pairs: faces meeting at equal positions
    but different indices do not share an edge (no cleaning).  A face listing a
    vertex twice, ``(a, a, b)``, has the edge ``(a, b)``, and the edge ``(a, a)`` that
    every face using ``a`` contains: it is a boundary edge if ``a`` is used by that face
    only.
    """
    m = len(faces)
    owner, key = _edge_keys(faces)
    _, inverse, counts = np.unique(key, return_inverse=True, return_counts=True)
    boundary = np.zeros(m, dtype=bool)
    boundary[owner[counts[inverse] == 1]] = True
    repeated = (
        (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 0] == faces[:, 2])
    )
    if repeated.any():
        users = np.unique(np.stack([np.repeat(np.arange(m), 3), faces.ravel()], axis=1), axis=0)
        uses = np.bincount(users[:, 1], minlength=int(faces.max()) + 1)
        for f in np.flatnonzero(repeated):
            a, b, c = faces[f]
            doubled = a if a in (b, c) else b
            if uses[doubled] == 1:
                boundary[f] = True
    return boundary


def face_adjacency(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pairs of faces sharing an edge (two vertex indices): ``(first, second)`` arrays.

    Where more than two faces share an edge, every two of them are adjacent.  Each
    pair is listed once (first < second).
    """
    owner, key = _edge_keys(faces)
    order = np.lexsort((owner, key))
    owner, key = owner[order], key[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    sizes = np.diff(np.r_[starts, len(key)])
    first, second = [], []
    for gap in range(1, int(sizes.max()) if len(sizes) else 1):
        index = np.flatnonzero(np.r_[key[gap:] == key[:-gap], np.zeros(gap, dtype=bool)])
        first.append(owner[index])
        second.append(owner[index + gap])
    if not first:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    a, b = np.concatenate(first), np.concatenate(second)
    pairs = np.unique(np.stack([np.minimum(a, b), np.maximum(a, b)], axis=1), axis=0)
    return pairs[:, 0], pairs[:, 1]


# --- implicit fairing -----------------------------------------------------------------------

#: How a cotangent is computed: ``"stable"`` (``dot / |cross|`` of the two edges at the
#: corner; a degenerate corner counts 0) or ``"arccos"`` (MorphoTester's: the angle as the
#: arccos of the normalised dot product, clamped to [-1, 1], each edge length floored at
#: machine epsilon, then ``1 / tan``; an angle of exactly 0 counts 0).
COTANGENTS = ("stable", "arccos")


def _cotangents(u: np.ndarray, v: np.ndarray, how: str) -> np.ndarray:
    """The cotangent of the angle between edges `u` and `v` (rows), computed as `how` says."""
    if how == "stable":
        cross = np.linalg.norm(np.cross(u, v), axis=1)
        dot = np.einsum("ij,ij->i", u, v)
        return np.divide(dot, cross, out=np.zeros_like(dot), where=cross > 0)
    lu = np.maximum(np.linalg.norm(u, axis=1), EPSILON)
    lv = np.maximum(np.linalg.norm(v, axis=1), EPSILON)
    angle = np.arccos(np.clip(np.einsum("ij,ij->i", u, v) / (lu * lv), -1.0, 1.0))
    cot = np.zeros_like(angle)
    np.divide(1.0, np.tan(angle), out=cot, where=angle != 0)
    return cot


def _face_cotangents(vertices: np.ndarray, faces: np.ndarray, how: str) -> np.ndarray:
    """(m, 3): the cotangent of each face's angle at each of its corners."""
    out = np.empty(faces.shape)
    for corner in range(3):
        k = faces[:, corner]
        u = vertices[faces[:, (corner + 1) % 3]] - vertices[k]
        v = vertices[faces[:, (corner + 2) % 3]] - vertices[k]
        out[:, corner] = _cotangents(u, v, how)
    return out


def cotangent_operator(
    vertices: np.ndarray, faces: np.ndarray, *, cotangents: str = "stable"
) -> sparse.csr_matrix:
    """MorphoTester's curvature-flow operator L: cotangent weights, diagonal minus their sum.

    ``L[i, j]`` (i != j) is the sum of the cotangents of the angles facing edge
    ``ij`` (one per face using the edge), ``L[i, i] = -sum_j L[i, j]``; no one-half
    factor, not divided by areas.  Symmetric, shape (n, n).  `cotangents`: see
    :data:`COTANGENTS` (``"arccos"`` is MorphoTester's own arithmetic).

    With cotangents computed consistently (``"stable"``), ``-L`` is twice the P1 finite
    element stiffness matrix, a sum of one positive semi-definite matrix per face, obtuse
    faces included: ``I - step L`` is then positive definite for any step > 0, up to
    rounding.  The arccos form loses that on nearly degenerate faces (an angle within
    about 1e-8 rad of 0 or 180 degrees gives a cotangent off by orders of magnitude).
    """
    n = len(vertices)
    cot = _face_cotangents(vertices, faces, cotangents)
    rows, cols, weights = [], [], []
    for corner in range(3):
        i = faces[:, (corner + 1) % 3]
        j = faces[:, (corner + 2) % 3]  # the angle at `corner` faces edge ij
        rows += [i, j]
        cols += [j, i]
        weights += [cot[:, corner], cot[:, corner]]
    w = sparse.coo_matrix(
        (np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n)
    ).tocsr()
    w.sum_duplicates()
    return (w - sparse.diags(np.asarray(w.sum(axis=1)).ravel())).tocsr()


class NotPositiveDefiniteError(ValueError):
    """``I - step * L`` is not positive definite: where MorphoTester stops with a Cholesky error.

    Attributes
    ----------
    negative_edges : int
        Edges whose cotangent weight ``L[i, j]`` is negative.
    worst_face : int
        The face with the most negative cotangent (-1 if none is negative).
    """

    def __init__(self, message: str, negative_edges: int, worst_face: int):
        super().__init__(message)
        self.negative_edges = negative_edges
        self.worst_face = worst_face


def positive_definite_solver(system: sparse.spmatrix):
    """The solve of a symmetric `system` if it is positive definite, else None.

    Decided as a Cholesky factorisation decides it, on the sparse matrix: an LU
    factorisation in symmetric mode with every pivot kept on the diagonal (SuperLU with
    ``diag_pivot_thresh=0`` and one fill-reducing ordering for rows and columns) is
    ``P A P^T = L D L^T`` with ``D`` the pivots; by Sylvester's law of inertia ``A`` is
    positive definite exactly when every pivot is positive.  A zero diagonal pivot makes
    SuperLU take another row (or fail): not positive definite either.  About 10 ms for a
    5,000-vertex crown (a dense Cholesky takes seconds and 8 n**2 bytes).
    """
    try:
        lu = splu(
            sparse.csc_matrix(system),
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError:  # exactly singular
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    pivots = lu.U.diagonal()
    if not (np.all(np.isfinite(pivots)) and np.all(pivots > 0)):
        return None
    return lu.solve


def _not_positive_definite(vertices, faces, operator, step, cotangents, *, pinned: bool):
    weights = sparse.triu(operator, k=1).tocoo()
    negative = int(np.count_nonzero(weights.data < 0))
    cot = _face_cotangents(vertices, faces, cotangents)
    worst = int(np.argmin(cot.min(axis=1))) if len(faces) else -1
    if worst >= 0 and cot[worst].min() >= 0:
        worst = -1
    where = ""
    if worst >= 0:
        angles = []
        for corner in range(3):
            k = faces[worst, corner]
            u = vertices[faces[worst, (corner + 1) % 3]] - vertices[k]
            v = vertices[faces[worst, (corner + 2) % 3]] - vertices[k]
            angles.append(np.degrees(np.arctan2(np.linalg.norm(np.cross(u, v)), u @ v)))
        where = (
            f"; the most negative cotangent, {cot[worst].min():.3g}, is face {worst}'s, whose "
            f"angles are {', '.join(f'{a:.6g}' for a in angles)} degrees"
        )
    how = (
        "as MorphoTester computes them, from the arccos of each angle, which is inaccurate "
        "on nearly degenerate faces"
        if cotangents == "arccos"
        else "on nearly degenerate faces, where rounding dominates"
    )
    system = "the free vertices' part of I - step*L" if pinned else "I - step*L"
    return NotPositiveDefiniteError(
        f"implicit fairing: {system} is not positive definite (step {step:g}): "
        f"{negative} edges have a negative cotangent weight (obtuse angles facing them), "
        f"and some are too negative to be consistent ({how}){where}; MorphoTester stops "
        "here with a Cholesky error and reports no DNE; measure the crown unsmoothed, or "
        "remove its degenerate faces (remesh or decimate) before smoothing",
        negative,
        worst,
    )


def implicit_fairing(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    iterations: int,
    step: float,
    pinned: np.ndarray | None = None,
    cotangents: str = "stable",
) -> np.ndarray:
    """`iterations` solves of ``(I - step * L) X_new = X`` (L: :func:`cotangent_operator`).

    `pinned` vertices keep their place (their rows are identity rows; the system solved
    for the others is the free vertices' principal submatrix).  ``L`` is built once from
    the input and factorised once.  A new array.

    Raises
    ------
    NotPositiveDefiniteError
        (a ``ValueError``) if the system solved is not positive definite: MorphoTester
        factorises it by Cholesky and stops there with a Cholesky error; so does this.
    ValueError
        If the solve gives non-finite coordinates.
    """
    x = np.array(vertices, dtype=np.float64, copy=True)
    if iterations == 0 or len(x) == 0:
        return x
    operator = cotangent_operator(x, faces, cotangents=cotangents)
    free = np.ones(len(x), dtype=bool)
    if pinned is not None and len(pinned):
        free[pinned] = False
    index = np.flatnonzero(free)
    if len(index) == 0:
        return x
    system = (sparse.identity(len(x), format="csr") - step * operator).tocsr()
    rows = system[index]
    solve = positive_definite_solver(rows[:, index])
    if solve is None:
        raise _not_positive_definite(x, faces, operator, step, cotangents, pinned=not free.all())
    coupling = None if free.all() else rows[:, ~free]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        for _ in range(iterations):
            rhs = x[index]
            if coupling is not None:
                rhs = rhs - coupling @ x[~free]
            x[index] = solve(rhs)
    if not np.isfinite(x).all():
        raise ValueError(
            f"implicit fairing gave non-finite coordinates with step {step:g} over "
            f"{iterations} iterations (a degenerate mesh, or too large a step?)"
        )
    return x

"""Mesh input: reading, validation, cleaning and normalisation.

Everything that turns what a caller hands us (a ``trimesh.Trimesh``, a path, or
``(vertices, faces)`` arrays) into the cleaned, unit-area working copy that the
curvature computation uses.  The caller's object is never modified: all work is
done on copies.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ._faces import first_faces, vertex_areas, vertex_normals
from ._lazy import LazyMesh, MeshLater
from ._read import as_arrays
from ._tolerance import length_scale, nondegenerate_faces
from ._topology import boundary_edges, edge_uses, orient_consistently, smallest_connected

if TYPE_CHECKING:
    import trimesh


@dataclass(frozen=True)
class PreparedMesh:
    """A cleaned mesh and the derived quantities every later stage needs.

    Attributes
    ----------
    points : (n, 3) float
        Vertices translated to their mean and scaled to unit total area.
    vertex_area_raw : (n,) float
        One third of the area of the faces using each vertex, in mesh units.
    vertex_area : (n,) float
        The same after scaling, so that it sums to one.
    normals : (n, 3) float
        Unit vertex normals: the normalised sum of incident unit face normals,
        after orienting the faces consistently (a no-op for the usual,
        consistently oriented mesh; it rescues meshes with flipped faces).
    scale : float
        The factor that maps mesh units to the unit-area scale.
    mesh : trimesh.Trimesh
        The cleaned mesh, in the caller's units (a private copy), what was
        changed in ``mesh.metadata["cleaning"]``; built when it is first read
        (:mod:`dentopo.mesh._lazy`: trimesh is not imported before).
    """

    points: np.ndarray
    vertex_area_raw: np.ndarray
    vertex_area: np.ndarray
    normals: np.ndarray
    scale: float
    mesh: trimesh.Trimesh = field(default=LazyMesh())


def _may_have_small_holes(faces: np.ndarray, n_vertices: int) -> bool:
    """False when trimesh's ``fill_holes`` provably adds nothing (it is slow on big meshes).

    ``fill_holes`` caps the 3- and 4-edge cycles of a cycle basis of the boundary
    edges.  If every boundary component is one simple loop (every boundary
    vertex on exactly two boundary edges) of at least 5 edges, the basis holds
    only those loops and nothing is added.
    """
    edges = boundary_edges(faces, n_vertices)
    if len(edges) == 0:
        return False  # watertight
    if len(edges) < 3:
        return True  # trimesh's own special case: let it decide
    degree = np.bincount(edges.ravel(), minlength=n_vertices)
    if np.any(degree[degree > 0] != 2):
        return True
    label = smallest_connected(edges, n_vertices)  # no scipy: see smallest_connected
    loop_size = np.bincount(label[edges[:, 0]])
    return bool(np.any((loop_size > 0) & (loop_size < 5)))


@dataclass(frozen=True)
class Cleaning:
    """What cleaning changed in a mesh, and what it left that is not a surface.

    Kept with the cleaned mesh as ``mesh.metadata["cleaning"]`` (so ariaDNE's
    result carries it), and given by :func:`clean_listed`.

    Attributes
    ----------
    holes_filled, faces_added : int
        Holes of three or four edges filled (scan defects), and the faces that
        filled them.
    bases_kept : tuple of int
        The edge counts of the small boundary loops left open because each is
        the longest loop of its piece of surface: its open base (a crown's
        cervix), open whatever its size (the published cleaning fills it).
    degenerate_faces, zero_area_faces : int
        Faces of no height dropped, and how many of them have no area at all
        (dropped by every metric's cleaning; the others are slivers).
    duplicate_faces, unused_vertices : int
        Faces repeating an earlier face's three vertices dropped, and vertices
        no face uses dropped.
    nonmanifold_edges : int
        Edges of the cleaned mesh shared by three or more faces (a fin on the
        surface, or pieces joined along an edge).
    first_nonmanifold : ((3,) tuple, (3,) tuple) or None
        The ends of the first such edge, in mesh units.
    """

    holes_filled: int = 0
    faces_added: int = 0
    bases_kept: tuple[int, ...] = ()
    degenerate_faces: int = 0
    zero_area_faces: int = 0
    duplicate_faces: int = 0
    unused_vertices: int = 0
    nonmanifold_edges: int = 0
    first_nonmanifold: tuple[tuple[float, ...], tuple[float, ...]] | None = None

    def notes(self, *, duplicates: bool = True) -> list[str]:
        """Sentences saying what cleaning changed (`duplicates`: the repeated faces too)."""
        notes = []
        changed = []
        if self.holes_filled:
            changed.append(
                f"filled {_count(self.holes_filled, 'hole')} of three or four edges "
                f"({_count(self.faces_added, 'face')} added)"
            )
        slivers = self.degenerate_faces - self.zero_area_faces  # faces of no area change nothing
        if slivers:
            changed.append(f"dropped {_count(slivers, 'sliver face')} (of no height)")
        if duplicates and self.duplicate_faces:
            changed.append(
                f"dropped {_count(self.duplicate_faces, 'face')} repeating an earlier face"
            )
        if changed:
            notes.append(
                f"cleaning {' and '.join(changed)}: every metric of the row measures the "
                "cleaned surface"
            )
        if self.bases_kept:
            edges = " and ".join(str(k) for k in self.bases_kept)
            notes.append(
                f"an open boundary of {edges} edges was left open, as the longest of its piece "
                "of surface (its base), though the published cleaning fills holes of three or "
                "four edges"
            )
        if self.nonmanifold_edges:
            a, b = (", ".join(f"{x:.6g}" for x in end) for end in self.first_nonmanifold)
            notes.append(
                f"{_count(self.nonmanifold_edges, 'edge')} shared by three or more faces "
                f"(non-manifold: a fin, or pieces joined along an edge), the first from ({a}) "
                f"to ({b}): every metric measures those faces as given, but they are not a "
                "surface"
            )
        return notes


def _count(n: int, what: str) -> str:
    return f"{n} {what}" if n == 1 else f"{n} {what}s"


@dataclass(frozen=True)
class Listed:
    """A mesh cleaned as :func:`clean` cleans it, faces listed again kept (:func:`clean_listed`).

    Attributes
    ----------
    vertices : (n, 3) float64
        The vertices (unused ones included).
    faces : (m, 3) int64
        The faces :func:`clean` keeps and, in their order, those repeating them.
    cleaning : Cleaning
        What :func:`clean` changes.
    """

    vertices: np.ndarray
    faces: np.ndarray
    cleaning: Cleaning


def clean(vertices, faces) -> trimesh.Trimesh:
    """Clean a mesh as the published computation does, on a private copy.

    Fills trivially small holes (trimesh ``fill_holes``: three- and four-edge
    holes) but never a piece of surface's open base (its longest boundary loop,
    whatever its size: an open surface stays open), drops degenerate faces (not
    higher than ``DEGENERATE_HEIGHT`` median edge lengths: relative to the
    mesh, so the units do not matter), drops duplicate faces and unreferenced
    vertices.  The input is validated first (see :func:`as_arrays`):
    non-finite coordinates and indices outside the vertices are errors, never
    dropped.  What was changed is ``mesh.metadata["cleaning"]``, a
    :class:`Cleaning`.

    Raises
    ------
    ValueError
        If the input is invalid, or nothing usable is left.
    """
    return _clean(*as_arrays((vertices, faces)))


def clean_listed(mesh) -> Listed:
    """`mesh` cleaned as :func:`clean` cleans it, but with the faces listed again kept.

    :func:`dentopo.topography.prepare_surface` then drops the repeats (or
    keeps them, if asked): with ``duplicates="drop"`` the surface it measures
    is the very triangles :func:`clean` keeps, and so ariaDNE measures.
    """
    vertices, faces = as_arrays(mesh)
    vertices, faces, keep, filled = _fill_and_keep(vertices, faces)
    first = first_faces(faces, keep, len(vertices))
    return Listed(vertices, faces[keep], _cleaning(vertices, faces, keep, first, filled))


def _clean(vertices: np.ndarray, faces: np.ndarray) -> trimesh.Trimesh:
    """:func:`clean` for arrays that :func:`as_arrays` has validated."""
    import trimesh  # only here: ariaDNE's run builds no Trimesh (see PreparedMesh)

    vertices, faces, cleaning = _clean_arrays(vertices, faces)
    cleaned = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    cleaned.metadata["cleaning"] = cleaning
    return cleaned


def _clean_arrays(vertices: np.ndarray, faces: np.ndarray):
    """The cleaned ``(vertices, faces)`` of validated arrays, and their :class:`Cleaning`.

    trimesh's steps (``fill_holes``, bases excepted, ``update_faces(nondegenerate_faces)``,
    ``update_faces(unique_faces())``, ``remove_unreferenced_vertices``) with
    the same result, in linear compiled passes (see ``_faces``).
    """
    vertices, faces, keep, filled = _fill_and_keep(vertices, faces)
    first = first_faces(faces, keep, len(vertices))
    cleaning = _cleaning(vertices, faces, keep, first, filled)
    faces = faces[first]
    vertices, faces = _referenced(vertices, faces)
    if len(faces) == 0:
        raise ValueError("cleaning left the mesh empty: every face is degenerate")
    if len(vertices) < 4:
        raise ValueError(f"cleaning left {len(vertices)} vertices; at least 4 are needed")
    return vertices, faces, cleaning


def _fill_and_keep(vertices: np.ndarray, faces: np.ndarray):
    """Small holes filled (bases excepted), and which faces are not degenerate."""
    scale = length_scale(vertices, faces)
    filled = (0, 0, ())
    if _may_have_small_holes(faces, len(vertices)):
        vertices, faces, filled = _fill_small_holes(vertices, faces)
    keep = nondegenerate_faces(vertices, faces, scale=scale)
    return vertices, faces, keep, filled


def _cleaning(vertices, faces, keep, first, filled) -> Cleaning:
    """The :class:`Cleaning` of `faces` of which ``first`` are kept (``keep``: not degenerate)."""
    holes, added, bases = filled
    kept = faces[first]
    used = np.zeros(len(vertices), dtype=bool)
    used[kept] = True
    count, first_edge = 0, None
    if len(kept):
        uses, _ = edge_uses(kept, len(vertices))
        crowded = np.flatnonzero(uses >= 3)
        if len(crowded):
            m = len(kept)
            corner, face = crowded // m, crowded % m
            ends = np.column_stack([kept[face, corner], kept[face, (corner + 1) % 3]])
            ends = np.sort(ends, axis=1)
            count = len(np.unique(ends, axis=0))
            a, b = ends[0]
            first_edge = (tuple(map(float, vertices[a])), tuple(map(float, vertices[b])))
    dropped = faces[~keep]
    tri = vertices[dropped]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return Cleaning(
        holes_filled=holes,
        faces_added=added,
        bases_kept=bases,
        degenerate_faces=len(dropped),
        zero_area_faces=int(np.count_nonzero(~cross.any(axis=1))),
        duplicate_faces=int(np.count_nonzero(keep) - np.count_nonzero(first)),
        unused_vertices=int(np.count_nonzero(~used)),
        nonmanifold_edges=count,
        first_nonmanifold=first_edge,
    )


def _fill_small_holes(vertices: np.ndarray, faces: np.ndarray):
    """trimesh's ``fill_holes``, but never filling a piece of surface's open base.

    The base of each connected piece is its longest boundary loop (every loop
    of that length, if several tie); a hole of three or four edges beside a
    longer base is a defect, and is filled.

    Returns
    -------
    vertices, faces, (holes filled, faces added, edge counts of the small bases kept open)
    """
    import trimesh  # only for a mesh that may have small holes (and its networkx)

    filled = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    filled.fill_holes()
    new_faces = np.asarray(filled.faces, dtype=np.int64)
    added = new_faces[len(faces) :]
    if len(added) == 0 or not np.array_equal(new_faces[: len(faces)], faces):
        return vertices, new_faces, (0, len(added), ())
    loop_of, is_base, length = _boundary_loops(faces, len(vertices))
    label = loop_of[added]
    one_loop = (label[:, 0] >= 0) & (label == label[:, :1]).all(axis=1)
    left_open = one_loop & is_base[np.where(one_loop, label[:, 0], 0)]
    holes = len(np.unique(label[~left_open, 0]))
    bases = tuple(int(length[k]) for k in np.unique(label[left_open, 0]))
    faces = np.vstack([faces, added[~left_open]])
    return vertices, faces, (holes, int(np.count_nonzero(~left_open)), bases)


def _boundary_loops(faces: np.ndarray, n_vertices: int):
    """Each vertex's boundary loop (-1: none), whether each loop is a base, and its length.

    A loop is a connected set of boundary edges and its length its number of
    edges; a base is a loop at least as long as every other loop of its
    connected piece of surface.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    def components(edges: np.ndarray) -> np.ndarray:
        ones = np.ones(len(edges))
        graph = coo_matrix((ones, (edges[:, 0], edges[:, 1])), shape=(n_vertices, n_vertices))
        return connected_components(graph, directed=False)[1]

    edges = boundary_edges(faces, n_vertices)
    loop_of = np.full(n_vertices, -1, dtype=np.int64)
    on_loop = np.zeros(n_vertices, dtype=bool)
    on_loop[edges.ravel()] = True
    loop_of[on_loop] = np.unique(components(edges)[on_loop], return_inverse=True)[1].ravel()
    n_loops = int(loop_of.max()) + 1
    length = np.bincount(loop_of[edges[:, 0]], minlength=n_loops)
    piece = components(np.vstack([faces[:, [0, 1]], faces[:, [1, 2]]]))
    piece_of_loop = np.zeros(n_loops, dtype=np.int64)
    piece_of_loop[loop_of[edges[:, 0]]] = piece[edges[:, 0]]
    longest = np.zeros(int(piece.max()) + 1, dtype=np.int64)
    np.maximum.at(longest, piece_of_loop, length)
    return loop_of, length >= longest[piece_of_loop], length


def _referenced(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The vertices some face uses, in order, and the faces renumbered (trimesh's way)."""
    referenced = np.zeros(len(vertices), dtype=bool)
    referenced[faces] = True
    if referenced.all():
        return vertices, faces
    inverse = np.zeros(len(vertices), dtype=np.int64)
    inverse[referenced] = np.arange(np.count_nonzero(referenced))
    return vertices[referenced], inverse[faces]


def prepare(mesh) -> PreparedMesh:
    """Validate, clean and normalise any accepted mesh input (see `as_arrays`)."""
    vertices, faces = as_arrays(mesh)
    vertices, faces, cleaning = _clean_arrays(vertices, faces)
    # the arrays as trimesh.Trimesh(vertices, faces) holds them: float64 and int64, C order
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    # vertex normals need neighbouring faces to agree; a no-op for consistent meshes
    f = orient_consistently(faces, len(v))
    area_raw = vertex_areas(v, f)
    total = float(area_raw.sum())
    if not total > 0:
        raise ValueError("the mesh has zero surface area")
    scale = 1.0 / np.sqrt(total)
    points = (v - v.mean(axis=0)) * scale
    return PreparedMesh(
        mesh=MeshLater(v, faces, {"cleaning": cleaning}),
        points=points,
        vertex_area_raw=area_raw,
        vertex_area=area_raw / total,
        normals=vertex_normals(v, f),
        scale=float(scale),
    )

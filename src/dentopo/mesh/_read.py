"""Reading a mesh file, and turning any accepted mesh input into validated arrays."""

from __future__ import annotations

import inspect
import os
import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ._ply import check_regular, open_regular, read_ply
from ._tolerance import merge_vertices
from ._validate import check_finite, check_indices, plural

if TYPE_CHECKING:  # imported where a Trimesh is built or a non-PLY file read (about 0.5 s)
    import trimesh

#: ``geometry=ALL``: every mesh of a file, joined into one surface.
ALL = "all"

#: Geometries listed by name in an error message, at most.
_LISTED = 12


def check_geometry(geometry) -> str | None:
    """Validate the ``geometry`` option of :func:`load_mesh` (None, ``"all"`` or a name).

    Raises
    ------
    TypeError
        If it is neither None nor a string.
    ValueError
        If it is an empty (or blank) string.
    """
    if geometry is None:
        return None
    if not isinstance(geometry, str):
        raise TypeError(
            f"geometry must be a name (str), 'all' or None; got {type(geometry).__name__}"
        )
    if not geometry.strip():
        raise ValueError("geometry must be a non-empty name, or 'all'")
    return geometry


def _obj_options() -> dict:
    """How OBJ files are read: one geometry per object (``o``), whatever its materials.

    trimesh's default merges all objects without materials into one mesh (two
    specimens would be measured as one) and splits one object into several
    meshes where its material changes (one surface torn in pieces).  From trimesh
    4.10 on, ``split_objects`` and ``group_material=False`` give exactly one
    geometry per object.  Older versions lack ``split_objects``: there
    ``group_material=False`` keeps objects apart but still splits at material
    changes, so such a surface needs ``geometry="all"`` (which joins it again).
    """
    from trimesh.exchange import obj

    options = {"group_material": False}
    if "split_objects" in inspect.signature(obj.load_obj).parameters:
        options["split_objects"] = True
    return options


@dataclass(frozen=True)
class _Instance:
    """One placement of a triangle mesh in a file's scene graph."""

    node: str
    name: str  # the geometry's name
    transform: np.ndarray
    mesh: trimesh.Trimesh

    def world(self) -> trimesh.Trimesh:
        """The mesh in world coordinates: its scene-graph transform applied (to a copy)."""
        if np.array_equal(self.transform, np.eye(4)):
            return self.mesh
        return self.mesh.copy().apply_transform(self.transform)


def _checked(path: str, scene: trimesh.Scene) -> dict[str, trimesh.Trimesh]:
    """Every triangle mesh of `scene` by name: validated, coincident vertices merged.

    trimesh reads with ``process=False`` (nothing dropped): here non-finite
    coordinates and indices outside the vertices are errors, and vertices are
    merged with a tolerance relative to the mesh (see ``_tolerance``).
    """
    import trimesh

    meshes = {}
    several = sum(isinstance(g, trimesh.Trimesh) for g in scene.geometry.values()) > 1
    for name, geometry in scene.geometry.items():
        if not isinstance(geometry, trimesh.Trimesh):
            continue
        where = f"{path!r} (geometry {name!r}): " if several else f"{path!r}: "
        vertices = np.asarray(geometry.vertices, dtype=np.float64)
        faces = np.asarray(geometry.faces, dtype=np.int64).reshape(-1, 3)
        check_finite(vertices, where=where)
        check_indices(faces, len(vertices), where=where)
        vertices, faces = merge_vertices(vertices, faces)
        meshes[str(name)] = trimesh.Trimesh(
            vertices, faces, process=False, metadata=dict(geometry.metadata)
        )
    return meshes


def _instances(scene: trimesh.Scene, meshes: dict[str, trimesh.Trimesh]) -> list[_Instance]:
    """Every placement of a triangle mesh in `scene`, sorted by geometry name and node."""
    found = []
    for node in scene.graph.nodes_geometry:
        transform, name = scene.graph[node]
        mesh = meshes.get(str(name))
        if mesh is not None:
            found.append(_Instance(str(node), str(name), np.asarray(transform), mesh))
    return sorted(found, key=lambda i: (i.name, i.node))


def _selectors(instances: list[_Instance]) -> list[str]:
    """The ``geometry=`` value that selects each instance: its geometry, or its node if shared."""
    placed: dict[str, int] = {}
    for instance in instances:
        placed[instance.name] = placed.get(instance.name, 0) + 1
    return [i.name if placed[i.name] == 1 else i.node for i in instances]


def _listing(instances: list[_Instance]) -> str:
    """The instances as a message lists them: selector and face count."""
    labels = [
        f"{selector!r} ({len(i.mesh.faces)} faces)"
        if selector == i.name
        else f"node {selector!r} of {i.name!r} ({len(i.mesh.faces)} faces)"
        for selector, i in zip(_selectors(instances), instances, strict=True)
    ]
    if len(labels) > _LISTED:
        labels = [*labels[:_LISTED], f"and {len(labels) - _LISTED} more"]
    return ", ".join(labels)


def _join(instances: list[_Instance]) -> trimesh.Trimesh:
    """Every instance in world coordinates as one mesh, coincident vertices merged.

    Merging rejoins a surface that the file stores in pieces (by material, or as
    several glTF primitives); meshes that share no vertex stay apart.
    """
    import trimesh

    pieces = [i.world() for i in instances]
    joined = trimesh.util.concatenate(pieces) if len(pieces) > 1 else pieces[0]
    vertices, faces = merge_vertices(joined.vertices, joined.faces)
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)


def _choose(path: str, instances: list[_Instance], geometry: str | None) -> trimesh.Trimesh:
    """The mesh `geometry` asks for, in world coordinates (see :func:`load_mesh`)."""
    if geometry == ALL:
        return _join(instances)
    if geometry is None:
        if len(instances) == 1:
            return instances[0].world()
        example = _selectors(instances)[0]
        raise ValueError(
            f"{path!r} holds {len(instances)} meshes: {_listing(instances)}; dentopo does "
            f"not choose one for you: read one with load_mesh(path, geometry={example!r}), "
            "or join them all into one surface with geometry='all'"
        )
    chosen = [i for i in instances if i.name == geometry]
    if len(chosen) > 1:
        nodes = ", ".join(repr(i.node) for i in chosen)
        raise ValueError(
            f"{path!r}: the geometry {geometry!r} is placed {len(chosen)} times "
            f"(nodes {nodes}); choose one placement by its node name"
        )
    if not chosen:
        chosen = [i for i in instances if i.node == geometry]
    if not chosen:
        raise ValueError(
            f"{path!r} has no geometry named {geometry!r}; it holds "
            f"{len(instances)}: {_listing(instances)}"
        )
    return chosen[0].world()


def load_mesh(path: str | os.PathLike, *, geometry: str | None = None) -> trimesh.Trimesh:
    """Read a triangle mesh from a file, in world coordinates.

    Formats such as GLB/glTF, 3MF and OBJ can hold several meshes (a scene);
    a mesh is never picked from several silently.  Nothing wrong is measured
    silently either: PLY files are read by dentopo's strict reader (a file cut
    short, or whose header counts disagree with its data, is an error), and in
    every format a vertex with a NaN or infinite coordinate, or a face index
    outside the vertices, is an error naming how many and the first.

    Parameters
    ----------
    path : str or path-like
        A PLY file, or a file in any other format trimesh reads (OBJ, STL, OFF,
        GLB, ...).
    geometry : str, optional
        Which mesh of the file to read.  By default the file must hold exactly
        one (placed once); several raise a ``ValueError`` that lists their names
        and face counts.  A name selects that geometry (or, for a geometry
        placed several times, that scene-graph node); ``"all"`` joins every
        mesh into one surface, coincident vertices merged.  Each placement of a
        geometry counts as one mesh.  In an OBJ file each object (``o``) is one
        geometry, whatever its materials.

    Returns
    -------
    trimesh.Trimesh
        The mesh, with its scene-graph transform applied (world coordinates),
        coincident vertices merged and vertices in no face dropped, as
        trimesh's default loading does but with a tolerance relative to the
        mesh's size (see :func:`dentopo.mesh.merge_vertices`).  Polygons are cut
        into triangles as trimesh cuts them.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        If the file cannot be read (truncated, counts that do not match the
        data, ...), has non-finite coordinates or face indices outside the
        vertices, holds no triangle mesh, holds several and `geometry` does not
        say which, or has no geometry of that name.  The message is one line
        naming the file.

    Examples
    --------
    >>> from dentopo import ariaDNE, load_mesh
    >>> crown = load_mesh("scan.glb", geometry="crown")  # doctest: +SKIP
    >>> ariaDNE(load_mesh("scan.glb", geometry="all")).dne  # doctest: +SKIP
    """
    import trimesh

    geometry = check_geometry(geometry)
    path = _checked_path(path)
    extension = os.path.splitext(path)[1].lower()
    if extension == ".ply":
        return _choose(path, _ply_instances(path), geometry)
    if extension == ".obj":
        _check_obj_vertices(path)
    options = _obj_options() if extension == ".obj" else {}
    try:
        scene = trimesh.load(path, force="scene", process=False, **options)
    except PermissionError:
        raise
    except Exception as exc:  # trimesh raises many types for corrupt files
        raise ValueError(f"could not read mesh file {path!r}: {exc}") from exc
    instances = _instances(scene, _checked(path, scene))
    if not instances:
        kinds = sorted({type(g).__name__ for g in scene.geometry.values()})
        if not kinds:
            raise ValueError(f"{path!r} holds no triangle mesh")
        raise ValueError(f"{path!r} holds no triangle mesh, only {' and '.join(kinds)} (no faces)")
    return _choose(path, instances, geometry)


def _checked_path(path: str | os.PathLike) -> str:
    """`path` as a string if it is a non-empty regular file; else :func:`load_mesh`'s error."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"mesh file not found: {path!r}")
    if os.path.isdir(path):
        raise ValueError(f"{path!r} is a directory, not a mesh file")
    check_regular(os.stat(path), path)  # a FIFO would block, a device never end
    if os.path.getsize(path) == 0:
        raise ValueError(f"mesh file is empty: {path!r}")
    return path


def _ply_instances(path: str) -> list[_Instance]:
    """A PLY file as the one placement of one mesh, read by our strict reader and merged."""
    import trimesh

    vertices, faces = _ply_arrays(path)
    name = os.path.basename(path)
    metadata = {"file_name": name, "file_path": os.path.abspath(path)}
    mesh = trimesh.Trimesh(vertices, faces, process=False, metadata=metadata)
    return [_Instance(name, name, np.eye(4), mesh)]


def _ply_arrays(path: str) -> tuple[np.ndarray, np.ndarray]:
    """The mesh of a PLY file read by our strict reader, coincident vertices merged."""
    vertices, faces = read_ply(path)
    if len(vertices) == 0:
        raise ValueError(f"{path!r} holds no triangle mesh (no vertices)")
    if len(faces) == 0:
        raise ValueError(
            f"{path!r} holds no triangle mesh, only PointCloud "
            f"({plural(len(vertices), 'vertex', 'vertices')}, no faces)"
        )
    return merge_vertices(vertices, faces)


def _check_obj_vertices(path: str) -> None:
    """Raise if a ``v`` line of an OBJ file holds NaN or infinity.

    trimesh's OBJ reader drops vertices that no face uses before we see them, so
    the file itself is scanned (only when "nan" or "inf" appears in it at all).
    """
    with open_regular(path) as handle:
        data = handle.read()
    lowered = data.lower()
    if b"nan" not in lowered and b"inf" not in lowered:
        return
    vertex, bad = 0, []
    for number, line in enumerate(data.split(b"\n"), start=1):
        words = line.split()
        if not words or words[0] != b"v":
            continue
        vertex += 1
        try:
            finite = all(np.isfinite(float(word)) for word in words[1:4])
        except ValueError:
            continue  # trimesh reports what it cannot read
        if not finite:
            bad.append((vertex, number))
    if bad:
        verb = "has" if len(bad) == 1 else "have"
        raise ValueError(
            f"{path!r}: {plural(len(bad), 'vertex', 'vertices')} {verb} non-finite (NaN or "
            f"infinite) coordinates, the first is vertex {bad[0][0]} on line {bad[0][1]} "
            "(OBJ counts vertices from 1)"
        )


def as_arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Return validated ``(vertices, faces)`` copies from any accepted mesh input.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The mesh.

    Returns
    -------
    vertices : (n, 3) float64
    faces : (m, 3) int64

    Raises
    ------
    TypeError
        If `mesh` is of an unsupported type.
    ValueError
        If the arrays are empty, non-finite, not triangles, or index out of range.
    """
    # trimesh is imported only if it has been already: an object cannot be one of its
    # classes otherwise, and a PLY file's path is read without it (importing it takes 0.5 s)
    trimesh = sys.modules.get("trimesh")
    if isinstance(mesh, (str, os.PathLike)):
        path = _checked_path(mesh)
        if os.path.splitext(path)[1].lower() == ".ply":  # load_mesh's mesh, as arrays
            mesh = _ply_arrays(path)
        else:
            mesh = load_mesh(path)
            trimesh = sys.modules["trimesh"]
    if trimesh is not None and isinstance(mesh, trimesh.Trimesh):
        vertices, faces = mesh.vertices, mesh.faces
    elif trimesh is not None and isinstance(mesh, trimesh.PointCloud):
        raise ValueError("a point cloud has no faces: ariaDNE needs a triangle mesh")
    elif isinstance(mesh, (tuple, list)) and len(mesh) == 2:
        vertices, faces = mesh
    else:
        raise TypeError(
            "mesh must be a trimesh.Trimesh, a path to a mesh file, or a "
            f"(vertices, faces) pair; got {type(mesh).__name__}"
        )
    try:
        vertices = np.array(vertices, dtype=np.float64, copy=True)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"vertices must be numeric: {exc}") from exc
    faces_in = np.asarray(faces)
    if vertices.size == 0:
        raise ValueError("the mesh is empty: it has no vertices")
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise ValueError(f"vertices must have shape (n, 3); got {vertices.shape}")
    if len(vertices) < 4:
        raise ValueError(f"the mesh has {len(vertices)} vertices; at least 4 are needed")
    check_finite(vertices)
    if faces_in.size == 0:
        raise ValueError("the mesh has no faces (a point cloud): a triangle mesh is needed")
    if faces_in.ndim != 2 or faces_in.shape[1] != 3:
        raise ValueError(f"faces must be triangles, shape (m, 3); got {faces_in.shape}")
    if not np.issubdtype(faces_in.dtype, np.integer):
        if not np.issubdtype(faces_in.dtype, np.floating) or not np.all(
            np.isfinite(faces_in) & (faces_in == np.round(faces_in))
        ):
            raise TypeError(f"faces must hold integer vertex indices; got {faces_in.dtype}")
    faces = faces_in.astype(np.int64, copy=True)
    check_indices(faces, len(vertices))
    return vertices, faces

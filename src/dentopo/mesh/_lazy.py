"""A result's ``mesh`` built when it is first read, not when the metric returns.

ariaDNE's result and every topography result carry the cleaned mesh their
per-vertex or per-face arrays refer to, as a ``trimesh.Trimesh``.  Building one
costs more than the small metrics themselves (about 0.1 ms on a crown of 8000
faces: trimesh's caches and visuals, and two copies of the arrays), and a batch
row never reads it; importing trimesh costs more still (about 0.5 s: it imports
networkx, scipy's spatial and optimize, shapely, lxml), and the command's plain
ariaDNE run never needs it.  So a metric hands its result a :class:`MeshLater`
(the arrays, by reference, and the mesh's metadata), and the :class:`LazyMesh`
field turns it into the ``Trimesh`` the first time ``result.mesh`` is read: the
same mesh as before (a private copy of the arrays, not processed, the metadata
added), built once and then kept.  :func:`mesh_metadata` reads the metadata
without building the mesh.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import trimesh


class MeshLater:
    """A mesh to build on demand from arrays that do not change (read-only, kept by reference).

    Several results may share one (OPCR's rotations): they then share the built mesh.
    """

    __slots__ = ("_built", "faces", "metadata", "vertices")

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, metadata: dict | None = None):
        self.vertices = vertices
        self.faces = faces
        self.metadata = {} if metadata is None else metadata
        self._built = None

    def build(self) -> trimesh.Trimesh:
        """The ``trimesh.Trimesh`` (faces as stored, not processed; private copies), built once.

        Its ``metadata`` holds this one's items (the same objects).
        """
        if self._built is None:
            import trimesh  # only here: a plain run never builds the mesh

            built = trimesh.Trimesh(self.vertices.copy(), self.faces.copy(), process=False)
            built.metadata.update(self.metadata)
            self._built = built
        return self._built

    def __getstate__(self):
        return self.vertices, self.faces, self.metadata, self._built

    def __setstate__(self, state):
        self.vertices, self.faces, self.metadata, self._built = state


class LazyMesh:
    """A dataclass field (its default, as a descriptor) holding a mesh or a :class:`MeshLater`.

    Reading the field builds the mesh a :class:`MeshLater` stands for and keeps
    it in its place; a ``trimesh.Trimesh`` given is kept as it is.  Use as
    ``mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)``
    (the field must still be given: leaving it out raises ``TypeError``).
    """

    def __set_name__(self, owner, name):
        self.name = name

    def __get__(self, obj, owner=None):
        if obj is None:
            return self
        value = obj.__dict__[self.name]
        if isinstance(value, MeshLater):
            value = value.build()
            obj.__dict__[self.name] = value
        return value

    def __set__(self, obj, value):
        if value is self:
            raise TypeError(f"{type(obj).__name__}: missing the argument {self.name!r}")
        obj.__dict__[self.name] = value


def unbuilt(owner, name: str = "mesh"):
    """What `owner`'s :class:`LazyMesh` field `name` holds, not building it.

    A :class:`MeshLater` or a ``trimesh.Trimesh``: both have ``vertices``,
    ``faces`` and ``metadata``.
    """
    return vars(owner)[name]

"""A result's ``mesh`` built when it is first read (:mod:`dentopo.mesh._lazy`, ariaDNE's too)."""

from ..mesh._lazy import LazyMesh, MeshLater

__all__ = ["LazyMesh", "MeshLater"]

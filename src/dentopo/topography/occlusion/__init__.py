"""PCV (portion de ciel visible, ambient occlusion) as CloudCompare's qPCV computes it.

``_directions``: the light directions, centres of Leopardi's equal-area partition of the
sphere (qPCV's "northern hemisphere only" rule); ``_depth``: which directions light each
vertex, through an orthographic depth buffer per direction (CloudCompare's way);
``_rays``: the same counted exactly, one ray per vertex and direction; ``_pcv``: the
public :func:`dentopo.topography.pcv` and its result.

May import: :mod:`dentopo.mesh`, :mod:`dentopo.topography.surface` and the shared checks.
"""

"""How each tool reads a crown's surface, and the passes the metric families share.

``_molar``: molaR's surface preparation (its duplicate handling, face areas and scale:
:func:`prepare_surface`), which molaR's metrics and doolkit's share; ``_orientation``: which way
the crown points and the checks of the metrics that assume +z; ``_vcg``: a float32 emulation of
the VCG library's geometry, under molaR's ARC and doolkit's curvature metrics; ``_kernels``: the
compiled per-face and per-edge passes (edge groups, patch labels, energy densities);
``_morphotester``: how MorphoTester 1.1.1 reads a crown (its normals and their vote, boundary
faces, areas) and implicit fairing, which :mod:`dentopo.prepare` reuses.

May import: :mod:`dentopo.mesh`, and the shared checks of :mod:`dentopo.topography`
(``_parameters``, ``_units``, ``_metrics``); no metric family.
"""

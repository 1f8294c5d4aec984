"""Dirichlet normal energy as each peer computes it.

``_molar``: molaR 6.0's ``DNE`` (classic DNE with its convex/concave split); ``_doolkit``:
doolkit 1.42's DNE on its VCG curvature; ``_morphotester``: MorphoTester 1.1.1's DNE (its
condition-number check, outlier types and implicit fairing).  ariaDNE, the robust DNE, is
:mod:`dentopo.ariadne`.

May import: :mod:`dentopo.mesh`, :mod:`dentopo.topography.surface` and the shared checks.
"""

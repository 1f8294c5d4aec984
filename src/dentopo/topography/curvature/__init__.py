"""Curvature metrics: molaR's and doolkit's ARC (``_arc``) and doolkit's angularity
(``_angularity``), on the VCG geometry of :mod:`dentopo.topography.surface`.

May import: :mod:`dentopo.mesh`, :mod:`dentopo.topography.surface` and the shared checks.
"""

"""Face slope, inclination and bearing as each peer computes them.

``_molar``: molaR's ``Slope``; ``_doolkit``: doolkit's face slope, inclination and bearing on the
mesh as its reader leaves it (its mesh is reused by doolkit's OPC and relief metrics).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.topography.surface` and the shared checks.
"""

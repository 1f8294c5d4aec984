"""Orientation patch count and its rotated mean (OPC, OPCR) as each peer computes them.

``_molar``: molaR's ``OPC`` and ``OPCr``; ``_doolkit``: doolkit's OPC and OPCR on its own mesh;
``_morphotester``: MorphoTester 1.1.1's OPCR (its bins, shared-edge patches, minimum patch).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.topography.surface`,
:mod:`dentopo.topography.slope` and the shared checks.
"""

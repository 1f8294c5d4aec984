"""The crown's footprint (its outline projected on the occlusal plane), as each peer draws it.

``_alphahull``: molaR's alpha shape (on ``_delaunay``, a compiled, certified Delaunay sweep with
qhull as the fallback); ``_doolkit``: doolkit's ``area2d``, convex or concave, its concave hull a
port of mapbox's concaveman (``_concaveman``, on its R-tree ``_rbush`` and V8's arithmetic
``_jsmath``); ``_morphotester``: MorphoTester 1.1.1's outline, counted in a picture drawn by
matplotlib's Agg as it draws it; ``_projected``: the exact projected footprint (the union of the
projected triangles, which no earlier tool computes).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.topography.surface` and the shared checks.
"""

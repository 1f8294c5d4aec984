"""Relief: surface area over footprint area, and the other height measures.

``_molar``: molaR's ``RFI`` with its alpha-shape footprint and its search for an alpha;
``_doolkit``: doolkit's elevation, Ungar, Boyer and Guy relief indices, relief rate, shape index
and hypsodonty; ``_morphotester``: MorphoTester 1.1.1's RFI (its surface area over its rendered
outline, both rounded as it prints them); ``_projected``: the relief index on the exact projected
footprint, in Boyer's and Ungar's forms.

May import: :mod:`dentopo.mesh`, :mod:`dentopo.topography.surface`,
:mod:`dentopo.topography.footprint`, :mod:`dentopo.topography.slope` and the shared checks.
"""

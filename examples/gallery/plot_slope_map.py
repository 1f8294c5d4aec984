"""
Slope per face
==============

molaR's mean surface slope on the sample crown, and each face's slope drawn by
``render_slope``: 0 degrees (facing straight up) dark, 90 degrees (vertical)
yellow, on a scale fixed for every specimen.  By default (``orient="auto"``) a
crown that points to -z is turned up first; ``orient="as-is"`` measures it as
it lies, as molaR does.
"""

from dentopo import render_slope, slope
from dentopo.samples import sample_paths

crown = sample_paths()["tooth"]
result = slope(crown)
print(f"mean slope {result.slope:.2f} degrees; orientation: {result.orientation}")

render_slope(result.mesh, result.face_slope, screenshot="slope.png", source=crown)

"""
Signed ariaDNE on a crown
=========================

ariaDNE's local curvature with its sign: red where the surface is convex (the
cusps, the ridges), blue where it is concave (the central basin), on the sample
crown bundled with dentopo.  ``render_curvature`` draws it off-screen (no
display needed) into a PNG, seen from the occlusal side; the colour scale is
symmetric about zero, to the 98th percentile of the magnitude.
"""

from dentopo import ariaDNE, render_curvature
from dentopo.samples import sample_paths

crown = sample_paths()["tooth"]
result = ariaDNE(crown)
print(f"DNE {result.dne:.4f}: convex {result.positive_dne:.4f}, concave {result.negative_dne:.4f}")

render_curvature(crown, result, screenshot="signed.png", window_size=(1000, 800))

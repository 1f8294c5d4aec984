"""
Orientation patches (OPC)
=========================

OPC counts the patches of faces that face the same way: each face's aspect
falls in one of eight bins of 45 degrees, and neighbouring faces of one bin
form a patch.  ``render_opc`` colours each face by its bin, with the patch
borders in dark lines.  The sample crown's four cusps each split into several
patches around their tips.
"""

from dentopo import opc, render_opc
from dentopo.samples import sample_paths

crown = sample_paths()["tooth"]
result = opc(crown)
print(f"OPC {result.opc}: patches in each bin {list(result.bin_counts)}")

render_opc(result.mesh, result.face_bin, result.face_patch, screenshot="opc.png", source=crown)

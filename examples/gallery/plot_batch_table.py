"""
A small batch, as a table
=========================

``compute_batch`` measures many meshes with the command line's settings and
returns one record per mesh (the columns of ``dentopo``'s table); with pandas
(the ``table`` extra) ``to_dataframe`` makes it a DataFrame.  Here: the sample
crown generated at three resolutions (721 to 10,981 vertices), measured by
ariaDNE, molaR's mean slope and OPCR: on this smooth crown none of them moves
much with the resolution.
"""

import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

from dentopo import compute_batch, to_dataframe
from dentopo.samples import tooth

folder = Path(tempfile.mkdtemp())
for rings in (15, 30, 60):
    tooth(rings=rings).export(folder / f"crown-{rings:02d}-rings.ply")

records = compute_batch(folder, metrics=("ariadne", "slope", "opcr"))
table = to_dataframe(records)
table["file"] = table["file"].map(lambda path: Path(path).name)
table[["file", "vertices", "dne", "positive_dne", "negative_dne", "slope", "opcr", "status"]]

# %%
# The convex and concave parts of DNE, side by side:

ax = table.plot.bar(x="file", y=["positive_dne", "negative_dne"], color=["#b40426", "#3b4cc0"])
ax.set_ylabel("DNE")
ax.set_xlabel("")
plt.xticks(rotation=0)
plt.tight_layout()
plt.show()

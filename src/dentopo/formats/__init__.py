"""Output files: result tables and per-vertex files, each written atomically.

``_atomic`` (write to a temporary file, rename over the target), ``_tables``
(the result table's columns; writers and readers by file extension),
``_per_vertex`` (each mesh's cleaned vertices with their values).

May import: :mod:`dentopo.ariadne` (the result's field names),
:mod:`dentopo.figures` (the colour scale of per-vertex colours).  Nothing from
batch, study or cli.
"""

from ._atomic import atomic_write
from ._per_vertex import OUTPUT_SUFFIX, per_vertex_names, write_per_vertex
from ._tables import COLUMNS, FORMATS, output_format, read_table, write_table

__all__ = [
    "COLUMNS",
    "FORMATS",
    "OUTPUT_SUFFIX",
    "atomic_write",
    "output_format",
    "per_vertex_names",
    "read_table",
    "write_per_vertex",
    "write_table",
]

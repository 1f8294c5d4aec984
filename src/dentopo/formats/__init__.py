"""Output files: result tables and per-vertex files, each written atomically.

``_atomic`` (write to a temporary file, rename over the target), ``_journal``
(finished rows appended as they finish, so that a killed run loses none),
``_lock`` (one writer per table; a table that cannot be written found before
any work), ``_tables``
(the result table's column layouts and file formats, one registry each:
:data:`LAYOUTS`, :data:`FORMATS`), ``_per_vertex`` (each mesh's cleaned
vertices with their values, as PLY, VTP, NPZ or CSV, and reading them back).

May import: :mod:`dentopo.ariadne` (the result's field names),
:mod:`dentopo.figures` (the colour scale of per-vertex colours).  Nothing from
batch, study or cli.
"""

from ._atomic import atomic_write
from ._journal import JOURNAL_SUFFIX, Journal, journal_path, read_journal
from ._lock import OutputLock, check_writable, lock_path
from ._per_vertex import (
    DEFAULT_PER_VERTEX_FORMATS,
    OUTPUT_SUFFIX,
    PER_VERTEX_FORMATS,
    PerVertexOptions,
    per_vertex_arrays,
    per_vertex_formats,
    per_vertex_names,
    read_per_vertex,
    write_per_vertex,
)
from ._tables import (
    COLUMNS,
    FORMATS,
    LAYOUTS,
    Column,
    Layout,
    TableFormat,
    layout,
    output_format,
    read_table,
    table_format,
    write_table,
)

__all__ = [
    "COLUMNS",
    "DEFAULT_PER_VERTEX_FORMATS",
    "FORMATS",
    "JOURNAL_SUFFIX",
    "LAYOUTS",
    "OUTPUT_SUFFIX",
    "PER_VERTEX_FORMATS",
    "Column",
    "Journal",
    "Layout",
    "OutputLock",
    "PerVertexOptions",
    "TableFormat",
    "atomic_write",
    "check_writable",
    "journal_path",
    "layout",
    "lock_path",
    "output_format",
    "per_vertex_arrays",
    "per_vertex_formats",
    "per_vertex_names",
    "read_journal",
    "read_per_vertex",
    "read_table",
    "table_format",
    "write_per_vertex",
    "write_table",
]

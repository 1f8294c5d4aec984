"""Output files: result tables and per-vertex files, each written atomically.

``_atomic`` (write to a temporary file, rename over the target), ``_journal``
(finished rows appended as they finish, so that a killed run loses none),
``_lock`` (one writer per table; a table that cannot be written found before
any work), ``_layouts`` (the result table's column layouts, in one
registry: :data:`LAYOUTS`), ``_tables`` (its file formats, in another:
:data:`FORMATS`, and writing, reading and converting a table),
``_per_vertex`` (each mesh's cleaned vertices with their values, as PLY, VTP,
NPZ or CSV, and reading them back),
``_per_face`` (the face-wise slope and OPC values, in the same formats),
``_prepared`` (a prepared crown's mesh and its ``.prepare.json`` record).

May import: :mod:`dentopo.ariadne` (the result's field names),
:mod:`dentopo.topography` (the metrics' names and keys),
:mod:`dentopo.figures` (the colour scale of per-vertex colours),
:mod:`dentopo.prepare` (the prepared crown's record).  Nothing from
batch, study or cli.
"""

from ._atomic import atomic_write
from ._journal import (
    JOURNAL_HEADER,
    JOURNAL_SUFFIX,
    Journal,
    NotAJournalError,
    journal_path,
    read_journal,
)
from ._layouts import (
    COLUMNS,
    DOOLKIT_NAMES,
    LAYOUTS,
    METRIC_KEYS,
    MORPHOTESTER_NAMES,
    PROTOCOL_KEY,
    SETTING_KEYS,
    Column,
    Layout,
    layout,
    record_keys,
)
from ._lock import ForeignLockError, OutputLock, check_writable, lock_path
from ._per_face import FACES_SUFFIX, per_face_arrays, write_per_face
from ._per_vertex import (
    DEFAULT_PER_VERTEX_FORMATS,
    OUTPUT_SUFFIX,
    PER_VERTEX_FORMATS,
    SOURCES_FILE,
    PerVertexOptions,
    naming_the_file,
    per_vertex_arrays,
    per_vertex_formats,
    per_vertex_names,
    per_vertex_paths,
    read_per_vertex,
    record_source,
    recorded_sources,
    replaced_files,
    write_per_vertex,
)
from ._prepared import (
    RECORD_SUFFIX,
    prepared_ply_bytes,
    prepared_record,
    read_record,
    safe_folder,
    sha256_file,
    write_prepared,
)
from ._tables import (
    FORMATS,
    TableFormat,
    convert_table,
    output_format,
    read_table,
    table_format,
    write_table,
)

__all__ = [
    "COLUMNS",
    "DEFAULT_PER_VERTEX_FORMATS",
    "DOOLKIT_NAMES",
    "FACES_SUFFIX",
    "FORMATS",
    "JOURNAL_HEADER",
    "JOURNAL_SUFFIX",
    "LAYOUTS",
    "METRIC_KEYS",
    "MORPHOTESTER_NAMES",
    "OUTPUT_SUFFIX",
    "PER_VERTEX_FORMATS",
    "PROTOCOL_KEY",
    "RECORD_SUFFIX",
    "SETTING_KEYS",
    "SOURCES_FILE",
    "Column",
    "ForeignLockError",
    "Journal",
    "Layout",
    "NotAJournalError",
    "OutputLock",
    "PerVertexOptions",
    "TableFormat",
    "atomic_write",
    "check_writable",
    "convert_table",
    "journal_path",
    "layout",
    "lock_path",
    "naming_the_file",
    "output_format",
    "per_face_arrays",
    "per_vertex_arrays",
    "per_vertex_formats",
    "per_vertex_names",
    "per_vertex_paths",
    "prepared_ply_bytes",
    "prepared_record",
    "read_journal",
    "read_per_vertex",
    "read_record",
    "read_table",
    "record_keys",
    "record_source",
    "recorded_sources",
    "replaced_files",
    "safe_folder",
    "sha256_file",
    "table_format",
    "write_per_face",
    "write_per_vertex",
    "write_prepared",
    "write_table",
]

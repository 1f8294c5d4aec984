"""The collection report: one self-contained HTML page for a whole results table.

``_collect`` (the table's rows, where their files are, which group each belongs
to), ``_columns`` (which of its columns are metrics, of which family, in which
unit; which are settings), ``_fields`` (each specimen's signed local
curvature, recomputed with the table's settings, in worker processes),
``_thumbnails`` (small off-screen pictures through one pyvista plotter),
``_payload`` (each mesh packed small for the page's 3D view, unpacked only when
asked), ``_page`` (the HTML: the sortable table, the per-group plots, the
warnings, the viewer; plotly's JavaScript inlined once), ``_static`` (its
styles and scripts), ``_report`` (the entry point
:func:`write_report`).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.sign`, :mod:`dentopo.ariadne`,
:mod:`dentopo.topography`, :mod:`dentopo.figures`, :mod:`dentopo.formats`,
:mod:`dentopo.batch` (the report is of a batch's table).  Nothing from study or cli.
"""

from ._payload import pack_mesh, unpack_mesh
from ._report import ReportSummary, check_report_extras, write_report
from ._static import UNPACK_JS
from ._thumbnails import report_camera

__all__ = [
    "UNPACK_JS",
    "ReportSummary",
    "check_report_extras",
    "pack_mesh",
    "report_camera",
    "unpack_mesh",
    "write_report",
]

"""``dentopo app``: the whole study in the browser, for those who do not program.

A local web server over the library and the command: the folder's meshes
(``_folder``), their preparation previewed (``_preview``) and saved as
protocols, runs of the command with live progress (``_progress``), results,
maps, the report and exports (``_workspace``; the work done by the command in
child processes: ``_jobs``; the maps by one warm worker process:
``_pictures``), the addresses (``_routes``, Starlette; refusals: ``_errors``),
the door (``_security``: the secret, the Host and Origin checks, safe paths,
the headers) and the server (``_server``, uvicorn).  The page (``static/``) is plain HTML, CSS and
JavaScript shipped in the package, with plotly for the 3D view (served from
the installed plotly) and the report's unpacking of meshes.

May import: :mod:`dentopo.mesh`, :mod:`dentopo.sign`, :mod:`dentopo.ariadne`,
:mod:`dentopo.topography`, :mod:`dentopo.prepare`, :mod:`dentopo.figures`,
:mod:`dentopo.formats`, :mod:`dentopo.batch`, :mod:`dentopo.report`.  Nothing
from study or cli (the command is run as a program, never imported).
"""

from ._security import PathRefusedError, inside
from ._server import DEFAULT_PORT, AppServer, is_loopback
from ._workspace import OUTPUT_NAME, AppError, RunOptions, Workspace

__all__ = [
    "DEFAULT_PORT",
    "OUTPUT_NAME",
    "AppError",
    "AppServer",
    "PathRefusedError",
    "RunOptions",
    "Workspace",
    "inside",
    "is_loopback",
]

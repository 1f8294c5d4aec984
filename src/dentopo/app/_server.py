"""Serving the app: a socket bound first (so the address is known), then uvicorn on it.

uvicorn is the reference ASGI server (well kept, pure Python with h11, small).
It runs with its own handling of Ctrl-C and SIGTERM (finish the requests in
flight, then stop); :meth:`AppServer.serve` then stops the background work,
a run writing the rows it finished, and the picture worker (started, and
warmed in the background, as the server starts).
"""

from __future__ import annotations

import errno
import ipaddress
import secrets
import socket

from ._routes import build_app
from ._security import LOOPBACK
from ._workspace import Workspace

#: Addresses that mean every interface.
WILDCARDS = ("0.0.0.0", "::", "")
#: The port tried first when none is given (another is chosen if it is taken).
DEFAULT_PORT = 8765


def is_loopback(host: str) -> bool:
    """Whether `host` is a loopback address or name."""
    if host in LOOPBACK:
        return True
    try:
        return ipaddress.ip_address(host.strip("[]")).is_loopback
    except ValueError:
        return False


class AppServer:
    """The app for `folder`, bound to `host`:`port` (0: any free port) with a new secret.

    Parameters
    ----------
    folder : path-like
        The folder of meshes.
    output : path-like, optional
        Where the app writes (default ``FOLDER/dentopo-app``).
    host : str
        The address to listen on (default the loopback, 127.0.0.1).
    port : int or None
        The port; None tries :data:`DEFAULT_PORT`, then any free one.

    Raises
    ------
    OSError
        If the port is taken (an explicit one) or the address cannot be bound.
    ValueError
        If `folder` is not a folder.
    """

    def __init__(self, folder, *, output=None, host: str = "127.0.0.1", port: int | None = None):
        self.workspace = Workspace(str(folder), None if output is None else str(output))
        self.host = host
        self.token = secrets.token_urlsafe(32)
        self.socket = _bind(host, DEFAULT_PORT if port is None else port, fallback=port is None)
        self.port = self.socket.getsockname()[1]
        wildcard = host.strip("[]") in WILDCARDS
        hosts: tuple[str, ...] = () if is_loopback(host) else (host,)
        if wildcard:  # every interface: reached by any of this computer's addresses or names
            hosts = (socket.gethostname(), socket.getfqdn())
        self.app = build_app(
            self.workspace, self.token, port=self.port, hosts=hosts, any_address=wildcard
        )

    @property
    def url(self) -> str:
        """The address to open: it carries the secret."""
        shown = "127.0.0.1" if self.host in ("127.0.0.1", *WILDCARDS) else self.host
        if shown == "::":
            shown = "::1"
        if ":" in shown and not shown.startswith("["):
            shown = f"[{shown}]"
        return f"http://{shown}:{self.port}/?token={self.token}"

    def serve(self) -> None:
        """Serve until Ctrl-C or SIGTERM; then stop the background work (rows are kept)."""
        import uvicorn

        config = uvicorn.Config(
            self.app, log_level="warning", access_log=False, lifespan="off", server_header=False
        )
        self.workspace.drawer.warm()  # the picture worker, ready before the first map is asked
        try:
            uvicorn.Server(config).run(sockets=[self.socket])
        finally:
            self.workspace.close()
            self.socket.close()


def _bind(host: str, port: int, *, fallback: bool) -> socket.socket:
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host.strip("[]"), port))
    except OSError as exc:
        if not (fallback and exc.errno == errno.EADDRINUSE):
            sock.close()
            raise
        sock.bind((host.strip("[]"), 0))
    sock.listen(128)
    sock.set_inheritable(False)
    return sock

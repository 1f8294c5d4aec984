"""The app's door: the secret, the Host and Origin checks, the headers, and safe paths.

A local server is a door into the user's files, so every request passes one
ASGI middleware (:class:`Guard`) before any route sees it:

1. **Host.**  The ``Host`` header must name the loopback (``127.0.0.1``,
   ``localhost``, ``[::1]``) or the address given with ``--host`` (for
   ``--host 0.0.0.0``, any IP address and this computer's names), and the
   server's port.  A page on another site that the attacker's DNS points at
   127.0.0.1 (DNS rebinding) sends its own name: it gets 403.
2. **The secret.**  Every request carries the secret printed in the app's
   address: as ``?token=`` (the first visit), the cookie that visit sets
   (HttpOnly, SameSite=Strict, named after the port so two apps do not
   overwrite each other's), or the ``X-Dentopo-Token`` header.  None: 401; a
   wrong one: 403.  Compared in constant time.
3. **Changes come from the page.**  A request that changes anything (any
   method but GET and HEAD) must carry the secret in the ``X-Dentopo-Token``
   header (a cookie alone is refused: a form on another site can make the
   browser send the cookie, never a header) and, where the browser says where
   it comes from (``Origin``, ``Sec-Fetch-Site``), come from the app's own
   origin.  Otherwise 403 (cross-site request forgery).

Every response gets a Content-Security-Policy (the page loads only the app's
own scripts and talks only to the app), ``nosniff``, no referrer, no framing
and no caching.  Pages of the output folder (the collection report) get the
report's own policy in a sandbox: their scripts run, but as an opaque origin
that cannot call the app.

Paths: :func:`inside` resolves a relative path below a folder and refuses
absolute paths, ``..`` and ``.`` parts, backslashes, NUL and anything whose
real path (symlinks followed) leaves the folder.  Names reach the page as data
only (the page sets ``textContent``); the index's one substitution, the
secret, is HTML-escaped.
"""

from __future__ import annotations

import hmac
import http.cookies
import ipaddress
import json
import os
from urllib.parse import parse_qs, urlsplit

#: The page's policy: its own scripts (plotly's WebGL needs eval, its styles inline), its own API.
PAGE_CSP = (
    "default-src 'none'; script-src 'self' 'unsafe-eval'; style-src 'self' 'unsafe-inline'; "
    "img-src 'self' data: blob:; connect-src 'self'; frame-src 'self'; base-uri 'none'; "
    "form-action 'self'; frame-ancestors 'none'"
)
#: The output folder's pages (the report): its own inline scripts, nothing fetched, sandboxed.
OUTPUT_CSP = (
    "sandbox allow-scripts allow-popups allow-downloads; default-src 'none'; "
    "script-src 'unsafe-inline' 'unsafe-eval'; style-src 'unsafe-inline'; img-src data: blob:; "
    "font-src data:; frame-ancestors 'self'"
)
#: Hosts that name the loopback.
LOOPBACK = ("127.0.0.1", "localhost", "::1")
#: Methods that change nothing.
SAFE_METHODS = ("GET", "HEAD")
#: The request header that carries the secret (the page's requests that change anything).
TOKEN_HEADER = "x-dentopo-token"


class PathRefusedError(ValueError):
    """A path that is not a plain relative path inside the folder."""


def inside(folder: str, relative: str) -> str:
    """The real path of `relative` below `folder`, or :class:`PathRefusedError`.

    `relative` uses ``/``; it must be non-empty, not absolute, free of NUL,
    backslashes and ``.``/``..`` parts, and its real path (every symlink
    followed) must lie inside the real path of `folder`.
    """
    if not isinstance(relative, str) or not relative:
        raise PathRefusedError("no path given")
    if "\x00" in relative or "\\" in relative:
        raise PathRefusedError("a path may not hold NUL or backslashes")
    if relative.startswith("/") or (len(relative) > 1 and relative[1] == ":"):
        raise PathRefusedError("an absolute path is refused: paths are relative to the folder")
    parts = relative.split("/")
    if any(part in ("", ".", "..") for part in parts):
        raise PathRefusedError("a path may not hold '.', '..' or empty parts")
    root = os.path.realpath(folder)
    real = os.path.realpath(os.path.join(root, *parts))
    if os.path.commonpath([root, real]) != root:
        raise PathRefusedError("the path leads out of the folder")
    return real


def relative_to(folder: str, path: str) -> str:
    """`path` relative to `folder`, with ``/`` separators."""
    return os.path.relpath(path, folder).replace(os.sep, "/")


def _header(scope, name: bytes) -> str | None:
    for key, value in scope.get("headers", ()):
        if key == name:
            return value.decode("latin-1")
    return None


def _split_host(host: str) -> tuple[str, int | None]:
    """(hostname, port) of a Host header; port None when absent or not a number."""
    parts = urlsplit("//" + host)
    try:
        port = parts.port
    except ValueError:
        return "", None
    return (parts.hostname or ""), port


def _is_ip(name: str) -> bool:
    try:
        ipaddress.ip_address(name)
    except ValueError:
        return False
    return True


def cookie_name(port: int) -> str:
    """The cookie that keeps the secret for the app on `port`."""
    return f"dentopo-app-{port}"


class Guard:
    """ASGI middleware: the Host, secret and origin checks, and the security headers.

    Parameters
    ----------
    app : ASGI application
    token : str
        The secret.
    port : int
        The port the server listens on (the Host header must name it);
        0 until the server is bound (:meth:`bind`).
    hosts : sequence of str
        Further host names accepted besides the loopback (``--host``).
    any_address : bool
        Also accept any IP address as the Host (the server listens on every
        interface: ``--host 0.0.0.0``).  A DNS-rebinding page sends a name,
        never an address, so this keeps that door shut.
    """

    def __init__(self, app, token: str, port: int = 0, hosts=(), any_address: bool = False):
        self.app = app
        self.token = token
        self.port = port
        self.hosts = {h.lower().strip("[]") for h in hosts}
        self.any_address = any_address

    def bind(self, port: int) -> None:
        """The port the server is listening on (known once it is bound)."""
        self.port = port

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            if scope["type"] == "websocket":  # none are served
                await send({"type": "websocket.close", "code": 1008})
                return
            await self.app(scope, receive, send)
            return
        query = parse_qs(scope.get("query_string", b"").decode("latin-1"))
        problem = self._problem(scope, query)
        if problem is not None:
            status, message = problem
            await _refuse(send, status, message)
            return
        if scope["method"] == "GET" and scope["path"] == "/" and "token" in query:
            await _enter(send, cookie_name(self.port), self.token)
            return
        await self.app(scope, receive, _with_headers(send, scope["path"]))

    def _problem(self, scope, query: dict) -> tuple[int, str] | None:
        host = _header(scope, b"host")
        if host is None:
            return 400, "the request names no Host"
        name, port = _split_host(host)
        known = name.lower() in (*LOOPBACK, *self.hosts) or (self.any_address and _is_ip(name))
        if not known or (self.port and port != self.port):
            return 403, f"refused: Host {host!r} is not this app's address"
        given = self._given_token(scope, query)
        if given is None:
            return 401, "this app needs its secret: open the address that dentopo app printed"
        if not hmac.compare_digest(given.encode("utf-8", "replace"), self.token.encode()):
            return 403, "refused: wrong secret; open the address that dentopo app printed"
        if scope["method"] not in SAFE_METHODS:
            header = _header(scope, TOKEN_HEADER.encode())
            if header is None or not hmac.compare_digest(
                header.encode("utf-8", "replace"), self.token.encode()
            ):
                return 403, "refused: a change must come from the app's page (its secret header)"
            origin = _header(scope, b"origin")
            if origin is not None and origin != f"http://{host}":
                return 403, f"refused: a change from another origin ({origin!r})"
            site = _header(scope, b"sec-fetch-site")
            if site is not None and site not in ("same-origin", "none"):
                return 403, f"refused: a change from another site (Sec-Fetch-Site {site})"
        return None

    def _given_token(self, scope, query: dict) -> str | None:
        header = _header(scope, TOKEN_HEADER.encode())
        if header is not None:
            return header
        if "token" in query:
            return query["token"][-1]
        cookie = _header(scope, b"cookie")
        if cookie:
            jar = http.cookies.SimpleCookie()
            try:
                jar.load(cookie)
            except http.cookies.CookieError:
                return None
            morsel = jar.get(cookie_name(self.port))
            if morsel is not None:
                return morsel.value
        return None


_COMMON_HEADERS = [
    (b"x-content-type-options", b"nosniff"),
    (b"referrer-policy", b"no-referrer"),
    (b"cache-control", b"no-store"),
    (b"cross-origin-opener-policy", b"same-origin"),
    (b"cross-origin-resource-policy", b"same-origin"),
]


def security_headers(path: str) -> list[tuple[bytes, bytes]]:
    """The headers every response gets (the output folder's pages: the sandboxed policy)."""
    csp = OUTPUT_CSP if path.startswith("/output/") else PAGE_CSP
    frame = b"SAMEORIGIN" if path.startswith("/output/") else b"DENY"
    return [
        *_COMMON_HEADERS,
        (b"content-security-policy", csp.encode()),
        (b"x-frame-options", frame),
    ]


def _with_headers(send, path: str):
    extra = security_headers(path)

    async def sending(message):
        if message["type"] == "http.response.start":
            names = {k.lower() for k, _ in message.get("headers", [])}
            headers = list(message.get("headers", []))
            headers += [(k, v) for k, v in extra if k not in names]
            message = {**message, "headers": headers}
        await send(message)

    return sending


async def _refuse(send, status: int, message: str) -> None:
    body = json.dumps({"error": message}).encode()
    headers = [
        (b"content-type", b"application/json"),
        (b"content-length", str(len(body)).encode()),
        *security_headers("/"),
    ]
    if status == 401:
        headers.append((b"www-authenticate", b'Token realm="dentopo app"'))
    await send({"type": "http.response.start", "status": status, "headers": headers})
    await send({"type": "http.response.body", "body": body})


async def _enter(send, name: str, token: str) -> None:
    """The first visit, ``/?token=``: keep the secret in a cookie, go to ``/`` without it."""
    cookie = f"{name}={token}; Path=/; HttpOnly; SameSite=Strict"
    headers = [
        (b"location", b"/"),
        (b"set-cookie", cookie.encode()),
        (b"content-length", b"0"),
        *security_headers("/"),
    ]
    await send({"type": "http.response.start", "status": 303, "headers": headers})
    await send({"type": "http.response.body", "body": b""})

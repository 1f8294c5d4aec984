"""What a picture shows and how it was made, kept inside the picture.

Every PNG written by dentopo carries a text chunk named ``dentopo`` holding
JSON; every HTML page carries the same JSON in a
``<script type="application/json" id="dentopo-provenance">`` block:

``software``, ``version``
    ``"dentopo"`` and the package version.
``metric``
    What the colours show (``"local_curvature"``, ``"slope"``, ``"opc"`` ...).
``parameters``
    How it was computed and drawn: bandwidth, method, ... and the colour
    limits, where they apply.
``input``, ``camera``
    For a picture of one mesh: the input file's name and SHA-256 (both null
    for a mesh given as an object without ``source=``), and the camera
    (``position``, ``focal_point``, ``up`` in the mesh's coordinates, the
    view, azimuth and elevation it came from, the projection).
``panels``
    One ``{"label", "input", "camera"}`` record per mesh drawn (also for
    one mesh).

:func:`read_provenance` reads it back (``dentopo info FILE``).  numpy-free,
standard library only.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import struct
import zlib

#: The PNG text chunk's keyword and the HTML block's id.
KEYWORD = "dentopo"
HTML_ID = "dentopo-provenance"

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def source_record(source) -> dict:
    """``{"file": name, "sha256": hex}`` of an input file, or nulls for None."""
    if source is None:
        return {"file": None, "sha256": None}
    path = os.fspath(source)
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return {"file": os.path.basename(path), "sha256": digest.hexdigest()}


def _plain(value):
    """`value` as JSON-ready values (numpy scalars and arrays, tuples)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "tolist"):
        return _plain(value.tolist())
    if isinstance(value, float) and value != value:
        return None
    return value


def build(metric: str, parameters: dict, panels: list[tuple]) -> dict:
    """The provenance record.

    Parameters
    ----------
    metric : str
        What the colours show.
    parameters : dict
        Computation and drawing parameters.
    panels : list of (label, source, camera)
        Per mesh: its label, its input file (or None) and its
        :class:`~._camera.Camera`.
    """
    from .._version import __version__

    records = [
        {"label": label, "input": source_record(source), "camera": camera.as_dict()}
        for label, source, camera in panels
    ]
    record = {
        "software": "dentopo",
        "version": __version__,
        "metric": metric,
        "parameters": _plain(parameters),
    }
    if len(records) == 1:
        record["input"] = records[0]["input"]
        record["camera"] = records[0]["camera"]
    record["panels"] = records
    return record


def dumps(record: dict) -> str:
    """The record as one line of ASCII JSON (fits a PNG tEXt chunk)."""
    return json.dumps(record, ensure_ascii=True, separators=(",", ":"), allow_nan=False)


#: What JSON text inside an HTML ``<script>`` element may not hold as it is, and its escape.
_HTML_UNSAFE = {"<": "\\u003c", ">": "\\u003e", "&": "\\u0026"}


def html_json(text: str) -> str:
    """JSON text made safe inside an HTML ``<script>`` element, for the same JSON value.

    ``<``, ``>`` and ``&`` become ``\\u003c``, ``\\u003e`` and ``\\u0026``: JSON has
    them only inside strings, where these escapes mean the same characters, so
    ``JSON.parse`` and :func:`json.loads` read the same value; and the page's
    parser sees no ``</script>``, no ``<!--`` (which, followed by ``<script>``,
    keeps the element open to the end of the page) and, should the page be
    read as XML, no entity.  Every JSON
    block in dentopo's pages goes through here.
    """
    for character, escape in _HTML_UNSAFE.items():
        text = text.replace(character, escape)
    return text


def html_block(record: dict) -> str:
    """The ``<script type="application/json">`` block of an HTML page."""
    return f'<script type="application/json" id="{HTML_ID}">{html_json(dumps(record))}</script>'


def _png_text(path) -> str | None:
    with open(path, "rb") as handle:
        data = handle.read()
    if not data.startswith(_PNG_SIGNATURE):
        raise ValueError(f"{os.fspath(path)!r} is not a PNG file")
    offset = len(_PNG_SIGNATURE)
    while offset + 8 <= len(data):
        (length,) = struct.unpack(">I", data[offset : offset + 4])
        kind = data[offset + 4 : offset + 8]
        body = data[offset + 8 : offset + 8 + length]
        offset += 12 + length
        if kind == b"IEND":
            break
        if kind not in (b"tEXt", b"zTXt", b"iTXt"):
            continue
        keyword, _, rest = body.partition(b"\0")
        if keyword.decode("latin-1") != KEYWORD:
            continue
        if kind == b"tEXt":
            return rest.decode("latin-1")
        if kind == b"zTXt":
            return zlib.decompress(rest[1:]).decode("latin-1")
        compressed, rest = rest[0], rest[2:]
        _language, _, rest = rest.partition(b"\0")
        _translated, _, text = rest.partition(b"\0")
        return (zlib.decompress(text) if compressed else text).decode("utf-8")
    return None


def read_provenance(path) -> dict:
    """The provenance JSON of a PNG or HTML picture written by dentopo.

    Parameters
    ----------
    path : str or path-like
        A ``.png`` or ``.html`` file.

    Returns
    -------
    dict
        The record (see the module's description).

    Raises
    ------
    ValueError
        If the file holds no dentopo provenance, or is neither PNG nor HTML.
    OSError
        If it cannot be read.

    Examples
    --------
    >>> from dentopo.figures import read_provenance
    >>> read_provenance("tooth.png")["input"]["file"]  # doctest: +SKIP
    'tooth.ply'
    """
    name = os.fspath(path)
    with open(name, "rb") as handle:
        head = handle.read(8)
    if head == _PNG_SIGNATURE:
        text = _png_text(name)
    else:
        with open(name, encoding="utf-8", errors="replace") as handle:
            page = handle.read(4096)  # not a whole scan of a gigabyte: the start tells
            if "<html" not in page.lower():
                raise ValueError(f"{name!r} is neither a PNG nor an HTML file")
            page += handle.read()
        found = re.search(
            rf'<script type="application/json" id="{HTML_ID}">(.*?)</script>', page, re.S
        )
        text = found.group(1) if found else None  # "<\\/" of older pages is JSON for "</"
    if text is None:
        raise ValueError(f"{name!r} holds no dentopo provenance (not written by dentopo?)")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{name!r}: its dentopo provenance is not valid JSON: {exc}") from exc

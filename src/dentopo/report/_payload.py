"""Each mesh packed small for the page's 3D view, unpacked in the browser only when asked.

The layout (little-endian, then deflated with zlib and written as base64):

* vertices: each coordinate quantised to 16 bits within the mesh's bounding
  cube (``low + q / 65535 * extent``, one extent for all three axes, so the
  shape keeps its proportions; an error of at most 1/131070 of the largest
  side), stored x column, y column, z column;
* faces: the three indices of each face in turn, 16 bits when there are at
  most 65,536 vertices, else 32;
* colours: one byte per vertex, the index into the 255 colours of the
  diverging scale (127 is zero) on the collection's limits.

Vertex coordinates (per column) and face indices are stored as the zigzag
code of the difference from the previous one (wrapping at 16 or 32 bits), and
each array's words are split into byte planes (all low bytes, then the high
bytes): neighbouring values are close, and deflate then finds long runs.  The
page undoes this in a few lines of JavaScript (``unpack`` in ``_page``).
"""

from __future__ import annotations

import base64
import zlib

import numpy as np

from ..figures import ColorScale

#: Entries of the colour table (odd, so that zero falls in the middle entry).
COLOR_STEPS = 255


def _zigzag_deltas(words: np.ndarray, bits: int) -> np.ndarray:
    """Zigzag code of each word's difference from the one before (the first from 0)."""
    words = words.astype(np.int64)
    deltas = np.diff(words, prepend=np.int64(0))
    half, modulus = 1 << (bits - 1), 1 << bits
    deltas = (deltas + half) % modulus - half
    return ((deltas << 1) ^ (deltas >> 63)).astype(f"<u{bits // 8}")


def _planes(words: np.ndarray) -> bytes:
    """The bytes of `words` plane by plane: every word's byte 0, then every byte 1, ..."""
    return np.ascontiguousarray(words.view(np.uint8).reshape(-1, words.itemsize).T).tobytes()


def color_indices(values: np.ndarray, scale: ColorScale) -> np.ndarray:
    """uint8 index into the :data:`COLOR_STEPS` colours of `scale` (127 is zero)."""
    half = (COLOR_STEPS - 1) / 2
    return np.round((scale.normalize(values) + 1.0) * half).astype(np.uint8)


def pack_mesh(
    vertices: np.ndarray, faces: np.ndarray, values: np.ndarray, scale: ColorScale
) -> dict:
    """The payload of one mesh: ``{"n", "m", "wide", "low", "extent", "data"}``.

    ``n`` vertices, ``m`` faces, ``wide`` whether indices take 32 bits,
    ``low`` and ``extent`` to undo the quantisation, ``data`` the base64 text.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    low = vertices.min(axis=0)
    extent = float((vertices.max(axis=0) - low).max()) or 1.0
    quantised = np.round((vertices - low) / extent * 65535.0).astype(np.int64)
    wide = len(vertices) > 65536
    parts = [  # the x, y and z columns each start again from zero
        _planes(np.concatenate([_zigzag_deltas(column, 16) for column in quantised.T])),
        _planes(_zigzag_deltas(faces.ravel(), 32 if wide else 16)),
        color_indices(values, scale).tobytes(),
    ]
    data = base64.b64encode(zlib.compress(b"".join(parts), 6)).decode("ascii")
    return {
        "n": len(vertices),
        "m": len(faces),
        "wide": wide,
        "low": [float(x) for x in low],
        "extent": extent,
        "data": data,
    }


def unpack_mesh(payload: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Vertices (dequantised), faces and colour indices of a payload (as the page reads it)."""
    raw = np.frombuffer(zlib.decompress(base64.b64decode(payload["data"])), dtype=np.uint8)
    n, m, wide = payload["n"], payload["m"], payload["wide"]

    def words(offset: int, count: int, size: int) -> np.ndarray:
        planes = raw[offset : offset + count * size].reshape(size, count).astype(np.int64)
        return sum(planes[b] << (8 * b) for b in range(size))

    def undo(codes: np.ndarray, bits: int) -> np.ndarray:
        deltas = (codes >> 1) ^ -(codes & 1)
        return np.cumsum(deltas) % (1 << bits)

    coords = words(0, 3 * n, 2).reshape(3, n)
    quantised = np.stack([undo(column, 16) for column in coords], axis=1)
    size = 4 if wide else 2
    faces = undo(words(6 * n, 3 * m, size), 8 * size).reshape(m, 3)
    colors = raw[6 * n + 3 * m * size :]
    vertices = np.asarray(payload["low"]) + quantised / 65535.0 * payload["extent"]
    return vertices, faces, colors

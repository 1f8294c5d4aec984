"""Which directions light each vertex, by a depth buffer per direction (CloudCompare's way).

For each light direction ``d`` (a unit vector towards the light) the mesh is seen along
``-d`` in an orthographic view: a square image of ``resolution`` pixels a side, centred on
the mesh's bounding box and as wide as the box's diagonal.  The view's axes are ``u``
(``z x d`` normalised, or ``x`` when ``d`` is within 1e-6 of the z axis) and ``v = d x u``:
the image's "up" is world z (a look-at view with up = z; for ``d = z``: ``u = x``, ``v = y``),
as probed in CloudCompare 2.11.3; a point ``p``
lands at pixel coordinates ``((p - c) . u / diagonal + 1/2) * resolution`` (and the same
with ``v``); its height ``h = (p - c) . d + diagonal`` is measured from the far plane.

Every triangle, whichever way it faces, is drawn: a pixel holds the greatest height of
the triangles covering its centre.  A vertex reads the pixel it falls in (coordinates
rounded down) and is lit when ``h >= (1 - TOLERANCE) * held`` (a tolerance relative to
the height above the far plane: probed in CloudCompare, 0.002 to within 0.1 %, whatever
the box).  A vertex whose pixel is empty is lit when the next pixel in ``+u``, ``+v`` or
both is drawn, whatever it holds, and unlit otherwise: CloudCompare 2.11.3 does so (a flat
square's near borders are always lit, its far borders only when the pixel centre is
inside, an isolated vertex never; with ``d = z`` this rule and the tolerance give its
values on the crowns exactly).  No cosine weight: each direction counts 1.

Two kernels give these counts.  A vertex reads its own pixel and, when that is empty, the
three next in ``+u``/``+v``; a crown's image of ``resolution**2`` pixels per direction is
mostly never read (a 4,050-vertex crown reads at most 16,200 of 1,048,576).  So the
*queries* kernel computes only the pixels read.  Per direction it puts each face in the
tiles of a few pixels that its pixel box touches, each tile's faces from the highest
corner down (a counting sort on the heights); each vertex then reads its tile from the top
down to the faces too low to hide it (a face cannot hide what is above its highest
corner), gathering the faces whose box holds its pixel and testing them; only a vertex
no such face covers reads further down, and the few on an empty pixel read the next
pixels' tiles.  Its cost grows with vertices plus faces, not pixels.  The
*image* kernel draws the whole image, face by face over its pixel box: cheaper once faces are
smaller than pixels (above about 30,000 vertices at 1,024 pixels, :data:`IMAGE_ABOVE`).  Both
use the same test and the same height at a pixel centre, so their counts are equal (the
tests compare both with an image drawn by numpy).

The directions run in parallel, each thread with its own arrays and its own counts (summed
at the end, integers), so that the counts do not depend on the number of threads.

May import: :mod:`dentopo._jit`.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import in_threads, njit

#: A vertex is lit when its height above the far plane is at least ``1 - TOLERANCE`` times
#: the buffer's at its pixel (CloudCompare 2.11.3: 0.002, probed to within 0.1 %).
TOLERANCE = 2e-3

#: The queries kernel sorts faces by their highest corner in this many levels of the
#: bounding box's diagonal (heights above the far plane lie between 1/2 and 3/2 of it).
LEVELS = 4096

#: The queries kernel's tile entries: a row of four int32 each (face, key, ``left | right <<
#: 16``, ``bottom | top << 16``: pixel coordinates below 32,768), 16 bytes, so that writing or
#: reading an entry touches one cache line and the entries of a crown stay in the core's own
#: cache (with the box in two arrays beside the face and key: 12 % more CPU on 10,080 vertices).
ENTRY = 4

#: The largest image side the kernels take: the tile entries keep pixel coordinates in 16 bits
#: (a 32,768-pixel side is an image of 10^9 pixels per direction; CloudCompare's default is
#: 1,024).
MAX_RESOLUTION = 32768


def _view(vertices: np.ndarray, resolution: int) -> tuple[np.ndarray, float, float]:
    """The bounding box's centre, its diagonal (1 for a single point) and pixels per unit."""
    lo = vertices.min(axis=0)
    hi = vertices.max(axis=0)
    centre = 0.5 * (lo + hi)
    side = hi - lo
    diagonal = math.sqrt(float(side[0] * side[0] + side[1] * side[1] + side[2] * side[2]))
    if not diagonal > 0.0:
        diagonal = 1.0
    return centre, diagonal, resolution / diagonal


@njit(cache=True)
def _project(vertices, d, centre, diagonal, scale, resolution, px, py, pz):  # pragma: no cover
    """Each vertex's image coordinates (``px``, ``py``, pixels) and height above the far
    plane (``pz``) seen along ``-d``: ``u = z x d`` normalised (``x`` when ``d`` is on the z
    axis), ``v = d x u``."""
    d0, d1, d2 = d[0], d[1], d[2]
    ux, uy, uz = -d1, d0, 0.0  # z x d: the view's "up" is z
    norm = math.sqrt(ux * ux + uy * uy)
    if norm < 1e-6:
        ux, uy, uz = 1.0, 0.0, 0.0
    else:
        ux /= norm
        uy /= norm
    vx = d1 * uz - d2 * uy
    vy = d2 * ux - d0 * uz
    vz = d0 * uy - d1 * ux
    for i in range(vertices.shape[0]):
        x = vertices[i, 0] - centre[0]
        y = vertices[i, 1] - centre[1]
        z = vertices[i, 2] - centre[2]
        px[i] = (x * ux + y * uy + z * uz) * scale + 0.5 * resolution
        py[i] = (x * vx + y * vy + z * vz) * scale + 0.5 * resolution
        pz[i] = x * d0 + y * d1 + z * d2 + diagonal  # above the far plane, > 0


@njit(cache=True)
def _setup(px, py, vleft, vright, vbottom, vtop, resolution, a, b, c):  # pragma: no cover
    """A face's pixel box (left, right, bottom, top; empty when left > right or bottom >
    top) and ``1 / twice its signed area`` (0 when flat in the image).

    The box from its corners' bounds (:func:`_pixel_bounds`): the pixel centres from
    ``ceil(min(x) - 1/2)`` to ``floor(max(x) - 1/2)``, within the image.
    """
    ax, ay, bx, by, cx, cy = px[a], py[a], px[b], py[b], px[c], py[c]
    area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if area == 0.0:
        return 1, 0, 1, 0, 0.0
    left = max(min(vleft[a], vleft[b], vleft[c]), 0)
    right = min(max(vright[a], vright[b], vright[c]), resolution - 1)
    bottom = max(min(vbottom[a], vbottom[b], vbottom[c]), 0)
    top = min(max(vtop[a], vtop[b], vtop[c]), resolution - 1)
    return left, right, bottom, top, 1.0 / area


@njit(cache=True)
def _depth_at(px, py, pz, a, b, c, inverse, col, row):  # pragma: no cover
    """The face's height at the pixel centre (col + 1/2, row + 1/2), or -1 where it does
    not cover it (the caller has checked that the pixel is in the face's box)."""
    ax, ay, bx, by, cx, cy = px[a], py[a], px[b], py[b], px[c], py[c]
    sx = col + 0.5
    sy = row + 0.5
    wa = ((bx - sx) * (cy - sy) - (by - sy) * (cx - sx)) * inverse
    wb = ((cx - sx) * (ay - sy) - (cy - sy) * (ax - sx)) * inverse
    wc = 1.0 - wa - wb
    if wa < 0.0 or wb < 0.0 or wc < 0.0:
        return -1.0
    return wa * pz[a] + wb * pz[b] + wc * pz[c]


@njit(cache=True)
def _pixel_bounds(px, py, resolution, col, row, left, right, bottom, top):  # pragma: no cover
    """Each vertex's pixel (rounded down, clamped to the image) and the pixel centres around
    it: ``ceil(x - 1/2)`` and ``floor(x - 1/2)`` in each axis.  A face's box is their min
    and max over its corners (:func:`_setup`; ``ceil`` and ``floor`` are monotonic, so these
    are the bounds of the corners' coordinates)."""
    for i in range(px.shape[0]):
        x = px[i]
        y = py[i]
        col[i] = min(max(math.floor(x), 0), resolution - 1)
        row[i] = min(max(math.floor(y), 0), resolution - 1)
        left[i] = math.ceil(x - 0.5)
        right[i] = math.floor(x - 0.5)
        bottom[i] = math.ceil(y - 0.5)
        top[i] = math.floor(y - 0.5)


@njit(cache=True)
def _bin_faces(
    faces,
    px,
    py,
    pz,
    resolution,
    shift,
    tiles,
    low,
    levels_per,
    vleft,
    vright,
    vbottom,
    vtop,
    box,
    inverses,
    keys,
    order,
    level_start,
    start,
    entries,
):  # pragma: no cover
    """The faces that cover a pixel centre, in the tiles their pixel box touches, each
    tile's highest first: tile ``s`` holds rows ``start[s]:start[s + 1]`` of ``entries``
    (face, key, its pixel box: :data:`ENTRY`), by descending key (the face's highest corner,
    in :data:`LEVELS` levels of the box's depth).  Returns ``entries`` (grown when needed)."""
    m = faces.shape[0]
    nb = tiles * tiles
    level_start[:] = 0
    start[:] = 0
    for f in range(m):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        left, right, bottom, top, inverse = _setup(
            px, py, vleft, vright, vbottom, vtop, resolution, a, b, c
        )
        if left > right or bottom > top:  # covers no pixel centre: marked by left > right
            box[f, 0] = 1
            box[f, 1] = 0
            continue
        box[f, 0], box[f, 1], box[f, 2], box[f, 3] = left, right, bottom, top
        inverses[f] = inverse
        key = min(max(int((max(pz[a], pz[b], pz[c]) - low) * levels_per), 0), LEVELS)
        keys[f] = key
        level_start[LEVELS - key + 1] += 1  # the highest first
        tx0, tx1, ty0, ty1 = left >> shift, right >> shift, bottom >> shift, top >> shift
        wide = tx1 - tx0
        tall = ty1 - ty0
        if wide <= 1 and tall <= 1:  # at most 2 x 2 tiles: counted without a branch
            s = ty0 * tiles + tx0 + 1
            start[s] += 1
            start[s + wide] += wide
            start[s + tall * tiles] += tall
            start[s + tall * tiles + wide] += tall & wide
        else:
            for ty in range(ty0, ty1 + 1):
                for tx in range(tx0, tx1 + 1):
                    start[ty * tiles + tx + 1] += 1
    for s in range(LEVELS + 1):
        level_start[s + 1] += level_start[s]
    for f in range(m):
        if box[f, 0] <= box[f, 1]:
            s = LEVELS - keys[f]
            order[level_start[s]] = f
            level_start[s] += 1
    count = level_start[LEVELS]
    for s in range(nb):
        start[s + 1] += start[s]
    total = start[nb]  # tile nb: the slot past the last entry, for the masked writes
    if total + 1 > entries.shape[0]:
        entries = np.empty((2 * total + 1, ENTRY), dtype=np.int32)
    for q in range(count):
        f = order[q]
        left, right, bottom, top = box[f, 0], box[f, 1], box[f, 2], box[f, 3]
        key = keys[f]
        for ty in range(bottom >> shift, (top >> shift) + 1):
            for tx in range(left >> shift, (right >> shift) + 1):
                s = ty * tiles + tx
                e = start[s]
                entries[e, 0] = f
                entries[e, 1] = key
                entries[e, 2] = left | (right << 16)
                entries[e, 3] = bottom | (top << 16)
                start[s] = e + 1
    for s in range(nb - 1, -1, -1):  # start[s] is now tile s's end
        start[s + 1] = start[s]
    start[0] = 0
    return entries


@njit(cache=True)
def _drawn(px, py, pz, faces, inverses, entries, first, last, col, row):  # pragma: no cover
    """Whether a face of entries ``first:last`` covers the pixel centre (col + 1/2, row + 1/2)."""
    for q in range(first, last):
        across = entries[q, 2]
        if col < (across & 0xFFFF) or col > (across >> 16):
            continue
        up = entries[q, 3]
        if row < (up & 0xFFFF) or row > (up >> 16):
            continue
        f = entries[q, 0]
        if _depth_at(px, py, pz, faces[f, 0], faces[f, 1], faces[f, 2], inverses[f], col, row) >= 0:
            return True
    return False


@njit(cache=True)
def _next_drawn(
    px, py, pz, faces, inverses, entries, start, shift, tiles, resolution, ci, ri
):  # pragma: no cover
    """Whether the next pixel in +u, +v or both is drawn (a vertex on an empty pixel is lit
    then)."""
    c2 = min(ci + 1, resolution - 1)
    r2 = min(ri + 1, resolution - 1)
    for w in range(3):
        cc = c2 if w != 1 else ci
        rr = r2 if w != 0 else ri
        s = (rr >> shift) * tiles + (cc >> shift)
        if _drawn(px, py, pz, faces, inverses, entries, start[s], start[s + 1], cc, rr):
            return True
    return False


@njit(cache=True, nogil=True)
def _lit_directions(
    vertices,
    faces,
    directions,
    resolution,
    keep,
    shift,
    tiles,
    centre,
    diagonal,
    scale,
    t,
    threads,
    counts,
):  # pragma: no cover
    """The queries kernel on thread `t`: directions ``t, t + threads, ...`` into ``counts[t]``.

    For each vertex: a face can hide it only if the face's highest corner is at least the
    vertex's height divided by ``keep``, so its key is then at least ``kt`` (one level of
    margin for the rounding of the keys and of a height interpolated at a pixel centre).
    The vertex's tile is read from its highest face down to ``kt``; the faces whose box
    holds the vertex's pixel are gathered without a branch per face (a branch mispredicted
    on every other face cost more than the test) and tested without one; below ``kt`` a
    face is looked for only while none has been found at the pixel.

    Run on numba's threads by :func:`dentopo._jit.in_threads` (``nogil``), not from a
    ``prange`` loop: numba compiled a parallel loop's body once more for its threads, and
    this kernel twice (6.5 -> 3 s of CPU on a fresh install); a thread's work is
    milliseconds, so starting it from Python costs nothing measurable.
    """
    n = vertices.shape[0]
    m = faces.shape[0]
    k = directions.shape[0]
    px = np.empty(n)
    py = np.empty(n)
    pz = np.empty(n)
    col = np.empty(n, dtype=np.int64)
    row = np.empty(n, dtype=np.int64)
    vleft = np.empty(n, dtype=np.int32)
    vright = np.empty(n, dtype=np.int32)
    vbottom = np.empty(n, dtype=np.int32)
    vtop = np.empty(n, dtype=np.int32)
    box = np.empty((m, 4), dtype=np.int32)
    inverses = np.empty(m)
    keys = np.empty(m, dtype=np.int32)
    order = np.empty(m, dtype=np.int32)
    level_start = np.empty(LEVELS + 2, dtype=np.int64)
    start = np.empty(tiles * tiles + 1, dtype=np.int64)
    entries = np.empty((4 * m + 1, ENTRY), dtype=np.int32)  # grown when needed
    candidates = np.empty(m, dtype=np.int64)
    low = 0.5 * diagonal  # the lowest height a vertex can have (above the far plane)
    levels_per = LEVELS / diagonal
    for j in range(t, k, threads):
        _project(vertices, directions[j], centre, diagonal, scale, resolution, px, py, pz)
        _pixel_bounds(px, py, resolution, col, row, vleft, vright, vbottom, vtop)
        entries = _bin_faces(
            faces,
            px,
            py,
            pz,
            resolution,
            shift,
            tiles,
            low,
            levels_per,
            vleft,
            vright,
            vbottom,
            vtop,
            box,
            inverses,
            keys,
            order,
            level_start,
            start,
            entries,
        )
        for i in range(n):
            ci = col[i]
            ri = row[i]
            height = pz[i]
            s = (ri >> shift) * tiles + (ci >> shift)
            kt = int((height / keep - low) * levels_per) - 1
            q = start[s]
            end = start[s + 1]
            found = 0
            while q < end and entries[q, 1] >= kt:
                candidates[found] = entries[q, 0]
                across = entries[q, 2]
                up = entries[q, 3]
                found += (
                    (ci >= (across & 0xFFFF))
                    & (ci <= (across >> 16))
                    & (ri >= (up & 0xFFFF))
                    & (ri <= (up >> 16))
                )
                q += 1
            sx = ci + 0.5
            sy = ri + 0.5
            hidden = False
            covered = False
            for p in range(found):  # _depth_at without its branches
                f = candidates[p]
                a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
                ax, ay, bx, by, cx, cy = px[a], py[a], px[b], py[b], px[c], py[c]
                inverse = inverses[f]
                wa = ((bx - sx) * (cy - sy) - (by - sy) * (cx - sx)) * inverse
                wb = ((cx - sx) * (ay - sy) - (cy - sy) * (ax - sx)) * inverse
                wc = 1.0 - wa - wb
                inside = (wa >= 0.0) & (wb >= 0.0) & (wc >= 0.0)
                depth = wa * pz[a] + wb * pz[b] + wc * pz[c]
                hidden |= inside & (height < depth * keep)
                covered |= inside
            if hidden:
                continue
            if not covered:  # lower faces cannot hide it: is the pixel drawn at all?
                covered = _drawn(px, py, pz, faces, inverses, entries, q, end, ci, ri)
            if covered or _next_drawn(
                px, py, pz, faces, inverses, entries, start, shift, tiles, resolution, ci, ri
            ):
                counts[t, i] += 1


@njit(cache=True, nogil=True)
def _lit_directions_image(
    vertices, faces, directions, resolution, tolerance, centre, diagonal, scale, t, threads, counts
):  # pragma: no cover
    """The image kernel on thread `t` (see ``_lit_directions``)."""
    n = vertices.shape[0]
    k = directions.shape[0]
    buffer = np.zeros((resolution, resolution))  # 0: nothing drawn (the far plane)
    px = np.empty(n)
    py = np.empty(n)
    pz = np.empty(n)
    col = np.empty(n, dtype=np.int64)
    row = np.empty(n, dtype=np.int64)
    vleft = np.empty(n, dtype=np.int32)
    vright = np.empty(n, dtype=np.int32)
    vbottom = np.empty(n, dtype=np.int32)
    vtop = np.empty(n, dtype=np.int32)
    for j in range(t, k, threads):
        _project(vertices, directions[j], centre, diagonal, scale, resolution, px, py, pz)
        _pixel_bounds(px, py, resolution, col, row, vleft, vright, vbottom, vtop)
        x0, x1, y0, y1 = resolution, -1, resolution, -1
        for f in range(faces.shape[0]):
            a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
            left, right, bottom, top, inverse = _setup(
                px, py, vleft, vright, vbottom, vtop, resolution, a, b, c
            )
            if left > right or bottom > top:
                continue
            x0, x1 = min(x0, left), max(x1, right)
            y0, y1 = min(y0, bottom), max(y1, top)
            for r in range(bottom, top + 1):
                for q in range(left, right + 1):
                    depth = _depth_at(px, py, pz, a, b, c, inverse, q, r)
                    if depth > buffer[r, q]:
                        buffer[r, q] = depth
        for i in range(n):
            ci = col[i]
            ri = row[i]
            held = buffer[ri, ci]
            if held > 0.0:
                if pz[i] >= held * (1.0 - tolerance):
                    counts[t, i] += 1
            else:  # an empty pixel: lit when the next one in +u, +v or both is drawn
                c2 = min(ci + 1, resolution - 1)
                r2 = min(ri + 1, resolution - 1)
                if buffer[ri, c2] > 0.0 or buffer[r2, ci] > 0.0 or buffer[r2, c2] > 0.0:
                    counts[t, i] += 1
        for r in range(y0, y1 + 1):  # clear what was drawn
            for q in range(x0, x1 + 1):
                buffer[r, q] = 0.0


def _shift(n: int, resolution: int) -> int:
    """Tiles of ``2**shift`` pixels a side: about one vertex a tile for a crown that fills a
    third of the image (16 pixels for the 4,050-vertex crowns at 1,024 pixels and 8 for
    the 10,080-vertex one, the fastest there)."""
    side = math.log2(resolution / math.sqrt(max(n, 1)))
    return max(0, min(round(side), int(math.log2(resolution))))


#: Above this many vertices per pixel of the image, drawing the whole image is cheaper than
#: querying the vertices' pixels (measured on a crown subdivided to 16,000, 64,000 and
#: 256,000 vertices, CPU a vertex and direction: the queries 230, 380 and 450 ns, the
#: image 780, 290 and 120 ns; they cross near 30,000 vertices at 1,024 pixels).
IMAGE_ABOVE = 1 / 32


def lit_counts_depth_buffer(
    vertices: np.ndarray,
    faces: np.ndarray,
    directions: np.ndarray,
    resolution: int = 1024,
    *,
    path: str | None = None,
) -> np.ndarray:
    """(n,) int64: from how many of the `directions` each vertex is lit (module's notes).

    `vertices` (n, 3) float, `faces` (m, 3) int, `directions` (k, 3) unit vectors towards
    the light.  `path`: ``"queries"`` (each vertex's pixels), ``"image"`` (the whole image
    drawn), or None: the cheaper for the mesh's size (the counts are the same).  Never
    modifies its arguments.
    """
    import numba

    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int32)  # half the int64's cache lines
    directions = np.ascontiguousarray(directions, dtype=np.float64)
    threads = max(1, min(numba.get_num_threads(), len(directions)))
    resolution = int(resolution)
    if not 1 <= resolution <= MAX_RESOLUTION:
        raise ValueError(f"resolution must be between 1 and {MAX_RESOLUTION}; got {resolution}")
    if path is None:
        path = "image" if len(vertices) > IMAGE_ABOVE * resolution**2 else "queries"
    centre, diagonal, scale = _view(vertices, resolution)
    counts = np.zeros((threads, len(vertices)), dtype=np.int64)
    if path == "image":

        def work(t: int) -> None:
            _lit_directions_image(
                vertices, faces, directions, resolution, TOLERANCE, centre, diagonal, scale,
                t, threads, counts,
            )  # fmt: skip

    else:
        shift = _shift(len(vertices), resolution)
        tiles = ((resolution - 1) >> shift) + 1
        keep = 1.0 - TOLERANCE

        def work(t: int) -> None:
            _lit_directions(
                vertices, faces, directions, resolution, keep, shift, tiles, centre, diagonal,
                scale, t, threads, counts,
            )  # fmt: skip

    # thread t takes directions t, t + threads, ...: its own counts, summed at the end
    in_threads(0, threads, lambda a, b: [work(t) for t in range(a, b)])
    return counts.sum(axis=0)

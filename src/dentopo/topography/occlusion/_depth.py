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
*queries* kernel computes only the pixels read: each face first at its own corners' pixels
(which covers nearly every vertex), then, the vertices sorted by height into tiles of a few
pixels, each face tests only the vertices of the tiles its pixel box touches that lie below
its highest corner (a face cannot hide what is above it), and every face the few vertices
that no face of their own covers.  Its cost grows with vertices plus faces, not pixels.  The
*image* kernel draws the whole image, face by face over its pixel box: cheaper once faces are
smaller than pixels (above about 30,000 vertices at 1,024 pixels, :data:`IMAGE_ABOVE`).  Both
use the same test and the same height at a pixel centre, so their counts are equal (the
tests compare both with an image drawn by numpy).

The directions run in parallel, each thread with its own arrays and its own counts (summed
at the end), so that the counts do not depend on the number of threads.

May import: :mod:`dentopo._jit`.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import njit, prange

#: A vertex is lit when its height above the far plane is at least ``1 - TOLERANCE`` times
#: the buffer's at its pixel (CloudCompare 2.11.3: 0.002, probed to within 0.1 %).
TOLERANCE = 2e-3


@njit(cache=True)
def _view(vertices, resolution):  # pragma: no cover
    """The bounding box's centre, its diagonal (1 for a single point) and pixels per unit."""
    lo = np.empty(3)
    hi = np.empty(3)
    for a in range(3):
        lo[a] = vertices[:, a].min()
        hi[a] = vertices[:, a].max()
    centre = 0.5 * (lo + hi)
    diagonal = math.sqrt(np.sum((hi - lo) ** 2))
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
def _setup(px, py, resolution, a, b, c):  # pragma: no cover
    """A face's pixel box (left, right, bottom, top; empty when left > right or bottom >
    top) and ``1 / twice its signed area`` (0 when flat in the image)."""
    ax, ay, bx, by, cx, cy = px[a], py[a], px[b], py[b], px[c], py[c]
    area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    if area == 0.0:
        return 1, 0, 1, 0, 0.0
    left = max(math.ceil(min(ax, bx, cx) - 0.5), 0)
    right = min(math.floor(max(ax, bx, cx) - 0.5), resolution - 1)
    bottom = max(math.ceil(min(ay, by, cy) - 0.5), 0)
    top = min(math.floor(max(ay, by, cy) - 0.5), resolution - 1)
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
def _sort(
    members, count, col, row, pz, keyed, shift, tiles, start, order, height
):  # pragma: no cover
    """Sort ``members[:count]`` into square tiles of ``2**shift`` pixels: tile ``s`` holds
    ``order[start[s]:start[s + 1]]``, lowest first (``height`` their heights; -1 for those
    not `keyed`, first)."""
    start[:] = 0
    for q in range(count):
        i = members[q]
        start[(row[i] >> shift) * tiles + (col[i] >> shift) + 1] += 1
    for s in range(tiles * tiles):
        start[s + 1] += start[s]
    for q in range(count):  # filled from each tile's end, so that start ends as it began
        i = members[q]
        s = (row[i] >> shift) * tiles + (col[i] >> shift) + 1
        start[s] -= 1
        order[start[s]] = i
    for s in range(tiles * tiles):  # start[s + 1] is now tile s's first
        start[s] = start[s + 1]
    start[tiles * tiles] = count
    for q in range(count):
        height[q] = pz[order[q]] if keyed[order[q]] else -1.0
    for s in range(tiles * tiles):  # each tile by height (a handful of vertices)
        for q in range(start[s] + 1, start[s + 1]):
            i, h = order[q], height[q]
            r = q - 1
            while r >= start[s] and height[r] > h:
                order[r + 1] = order[r]
                height[r + 1] = height[r]
                r -= 1
            order[r + 1] = i
            height[r + 1] = h


@njit(cache=True)
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
    """``_lit_counts``' work on thread `t`: directions ``t, t + threads, ...`` into ``counts[t]``.

    A function of its own, not the body of the ``prange`` loop: numba compiles a parallel
    loop's body once more for its threads, and this is most of the kernel (seconds saved
    on a fresh install).
    """
    n = vertices.shape[0]
    m = faces.shape[0]
    k = directions.shape[0]
    px = np.empty(n)
    py = np.empty(n)
    pz = np.empty(n)
    col = np.empty(n, dtype=np.int64)
    row = np.empty(n, dtype=np.int64)
    covered = np.empty(n, dtype=np.bool_)  # by a face of the vertex's own
    hidden = np.empty(n, dtype=np.bool_)  # a face at its pixel is too high
    held = np.empty(n)  # the greatest height at the pixel (vertices left uncovered)
    near = np.empty(n, dtype=np.bool_)  # a next pixel in +u/+v is drawn (the same)
    members = np.empty(n, dtype=np.int64)
    start = np.empty(tiles * tiles + 1, dtype=np.int64)
    order = np.empty(n, dtype=np.int64)
    height = np.empty(n)
    boxes = np.empty((m, 4), dtype=np.int64)
    inverses = np.empty(m)
    for j in range(t, k, threads):
        _project(vertices, directions[j], centre, diagonal, scale, resolution, px, py, pz)
        for i in range(n):
            col[i] = min(max(math.floor(px[i]), 0), resolution - 1)
            row[i] = min(max(math.floor(py[i]), 0), resolution - 1)
            covered[i] = False
            hidden[i] = False
        # 1. each face at its own corners' pixels
        for f in range(m):
            a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
            left, right, bottom, top, inverse = _setup(px, py, resolution, a, b, c)
            boxes[f, 0], boxes[f, 1], boxes[f, 2], boxes[f, 3] = left, right, bottom, top
            inverses[f] = inverse
            if left > right or bottom > top:
                continue
            for i in (a, b, c):
                if col[i] < left or col[i] > right or row[i] < bottom or row[i] > top:
                    continue
                depth = _depth_at(px, py, pz, a, b, c, inverse, col[i], row[i])
                if depth >= 0.0:
                    covered[i] = True
                    if pz[i] < depth * keep:
                        hidden[i] = True
        # 2. any face too high at the pixel of a vertex covered so (the tiles' lowest
        # first, so that a face stops at the first vertex above it); every face at the
        # pixel of a vertex no face of its own covers, and at the next in +u/+v
        count = 0
        for i in range(n):
            if not covered[i] or not hidden[i]:
                members[count] = i
                count += 1
                held[i] = 0.0
                near[i] = False
        _sort(members, count, col, row, pz, covered, shift, tiles, start, order, height)
        for f in range(m):
            left, right, bottom, top = boxes[f, 0], boxes[f, 1], boxes[f, 2], boxes[f, 3]
            if left > right or bottom > top:
                continue
            a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
            highest = max(pz[a], pz[b], pz[c])
            for ty in range(max(bottom - 1, 0) >> shift, (top >> shift) + 1):
                for tx in range(max(left - 1, 0) >> shift, (right >> shift) + 1):
                    s = ty * tiles + tx
                    for q in range(start[s], start[s + 1]):
                        if height[q] >= highest:
                            break  # the face is below the rest of the tile
                        i = order[q]
                        ci, ri = col[i], row[i]
                        if covered[i]:
                            # one branch, rarely taken: the pixel in the box, the vertex
                            # not yet hidden, not a corner of this face
                            test = (
                                (ci >= left)
                                & (ci <= right)
                                & (ri >= bottom)
                                & (ri <= top)
                                & (not hidden[i])
                                & (i != a)
                                & (i != b)
                                & (i != c)
                            )
                            if test:
                                depth = _depth_at(px, py, pz, a, b, c, inverses[f], ci, ri)
                                if depth >= 0.0 and pz[i] < depth * keep:
                                    hidden[i] = True
                            continue
                        if ci + 1 < left or ci > right or ri + 1 < bottom or ri > top:
                            continue
                        if ci >= left and ri >= bottom:
                            depth = _depth_at(px, py, pz, a, b, c, inverses[f], ci, ri)
                            if depth > held[i]:
                                held[i] = depth
                        if held[i] > 0.0 or near[i]:
                            continue
                        c2 = min(ci + 1, resolution - 1)
                        r2 = min(ri + 1, resolution - 1)
                        for cc, rr in ((c2, ri), (ci, r2), (c2, r2)):
                            if cc < left or cc > right or rr < bottom or rr > top:
                                continue
                            if _depth_at(px, py, pz, a, b, c, inverses[f], cc, rr) >= 0.0:
                                near[i] = True
                                break
        for i in range(n):
            if covered[i]:
                lit = not hidden[i]
            elif held[i] > 0.0:
                lit = pz[i] >= held[i] * keep
            else:  # an empty pixel: lit when the next one in +u, +v or both is drawn
                lit = near[i]
            if lit:
                counts[t, i] += 1


@njit(cache=True, parallel=True)
def _lit_counts(
    vertices, faces, directions, resolution, tolerance, threads, shift, total
):  # pragma: no cover
    n = vertices.shape[0]
    centre, diagonal, scale = _view(vertices, resolution)
    keep = 1.0 - tolerance
    tiles = ((resolution - 1) >> shift) + 1
    counts = np.zeros((threads, n), dtype=np.int64)
    for t in prange(threads):
        _lit_directions(
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
        )
    for t in range(threads):  # into the caller's array: a kernel returns no array
        for i in range(n):  # element by element: see _sort
            total[i] += counts[t, i]


@njit(cache=True)
def _lit_directions_image(
    vertices, faces, directions, resolution, tolerance, centre, diagonal, scale, t, threads, counts
):  # pragma: no cover
    """``_lit_counts_image``' work on thread `t` (see ``_lit_directions``)."""
    n = vertices.shape[0]
    k = directions.shape[0]
    buffer = np.zeros((resolution, resolution))  # 0: nothing drawn (the far plane)
    px = np.empty(n)
    py = np.empty(n)
    pz = np.empty(n)
    for j in range(t, k, threads):
        _project(vertices, directions[j], centre, diagonal, scale, resolution, px, py, pz)
        x0, x1, y0, y1 = resolution, -1, resolution, -1
        for f in range(faces.shape[0]):
            a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
            left, right, bottom, top, inverse = _setup(px, py, resolution, a, b, c)
            if left > right or bottom > top:
                continue
            x0, x1 = min(x0, left), max(x1, right)
            y0, y1 = min(y0, bottom), max(y1, top)
            for row in range(bottom, top + 1):
                for col in range(left, right + 1):
                    depth = _depth_at(px, py, pz, a, b, c, inverse, col, row)
                    if depth > buffer[row, col]:
                        buffer[row, col] = depth
        for i in range(n):
            col = min(max(math.floor(px[i]), 0), resolution - 1)
            row = min(max(math.floor(py[i]), 0), resolution - 1)
            held = buffer[row, col]
            if held > 0.0:
                if pz[i] >= held * (1.0 - tolerance):
                    counts[t, i] += 1
            else:  # an empty pixel: lit when the next one in +u, +v or both is drawn
                c2 = min(col + 1, resolution - 1)
                r2 = min(row + 1, resolution - 1)
                if buffer[row, c2] > 0.0 or buffer[r2, col] > 0.0 or buffer[r2, c2] > 0.0:
                    counts[t, i] += 1
        for row in range(y0, y1 + 1):  # clear what was drawn
            for col in range(x0, x1 + 1):
                buffer[row, col] = 0.0


@njit(cache=True, parallel=True)
def _lit_counts_image(
    vertices, faces, directions, resolution, tolerance, threads, total
):  # pragma: no cover
    n = vertices.shape[0]
    centre, diagonal, scale = _view(vertices, resolution)
    counts = np.zeros((threads, n), dtype=np.int64)
    for t in prange(threads):
        _lit_directions_image(
            vertices,
            faces,
            directions,
            resolution,
            tolerance,
            centre,
            diagonal,
            scale,
            t,
            threads,
            counts,
        )
    for t in range(threads):  # into the caller's array: a kernel returns no array
        for i in range(n):  # element by element: see _sort
            total[i] += counts[t, i]


def _shift(n: int, resolution: int) -> int:
    """Tiles of ``2**shift`` pixels a side: a few vertices a tile (8 pixels for the 4,050-
    and 10,080-vertex crowns at 1,024 pixels, the fastest there; 1 pixel for a million)."""
    side = math.log2(resolution / math.sqrt(max(n, 1))) - 0.6
    return max(0, min(round(side), int(math.log2(resolution))))


#: Above this many vertices per pixel of the image, drawing the whole image is cheaper than
#: querying the vertices' pixels (measured: the queries cost about 450 ns a vertex and
#: direction, the image about 120 ns at 256,000 vertices and 720 at 16,000; they cross
#: near 30,000 vertices at 1,024 pixels).
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
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    directions = np.ascontiguousarray(directions, dtype=np.float64)
    threads = max(1, min(numba.get_num_threads(), len(directions)))
    resolution = int(resolution)
    if path is None:
        path = "image" if len(vertices) > IMAGE_ABOVE * resolution**2 else "queries"
    total = np.zeros(len(vertices), dtype=np.int64)
    if path == "image":
        _lit_counts_image(vertices, faces, directions, resolution, TOLERANCE, threads, total)
    else:
        shift = _shift(len(vertices), resolution)
        _lit_counts(vertices, faces, directions, resolution, TOLERANCE, threads, shift, total)
    return total

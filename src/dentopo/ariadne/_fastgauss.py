"""Fast Gauss transform of the kernel moments, for large meshes (``method="fast"``).

The Euclidean kernel sums of ariaDNE are a discrete Gauss transform:
``F(x) = sum_j exp(-|x - x_j|**2 / h**2)`` evaluated at every vertex.  All ten
moments follow from ``F`` and its derivatives, because differentiating the
kernel brings down the offsets ``x_j - x``:

* ``S0_i = F(x_i)``
* ``sum_j w_ij (x_j - x_i) = (h**2 / 2) grad F(x_i)``
* ``sum_j w_ij (x_j - x_i)(x_j - x_i)^T = (h**4 / 4) Hess F(x_i) + (h**2 / 2) F(x_i) I``

``F`` is computed spectrally on a periodic box padded by more than the
kernel's reach (so no periodic image contributes a weight above 1e-17): one
type-1 non-uniform FFT (FINUFFT, Barnett, Magland & af Klinteberg 2019,
doi:10.1137/18M120885X) takes the vertices to Fourier modes, the modes are
multiplied by the Gaussian's Fourier transform (and by ``i k`` and ``-k k^T``
for the derivatives), and type-2 transforms evaluate the ten real fields at the
vertices, packed in pairs as the real and imaginary parts of five complex ones.
Cost: O(n + N log N) for N Fourier modes (N grows as ``(extent / h)**3``,
independent of n); memory linear in n.

Error model.  FINUFFT's tolerance ``eps`` bounds the relative l2 error of each
transform.  Because the moments are taken *about each vertex* through the
derivatives (never as raw moments ``sum w x x^T`` minus ``g g^T``), no large
coordinate offsets cancel: the covariance ``C_i`` has an absolute error of about
``eps * h**2``, i.e. about ``eps`` relative to its trace, and the local bending
``lambda / trace`` an absolute error of a few ``eps``.  The one cancellation
left is in the normal direction, where ``(h**4/4) F_nn`` and ``(h**2/2) F``
nearly cancel; it costs nothing relative to the trace, which is what the
bending is divided by.  The weighted centroid has an absolute error of about
``eps * h``; only centroids that close to the closed surface can change sign.
With the default ``eps = 1e-10`` the totals agreed with the exact sums to 2e-12
relative or better and every sign was identical on noisy crowns of 10k-120k
vertices (benchmarks/bench_scaling.py; tests/test_fastgauss.py checks 1e-8).
That cancellation grows as ``eps (h / extent)**2`` relative to the trace once
the kernel reaches far beyond the mesh (1e-8 at ``h`` = 10 extents, nonsense
at 1e4).  Above ``DERIVATIVES_UP_TO`` extents (a huge bandwidth, or a mesh
shrunk by the unit-area scaling because a stray vertex's long triangles
count in its area) the moments therefore come from the raw sums
``sum_j w_ij x_j^p`` (five type-1 transforms of packed strengths), about the
box's centre: every weight is then close to 1 and nothing large cancels.

Bounding boxes.  The mode grid spans the points' bounding box, which one stray
vertex far away can make ~1e18 modes.  When all the points do not fit, they
are cut into groups out of one another's reach (``plan_fast``): each large
group gets its own transform and small ones (the stray vertex) the exact sums.

Determinism.  FINUFFT's multithreaded spreading (type 1) adds the threads'
subgrids in whichever order they finish, and its FFTs round differently with
the thread count, so results varied in the last bits between runs and between
``-j`` settings.  Every transform therefore runs single-threaded (FINUFFT's
option ``nthreads=1``), which is deterministic, and threads share the five
independent type-2 transforms instead: the same bits at any thread count, for
about the cost of the multithreaded type 1 (measured on a 100k-vertex crown).
From ``SPLIT_SPECTRUM_FROM`` (200,000) points on, the type-1 transform is cut
into two runs of consecutive points, on two threads, whose spectra are added in
a fixed order: the same bits at any thread count again (they differ from one
transform's by rounding, about 1e-14 relative).

A weight cutoff ``c > 0`` truncates the kernel, which a Gauss transform cannot
do; the fast path requires ``cutoff == 0`` and Euclidean distances.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from .._jit import in_threads, njit
from .._optional import FAST_METHOD
from ._eigen import PARALLEL_VERTICES
from ._kernel import (
    COUNTED_UP_TO,
    KernelMoments,
    euclidean_moments,
    few_neighbour_counts,
    kernel_radius,
)
from ._parameters import check_bandwidth

#: FINUFFT tolerance used by default (see the module's error model).
DEFAULT_TOLERANCE = 1e-10

#: Fourier modes are kept while the Gaussian's multiplier exceeds exp(-CUT**2).
_SPECTRAL_CUT = 6.3
#: The periodic box is padded by this many bandwidths beyond the vertices'
#: extent: images are then at least this far away (weight below 6e-18).
_PERIODIC_PAD = 6.3
#: Above this many Fourier modes the fast path refuses (memory, and the exact
#: sums are cheap anyway when h is that small relative to the mesh).
MAX_MODES = 64_000_000
#: Above this many times the points' largest extent, the moments come from the
#: raw sums (``_raw_moments``): ``(h**4/4) F_nn`` and ``(h**2/2) F`` cancel to
#: ``eps (h / extent)**2`` relative (1e-8 at 10 extents, nonsense at 1e4),
#: while the raw sums' error falls as h grows; on a crown they cross near half
#: the extent (both about 3e-11 relative to the covariance's trace).
DERIVATIVES_UP_TO = 0.5
#: Groups of fewer points than this are summed exactly (at most this many pairs per point).
MIN_FAST_POINTS = 256


def _require_finufft():
    """The ``finufft`` module, or :class:`~dentopo._optional.MissingExtraError` (fast extra)."""
    return FAST_METHOD.require()


def finufft_available() -> bool:
    """True if the optional ``finufft`` package can be imported."""
    try:
        _require_finufft()
    except ImportError:  # not installed, or installed but broken: the exact sums it is
        return False
    return True


def mode_grid(points: np.ndarray, bandwidth: float) -> tuple[np.ndarray, np.ndarray]:
    """Periods ``L`` (3,) and odd mode counts ``N`` (3,) of the periodic box.

    The counts are floats (they can exceed any integer type for a tiny
    bandwidth); compare their product with ``MAX_MODES`` before using them.
    """
    span = np.ptp(points, axis=0)
    period = span + _PERIODIC_PAD * bandwidth
    k_max = 2.0 * _SPECTRAL_CUT / bandwidth
    half = np.ceil(k_max * period / (2.0 * np.pi))
    return period, 2.0 * half + 1.0


def _transform_problem(points: np.ndarray, bandwidth: float) -> str | None:
    """Why the transform cannot cover `points` (one group), or None if it can."""
    _, modes = mode_grid(points, bandwidth)
    count = float(np.prod(modes))
    if not count <= MAX_MODES:
        return (
            f"bandwidth {bandwidth:g} is too small for the fast transform on this mesh "
            f"({count:.3g} Fourier modes > {MAX_MODES}); use method='exact'"
        )
    return None


def _islands(points: np.ndarray, reach: float) -> list[np.ndarray]:
    """Sorted index groups of the points, farther than `reach` from one another.

    Every group is cut at each gap wider than `reach` in its coordinates along
    each axis in turn, until no group splits (at most a few rounds; stopping
    early would only leave larger groups, never wrong ones).  O(n log n) per round.
    """
    n = len(points)
    labels = np.zeros(n, dtype=np.int64)
    for _ in range(4):
        split = False
        for axis in range(3):
            order = np.lexsort((points[:, axis], labels))
            x = points[order, axis]
            same = labels[order][1:] == labels[order][:-1]
            cut = same & (np.diff(x) > reach)
            split = split or bool(cut.any())
            labels[order] = np.cumsum(np.concatenate([[0], ~same | cut]))
        if not split:
            break
    order = np.argsort(labels, kind="stable")  # indices ascending within each group
    return np.split(order, np.flatnonzero(np.diff(labels[order])) + 1)


@dataclass(frozen=True)
class FastPlan:
    """How the moments of a point set are computed: transforms per group, exact for the rest.

    ``groups`` are index arrays each covered by one transform (``None``: all
    the points); ``exact`` the indices summed exactly (small groups far from
    every other point); ``problem`` why the transform cannot run (then it
    must not be used), or None.
    """

    groups: list
    exact: np.ndarray
    problem: str | None


def plan_fast(points: np.ndarray, bandwidth: float) -> FastPlan:
    """Split `points` for the fast transform (see :class:`FastPlan`).

    All the points go into one transform when they fit (the ordinary case).
    Otherwise (typically one stray vertex far away, whose bounding box would
    need far too many Fourier modes) they are cut into groups farther apart
    than the kernel's reach, where every weight between groups is below
    ``exp(-_PERIODIC_PAD**2)``, as the periodic images already are: groups of
    ``MIN_FAST_POINTS`` or more get their own transform, smaller ones the
    exact sums.
    """
    empty = np.empty(0, dtype=np.int64)
    problem = _transform_problem(points, bandwidth)
    if problem is None:
        return FastPlan([None], empty, None)
    groups, exact = [], []
    for group in _islands(points, _PERIODIC_PAD * bandwidth):
        if len(group) < MIN_FAST_POINTS:
            exact.append(group)
            continue
        problem = _transform_problem(points[group], bandwidth)
        if problem is not None:
            return FastPlan([], empty, problem)
        groups.append(group)
    exact = np.sort(np.concatenate(exact)) if exact else empty
    return FastPlan(groups, exact, None)


def fits(points: np.ndarray, bandwidth: float) -> bool:
    """True if the fast transform can compute the moments of `points` (see `plan_fast`)."""
    return plan_fast(points, bandwidth).problem is None


def fast_euclidean_moments(
    points: np.ndarray,
    bandwidth: float,
    *,
    tolerance: float = DEFAULT_TOLERANCE,
    nthreads: int | None = None,
) -> KernelMoments:
    """Kernel moments with straight-line distances by a fast Gauss transform.

    Parameters
    ----------
    points : (n, 3) float
        Vertex positions (unit-area scale, centred).
    bandwidth : float
        Kernel bandwidth ``h``; every weight ``exp(-d**2 / h**2)`` is summed
        (no cutoff).
    tolerance : float, default ``DEFAULT_TOLERANCE``
        FINUFFT's relative tolerance (see the module's error model).
    nthreads : int, optional
        Threads (default: numba's thread count).  The result does not depend
        on it: every transform runs single-threaded (FINUFFT's multithreaded
        spreading adds its subgrids in whichever order the threads finish, and
        its FFTs differ with the thread count), and the threads share the five
        output transforms.

    Returns
    -------
    KernelMoments
        As ``euclidean_moments`` returns, except that ``count`` is exact only
        where it is below 4 (vertices with more neighbours get 4): counts are
        used only to warn about vertices with 3 or fewer neighbours.

    Raises
    ------
    ImportError
        If FINUFFT is not installed.
    ValueError
        If the mesh is so large relative to ``bandwidth`` that the mode grid
        would exceed ``MAX_MODES`` (see ``plan_fast``).
    """
    finufft = _require_finufft()
    if nthreads is None:
        import numba

        nthreads = numba.get_num_threads()
    points = np.ascontiguousarray(points, dtype=np.float64)
    h = check_bandwidth(bandwidth)
    plan = plan_fast(points, h)
    if plan.problem is not None:
        raise ValueError(plan.problem)
    if len(plan.groups) == 1 and plan.groups[0] is None:  # all the points, one transform
        return _transform_moments(finufft, points, h, tolerance, nthreads)
    n = len(points)
    weight, first = np.zeros(n), np.zeros((n, 3))
    second, count = np.zeros((n, 3, 3)), np.zeros(n, dtype=np.int64)
    parts = [
        (group, _transform_moments(finufft, points[group], h, tolerance, nthreads))
        for group in plan.groups
    ]
    if len(plan.exact):
        parts.append((plan.exact, euclidean_moments(points[plan.exact], h, 0.0)))
    for index, moments in parts:
        weight[index] = moments.weight
        first[index] = moments.first
        second[index] = moments.second
        count[index] = np.minimum(moments.count, COUNTED_UP_TO)
    return KernelMoments(weight, first, second, count)


def _run_plans(finufft, kind, shape, coords, inputs, tolerance, nthreads):
    """One single-threaded FINUFFT transform per input, spread over `nthreads` threads.

    Single-threaded transforms are deterministic and independent of the thread
    count; ctypes releases the GIL while FINUFFT runs, so they run in parallel.
    Type-2 transforms go to :func:`_interpolate`.
    """
    if kind == 2:
        return _interpolate(finufft, shape, coords, inputs, tolerance, nthreads)
    shape = tuple(int(m) for m in shape)

    def run(data):
        plan = finufft.Plan(kind, shape, n_trans=1, eps=tolerance, isign=-1, nthreads=1)
        plan.setpts(*coords)
        return plan.execute(data)

    workers = max(1, min(int(nthreads), len(inputs)))
    if workers == 1:
        return [run(data) for data in inputs]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=workers) as pool:
        return list(pool.map(run, inputs))


#: Type-2 transforms cut their points into parts of at least this many, one per thread.
MIN_INTERPOLATED = 50_000


def _interpolate(finufft, shape, coords, spectra, tolerance, nthreads):
    """Type-2 transforms of every spectrum at every point, the points cut among the threads.

    FINUFFT's type 2 spreads the spectrum on its fine grid (independent of the
    points) and then interpolates each point from that grid alone, in the same
    order whichever other points its plan holds: each value has the same bits
    however the points are cut (``tests/test_fastgauss.py`` checks it).  So
    each thread takes a part of the points (one plan, its points sorted once)
    through all the spectra: every thread busy to the end, where a transform
    per thread left one idle for the last of five.
    """
    shape = tuple(int(m) for m in shape)
    n = len(coords[0])
    parts = max(1, min(int(nthreads), n // MIN_INTERPOLATED))
    bounds = np.linspace(0, n, parts + 1).astype(np.int64)
    values = [np.empty(n, dtype=np.complex128) for _ in spectra]

    def run(first, stop):
        plan = finufft.Plan(2, shape, n_trans=1, eps=tolerance, isign=1, nthreads=1)
        plan.setpts(*(np.ascontiguousarray(c[first:stop]) for c in coords))
        for spectrum, out in zip(spectra, values, strict=True):
            out[first:stop] = plan.execute(spectrum)

    if parts == 1:
        run(0, n)
        return values
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=parts) as pool:
        for done in [pool.submit(run, a, b) for a, b in pairwise(bounds.tolist())]:
            done.result()
    return values


#: From this many points on, the type-1 transform of ``_derivative_moments`` is
#: cut into ``_SPECTRUM_PARTS`` runs of consecutive points whose spectra are
#: added in order: the threads share it, with the same bits at any thread count.
SPLIT_SPECTRUM_FROM = 200_000
_SPECTRUM_PARTS = 2


def _spectrum(finufft, shape, coords, tolerance, nthreads):
    """Type-1 transform of unit strengths at `coords`, in fixed parts for large point sets."""
    n = len(coords[0])
    parts = _SPECTRUM_PARTS if n >= SPLIT_SPECTRUM_FROM else 1
    bounds = np.linspace(0, n, parts + 1).astype(np.int64)
    pieces = [slice(int(a), int(b)) for a, b in pairwise(bounds)]
    isign, shape = -1, tuple(int(m) for m in shape)

    def run(piece):
        plan = finufft.Plan(1, shape, n_trans=1, eps=tolerance, isign=isign, nthreads=1)
        plan.setpts(*(np.ascontiguousarray(c[piece]) for c in coords))
        return plan.execute(np.ones(piece.stop - piece.start, dtype=np.complex128))

    workers = max(1, min(int(nthreads), parts))
    if workers == 1:
        spectra = [run(piece) for piece in pieces]
    else:
        from concurrent.futures import ThreadPoolExecutor

        with ThreadPoolExecutor(max_workers=workers) as pool:
            spectra = list(pool.map(run, pieces))
    spectrum = spectra[0]
    for more in spectra[1:]:  # in order: the same sum whichever thread finished first
        spectrum += more
    return spectrum


def _transform_moments(finufft, points, h, tolerance, nthreads) -> KernelMoments:
    """The moments of `points` (one group that fits) by the transforms."""
    period, modes = mode_grid(points, h)
    centre = (points.min(axis=0) + points.max(axis=0)) / 2.0
    offset = points - centre
    scaled = offset * (2.0 * np.pi / period)
    coords = [np.ascontiguousarray(scaled[:, a]) for a in range(3)]
    shape = tuple(int(m) for m in modes)

    # wavenumbers per axis (CMCL order: -(N-1)/2 .. (N-1)/2) and the Gaussian's
    # Fourier coefficients on the periodic box
    k = [
        2.0 * np.pi * np.arange(-(m // 2), m // 2 + 1) / p
        for m, p in zip(shape, period, strict=True)
    ]
    kx, ky, kz = k[0][:, None, None], k[1][None, :, None], k[2][None, None, :]
    gauss = (np.pi**1.5 * h**3 / np.prod(period)) * (
        np.exp(-(kx**2) * h**2 / 4.0)
        * np.exp(-(ky**2) * h**2 / 4.0)
        * np.exp(-(kz**2) * h**2 / 4.0)
    )
    if h > DERIVATIVES_UP_TO * float(np.ptp(points, axis=0).max()):
        weight, first, second = _raw_moments(
            finufft, shape, coords, offset, gauss, tolerance, nthreads
        )
    else:
        weight, first, second = _derivative_moments(
            finufft, shape, coords, (kx, ky, kz), gauss, h, tolerance, nthreads
        )
    radius = kernel_radius(h, 0.0)
    count = few_neighbour_counts(points, weight, radius)
    return KernelMoments(weight, first, second, count)


def _derivative_moments(finufft, shape, coords, k, gauss, h, tolerance, nthreads):
    """Weight, first and second moments from ``F`` and its derivatives (module docstring)."""
    kx, ky, kz = k
    spectrum = _spectrum(finufft, shape, coords, tolerance, nthreads)
    spectrum *= gauss
    # real and imaginary parts of each packed field are two real fields
    packed = [
        spectrum * (1.0 - 1j * kx**2),  # F,   F_xx
        spectrum * (-(ky**2) - 1j * kz**2),  # F_yy, F_zz
        spectrum * (-(kx * ky) - 1j * (kx * kz)),  # F_xy, F_xz
        spectrum * (-(ky * kz) - kx),  # F_yz, F_x  (i * i k_x = -k_x)
        spectrum * (1j * ky - kz),  # F_y,  F_z
    ]
    del spectrum
    values = _run_plans(finufft, 2, shape, coords, packed, tolerance, nthreads)
    del packed

    half_h2 = h**2 / 2.0
    quarter_h4 = h**4 / 4.0
    n = len(values[0])
    weight = np.ascontiguousarray(values[0].real)
    first = np.empty((n, 3))
    second = np.empty((n, 3, 3))
    for k, fields in enumerate(_FIELDS):  # filled, and freed, one transform at a time
        for part, where in zip((values[k].real, values[k].imag), fields, strict=True):
            if where is None:
                continue
            kind, index = where
            if kind == "first":
                np.multiply(part, half_h2, out=first[:, index])
                continue
            np.multiply(part, quarter_h4, out=second[:, index[0], index[1]])
            if index[0] != index[1]:
                second[:, index[1], index[0]] = second[:, index[0], index[1]]
        values[k] = None
    for a in range(3):
        second[:, a, a] += half_h2 * weight
    return weight, first, second


#: What the real and imaginary parts of the five type-2 outputs hold, in
#: ``_derivative_moments``: an entry of the Hessian (times ``h**4 / 4``, into
#: ``second``) or of the gradient (times ``h**2 / 2``, into ``first``); None: F.
_FIELDS = (
    (None, ("second", (0, 0))),
    (("second", (1, 1)), ("second", (2, 2))),
    (("second", (0, 1)), ("second", (0, 2))),
    (("second", (1, 2)), ("first", 0)),
    (("first", 1), ("first", 2)),
)


def _raw_moments(finufft, shape, coords, offset, gauss, tolerance, nthreads):
    """Weight, first and second moments from the raw sums ``sum_j w_ij x_j^p``.

    For a kernel far wider than the points (see ``DERIVATIVES_UP_TO``): the ten
    sums of ``w_ij`` times ``1, x_j, x_j x_j^T`` (coordinates about the box's
    centre, so at most half the extent), packed in pairs into five complex
    strengths, one type-1 and one type-2 transform each; the moments about
    ``x_i`` follow by expanding ``(x_j - x_i)``.  Every weight is then close to
    1, so nothing large cancels: the error is about ``eps`` relative to the
    covariance's trace.
    """
    x, y, z = offset.T
    strengths = [
        1.0 + 1j * x,
        y + 1j * z,
        x * x + 1j * (x * y),
        x * z + 1j * (y * y),
        y * z + 1j * (z * z),
    ]
    spectra = _run_plans(finufft, 1, shape, coords, strengths, tolerance, nthreads)
    del strengths
    values = _run_plans(
        finufft, 2, shape, coords, [spectrum * gauss for spectrum in spectra], tolerance, nthreads
    )
    del spectra
    s0 = values[0].real
    s1 = np.column_stack([values[0].imag, values[1].real, values[1].imag])
    sxx, sxy, sxz = values[2].real, values[2].imag, values[3].real
    syy, syz, szz = values[3].imag, values[4].real, values[4].imag
    s2 = np.stack([sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz], axis=1).reshape(-1, 3, 3)
    first = s1 - offset * s0[:, None]
    cross = offset[:, :, None] * s1[:, None, :]
    second = (
        s2
        - cross
        - cross.transpose(0, 2, 1)
        + s0[:, None, None] * (offset[:, :, None] * offset[:, None, :])
    )
    return np.ascontiguousarray(s0), first, second


@njit(cache=True, nogil=True)
def _jacobi_bending(second, weight, normals, out):  # pragma: no cover
    """``lambda / trace`` per vertex by cyclic Jacobi rotations (see :func:`bending`).

    The answer goes to ``out`` (from the caller: a returned array would be
    boxed with a little Python code, where a Ctrl-C that arrived meanwhile
    would be raised and crash the caller).
    """
    a = np.empty((3, 3))
    v = np.empty((3, 3))
    for i in range(second.shape[0]):
        for r in range(3):
            for c in range(3):
                a[r, c] = second[i, r, c] / weight[i]
                v[r, c] = 1.0 if r == c else 0.0
        negligible = _JACOBI_NEGLIGIBLE * (abs(a[0, 0]) + abs(a[1, 1]) + abs(a[2, 2]))
        for _ in range(_JACOBI_SWEEPS):
            if a[0, 1] == 0.0 and a[0, 2] == 0.0 and a[1, 2] == 0.0:
                break
            for p, q in ((0, 1), (0, 2), (1, 2)):
                apq = a[p, q]
                if abs(apq) <= negligible:
                    a[p, q] = a[q, p] = 0.0
                    continue
                app, aqq = a[p, p], a[q, q]
                theta = (aqq - app) / (2.0 * apq)
                t = 1.0 / (abs(theta) + np.sqrt(theta * theta + 1.0))
                if theta < 0.0:
                    t = -t
                cos = 1.0 / np.sqrt(t * t + 1.0)
                sin = t * cos
                for k in range(3):  # rotate columns p, q
                    akp, akq = a[k, p], a[k, q]
                    a[k, p] = cos * akp - sin * akq
                    a[k, q] = sin * akp + cos * akq
                for k in range(3):  # and rows p, q
                    apk, aqk = a[p, k], a[q, k]
                    a[p, k] = cos * apk - sin * aqk
                    a[q, k] = sin * apk + cos * aqk
                a[p, q] = a[q, p] = 0.0
                for k in range(3):
                    vkp, vkq = v[k, p], v[k, q]
                    v[k, p] = cos * vkp - sin * vkq
                    v[k, q] = sin * vkp + cos * vkq
        # eigenvalues ascending (numpy.linalg.eigh's order), then the first closest vector
        order = (0, 1, 2)
        d0, d1, d2 = a[0, 0], a[1, 1], a[2, 2]
        if d1 < d0:
            order = (1, 0, 2) if d2 >= d0 else ((1, 2, 0) if d2 >= d1 else (2, 1, 0))
        elif d2 < d1:
            order = (0, 2, 1) if d2 >= d0 else (2, 0, 1)
        best, lam, trace = -1.0, 0.0, 0.0
        for j in order:
            trace += a[j, j]
            close = abs(v[0, j] * normals[i, 0] + v[1, j] * normals[i, 1] + v[2, j] * normals[i, 2])
            if close > best:
                best, lam = close, a[j, j]
        out[i] = lam / trace if trace > 0 else 0.0


#: More than enough: cyclic Jacobi on a 3 x 3 matrix converges quadratically (4-6 sweeps).
_JACOBI_SWEEPS = 30
#: Off-diagonal entries below this times the trace are dropped (they move an
#: eigenvalue by their square over the gap; the transform's error is 1e-10).
_JACOBI_NEGLIGIBLE = 1e-22


def bending(moments: KernelMoments, normals: np.ndarray) -> np.ndarray:
    """Local bending ``lambda / trace`` of each weighted covariance, in one compiled pass.

    What ``unsigned_bending(moments.covariance, normals)`` computes (the
    eigenvalue whose eigenvector is closest to the vertex normal, over the
    trace), by Jacobi rotations instead of LAPACK: a few times faster, and
    without the ``(n, 3, 3)`` covariance, eigenvector and product arrays.  The
    eigenvalues agree to about 1e-16 relative to the trace, far below the
    transform's error; where two eigenvectors are equally close to the
    normal the eigenvalues nearly coincide.

    Parameters
    ----------
    moments : KernelMoments
    normals : (n, 3) float

    Returns
    -------
    (n,) float
    """
    second = np.ascontiguousarray(moments.second, dtype=np.float64)
    weight = np.ascontiguousarray(moments.weight, dtype=np.float64)
    normals = np.ascontiguousarray(normals, dtype=np.float64)
    out = np.empty(len(weight))
    # each vertex alone: slices of the rows on numba's threads give the same bits, from as
    # many vertices on as the exact path's solver (1M: 0.37 -> 0.2 s)
    in_threads(
        0,
        len(out),
        lambda a, b: _jacobi_bending(second[a:b], weight[a:b], normals[a:b], out[a:b]),
        threads_from=PARALLEL_VERTICES,
    )
    return out


METHODS = ("auto", "exact", "fast")

#: ``method="auto"`` uses the fast transform from this many vertices on.  Below
#: it the exact sums take a second or two (their cost grows as n**2 at the
#: default bandwidth, where the kernel reaches about half the unit-area mesh,
#: while the transform's grows as n) and they are the parity reference; the
#: robustness set's meshes (up to about 10k vertices) stay on the exact path.
AUTO_FAST_VERTICES = 20_000


def check_method(method) -> str:
    """Validate a ``method`` choice (case-insensitive)."""
    if not isinstance(method, str) or method.lower() not in METHODS:
        raise ValueError(f"method must be one of {METHODS}; got {method!r}")
    return method.lower()


def resolve_method(method: str, points: np.ndarray, bandwidth: float, cutoff: float, kind: str):
    """The method that will run: ``"exact"`` or ``"fast"``.

    ``kind`` is ``"euclidean"``, ``"geodesic"`` or ``"precomputed"``.  ``"auto"``
    picks ``"fast"`` for Euclidean distances, ``cutoff == 0``, at least
    ``AUTO_FAST_VERTICES`` vertices, a mode grid that fits and FINUFFT installed;
    ``"exact"`` otherwise.  An explicit ``"fast"`` that cannot run raises.
    """
    if method == "exact":
        return "exact"
    possible = kind == "euclidean" and cutoff == 0
    if method == "auto":
        large = len(points) >= AUTO_FAST_VERTICES
        if possible and large and finufft_available() and fits(points, bandwidth):
            return "fast"
        return "exact"
    if kind != "euclidean":
        raise ValueError(
            f'method="fast" needs Euclidean distances; {kind} distances use method="exact"'
        )
    if cutoff != 0:
        raise ValueError(
            f'method="fast" sums every kernel weight and cannot apply cutoff={cutoff}; '
            'use cutoff=0 or method="exact"'
        )
    _require_finufft()
    return "fast"

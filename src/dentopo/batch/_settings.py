"""What a batch computes with: its settings, validated once before any file.

:class:`Settings` (the ariaDNE options, the metrics and molaR's and doolkit's
options, the preparation protocol, how files are read and how many numba threads
each mesh gets), :func:`make_settings`, which checks every option as the metrics
would, up front, and :func:`check_extras`, which checks that the optional
packages a batch needs here are installed before anything is computed.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from dataclasses import dataclass, field

from .._optional import DASK, EXACT_OCCLUSION, FAST_METHOD, MORPHOTESTER_OUTLINE
from ..ariadne import check_bandwidth, check_cutoff, check_distance_type, check_method
from ..formats import record_keys
from ..mesh import check_geometry
from ..prepare import Protocol, load_protocol
from ..sign import check_sign_method
from ..topography import check_metrics, check_orient
from ._measure import TopographyOptions


@dataclass(frozen=True)
class Settings:
    """What every mesh of a batch is computed with.

    ``metrics`` says which metrics a row holds; the ariaDNE fields
    (``bandwidth`` ... ``method``) and ``topography`` (molaR's options) are
    output columns of their metrics: a row is only reused by ``--resume`` if
    it holds every metric asked for, computed with the same settings.
    ``threads`` and ``geometry`` are how, not what: ``geometry`` is how each
    file is read (:func:`dentopo.mesh.load_mesh`); it is not a column, so
    rows are only reused when it is None.  ``prepare`` is the preparation
    protocol each mesh is prepared with in memory before it is measured
    (:func:`dentopo.prepare`), or None: the ``protocol`` column holds its
    label, and a row is only reused for the same protocol digest.
    """

    bandwidth: float = 0.08
    cutoff: float = 0.0
    distance_type: str = "euclidean"
    sign_method: str = "centroid"
    method: str = "auto"
    threads: int | None = None  # numba threads per mesh; None: numba's default
    geometry: str | None = None  # which mesh of a file holding several (load_mesh)
    metrics: tuple[str, ...] = ("ariadne",)
    topography: TopographyOptions = field(default_factory=TopographyOptions)
    prepare: Protocol | None = None

    @property
    def protocol(self) -> str | None:
        """The ``protocol`` cell of this batch's rows: the protocol's label, or None."""
        return None if self.prepare is None else self.prepare.label

    def options(self) -> dict:
        """The ``ariaDNE`` keyword arguments."""
        return {name: getattr(self, name) for name in ARIADNE_OPTIONS}

    def rotations(self) -> tuple[float, ...]:
        """OPCR's rotations (degrees) if OPCR is computed, else none."""
        return self.topography.rotations() if "opcr" in self.metrics else ()

    def keys(self) -> tuple[str, ...]:
        """The keys of this batch's records, in table order."""
        return record_keys(self.metrics, self.rotations())


#: The fields of :class:`Settings` that are ``ariaDNE`` keywords.
ARIADNE_OPTIONS = ("bandwidth", "cutoff", "distance_type", "sign_method", "method")


def check_extras(settings: Settings, *, scheduler=None) -> None:
    """Check that the extras a batch needs here are installed, before computing anything.

    A `scheduler` needs dask.distributed in this process; ``method="fast"``
    needs finufft where the meshes are computed, i.e. here unless they run on
    a scheduler (whose workers report a missing finufft per file); MorphoTester's
    RFI needs matplotlib (its outline is counted in a picture) likewise, and PCV's
    exact method embreex.  Cheap:
    nothing is imported.

    Raises
    ------
    dentopo._optional.MissingExtraError
        Naming the extra to install.
    """
    if scheduler is not None:
        if isinstance(scheduler, str):  # a Client passed in proves distributed is there
            DASK.check()
    elif settings.method == "fast":
        FAST_METHOD.check()
    if scheduler is None and "morphotester_rfi" in settings.metrics:
        MORPHOTESTER_OUTLINE.check()  # matplotlib draws MorphoTester's outline
    exact = settings.topography.pcv_method == "exact"
    if scheduler is None and "pcv" in settings.metrics and exact:
        EXACT_OCCLUSION.check()  # Embree casts the rays


def make_settings(
    *,
    bandwidth: float = 0.08,
    cutoff: float = 0.0,
    distance_type: str = "euclidean",
    sign_method: str = "centroid",
    method: str = "auto",
    threads: int | None = None,
    geometry: str | None = None,
    metrics: str | Iterable[str] = ("ariadne",),
    alpha: float = 0.075,
    find_alpha: bool = False,
    opcr_steps: int = 8,
    opcr_step: float = 5.625,
    min_faces: int = 3,
    min_area: float = 0.0,
    dne_outliers: float = 0.1,
    dne_boundary: str = "vertex",
    dne_kappa: float = 0.0,
    arc_boundary: str = "vertex",
    arc_range: tuple[float, float] = (0.01, 0.99),
    orient: str = "auto",
    duplicates: str = "drop",
    prepare=None,
    unit=None,
    mt_condition_check: bool = True,
    mt_outliers: str = "energy",
    mt_percentile: float = 99.9,
    mt_smooth: bool = False,
    mt_min_patch: int = 5,
    pcv_rays: int = 256,
    pcv_hemisphere: bool = True,
    pcv_method: str = "cloudcompare",
) -> Settings:
    """Validated batch settings (the same checks as the metrics, made once up front).

    `prepare` is a preparation protocol (a :class:`dentopo.Protocol`, the
    name of a shipped one, a TOML file's path) or None; it is read and
    checked here, before any file.

    Raises
    ------
    TypeError, ValueError
        Naming the offending option (:class:`dentopo.ProtocolError`, a
        ``ValueError``, for the protocol).
    """
    bandwidth = check_bandwidth(bandwidth)
    cutoff = check_cutoff(cutoff)
    if threads is not None and (
        isinstance(threads, bool) or not isinstance(threads, int) or threads < 1
    ):
        raise ValueError(f"threads must be a positive integer or None; got {threads!r}")
    return Settings(
        bandwidth=bandwidth,
        cutoff=cutoff,
        distance_type=check_distance_type(distance_type),
        sign_method=check_sign_method(sign_method),
        method=check_method(method),
        threads=threads,
        geometry=check_geometry(geometry),
        metrics=check_metrics(metrics),
        topography=TopographyOptions(
            alpha=alpha,
            find_alpha=find_alpha,
            opcr_steps=opcr_steps,
            opcr_step=opcr_step,
            min_faces=min_faces,
            min_area=min_area,
            dne_outliers=dne_outliers,
            dne_boundary=dne_boundary,
            dne_kappa=dne_kappa,
            arc_boundary=arc_boundary,
            arc_range=arc_range,
            orient=check_orient(orient),
            duplicates=duplicates,
            unit=unit,
            mt_condition_check=mt_condition_check,
            mt_outliers=mt_outliers,
            mt_percentile=mt_percentile,
            mt_smooth=mt_smooth,
            mt_min_patch=mt_min_patch,
            pcv_rays=pcv_rays,
            pcv_hemisphere=pcv_hemisphere,
            pcv_method=pcv_method,
        ),
        prepare=None if prepare is None else _check_protocol(prepare),
    )


def _check_protocol(prepare) -> Protocol:
    """The protocol `prepare` names, read and checked (a file that cannot be read: ValueError)."""
    try:
        return load_protocol(prepare)
    except OSError as exc:
        where = exc.filename if exc.filename is not None else prepare
        raise ValueError(
            f"cannot read the protocol {os.fspath(where)!r}: {exc.strerror or exc}"
        ) from None

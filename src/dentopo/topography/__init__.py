"""Dental topography metrics in molaR 6.0's definitions: one module per metric.

Classic DNE with its convex/concave split (``_classic_dne``, molaR's ``DNE``);
mean surface slope (``_slope``, molaR's ``Slope``); orientation patch count and
its rotated mean (``_opc``, molaR's ``OPC`` and ``OPCr``); the relief index with
its alpha-shape footprint and molaR's search for an alpha (``_rfi``, molaR's
``RFI``).  They share molaR's surface preparation (``_surface``).

May import: :mod:`dentopo.mesh`.  Nothing from ariadne, figures, formats, batch,
study or cli.
"""

from ._classic_dne import CLASSIC_FIELDS, ClassicDNEResult, classic_dne
from ._opc import OPC_FIELDS, OPCResult, OPCRResult, opc, opcr
from ._rfi import RFI_FIELDS, AlphaAdjustmentError, RFIResult, rfi
from ._slope import SLOPE_FIELDS, SlopeResult, slope

__all__ = [
    "CLASSIC_FIELDS",
    "OPC_FIELDS",
    "RFI_FIELDS",
    "SLOPE_FIELDS",
    "AlphaAdjustmentError",
    "ClassicDNEResult",
    "OPCRResult",
    "OPCResult",
    "RFIResult",
    "SlopeResult",
    "classic_dne",
    "opc",
    "opcr",
    "rfi",
    "slope",
]

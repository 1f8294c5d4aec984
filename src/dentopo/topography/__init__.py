"""Dental topography metrics in molaR 6.0's definitions: one module per metric.

Today: classic DNE with its convex/concave split (``_classic_dne``), as molaR's
``DNE`` computes it, and the relief index with its alpha-shape footprint and
molaR's search for an alpha (``_rfi``), as molaR's ``RFI`` computes it.

May import: :mod:`dentopo.mesh`.  Nothing from ariadne, figures, formats, batch,
study or cli.
"""

from ._classic_dne import CLASSIC_FIELDS, ClassicDNEResult, classic_dne
from ._rfi import RFI_FIELDS, AlphaAdjustmentError, RFIResult, rfi

__all__ = [
    "CLASSIC_FIELDS",
    "RFI_FIELDS",
    "AlphaAdjustmentError",
    "ClassicDNEResult",
    "RFIResult",
    "classic_dne",
    "rfi",
]

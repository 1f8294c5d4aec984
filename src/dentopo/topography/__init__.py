"""Dental topography metrics in molaR 6.0's definitions: one module per metric.

Today: classic DNE with its convex/concave split (``_classic_dne``), as molaR's
``DNE`` computes it.

May import: :mod:`dentopo.mesh`.  Nothing from ariadne, figures, formats, batch,
study or cli.
"""

from ._classic_dne import CLASSIC_FIELDS, ClassicDNEResult, classic_dne

__all__ = ["CLASSIC_FIELDS", "ClassicDNEResult", "classic_dne"]

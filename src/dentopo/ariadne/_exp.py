"""``exp(-t)`` inline in the kernels' pair loops, without a table: vectorised, within 2 ulps.

libm's ``exp`` is a call that LLVM does not vectorise.  The kernels compute each
pair's weight ``exp(-t)``, ``t = d**2 / h**2 >= 0``, with Cody and Waite's range
reduction instead:

* ``k = round(t / ln 2)`` and ``r = k ln 2 - t`` in ``[-ln 2 / 2, ln 2 / 2]``, with
  ``ln 2`` in two parts (``LN2_HI`` has 32 significant bits, so ``k * LN2_HI`` is
  exact for every ``k`` here and ``k * LN2_HI - t`` is exact too);
* ``exp(r)`` by a degree-11 polynomial (interpolating ``exp`` at the Chebyshev
  nodes of the interval, solved in 60-digit decimal arithmetic: within 1 ulp
  of ``exp`` on the interval), in Estrin's form (short dependency chains);
* ``2**-k`` made from its bits: ``k`` is read off as an integer from the bits
  of ``k + 2**52`` and put into the exponent field.

Every step is arithmetic on registers (no table, so no gather), and LLVM
vectorises the pair loop with it inline.  On this module's test grid the value
is within 2 ulps of libm's ``exp`` for every ``t`` in ``[0, T_MAX]``; the
table-times-polynomial exponential it replaced was within 2 ulps too, and cost
about 20 % more per pair (1.78 against 1.44 ns in a single-thread pair loop).

``exp_neg`` is compiled with every fast-math flag but ``reassoc``: the
reduction must be evaluated as written (reassociated, ``k * LN2_HI + k *
LN2_LO`` becomes ``k * ln 2`` rounded, and ``(k + 2**52) - 2**52`` becomes
``k``).  LLVM keeps each instruction's flags when it inlines the function
into a kernel compiled with ``fastmath=True``, so the kernel's own sums are
still reassociated (vectorised) and this function is not.

``t`` above ``T_MAX`` (and NaN) gives ``exp(-T_MAX)``, 3.3e-308, the smallest
value whose ``2**-k`` is a normal number: a weight that small changes no sum
a kernel adds it to (every vertex's own weight is 1), and it is still kept or
dropped by the kernels' own tests (the radius, and ``w > cutoff``).
"""

from __future__ import annotations

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from .._jit import njit

#: ``t`` beyond this gives ``exp(-T_MAX)``: ``2**-k`` stays a normal number (k <= 1021).
T_MAX = 708.0
LOG2E = 1.4426950408889634
#: ``ln 2 = LN2_HI + LN2_LO``; ``LN2_HI`` has 32 significant bits (fdlibm's split).
LN2_HI = 6.93147180369123816490e-01
LN2_LO = 1.90821492927058770002e-10
_TWO52 = 4503599627370496.0
_ONE_BITS = 1023 << 52

#: ``exp(r) ~ sum C[j] r**j`` on ``|r| <= ln(2) / 2`` (Chebyshev interpolation, degree 11).
C0, C1, C2, C3 = 1.0, 1.0, 0.5000000000000019, 0.1666666666666668
C4, C5, C6, C7 = (
    0.04166666666648666,
    0.00833333333331949,
    0.0013888888952696516,
    0.00019841269890340666,
)
C8, C9, C10, C11 = (
    2.4801485074105115e-05,
    2.7557240604663896e-06,
    2.763279054211718e-07,
    2.511015364692893e-08,
)


@intrinsic
def _bits(typingctx, x):
    """The bits of a float64 as an int64 (no conversion: a vector bitcast)."""

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return types.int64(types.float64), codegen


@intrinsic
def _from_bits(typingctx, bits):
    """The float64 whose bits are the given int64."""

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.int64), codegen


@njit(cache=True, fastmath={"nnan", "ninf", "nsz", "arcp", "contract", "afn"})
def exp_neg(t):
    """``exp(-t)`` for ``t >= 0`` (see the module doc; ``t > T_MAX`` or NaN: ``exp(-T_MAX)``)."""
    t = t if t < T_MAX else T_MAX  # NaN too
    k = np.floor(t * LOG2E + 0.5)
    r = (k * LN2_HI - t) + k * LN2_LO
    r2 = r * r
    r4 = r2 * r2
    q0 = (C0 + C1 * r) + (C2 + C3 * r) * r2
    q1 = (C4 + C5 * r) + (C6 + C7 * r) * r2
    q2 = (C8 + C9 * r) + (C10 + C11 * r) * r2
    p = (q0 + q1 * r4) + q2 * (r4 * r4)
    power = _from_bits(_ONE_BITS - ((_bits(k + _TWO52) - _bits(_TWO52)) << 52))
    return p * power

"""Python's decimal rounding, ``round(float(x), ndigits)``, over an array at numpy's speed.

``round(x, n)`` returns the double nearest to ``k / 10**n``, where ``k`` is ``x * 10**n``
rounded half to even on the exact binary value of ``x``.  Here ``y = fl(x * 10**n)`` carries
a rounding error below ``|y| * 2**-53`` (under 1.2e-7 for ``|y| < 1e9``), so ``rint(y)`` is
that ``k`` unless ``y`` lies within 1e-6 of a half-integer; and ``k / 10**n`` is one
correctly rounded division of two exact doubles, the double nearest to ``k / 10**n``.  Values
near a half-integer, with ``|y| >= 1e9`` or not finite are rounded by ``round`` itself, so
every value equals ``round(float(x), n)`` bit for bit (tests/python/test_campaign_rounding.py).
"""
from __future__ import annotations

import numpy as np

#: |x * 10**n| below which the array path is exact (module docstring).
_Y_MAX = 1e9
#: Distance from a half-integer below which ``round`` decides.
_TIE_MARGIN = 1e-6


def decimal_round(values, ndigits: int) -> list[float]:
    """``[round(float(x), ndigits) for x in values]``, bit for bit (module docstring)."""
    x = np.asarray(values, dtype=float).reshape(-1)
    scale = 10.0 ** ndigits
    with np.errstate(invalid="ignore", over="ignore"):
        y = x * scale
        out = np.rint(y) / scale
        slow = ~(np.abs(y) < _Y_MAX) | (np.abs(np.abs(y - np.trunc(y)) - 0.5) < _TIE_MARGIN)
    rounded = out.tolist()
    for i in np.flatnonzero(slow).tolist():
        rounded[i] = round(float(x[i]), ndigits)
    return rounded

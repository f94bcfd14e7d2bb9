"""decimal_round equals Python's round(float(x), n) bit for bit: on probabilities, on values
next to every kind of rounding tie, on large, tiny, negative and non-finite values."""
from __future__ import annotations

import math
import struct

import numpy as np
import pytest

from f16mmae.campaign.engine.rounding import decimal_round


def _bits(values) -> list[bytes]:
    return [struct.pack("<d", v) for v in values]


def _check(values, n: int) -> None:
    got = decimal_round(values, n)
    want = [round(float(x), n) for x in values]
    assert all(type(v) is float for v in got)
    assert _bits(got) == _bits(want)


@pytest.mark.parametrize("n", [0, 1, 3, 5, 7])
def test_random_probabilities_and_wide_values(n):
    rng = np.random.default_rng(n)
    _check(rng.uniform(0.0, 1.0, 20_000), n)
    _check(rng.standard_normal(5_000) * 10.0 ** rng.integers(-12, 14, 5_000), n)


@pytest.mark.parametrize("n", [2, 5])
def test_values_at_and_beside_decimal_ties(n):
    # (2k + 1) / (2 * 10**n) is a decimal tie; the doubles nearest it and their neighbours
    # fall on either side of it, where a rounding of x * 10**n could pick the other k
    k = np.arange(0, 200_001, 7) if n == 5 else np.arange(0, 201)
    ties = (2 * k + 1) / (2 * 10.0 ** n)
    near = np.concatenate([ties, np.nextafter(ties, 0.0), np.nextafter(ties, 2.0),
                           np.nextafter(np.nextafter(ties, 2.0), 2.0), -ties])
    _check(near, n)


def test_special_values():
    values = [0.0, -0.0, 1.0, -1.0, 1e-320, 5e-324, 1e300, -1e300, 2.5e9, 123456789.123455,
              math.inf, -math.inf, math.nan, 0.999995, 0.000005, 0.000015, 0.5]
    got = decimal_round(values, 5)
    want = [round(v, 5) for v in values]
    assert [str(v) for v in got] == [str(v) for v in want]  # NaN compares by its text
    assert math.copysign(1.0, decimal_round([-0.0], 5)[0]) == -1.0

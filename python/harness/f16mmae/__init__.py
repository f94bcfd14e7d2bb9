"""f16mmae: multiple model adaptive estimation (MMAE) failure detection for the F-16.

Implements Eide & Maybeck, "An MMAE Failure Detection System for the F-16": a bank of
steady-state Kalman filters (C++ core, ``f16mmae.core``), a nonlinear JSBSim truth model
(``f16mmae.truth``), the filter design pipeline (``f16mmae.design``) and closed-loop
Monte Carlo campaigns.  The compiled core is imported lazily so the pure-Python parts
work on their own.
"""
from importlib.metadata import PackageNotFoundError, version as _version

try:
    __version__ = _version("f16mmae")
except PackageNotFoundError:  # running from a source tree that was never installed
    __version__ = "0.0.0+unknown"
